"""Start values of the pooled fits: eq. 17 as one regression over every record.

Eq. 17 integrated in time, record by record,

    m·(v − v_0) + ∫ (c1·sign v + σ·v + Σ_g w_g·stop_g(y) + offset) dt = ∫ u dt,

needs no differentiation of a noisy velocity. The rows of all records are
stacked and bounded linear least squares gives m, c1, the offset and the
stiffnesses w_g of a geometric grid of stops (relaxed at each record's first
sample: only a start), each record only while it moves (at rest the Coulomb
element's force is set-valued). The grid is a nonparametric virgin curve
G(s) = Σ_g w_g·min(s, r_g) of the elastic part, which `ModelSpec.start` turns
into the model's parameters. Free records (u = 0) determine everything only
per unit mass; the mass is then held at 1 (or its given value).

An asymmetric model (`ModelSpec.negative`) is started per direction: its motion
is exactly that of the symmetric model of the mean levels under
u − (F_c⁺ − F_c⁻)/2 (`ModelSpec`), so the regression with a force offset is the
regression per direction (sign(v) and a constant span the two directions'
columns, F_c± = F̄_c ± offset); the offset is then turned into the two sides
(their ratio kept within [1/3, 3]) and σ⁻ starts at σ.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from presliding.identification.problem import _pi_regression as pr
from presliding.identification.problem._model_spec import ModelSpec
from presliding.identification.records import _response_tools as rt
from presliding.identification.records._pooled_record import Record

FloatArray = NDArray[np.float64]


def _moving_rows(rec: Record, first_run: bool = False) -> tuple:
    """The record up to where it stops moving, or its first run of sliding only.

    At rest the Coulomb element carries whatever balances u − F_el, which the
    column sign(v) = 0 does not; after the first stop, presliding (elastic)
    friction takes over, which the Coulomb law alone does not describe.
    """
    t, y, v, u = rec.time, rec.position, rec.velocity, rec.applied_force
    fast = np.abs(v) > 0.05 * np.max(np.abs(v))
    moving = np.flatnonzero(fast)
    if not moving.size:
        return t, y, v, u
    begin, end = int(moving[0]), int(moving[-1]) + 2
    if first_run:
        slow = np.flatnonzero(~fast[begin:])
        end = begin + int(slow[0]) + 1 if slow.size else end
        begin = max(begin - 1, 0)
    else:
        begin = 0
    return t[begin:end], y[begin:end], v[begin:end], u[begin:end]


def _solve(blocks: list, rhs: list, lower: FloatArray) -> FloatArray | None:
    """Bounded linear least squares of the stacked rows (None if underdetermined)."""
    from scipy.optimize import lsq_linear
    from threadpoolctl import threadpool_limits

    mat, b = np.vstack(blocks), np.concatenate(rhs)
    if mat.shape[0] <= mat.shape[1]:
        return None
    scale = np.linalg.norm(mat, axis=0)
    scale[scale == 0] = 1.0
    # the right-hand side scaled too: the solver's start, trust region and stopping
    # tests are then the same in any consistent units (mm and ms, g, ...), not only
    # its columns' (the solution of unscaled forces·seconds came out otherwise)
    size = float(np.linalg.norm(b)) or 1.0
    with threadpool_limits(limits=1, user_api="blas"):  # a tall, thin problem
        # BVLS, an active-set method, ends at the exact bounded optimum: the start is the
        # same in any consistent units to rounding (the trust-region method stopped on its
        # tolerance, which on a nearly collinear grid moved k_1 by 5e-4 between unit systems)
        fit = lsq_linear(mat / scale, b / size, bounds=(lower / size, np.inf), method="bvls")
        return fit.x * size / scale


def pooled_start(
    records: list[Record],
    spec: ModelSpec,
    mass: float | None,
    offset: bool,
    viscous: bool = False,
) -> dict[str, float]:
    """Start values of the shared parameters (``mass``, the model's, ``viscous``, ``offset``;
    an asymmetric model's negative side, module notes).

    Two stages: m, F_c (and the offset) from the Coulomb law alone, which is
    robust; then, with that mass held, c1 and the grid stiffnesses.
    """
    if spec.negative is None:
        return _regression_start(records, spec, mass, offset, viscous)
    start = _regression_start(records, spec, mass, True, viscous)  # the mean levels, an offset
    half = start.pop("offset")
    mean = spec.coulomb_level(start) if spec.n else start["coulomb"]
    half = min(max(half, -0.5 * mean), 0.5 * mean)  # F_c⁻/F_c⁺ within [1/3, 3]
    start = spec.sided(start, (mean - half) / (mean + half))
    if viscous:
        start["viscous_negative"] = start["viscous"]
    return start


def _regression_start(records: list[Record], spec: ModelSpec, mass: float | None, offset: bool,
                      viscous: bool) -> dict[str, float]:  # fmt: skip
    """The two stages of `pooled_start` (the symmetric model's start)."""
    span = max(float(np.ptp(r.position)) for r in records) or 1.0
    steps = np.concatenate([np.abs(np.diff(r.position)) for r in records])
    steps = steps[steps > 0]
    quantum = float(np.min(steps)) if steps.size else 1e-5 * span
    # thresholds below ~1e-3 of the travel would stand in for the Coulomb element
    grid = pr.geometric_grid(max(2.0 * quantum, 1e-3 * span), 0.5 * span, span, 32)
    parts = [_moving_rows(r) for r in records]
    acc = float(np.mean([np.mean(np.abs(np.gradient(r.velocity, r.time))) for r in records]))
    # stage 1, first slides only: m·(v − v0) + F_c·∫sign v dt (+ offset·t) = ∫u dt
    blocks, rhs = [], []
    for t, _, v, u in (_moving_rows(r, first_run=True) for r in records):
        cols = [rt.integral(t, np.sign(v))] + ([rt.integral(t, v)] if viscous else [])
        cols += [t - t[0]] if offset else []
        b = rt.integral(t, u)
        if mass is None:
            cols.insert(0, v - v[0])
        else:
            b = b - mass * (v - v[0])
        blocks.append(np.column_stack(cols))
        rhs.append(b)
    lower = np.zeros(blocks[0].shape[1])
    if offset:
        lower[-1] = -np.inf
    sol = _solve(blocks, rhs, lower)
    m = mass if mass is not None else (float(sol[0]) if sol is not None else 1.0)
    if not m > 0:
        m = 1.0
    lead = int(mass is None)
    fc = float(sol[lead]) if sol is not None else m * acc
    sigma = float(sol[lead + 1]) if sol is not None and viscous else 0.0
    off = float(sol[-1]) if sol is not None and offset else 0.0
    if not fc > 1e-3 * m * acc:  # one acceleration only: m and F_c not separable
        fc = 0.5 * m * acc or 1.0
    # stage 2, the mass held: c1·∫sign v dt + Σ_g w_g·∫stop_g dt = ∫(u − offset) dt − m·(v − v0)
    blocks, rhs = [], []
    for t, y, v, u in parts:
        cols = [np.sign(v), *pr.stop_basis(y)(grid)[0].T]
        blocks.append(np.column_stack([rt.integral(t, c) for c in cols]))
        rhs.append(rt.integral(t, u - off - sigma * v) - m * (v - v[0]))
    sol = _solve(blocks, rhs, np.zeros(grid.shape[0] + 1)) if spec.n or spec.density else None
    c1, weights = (0.5 * fc, np.zeros_like(grid)) if sol is None else (float(sol[0]), sol[1:])
    elastic = float(weights @ grid)
    if elastic > 0 and not 0.5 < (c1 + elastic) / fc < 2.0:  # keep the robust level
        weights = weights * max(fc - c1, 0.1 * fc) / elastic
    c1 = min(c1, fc)
    if not 0.05 * fc < c1 < 0.95 * fc:
        c1 = min(max(c1, 0.05 * fc), 0.95 * fc)
    if not np.any(weights > 0):
        weights = np.zeros_like(grid)
        weights[len(grid) // 2] = (fc - c1) / grid[len(grid) // 2]
    start = {"mass": float(m), **spec.start(fc, c1, grid, weights)}
    if viscous:
        start["viscous"] = sigma
    if offset:
        start["offset"] = off
    return start
