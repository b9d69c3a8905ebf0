"""`simulate_network_moreau`: Moreau–Jean time stepping for structures with many contacts.

First order, no event location: one convex velocity-level contact problem per step,
solved by projected Gauss–Seidel on the Delassus matrix in a compiled loop (see
`presliding.network.stepping._moreau_kernel`; the per-contact law is solved exactly, so a
contact below break-away has u = 0.0 and does not creep). The θ-method treats the
smooth forces (θ = 1/2 by default); the contact law acts on the velocity at the end
of the step. Use it for structures with many contacts where the exact path
(`simulate_network`) has too many events; it converges to the exact path at first
order in the step.
"""

from __future__ import annotations

import math
from typing import Any, cast

import numpy as np
import scipy.sparse
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_count,
    as_positive_scalar,
    as_real_scalar,
    check_size,
    check_type,
    fmt,
)
from presliding.network._contacts import Contacts
from presliding.network._start import MAX_SAMPLES, run_start
from presliding.network.results import NetworkEnergy, NetworkResult, NetworkState
from presliding.network.stepping._moreau_kernel import moreau_loop
from presliding.network.stepping._moreau_sparse import primal_loop
from presliding.network.structure import NetworkStructure

__all__ = ["simulate_network_moreau"]

FloatArray = NDArray[np.float64]


def _csr(a: Any, drop: float = 1e-18) -> tuple[Any, Any, Any]:
    """CSR arrays of `a` (dense or sparse), entries below `drop` times its largest entry
    dropped."""
    m = scipy.sparse.csr_matrix(a, dtype=np.float64, copy=True)
    scale = float(np.max(np.abs(m.data), initial=0.0))
    m.data[np.abs(m.data) <= drop * scale] = 0.0
    m.eliminate_zeros()
    return (np.ascontiguousarray(m.indptr, dtype=np.int64),
            np.ascontiguousarray(m.indices, dtype=np.int64),
            np.ascontiguousarray(m.data, dtype=np.float64))  # fmt: skip


def simulate_network_moreau(
    structure: NetworkStructure,
    t_end: float,
    step: float,
    initial_position: ArrayLike | None = None,
    initial_velocity: ArrayLike | None = None,
    initial_state: str | NetworkState = "relaxed",
    *,
    theta: float = 1.0,
    samples: int = 1001,
    t_start: float | None = None,
    tolerance: float = 1e-12,
    max_sweeps: int = 200,
) -> NetworkResult:
    """Simulate a structure with friction contacts by Moreau–Jean time stepping.

    Parameters
    ----------
    structure : NetworkStructure
    t_end : float
        End time [s].
    step : float
        Time step h [s]; the span is cut into equal steps no longer than `step`.
    initial_position, initial_velocity, initial_state, t_start
        As for `simulate_network`.
    theta : float
        θ ∈ [1/2, 1] of the θ-method for the smooth forces. The default 1 (backward
        Euler) never creates energy: the energy residual is never positive beyond
        rounding, on any structure and step. 1/2 has no numerical damping of the linear
        structure (closer on lightly damped vibration at a given step), but the
        velocity-level contact impulses combined with it can create a little energy
        (up to ~5e-4 of the initial energy at h = 1e-3 s on small random structures,
        shrinking with the step); use it only where that is acceptable.
    samples : int
        About this many samples (every k-th step, k = max(1, steps // (samples − 1))).
    tolerance : float
        PGS stops when no contact impulse changed by more than this times the largest.
    max_sweeps : int
        PGS sweeps per step at most; steps that reach it are counted in the message and
        the status is "not_converged".

    Returns
    -------
    NetworkResult
        ``method`` "moreau"; stick intervals and reversals are read off the samples
        (to the sample spacing); the energy ``residual`` is the scheme's numerical
        dissipation (O(h); never positive with θ = 1).
    """
    check_type("structure", structure, NetworkStructure)
    n, n_c = structure.n_coordinates, structure.n_contacts
    cts = Contacts.of(structure.friction)
    h = as_positive_scalar("step", step)
    theta = as_real_scalar("theta", theta)
    if not 0.5 <= theta <= 1.0:
        raise ValueError(f"`theta` must be in [0.5, 1]; got {fmt(theta)}.")
    samples = as_count("samples", samples, minimum=2, maximum=MAX_SAMPLES)
    max_sweeps = as_count("max_sweeps", max_sweeps, minimum=1, maximum=1_000_000)
    tolerance = as_positive_scalar("tolerance", tolerance)
    w = structure.contacts
    start = run_start(w, cts.k.shape[0], initial_position, initial_velocity, initial_state,
                      t_start, t_end)  # fmt: skip
    t0, t_end, q, v, g, e, last = (start.t0, start.t_end, start.q, start.v, start.g, start.e,
                                   start.last)  # fmt: skip
    n_steps = check_size("step", step, math.ceil((t_end - t0) / h * (1 - 1e-12)), what="steps")
    h = (t_end - t0) / n_steps
    every = max(1, n_steps // (samples - 1))
    rows = n_steps // every + 1 + (1 if n_steps % every else 0)
    check_size("samples", samples, rows * (2 * n + 6 * n_c))
    separable = _separable(w) if structure.is_sparse else None
    m, k, damping = structure.mass, structure.stiffness, cast(Any, structure.damping)
    out = {name: np.zeros(shape) for name, shape in (
        ("q", (rows, n)), ("v", (rows, n)), ("a", (rows, n)), ("g", (rows, n_c)),
        ("lam", (rows, n_c)), ("fel", (rows, n_c)), ("ee", (rows,)), ("mode", (rows, n_c)),
        ("en", (rows, 3, n_c)), ("sd", (rows, 2)))}  # fmt: skip
    e_initial = float(0.5 * v @ (m @ v) + 0.5 * q @ (k @ q) + 0.5 * np.sum(cts.k * e * e))
    out["q"][0], out["v"][0], out["g"][0] = q, v, g
    out["mode"][0] = np.sign(v @ w)
    out["fel"][0] = cts.per_contact(cts.k * e)
    out["ee"][0] = 0.5 * np.sum(cts.k * e * e)
    p = np.zeros(n_c)
    ft = np.ascontiguousarray(structure.forcing_times, dtype=np.float64)
    fv = np.ascontiguousarray(structure.forcing_values, dtype=np.float64)
    q, v, g, e = (np.ascontiguousarray(a, dtype=np.float64) for a in (q, v, g, e))
    o = [out[name] for name in ("q", "v", "a", "g", "lam", "fel", "ee", "mode", "en", "sd")]
    shared = (cts.c1, cts.sigma, cts.k, cts.r, cts.start, tolerance, max_sweeps)
    if separable is not None:  # sparse: Gauss–Seidel on the velocities
        what = scipy.sparse.csr_array(m + (h * theta) * damping + (h * theta) ** 2 * k)
        most, capped = primal_loop(
            n_steps, h, theta, t0, q, v, g, e, p, *_csr(what), *_csr(damping),
            *_csr(k), ft, fv, *separable, *shared, every, *o,
        )  # fmt: skip
    else:
        md, kd, wd, cd = (np.asarray(cast(Any, x).toarray()) if scipy.sparse.issparse(x)
                          else np.asarray(x) for x in (m, k, w, damping))  # fmt: skip
        wi = np.linalg.inv(md + h * theta * cd + (h * theta) ** 2 * kd)
        b = wi @ wd
        gmat = wd.T @ b
        gmat = 0.5 * (gmat + gmat.T)
        rigid = bool(np.linalg.matrix_rank(wd) == n)
        most, capped = moreau_loop(
            n_steps, h, theta, t0, q, v, g, e, p, *_csr(wi), *_csr(b), *_csr(wd.T),
            *_csr(gmat), np.ascontiguousarray(np.diag(gmat)), *_csr(cd), *_csr(kd), ft, fv,
            *shared, rigid, every, *o,
        )  # fmt: skip
    return _result(structure, cts, out, t0, h, every, rows, q, v, g, e, last, e_initial,
                   n_steps, int(most), int(capped))  # fmt: skip


def _separable(w: Any) -> tuple[NDArray[np.int64], FloatArray] | None:
    """(the contact of each coordinate (−1: none), α_c) when each contact acts on one
    coordinate and each coordinate carries at most one (w_c = α_c·e_i); None otherwise
    (the dense Delassus path runs, its Ŵ⁻¹ checked for size)."""
    n, n_c = w.shape
    col = scipy.sparse.csc_array(w)
    col.eliminate_zeros()
    rows = col.indices
    if np.any(np.diff(col.indptr) != 1) or np.unique(rows).shape[0] != n_c:
        check_size("structure", f"{n} coordinates", 3.0 * n * n, what="entries of Ŵ⁻¹",
                   )  # fmt: skip
        return None
    contact_of = np.full(n, -1, dtype=np.int64)
    contact_of[rows] = np.arange(n_c, dtype=np.int64)
    return contact_of, np.ascontiguousarray(col.data, dtype=np.float64)


def _quadratic(x: FloatArray, a: Any) -> FloatArray:
    """xᵀ·A·x of every row of x (A dense or sparse)."""
    return np.asarray(np.sum((a @ x.T).T * x, axis=1))


def _result(structure: NetworkStructure, cts: Contacts, out: dict[str, FloatArray], t0: float,
            h: float, every: int, rows: int, q: FloatArray, v: FloatArray, g: FloatArray,
            e: FloatArray, last: FloatArray, e_initial: float, n_steps: int, most: int,
            capped: int) -> NetworkResult:  # fmt: skip
    time = np.minimum(t0 + h * every * np.arange(rows), t0 + h * n_steps)
    time[-1] = t0 + h * n_steps
    m, k, w = structure.mass, structure.stiffness, structure.contacts
    mode = out["mode"]
    n_c = w.shape[1]
    stick, rev_t, rev_g, stops = [], [], [], np.full(n_c, np.nan)
    last_dir = np.asarray(last, dtype=float).copy()
    for c in range(n_c):
        col = mode[:, c]
        stuck = col == 0.0
        starts = np.flatnonzero(stuck & np.concatenate([[True], ~stuck[:-1]]))
        ends = np.flatnonzero(stuck & np.concatenate([~stuck[1:], [True]]))
        stick.append(np.column_stack([time[starts], time[np.minimum(ends + 1, rows - 1)]]))
        moving = np.flatnonzero(~stuck)
        dirs = col[moving]
        flips = moving[1:][dirs[1:] != dirs[:-1]]
        if moving.size and last_dir[c] != 0.0 and dirs[0] != last_dir[c]:
            flips = np.concatenate([[moving[0]], flips])
        rev_t.append(time[flips])
        rev_g.append(out["g"][flips, c])
        if moving.size:
            last_dir[c] = dirs[-1]
        if stuck[-1] and starts.size:
            stops[c] = time[starts[-1]]
    gd = np.where(mode == 0.0, 0.0, out["v"] @ w)
    en = NetworkEnergy(
        kinetic=0.5 * _quadratic(out["v"], m),
        potential=0.5 * _quadratic(out["q"], k),
        elastic=out["ee"], coulomb=out["en"][:, 0, :], hysteretic=out["en"][:, 1, :],
        viscous=out["en"][:, 2, :], damping=out["sd"][:, 0], work=out["sd"][:, 1],
        initial=e_initial,
    )  # fmt: skip
    status = "success" if capped == 0 else "not_converged"
    solver = ("Gauss–Seidel on the velocities (sparse)" if structure.is_sparse and
              _separable(w) is not None else "PGS")  # fmt: skip
    message = (f"{n_steps} steps of {h!r} s (θ-method with Moreau–Jean contacts); {solver} "
               f"used at most {most} sweeps per step")  # fmt: skip
    if capped:
        message += f"; {capped} steps stopped at max_sweeps without converging"
    final = NetworkState(float(time[-1]), q.copy(), v.copy(), g.copy(), e.copy(),
                         mode[-1].copy(), last_dir)  # fmt: skip
    ft, fv = structure.forcing_times, structure.forcing_values
    idx = np.maximum(np.searchsorted(ft, time, side="right") - 1, 0)
    return NetworkResult(
        time=time,
        position=out["q"],
        velocity=out["v"],
        acceleration=out["a"],
        applied_force=np.asarray(fv)[idx],
        contact_displacement=out["g"],
        contact_velocity=gd,
        contact_force=out["lam"],
        elastic_force=out["fel"],
        contact_mode=mode,
        stick_intervals=stick,
        reversal_times=rev_t,
        reversal_displacements=rev_g,
        stop_times=stops,
        energy=en,
        final_state=final,
        forces_unique=True,
        status=status,
        message=message + ".",
        n_events=n_steps,
        method="moreau",
        structure=structure,
    )
