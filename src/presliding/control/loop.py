"""`simulate_loop`: an exact, compiled sampled-data position loop with PI friction.

    m·ÿ + c1·Sign(ẏ) + F_el(y) ∋ u(t),    u(t) = u_k on [t_k, t_k + dt)     (eq. 17)

with u_k from a discrete controller (`PID` or `DiscreteController`) that reads
the position y_k = y(t_k) and the reference r_k at t_k = t_start + k·dt. The
force is constant between samples, so each period is the exact event-driven
solution of eq. 17 (closed-form pieces, exact stiction; `presliding.motion._event`),
and the whole loop runs in one compiled call (`presliding.control._loop`). A
python-control loop of `to_iosys` blocks computes the same samples
(`tests/control/test_loop.py` holds them to 1e-12).

`simulate_loop_batch` runs many gain sets of one PID in parallel (tuning maps).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_choice,
    as_count,
    as_positive_scalar,
    as_real_array,
    as_real_scalar,
    as_real_vector,
    as_si,
    as_signal,
    check_finite_derived,
    check_size,
    check_time_span,
    fmt,
)
from presliding.control import _loop
from presliding.control.controllers import PID, DiscreteController
from presliding.control.results import LoopBatch, LoopResult
from presliding.friction._sides import require_symmetric, sides_of
from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis.operators import PIState
from presliding.motion import _run
from presliding.motion.results import MotionEnergy, member_statuses, motion_status

__all__ = ["simulate_loop", "simulate_loop_batch"]

FloatArray = NDArray[np.float64]
#: Largest number of samples a batch keeps in memory (B × (K + 1) × 2 floats).
MAX_BATCH_SAMPLES = 100_000_000


def as_controller(controller: Any) -> PID | DiscreteController:
    """A PID or DiscreteController; a discrete python-control LTI is converted."""
    if isinstance(controller, (PID, DiscreteController)):
        return controller
    mod = type(controller).__module__ or ""
    if mod.startswith("control"):
        return DiscreteController.from_lti(controller)
    raise TypeError(
        "`controller` must be a PID, a DiscreteController or a discrete python-control LTI "
        f"system; got {type(controller).__name__}."
    )


def _signal(
    name: str, value: Any, times: NDArray[np.floating[Any]] | None, n: int | None
) -> FloatArray:
    """A signal at the sample instants: a constant, samples, or a function of time."""
    if callable(value):
        if times is None:
            raise TypeError(
                f"`t_end` must be given when `{name}` is a function (it sets the number of "
                "samples); got None."
            )
        out = as_real_array(name, value(times))  # a function returning text is refused
        if out.ndim == 0:
            return np.full(times.shape, float(out))
        if out.size != times.shape[0] or out.squeeze().ndim > 1:
            # checked here, before any compiled code reads it: a longer array would be
            # read past the end of the instants, a shorter one past its own end
            raise ValueError(
                f"`{name}` must return one value per instant t_k when called with the "
                f"{times.shape[0]} instants (an array of shape ({times.shape[0]},)) or a "
                f"scalar; got shape {out.shape}."
            )
        return as_signal(name, out.reshape(-1))
    if np.ndim(value) == 0:
        x = as_real_scalar(name, value)
        return np.full(n if n is not None else 1, x)
    arr = as_signal(name, value)
    if n is not None and arr.shape[0] != n:
        raise ValueError(
            f"`{name}` must hold one sample per instant t_k (K + 1 = {n}); got {arr.shape[0]}."
        )
    return arr


def _instants(t0: float, dt: float, t_end: Any, reference: Any, feedforward: Any) -> int:
    """The number of instants K + 1, from `t_end` or the length of a sampled signal."""
    if t_end is not None:
        t_end = as_real_scalar("t_end", t_end)
        check_time_span("t_end", t_end, t_end - t0)
        periods = (t_end - t0) / dt
        if not np.isfinite(periods):
            raise ValueError(
                f"`t_end` − `t_start` must be a finite number of sample periods dt = {fmt(dt)}; "
                f"got {fmt(t_end - t0)}."
            )
        k = round(periods)
        if k < 1 or abs(periods - k) > 1e-9 * max(periods, 1.0):
            raise ValueError(
                "`t_end` − `t_start` must be a positive whole number of sample periods dt = "
                f"{fmt(dt)}; got {fmt(t_end - t0)} ({periods:.6g} periods)."
            )
        return int(k) + 1
    for value in (reference, feedforward):
        if value is not None and not callable(value) and np.ndim(value) == 1:
            n = np.shape(value)[0]
            if n < 2:
                raise ValueError(f"a sampled signal must have at least 2 samples; got {n}.")
            return int(n)
    raise TypeError(
        "`t_end` must be given unless `reference` or `feedforward` is sampled (its length sets "
        "the number of instants); got neither."
    )


def _setup(model, mass, controller, reference, feedforward, t_end, t_start, y0, v0, state,
           asymmetric_ok=False):  # fmt: skip
    if not asymmetric_ok:
        require_symmetric(model, "simulate_loop_batch")
    _run.check_model(model, asymmetric_ok=True)
    m = as_positive_scalar("mass", mass, kind="mass")
    ctrl = as_controller(controller)
    t0 = as_real_scalar("t_start", t_start, kind="time")
    y0 = as_real_scalar("initial_position", y0, kind="position")
    v0 = as_real_scalar("initial_velocity", v0, kind="velocity")
    t_end = None if t_end is None else as_si("t_end", t_end, "time")
    reference = as_si("reference", reference, "position")  # pint Quantities in SI
    feedforward = None if feedforward is None else as_si("feedforward", feedforward, "force")
    n = _instants(t0, ctrl.dt, t_end, reference, feedforward)
    # a run keeps about 13 arrays of one value per instant (instants, reference,
    # feedforward, controller samples, the motion's outputs): checked before any is made
    check_size("t_end", t_end, 13.0 * n, what="values (13 per instant t_k)")
    times = t0 + np.arange(n) * ctrl.dt
    ref = _signal("reference", reference, times, n)
    ff = np.zeros(n) if feedforward is None else _signal("feedforward", feedforward, times, n)
    f, last_dir = _run.initial_deformation(model, state, y0, v0, float(ref[0] - y0))
    k = np.array(model.stiffness, dtype=np.float64)  # writable: one kernel type
    r = np.array(model.threshold, dtype=np.float64)
    with np.errstate(over="ignore"):  # the exact pieces' rates (σ/2m)², Σk/m and ½·m·v0²
        rates = (np.float64(0.5 * model.viscous / m) ** 2, np.sum(k) / m, 0.5 * m * v0 * v0)
    check_finite_derived("damping rate (σ/2m)²", rates[0], ("model", "mass"))
    check_finite_derived("frequency² Σk/m", rates[1], ("model", "mass"))
    check_finite_derived("kinetic energy ½·m·v0²", rates[2], ("mass", "initial_velocity"))
    return m, ctrl, t0, y0, v0, times, ref, ff, f, last_dir, k, r


def _controller_arrays(ctrl: PID | DiscreteController):
    if isinstance(ctrl, PID):
        z2 = np.zeros((0, 0))
        return 0, ctrl.parameters(), np.zeros(4), z2, z2, np.zeros((1, 0)), np.zeros((1, 1)), \
            np.zeros(0)  # fmt: skip
    low, high = ctrl.limits
    return (1, np.array([low, high]), np.zeros(4), np.ascontiguousarray(ctrl.A),
            np.ascontiguousarray(ctrl.B), np.ascontiguousarray(ctrl.C),
            np.ascontiguousarray(ctrl.D), np.zeros(ctrl.n_states))  # fmt: skip


def _check_range(t: FloatArray, arrays: tuple[FloatArray, ...], m: float) -> None:
    """Raise when the loop left the floating-point range (an unstable loop, or extreme
    values): name the arguments that set it and the time it happened."""
    bad = np.zeros(t.shape[0], dtype=bool)
    for arr in arrays:
        bad |= ~np.isfinite(arr)
    if bad.any():
        raise ValueError(
            f"`mass` and `controller` must keep the loop in the floating-point range; got mass "
            f"= {fmt(m)}: the motion overflows at t = {fmt(t[int(np.argmax(bad))])} s (an "
            "unstable loop: lower gains, a shorter `t_end`, or units that keep values moderate)."
        )


def simulate_loop(
    model: PIFriction,
    mass: float,
    controller: PID | DiscreteController | Any,
    reference: float | ArrayLike | Callable[[FloatArray], Any] = 0.0,
    *,
    t_end: float | None = None,
    feedforward: ArrayLike | Callable[[FloatArray], Any] | None = None,
    initial_position: float = 0.0,
    initial_velocity: float = 0.0,
    initial_state: str | PIState = "relaxed",
    substeps: int = 1,
    t_start: float = 0.0,
    max_events: int = 10_000_000,
) -> LoopResult:
    """Simulate a sampled-data position loop around a mass with PI friction, exactly.

    Parameters
    ----------
    model : PIFriction
        Finite elements (eq. 8).
    mass : float
        m > 0 [kg].
    controller : PID, DiscreteController or discrete python-control LTI
        Acts at t_k = t_start + k·dt (its ``dt``); the output is held (zero-order hold).
    reference : float, array_like or callable
        r_k [m]: a constant, K + 1 samples, or a function r(t) of the instants.
    t_end : float, keyword only
        End time; t_end − t_start must be a whole number K of periods. Default: from
        the length of a sampled `reference` or `feedforward`.
    feedforward : array_like or callable, keyword only
        u_ff,k [N] added to the controller's output before the saturation.
    initial_position, initial_velocity : float, keyword only
        y(t_start) [m], ẏ(t_start) [m/s].
    initial_state : "relaxed", "saturated" or PIState, keyword only
        As in `simulate`; "saturated" at rest takes the direction of r_0 − y_0.
    substeps : int, keyword only
        Output samples per period (>= 1): the exact motion between the instants too.
    t_start : float, keyword only
    max_events : int, keyword only
        Event limit of the whole run (status "event_limit" when reached).

    Returns
    -------
    LoopResult
        A `MotionResult` sampled at t_start + (k + j/substeps)·dt, with the
        controller's samples (``control_time``, ``control``, ``reference``, ``measured``).

    Examples
    --------
    >>> import presliding as ps
    >>> model = ps.PIFriction(coulomb=0.1, stiffness=[2e4, 5e3], breakaway=[0.2, 0.2])
    >>> pid = ps.PID(400.0, 2000.0, 20.0, dt=1e-3)
    >>> res = ps.simulate_loop(model, 1.0, pid, reference=1e-3, t_end=2.0)
    >>> res.success, abs(res.error[-1]) < 1e-5
    (True, True)
    """
    m, ctrl, t0, y0, v0, times, ref, ff, f, last_dir, k, r = _setup(
        model, mass, controller, reference, feedforward, t_end, t_start, initial_position,
        initial_velocity, initial_state, asymmetric_ok=True,
    )  # fmt: skip
    sides = sides_of(model)
    c1n, sigman = sides.coulomb[1], sides.viscous[1]
    rn = r if model.threshold_negative is None else np.array(sides.threshold[1], dtype=np.float64)
    sides_tail = (c1n, sigman, rn)  # the negative side (the positive one for symmetric friction)
    sub = as_count("substeps", substeps, minimum=1)
    max_events = as_count("max_events", max_events, minimum=1)
    n = times.shape[0]
    n_out = (n - 1) * sub + 1
    check_size("substeps", substeps, n_out, what="output samples", item_bytes=9 * 8)
    kind, p, s, a, b, c, d, x = _controller_arrays(ctrl)
    sigma = float(model.viscous)
    e0 = 0.5 * m * v0 * v0 + 0.5 * float(np.dot(k * f, f))
    cap = 1024
    while True:
        ff_ = f.copy()
        out = [np.full(n_out, np.nan) for _ in range(9)]
        ctl = np.full(n, np.nan)
        rev = [np.empty(cap), np.empty(cap)]
        buffers = [*out, ctl, *rev]
        res = _loop.run_loop(m, float(model.coulomb), sigma, k, r, ff_, y0, v0, last_dir, kind,
                             p, s.copy(), a, b, c, d, x.copy(), ref, ff, t0, ctrl.dt, sub,
                             max_events, *[*buffers, *sides_tail])  # fmt: skip
        status, n_rev, rest, y_end, v_end, d_end, n_ev, done = res
        if n_rev <= cap:
            break
        cap = n_rev
    n_keep = n_out if status == 0 else done * sub
    n_ctl = n if status == 0 else done
    y_o, v_o, a_o, fel_o, u_o, eel_o, dis_o, work_o, vis_o = (o[:n_keep] for o in out)
    with np.errstate(over="ignore", invalid="ignore"):
        kinetic = 0.5 * (m * v_o) * v_o  # m·v first: a light mass moving fast stays finite
        residual = kinetic + eel_o + dis_o + vis_o - work_o - e0
        friction = u_o - m * a_o
    _check_range(t0 + np.arange(n_keep) * (ctrl.dt / sub),
                 (y_o, v_o, a_o, u_o, friction, kinetic, residual), m)  # fmt: skip
    energy = MotionEnergy(kinetic, eel_o, dis_o, work_o, residual, e0, viscous=vis_o)
    stop = None if (status != 0 or math.isnan(rest)) else float(rest)
    t_out = t0 + np.arange(n_keep) * (ctrl.dt / sub)
    t_out[::sub] = times[: (n_keep + sub - 1) // sub]
    message = (
        f"the loop was solved exactly over {n - 1} periods"
        if status == 0
        else f"the event limit max_events = {max_events} was reached after {done} periods"
    )
    return LoopResult(
        time=t_out, position=y_o, velocity=v_o, acceleration=a_o,
        friction_force=friction, elastic_force=fel_o, applied_force=u_o,
        reversal_times=rev[0][:n_rev].copy(), reversal_positions=rev[1][:n_rev].copy(),
        stop_time=stop, rest_position=None if stop is None else float(y_end), energy=energy,
        final_state=PIState(float(y_end), float(y_end) - ff_, float(d_end)),
        final_velocity=float(v_end), status=motion_status(int(status)), message=message,
        method="event",
        n_events=int(n_ev), mass=m, model=model, control_time=times[:n_ctl],
        control=ctl[:n_ctl], reference=ref[:n_ctl], measured=y_o[::sub][:n_ctl],
        feedforward=ff[:n_ctl], controller=ctrl,
    )  # fmt: skip


def simulate_loop_batch(
    model: PIFriction,
    mass: float,
    controller: PID,
    reference: float | ArrayLike | Callable[[FloatArray], Any] = 0.0,
    *,
    kp: ArrayLike | None = None,
    ki: ArrayLike | None = None,
    kd: ArrayLike | None = None,
    t_end: float | None = None,
    feedforward: ArrayLike | Callable[[FloatArray], Any] | None = None,
    initial_position: float = 0.0,
    initial_velocity: float = 0.0,
    initial_state: str | PIState = "relaxed",
    settle_time: float | None = None,
    outputs: str = "full",
    t_start: float = 0.0,
    max_events: int = 10_000_000,
) -> LoopBatch:
    """The loop of `simulate_loop` for many gain sets of one PID, compiled and in parallel.

    Parameters
    ----------
    controller : PID
        Sample time, filter, saturation and anti-windup shared by all members; its
        gains are the default of `kp`, `ki`, `kd`.
    kp, ki, kd : float or array_like, shape (B,), keyword only
        Gains of the members; lengths 1 or one common B.
    settle_time : float, keyword only
        Summaries (rms and max error, half range of y) use the instants from it on;
        default half way.
    outputs : "full" or "summary", keyword only
        Keep y_k and u_k of every member (B × (K + 1) each), or the summaries only.

    Other parameters as in `simulate_loop`.

    Returns
    -------
    LoopBatch
    """
    if not isinstance(controller, PID):
        raise TypeError(f"`controller` must be a PID; got {type(controller).__name__}.")
    m, ctrl, t0, y0, v0, times, ref, ff, f, last_dir, k, r = _setup(
        model, mass, controller, reference, feedforward, t_end, t_start, initial_position,
        initial_velocity, initial_state,
    )  # fmt: skip
    outputs = as_choice("outputs", outputs, ("full", "summary"))
    max_events = as_count("max_events", max_events, minimum=1)
    gains = {}
    for name, value in (("kp", kp), ("ki", ki), ("kd", kd)):
        vec = as_real_vector(name, getattr(ctrl, name) if value is None else value)
        if np.any(vec < 0):
            i = int(np.argmax(vec < 0))
            raise ValueError(f"`{name}` must be nonnegative; got {fmt(vec[i])} at index {i}.")
        gains[name] = vec
    lengths = {n: v.shape[0] for n, v in gains.items() if v.shape[0] != 1}
    if len(set(lengths.values())) > 1:
        got = ", ".join(f"{n} {v}" for n, v in lengths.items())
        raise ValueError(f"`kp`, `ki` and `kd` must have length 1 or one common length B; got "
                         f"lengths {got}.")  # fmt: skip
    n_b = max(lengths.values(), default=1)
    g = {n: np.broadcast_to(v, (n_b,)).copy() for n, v in gains.items()}
    zero = (g["kp"] == 0) & (g["ki"] == 0) & (g["kd"] == 0)
    if zero.any():
        raise ValueError(f"`kp`, `ki` and `kd` must not all be zero; got zeros at index "
                         f"{int(np.argmax(zero))}.")  # fmt: skip
    n = times.shape[0]
    settle = 0.5 * (times[0] + times[-1]) if settle_time is None else as_real_scalar(
        "settle_time", settle_time)  # fmt: skip
    if not times[0] <= settle <= times[-1]:
        raise ValueError(f"`settle_time` must lie within the run [{fmt(times[0])}, "
                         f"{fmt(times[-1])}] s; got {fmt(settle)}.")  # fmt: skip
    i_from = int(np.searchsorted(times, settle, side="left"))
    if outputs == "full" and n_b * n > MAX_BATCH_SAMPLES:
        raise ValueError(
            f"`outputs` 'full' would keep {n_b} × {n} samples of y and u (more than "
            f"{MAX_BATCH_SAMPLES:,}); pass outputs='summary' or fewer gain sets."
        )
    base = ctrl.parameters()
    p_all = np.tile(base, (n_b, 1))
    p_all[:, 0], p_all[:, 1], p_all[:, 2] = g["kp"], g["ki"], g["kd"]
    if ctrl.tracking_time is None and ctrl.anti_windup == "back-calculation":
        ok = (g["kp"] > 0) & (g["ki"] > 0)
        p_all[:, 8] = np.where(ok, g["kp"] / np.where(ok, g["ki"], 1.0), ctrl.dt)
    rows = n_b if outputs == "full" else 0
    o_y = np.full((rows, n), np.nan)
    o_u = np.full((rows, n), np.nan)
    status = np.zeros(n_b, dtype=np.int64)
    n_rev = np.zeros(n_b, dtype=np.int64)
    e_rms, e_max, half, y_end, v_end = (np.empty(n_b) for _ in range(5))
    _loop.run_loop_batch(m, float(model.coulomb), float(model.viscous), k, r, f, y0, v0,
                         last_dir, p_all,
                         np.zeros(4), ref, ff, t0, ctrl.dt, max_events, i_from, o_y, o_u,
                         status, n_rev, e_rms, e_max, half, y_end, v_end,
                         _loop.damped_flag(float(model.viscous)))  # fmt: skip
    # a loop that left the floating-point range (unstable gains) is not an event-limit failure
    diverged = ~(np.isfinite(e_rms) & np.isfinite(e_max) & np.isfinite(y_end) & np.isfinite(v_end))
    status[diverged] = -3
    notes = []
    if np.any(status == -1):
        notes.append(f"{int(np.sum(status == -1))} of {n_b} loops reached the event limit "
                     f"max_events = {max_events}")  # fmt: skip
    if np.any(diverged):
        notes.append(f"{int(np.sum(diverged))} of {n_b} loops left the floating-point range "
                     "(unstable gains; their summaries are NaN)")  # fmt: skip
    message = "; ".join(notes) or "all loops solved exactly"
    return LoopBatch(
        kp=g["kp"], ki=g["ki"], kd=g["kd"], time=times,
        position=o_y if rows else None, control=o_u if rows else None, error_rms=e_rms,
        error_max=e_max, half_range=half, n_reversals=n_rev, final_position=y_end,
        final_velocity=v_end, member_status=member_statuses(status),
        settle_time=float(times[i_from]), message=message,
    )  # fmt: skip
