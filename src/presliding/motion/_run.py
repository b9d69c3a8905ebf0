"""Set-up and runners behind `presliding.motion.simulation` (validation, grids, kernel calls)."""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from presliding._validation import (
    as_positive_scalar,
    as_real_scalar,
    as_signal,
    check_increasing,
    check_time_span,
    fmt,
)
from presliding.friction import _sides
from presliding.friction._parts import elements
from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis.operators import PIState
from presliding.motion import _event
from presliding.motion import _implicit_loop as _loop
from presliding.motion._forcing import Forcing
from presliding.motion.results import STATUS_ACCURACY_NOT_MET

FloatArray = NDArray[np.float64]
REVERSAL_CAPACITY = 1024
DEFAULT_STEPS = 10_000  # implicit steps over the span when `step` is not given
MAX_STEPS = 10**10  # implicit steps of one call (minutes of computing)


def check_model(model: Any, *, density_ok: bool = False, asymmetric_ok: bool = False) -> None:
    """A PIFriction; with finite elements unless `density_ok` (the implicit method), symmetric
    unless `asymmetric_ok` (`simulate`)."""
    if not isinstance(model, PIFriction):
        raise TypeError(f"`model` must be a PIFriction; got {type(model).__name__}.")
    if not asymmetric_ok:
        _sides.require_symmetric(model, "simulate_batch, free_response and simulate_loop")
    if not density_ok and not model.is_discrete:
        raise TypeError(
            "`model` has a continuous density; batches use the exact event method, which needs "
            "finite elements: simulate it with `simulate` (implicit method) or use a "
            "finite-element model (stiffness, breakaway), e.g. a fine discretisation of the "
            "density."
        )


def time_grid(t0: float, t_end: Any, t_eval: Any) -> tuple[float, FloatArray]:
    """Validated end time and sample times (default 1001 uniform samples)."""
    if t_end is None and t_eval is None:
        raise TypeError(
            "`t_end` or `t_eval` must be given (the end of the simulation); got neither."
        )
    times = None
    if t_eval is not None:
        times = as_signal("t_eval", t_eval)
        check_increasing("t_eval", times)
    if t_end is None:
        assert times is not None  # one of the two is given (checked above)
        t_end = float(times[-1])
    t_end = as_real_scalar("t_end", t_end)
    if not t_end > t0:
        raise ValueError(f"`t_end` must be greater than `t_start` = {fmt(t0)}; got {fmt(t_end)}.")
    check_time_span("t_end", t_end, t_end - t0)
    if times is None:
        return t_end, np.linspace(t0, t_end, 1001)
    if times[0] < t0 or times[-1] > t_end:
        bad = times[0] if times[0] < t0 else times[-1]
        raise ValueError(
            f"`t_eval` must lie in [t_start, t_end] = [{fmt(t0)}, {fmt(t_end)}]; got {fmt(bad)}."
        )
    return t_end, times


class Continuation(NamedTuple):
    """What an event run's final state remembers so that a continuation from it
    reproduces the whole run bit for bit: the exact deformations (y − play
    rounds), the trajectory's last direction, the rest start, and the start of
    the closed-form piece in progress (None at rest)."""

    t_end: float
    y: float
    v: float
    f: FloatArray
    direction: float
    rest_start: float
    piece: FloatArray | None
    key: tuple


def model_key(model: PIFriction, m: float) -> tuple:
    k, r, _ = elements(model)
    key = (m, float(model.coulomb), float(model.viscous), k.tobytes(), r.tobytes())
    if model.is_symmetric:
        return key
    sd = _sides.sides_of(model)
    return (*key, sd.coulomb[1], sd.viscous[1], sd.threshold[1].tobytes())


def continuation_of(state: Any, model: PIFriction, m: float, y0: float, v0: float, t0: float):
    """The `Continuation` an initial state carries, if it continues this very motion."""
    c = getattr(state, "_continuation", None)
    if not isinstance(c, Continuation):
        return None
    if (c.t_end, c.y, c.v, c.key) != (t0, y0, v0, model_key(model, m)):
        return None
    return c


def initial_deformation(
    model: PIFriction, initial_state: Any, y0: float, v0: float, u0: float
) -> tuple[FloatArray, float]:
    """Element deformations f_j = y − x_j at the start, and the direction of the last
    motion (of the velocity, else the memory's): the memory's direction at the end
    when the mass never moves.

    Nothing is snapped to the thresholds: a memory within rounding of
    saturation stays as given (the kernels treat |f_j| >= r_j as saturated), so a
    mass that never moves keeps its memory bit for bit.
    """
    r = np.asarray(model.threshold, dtype=np.float64)
    vdir = float(np.sign(v0))
    if isinstance(initial_state, str):
        if initial_state == "relaxed":
            return np.zeros(r.shape[0]), vdir
        if initial_state == "saturated":
            s = saturation_direction(vdir, u0)
            if s < 0 and model.threshold_negative is not None:
                return np.ascontiguousarray(-model.threshold_negative), s
            return np.ascontiguousarray(s * r), s
        raise ValueError(
            "`initial_state` must be 'relaxed', 'saturated' or a PIState; got "
            f"{fmt(initial_state)}."
        )
    if not isinstance(initial_state, PIState):
        raise TypeError(
            "`initial_state` must be 'relaxed', 'saturated' or a PIState (a MemoryState for a "
            f"density model); got {type(initial_state).__name__}."
        )
    if model.is_symmetric:
        initial_state.check_against(r, "initial_state")
    elif initial_state.play.shape != r.shape:
        initial_state.check_against(r, "initial_state")  # the count's error
    else:
        _sides.check_band(model, initial_state.last_input, initial_state.play, "initial_state")
    if initial_state.last_input != y0:
        raise ValueError(
            "`initial_state.last_input` must equal `initial_position`; got "
            f"{fmt(initial_state.last_input)} and {fmt(y0)}."
        )
    f = np.ascontiguousarray(initial_state.last_input - initial_state.play)
    return f, vdir if vdir != 0 else initial_state.direction


def final_state(y: float, f: FloatArray, direction: float, initial_state: Any, y0: float,
                f0: FloatArray) -> PIState:  # fmt: skip
    """The memory at the end: the initial PIState itself where nothing moved."""
    if y == y0 and np.array_equal(f, f0) and isinstance(initial_state, PIState):
        return PIState(initial_state.last_input, initial_state.play.copy(), direction)
    return PIState(y, y - f, direction)


def saturation_direction(vdir: Any, u0: float) -> Any:
    """Direction of a "saturated" start: of the velocity, or of u(t_start) at rest."""
    s = np.where(vdir != 0, vdir, np.sign(u0))
    if np.any(s == 0):
        raise ValueError(
            "`initial_velocity` or the applied force at `t_start` must be nonzero for "
            "`initial_state` 'saturated' (it takes their direction); got 0.0 and 0.0."
        )
    return float(s) if np.ndim(s) == 0 else s


def initial_acceleration(
    m: float, c1: float, fel: float, v0: float, u0: float, sigma: float = 0.0
) -> float:
    """ÿ at the start from eq. 17 (with σ·ẏ) and the set-valued sign."""
    if v0 != 0.0:
        return (u0 - c1 * np.sign(v0) - sigma * v0 - fel) / m
    g = u0 - fel
    return 0.0 if abs(g) <= c1 else (g - c1 * np.sign(g)) / m


def step_count(t0: float, t_end: float, step: Any) -> int:
    """Number of equal implicit steps of at most `step` over [t0, t_end], within limits."""
    span = t_end - t0  # finite (`time_grid`)
    if step is None:
        return DEFAULT_STEPS
    h = as_positive_scalar("step", step)
    n = np.ceil(span / h * (1.0 - 1e-9))  # a relative 1e-9 forgives the rounding of span / h
    if not n <= MAX_STEPS:
        raise ValueError(
            f"`step` must give at most {MAX_STEPS:.0e} implicit steps over [t_start, t_end] = "
            f"[{fmt(t0)}, {fmt(t_end)}]; got {fmt(h)}, which asks for {n:.3g} steps (use a "
            "larger `step` or a shorter span)."
        )
    return max(int(n), 1)


def accuracy_target(rtol: Any, atol: Any) -> tuple[float, float] | None:
    """(rtol, atol) of an accuracy target of the implicit method, or None without one."""
    from presliding._validation import as_nonnegative_scalar

    a = as_nonnegative_scalar("atol", atol)
    if rtol is None and a == 0.0:
        return None
    r = 0.0 if rtol is None else as_nonnegative_scalar("rtol", rtol)
    if r == 0.0 and a == 0.0:
        raise ValueError("`rtol` or `atol` must be positive for an accuracy target; got 0.0.")
    return r, a


def refine(run: Any, t0: float, t_end: float, n_steps: int, rtol: float, atol: float,
           max_steps: int = MAX_STEPS) -> Any:  # fmt: skip
    """Halve the implicit step until the step-doubling error estimate meets the target.

    ``run(h)`` simulates with the step h (at most `max_steps` steps). The error of the finer
    of two runs is about their difference (first order); the finer run is returned, with
    the estimate (positions at the samples) and how the step was chosen.
    """
    from dataclasses import replace

    coarse, err = run((t_end - t0) / n_steps), np.inf  # no estimate before the first doubling
    while True:
        if 2 * n_steps > max_steps:
            fine, met = coarse, False
            break
        n_steps *= 2
        fine = run((t_end - t0) / n_steps)
        err = float(np.max(np.abs(fine.position - coarse.position), initial=0.0))
        err = max(err, abs(fine.final_state.last_input - coarse.final_state.last_input))
        scale = float(np.max(np.abs(fine.position - fine.position[0]), initial=0.0))
        goal = atol + rtol * scale
        met = err <= goal
        if met:
            break
        coarse = fine
    h = (t_end - t0) / n_steps
    if met:
        message = (f"{n_steps} implicit steps of {h:.3g}, chosen by step doubling for an "
                   f"estimated position error {err:.3g} <= {goal:.3g}")  # fmt: skip
        return replace(fine, message=message, error_estimate=err)
    message = (f"the accuracy target was not met within {max_steps:.0e} steps: {n_steps} "
               f"steps of {h:.3g}")  # fmt: skip
    return replace(fine, status=STATUS_ACCURACY_NOT_MET, message=message,
                   error_estimate=err if np.isfinite(err) else None)  # fmt: skip


def check_energy(m: float, v0: float, e0: float) -> None:
    """The initial energy is finite (½·m·v0² and the elastic energy)."""
    if not np.isfinite(0.5 * m * v0 * v0):
        raise ValueError(
            "`initial_velocity` must give a finite kinetic energy ½·m·v0² with `mass` = "
            f"{fmt(m)}; got {fmt(v0)} (beyond the floating-point range)."
        )
    if not np.isfinite(e0):  # pragma: no cover - states are checked against the thresholds
        raise ValueError(f"`initial_state` must store a finite elastic energy; got {fmt(e0)}.")


def motion_overflow(t_end: float) -> None:
    """Raise: the motion left the floating-point range; name the arguments that set it."""
    raise ValueError(
        f"`t_end` must keep the motion in the floating-point range; got {fmt(t_end)}: the "
        "position, velocity or energy overflows before it (a shorter "
        "`t_end`, a smaller `applied_force` or `initial_velocity`, or units that keep the "
        "values moderate)."
    )


def _buffers(n: int, count: int) -> list[FloatArray]:
    return [np.empty(n) for _ in range(count)]


def run_event(
    m, c1, k, r, f0, y0, v0, last_dir, forcing: Forcing, times, t0, t_end, max_events, sigma=0.0,
    resume: Continuation | None = None, sides: _sides.Sides | None = None,
):  # fmt: skip
    """Run the exact event kernel; returns a dict of outputs.

    With `resume` (a continuation of the same motion) the kernel restarts the
    closed-form piece in progress at its own start, so that the motion is the
    whole run's bit for bit; dissipation, viscous loss and work are then
    counted from t0 as usual. `sides` (asymmetric friction) gives the negative
    Coulomb element, thresholds and viscous coefficient; None: equal sides.
    """
    c1n, rn, sigman = (c1, r, sigma) if sides is None else (
        sides.coulomb[1], sides.threshold[1], sides.viscous[1])  # fmt: skip
    u_t, u_val = forcing.event_pieces(t0, t_end)
    t_eval = times
    y_start, v_start, f_start = y0, v0, f0
    piece = resume.piece if resume is not None else None
    if piece is not None and piece[4] == u_val[0]:
        u_t = u_t.copy()
        u_t[0] = piece[0]
        y_start, v_start, last_dir = float(piece[1]), float(piece[2]), float(piece[3])
        f_start = np.ascontiguousarray(piece[5:])
        if times[0] != t0:
            t_eval = np.concatenate(([t0], times))
    else:
        piece = None
    n_out = t_eval.shape[0]
    k, r, u_t, u_val, t_eval = (_event.kernel_array(a) for a in (k, r, u_t, u_val, t_eval))
    rn = r if sides is None else _event.kernel_array(rn)
    # room for a reversal per piece of u (pages are touched only when written); more
    # reversals than that run the kernel again with room for all of them (rare)
    cap = max(REVERSAL_CAPACITY, 2 * u_t.shape[0])
    while True:
        f = f_start.copy()
        o = _buffers(n_out, 9)
        rev = _buffers(cap, 2)
        p_out = np.empty(5 + k.shape[0])
        tail = [*o[:7], o[8], *rev, sigma, sigman, o[7], p_out, _event.damped_flag(sigma, sigman)]
        res = _event.run_events_sided(m, c1, c1n, k, r, rn, f, y_start, v_start, last_dir,
                                      u_t, u_val, t_eval, t_end, max_events, *tail)  # fmt: skip
        status, n, n_rev, stop, y, v, d, n_ev, _, _, t_last, _ = res
        if n_rev <= cap:
            break
        cap = n_rev
    y_o, v_o, a_o, fel_o, u_o, eel_o, dis_o, vis_o, work_o = (b[:n] for b in o)
    if piece is not None and n:  # energies from t0, the extra first sample dropped
        for arr in (dis_o, vis_o, work_o):
            arr -= arr[0]
        if t_eval is not times:
            y_o, v_o, a_o, fel_o, u_o, eel_o, dis_o, vis_o, work_o = (
                b[1:] for b in (y_o, v_o, a_o, fel_o, u_o, eel_o, dis_o, vis_o, work_o)
            )
            n -= 1
    message = (
        "the motion was solved exactly"
        if status == 0
        else f"the event limit max_events = {max_events} was reached at t = {t_last:.6g} s"
    )
    return {
        "n": n, "time": times[:n], "position": y_o, "velocity": v_o, "acceleration": a_o,
        "elastic": fel_o,
        "applied": u_o, "friction": u_o - m * a_o, "e_el": eel_o, "dissipated": dis_o,
        "viscous": vis_o, "work": work_o, "rev_t": rev[0][:n_rev], "rev_y": rev[1][:n_rev],
        "stop": stop, "y": y, "v": v, "dir": d, "f": f, "count": n_ev, "status": status,
        "message": message, "piece": p_out if v != 0.0 else None, "t_end": t_end,
    }  # fmt: skip


def implicit_grid(t0: float, t_end: float, times: FloatArray, h: float):
    """Step grid through every sample time (equal substeps <= h); sample grid indices.

    The grid form of `presliding.motion._implicit.run_implicit`; `simulate` uses
    the uniform steps of `presliding.motion._implicit_loop` instead.
    """
    b = np.unique(np.concatenate(([t0], times, [t_end])))
    gaps = np.diff(b)
    n_sub = np.maximum(np.ceil(gaps / h * (1.0 - 1e-9)), 1.0).astype(np.int64)
    start = np.concatenate(([0], np.cumsum(n_sub)))
    which = np.repeat(np.arange(gaps.shape[0]), n_sub)
    within = np.arange(start[-1]) - start[which]
    grid = np.empty(start[-1] + 1)
    grid[:-1] = b[which] + gaps[which] * (within / n_sub[which])
    grid[-1] = b[-1]
    out_idx = start[np.searchsorted(b, times)]
    return grid, np.ascontiguousarray(out_idx)


def run_implicit(
    m, c1, k, r, f0, y0, v0, last_dir, forcing: Forcing, times, t0, t_end, n_steps, sigma=0.0,
    sides: _sides.Sides | None = None,
):  # fmt: skip
    """Run the implicit stepper: n_steps equal steps, samples read off the steps.

    `sides` (asymmetric friction) gives the negative Coulomb element, thresholds
    and viscous coefficient; None: equal sides."""
    c1n, rn, sigman = (c1, r, sigma) if sides is None else (
        sides.coulomb[1], _event.kernel_array(sides.threshold[1]), sides.viscous[1])  # fmt: skip
    u_kind, u_t, u_val, u_mid = forcing.loop_form(t0, t_end, n_steps)
    cap = REVERSAL_CAPACITY
    while True:
        f = f0.copy()
        o = _buffers(times.shape[0], 9)
        rev = _buffers(cap, 2)
        n_rev, stop, y, v, d, _, _, _ = _loop.run_uniform_sided(
            m, c1, c1n, sigma, sigman, k, r, rn, f, y0, v0, last_dir, t0, t_end, n_steps, u_kind,
            u_t, u_val, u_mid, times, *o, *rev,
        )  # fmt: skip
        if n_rev <= cap:
            break
        cap = n_rev
    y_o, v_o, a_o, fric_o, fel_o, eel_o, dis_o, vis_o, work_o = o
    applied = applied_force_at(forcing, u_kind, u_t, u_val, times)
    start_implicit_samples(times, t0, a_o, fric_o, applied, m, c1, float(np.dot(k, f0)), v0,
                           sigma, sides)  # fmt: skip
    h = (t_end - t0) / n_steps
    return {
        "n": times.shape[0], "time": times, "position": y_o, "velocity": v_o, "acceleration": a_o,
        "elastic": fel_o, "applied": applied,
        "friction": fric_o, "e_el": eel_o, "dissipated": dis_o, "viscous": vis_o,
        "work": work_o,
        "rev_t": rev[0][:n_rev], "rev_y": rev[1][:n_rev], "stop": stop, "y": y, "v": v,
        "dir": d, "f": f, "count": n_steps, "status": 0, "t_end": t_end,
        "message": f"{n_steps} implicit steps of {h:.3g}",
    }  # fmt: skip


def applied_force_at(forcing: Forcing, u_kind: int, u_t, u_val, times: FloatArray) -> FloatArray:
    """u at the sample times: compiled for a constant or sampled u, the callable otherwise."""
    if u_kind == _loop.U_ARRAY:
        return forcing(times)
    out = np.empty(times.shape[0])
    _loop.applied_at_times(u_kind, u_t, u_val, times, out)
    return out


def start_implicit_samples(times, t0, a_o, fric_o, applied, m, c1, fel0, v0, sigma,
                           sides: _sides.Sides | None = None) -> None:  # fmt: skip
    """Acceleration and friction force of the samples at t0 (from eq. 17 at the start)."""
    n0 = int(np.searchsorted(times, t0, side="right"))
    if n0:
        u0 = applied[0]
        if sides is not None and (v0 < 0 or (v0 == 0 and u0 - fel0 < 0)):
            c1, sigma = sides.coulomb[1], sides.viscous[1]  # the negative side acts
        a_o[:n0] = initial_acceleration(m, c1, fel0, v0, u0, sigma)
        fric_o[:n0] = u0 - m * a_o[:n0]
