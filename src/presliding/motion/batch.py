"""Many motions at once (eqs. 12, 17): `simulate_batch` and the fast `free_response`.

Both run compiled loops over the whole batch or time grid (see `presliding.motion._batch_events`),
with the same exact event method as `presliding.motion.simulation` for finite elements.
They are public through `presliding.motion`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from presliding._validation import (
    as_count,
    as_nonnegative_scalar,
    as_positive_scalar,
    as_real_scalar,
    check_finite_derived,
    check_size,
    check_time_span,
)
from presliding.friction.pi_friction import PIFriction
from presliding.motion import _batch_events as _batch
from presliding.motion import _batch_setup as _setup
from presliding.motion import _event, _run
from presliding.motion._forcing import as_forcing
from presliding.motion.results import FreeResponse, MotionBatch, motion_status


def simulate_batch(
    models: PIFriction | Sequence[PIFriction] | None = None,
    mass: float | ArrayLike = 1.0,
    initial_velocity: float | ArrayLike = 0.0,
    *,
    coulomb: ArrayLike | None = None,
    stiffness: ArrayLike | None = None,
    breakaway: ArrayLike | None = None,
    threshold: ArrayLike | None = None,
    viscous: float | ArrayLike | None = None,
    applied_force: float | tuple[ArrayLike, ArrayLike] = 0.0,
    initial_position: float | ArrayLike = 0.0,
    initial_state: str = "relaxed",
    t_end: float | None = None,
    t_eval: ArrayLike | None = None,
    t_start: float = 0.0,
    max_events: int = 10_000_000,
) -> MotionBatch:
    """Exact motions of many parameter sets and/or initial velocities, in parallel.

    Every member is solved by the exact event method of `simulate` (eq. 17 with
    finite elements, eq. 8, and the viscous term σ·ẏ) on one compiled thread
    per member. Lengths must be 1
    or one common batch size B; length-1 inputs are shared by all members.

    Parameters
    ----------
    models : PIFriction or sequence of PIFriction, optional
        One model per member (or one shared); members with fewer elements are
        padded with inert ones. Give either `models` or the parameter arrays.
    mass : float or array_like, shape (B,)
        m > 0 [kg].
    initial_velocity : float or array_like, shape (B,)
        ẏ(t_start) [m/s].
    coulomb : float or array_like, shape (B,), keyword only
        c1 >= 0 [N], the Coulomb element.
    stiffness : array_like, shape (B, N) or (N,), keyword only
        k_j > 0 [N/m] (eq. 6); a 1-D vector is shared by all members.
    breakaway, threshold : array_like, shape (B, N), (N,) or scalar, keyword only
        Exactly one of them: breakaway forces c_j = k_j·r_j [N] or thresholds
        r_j [m]; the other one must come out finite and positive (as in
        `PIFriction`).
    viscous : float or array_like, shape (B,), keyword only
        σ >= 0 [N·s/m], the viscous term σ·ẏ; default 0 (the paper's assumption
        (i)). With `models` it comes from each model's ``viscous``.
    applied_force : float or (time, value) pair, keyword only
        u [N], shared by all members: a constant, or samples held piecewise
        constant.
    initial_position : float or array_like, shape (B,), keyword only
        y(t_start) [m].
    initial_state : "relaxed" or "saturated", keyword only
        As in `simulate`.
    t_end : float, keyword only
        End time (> t_start); default ``t_eval[-1]``.
    t_eval : array_like, keyword only
        Strictly increasing sample times in [t_start, t_end]; default 1001
        uniform samples.
    t_start : float, keyword only
        Start time [s] (default 0).
    max_events : int, keyword only
        Event limit per member (a member that reaches it has the member status
        "event_limit").

    Returns
    -------
    MotionBatch
        Positions and velocities (B, T), stop times, reversal counts (sign
        changes of the velocity; a start from rest is not one), a status per
        member (``member_status``) and an overall ``status``.

    Examples
    --------
    >>> import presliding as ps
    >>> batch = ps.simulate_batch(coulomb=[1.0, 2.0], stiffness=[100.0], breakaway=2.0,
    ...                           initial_velocity=1.0, t_end=2.0)
    >>> batch.position.shape, bool(batch.stopped.all())
    ((2, 1001), True)
    """
    if models is not None:
        given = [n for n, v in (("coulomb", coulomb), ("stiffness", stiffness),
                                ("breakaway", breakaway), ("threshold", threshold),
                                ("viscous", viscous))
                 if v is not None]  # fmt: skip
        if given:
            raise TypeError(
                "`models` or parameter arrays (`coulomb`, `stiffness`, ...) must be given, not "
                f"both; got `models` and `{given[0]}`."
            )
        c1, sigma, k, r = _setup.stack_models(models)
        sizes = {"models": c1.shape[0]}
    else:
        params = _setup.stack_parameters(
            coulomb, stiffness, breakaway, threshold, 0.0 if viscous is None else viscous
        )
        sizes = dict(params[-1])
    t0 = as_real_scalar("t_start", t_start)
    forcing = as_forcing(applied_force, "zoh", t0)
    if not forcing.piecewise_constant:
        raise ValueError(
            "`applied_force` of a batch must be a constant or (time, value) samples; got a "
            "callable."
        )
    t_end, times = _run.time_grid(t0, t_end, t_eval)
    max_events = as_count("max_events", max_events, minimum=1)
    u0 = float(forcing(np.array([t0]))[0])
    arrays = {}
    for name, val in (("mass", mass), ("initial_velocity", initial_velocity),
                      ("initial_position", initial_position)):  # fmt: skip
        arrays[name] = _setup.as_batch_vector(name, val, positive=name == "mass")
        sizes[name] = arrays[name].shape[0]
    n_b = _setup.batch_size(sizes)
    if models is not None:
        c1, sigma, k, r = (
            np.array(np.broadcast_to(a, (n_b, *a.shape[1:]))) for a in (c1, sigma, k, r)
        )
    else:
        c1, sigma, k, r = _setup.broadcast_parameters(*params[:5], n_b)
    m, v0, y0 = (np.array(np.broadcast_to(arrays[n], (n_b,))) for n in
                 ("mass", "initial_velocity", "initial_position"))  # fmt: skip
    with np.errstate(over="ignore"):
        energy = 0.5 * m * v0 * v0
    check_finite_derived("kinetic energy ½·m·v0²", energy, ("mass", "initial_velocity"))
    f0, last_dir = _setup.batch_deformation(initial_state, r, v0, u0)
    u_t, u_val = forcing.event_pieces(t0, t_end)
    return _setup.run_batch(m, c1, sigma, k, r, f0, y0, v0, last_dir, u_t, u_val, times, t_end,
                          max_events)  # fmt: skip


def free_response(
    mass: float,
    coulomb: float,
    stiffness: ArrayLike,
    threshold: ArrayLike,
    initial_velocity: float,
    time_step: float,
    n_samples: int,
    *,
    initial_position: float = 0.0,
    initial_state: str = "saturated",
    applied_force: float = 0.0,
    viscous: float = 0.0,
    max_events: int = 10_000_000,
) -> FreeResponse:
    """Exact position and velocity at t = i·time_step, i < n_samples (compiled, fast).

    The parameter-vector form of `simulate` for least-squares losses: eq. 17
    with finite elements (eq. 8), an optional viscous term σ·ẏ and a constant
    applied force (default 0: free motion), solved by the exact event method.

    Parameters
    ----------
    mass : float
        m > 0 [kg].
    coulomb : float
        c1 >= 0 [N], the Coulomb element.
    stiffness : array_like, shape (N,)
        k_j > 0 [N/m] (eq. 6); may be empty when c1 > 0 (pure Coulomb friction).
    threshold : array_like, shape (N,)
        r_j > 0 [m]; the breakaway forces c_j = k_j·r_j must come out finite and
        positive (as in `PIFriction`).
    initial_velocity : float
        ẏ(0) [m/s].
    time_step : float
        Sample spacing [s] (> 0).
    n_samples : int
        Number of samples (>= 1), at t = 0, time_step, ...
    initial_position : float, keyword only
        y(0) [m].
    initial_state : "saturated" or "relaxed", keyword only
        "saturated" starts with every element at its threshold in the direction
        of the initial velocity (or of the applied force at rest): steady sliding
        before t = 0, as in the paper's experiments; "relaxed" with none deformed.
    applied_force : float, keyword only
        Constant u [N].
    viscous : float, keyword only
        σ >= 0 [N·s/m], the viscous term σ·ẏ (default 0).
    max_events : int, keyword only
        Event limit; when it is reached the result has status "event_limit" and
        holds only the samples computed before it.

    Returns
    -------
    FreeResponse
        ``time``, ``position``, ``velocity`` (n_samples,), ``stop_time``,
        ``n_reversals`` (sign changes of the velocity, as in `simulate`),
        ``status``, ``message`` and ``success``; check
        ``success`` (or ``status``) before using the samples.

    Examples
    --------
    >>> import presliding as ps
    >>> res = ps.free_response(1.0, 1.0, [100.0], [0.02], 1.0, 1e-3, 2000)
    >>> res.success, round(res.stop_time, 12), res.n_reversals
    (True, 0.647492598692, 1)
    """
    m = as_positive_scalar("mass", mass)
    c1, k, r = _setup.single_bank(coulomb, stiffness, threshold)
    v0 = as_real_scalar("initial_velocity", initial_velocity)
    y0 = as_real_scalar("initial_position", initial_position)
    dt = as_positive_scalar("time_step", time_step)
    n_t = as_count("n_samples", n_samples, minimum=1)
    check_time_span("time_step", dt, dt * (n_t - 1))
    # position, velocity, sample times and the kernel's six scratch rows
    check_size("n_samples", n_samples, n_t, what="samples", item_bytes=9 * 8)
    u = as_real_scalar("applied_force", applied_force)
    sigma = as_nonnegative_scalar("viscous", viscous)
    with np.errstate(over="ignore"):  # the damped pieces' rates (σ/2m)² and Σk/m
        rates = (np.float64(0.5 * sigma / m) ** 2, np.sum(k) / m, 0.5 * m * np.float64(v0) ** 2)
    check_finite_derived("damping rate (σ/2m)²", rates[0], ("viscous", "mass"))
    check_finite_derived("frequency² Σk/m", rates[1], ("stiffness", "mass"))
    check_finite_derived("kinetic energy ½·m·v0²", rates[2], ("mass", "initial_velocity"))
    limit = as_count("max_events", max_events, minimum=1)
    f0, last_dir = _setup.batch_deformation(initial_state, r[None, :], np.array([v0]), u)
    k, r, f0 = (_event.kernel_array(a) for a in (k, r, f0[0]))  # one compiled type
    y, v, status, stop, n_rev, n, t_last = _batch.free_kernel(
        m, c1, sigma, k, r, f0, y0, v0, float(last_dir[0]), u, dt, n_t, limit,
        _event.damped_flag(sigma),
    )  # fmt: skip
    if status == 0:
        message = "the motion was solved exactly"
    else:
        message = (
            f"the event limit max_events = {limit} was reached at t = {t_last:.6g} s; "
            f"{n} of {n_t} samples computed"
        )
    return FreeResponse(
        time=np.arange(n) * dt,
        position=y[:n],
        velocity=v[:n],
        stop_time=None if np.isnan(stop) or status != 0 else float(stop),
        n_reversals=int(n_rev),
        status=motion_status(int(status)),
        message=message,
    )
