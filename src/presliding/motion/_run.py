"""Set-up and runners behind `presliding.motion.simulation` (validation, grids, kernel calls)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._validation import (
    as_nonnegative_scalar,
    as_parameter_matrix,
    as_parameter_vector,
    as_real_scalar,
    as_real_vector,
    as_signal,
    check_derived,
    check_has_friction,
    check_increasing,
    check_same_length,
    fmt,
)
from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis.operators import PIState
from presliding.motion import _event, _implicit
from presliding.motion._forcing import Forcing

FloatArray = NDArray[np.float64]
REVERSAL_CAPACITY = 1024
# Deformations within this relative distance of a threshold count as saturated
# (PIState.saturated stores play = y − r, whose difference y − play rounds).
_SNAP = 64 * np.finfo(np.float64).eps


def check_model(model: Any, *, density_ok: bool = False) -> None:
    """A PIFriction; with finite elements unless `density_ok` (the implicit method)."""
    if not isinstance(model, PIFriction):
        raise TypeError(f"`model` must be a PIFriction; got {type(model).__name__}.")
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
        t_end = float(times[-1])
    t_end = as_real_scalar("t_end", t_end)
    if not t_end > t0:
        raise ValueError(f"`t_end` must be greater than `t_start` = {fmt(t0)}; got {fmt(t_end)}.")
    if times is None:
        return t_end, np.linspace(t0, t_end, 1001)
    if times[0] < t0 or times[-1] > t_end:
        bad = times[0] if times[0] < t0 else times[-1]
        raise ValueError(
            f"`t_eval` must lie in [t_start, t_end] = [{fmt(t0)}, {fmt(t_end)}]; got {fmt(bad)}."
        )
    return t_end, times


def initial_deformation(
    model: PIFriction, initial_state: Any, y0: float, v0: float, u0: float
) -> tuple[FloatArray, float]:
    """Element deformations f_j = y − x_j at the start, and the last motion direction."""
    r = np.asarray(model.threshold, dtype=np.float64)
    vdir = float(np.sign(v0))
    if isinstance(initial_state, str):
        if initial_state == "relaxed":
            return np.zeros(r.shape[0]), vdir
        if initial_state == "saturated":
            s = saturation_direction(vdir, u0)
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
    initial_state.check_against(r, "initial_state")
    if initial_state.last_input != y0:
        raise ValueError(
            "`initial_state.last_input` must equal `initial_position`; got "
            f"{fmt(initial_state.last_input)} and {fmt(y0)}."
        )
    f = initial_state.last_input - initial_state.play
    near = np.abs(f) >= r * (1.0 - _SNAP)
    f = np.where(near, np.sign(f) * r, f)
    return np.ascontiguousarray(f), vdir if vdir != 0 else initial_state.direction


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


def _buffers(n: int, count: int) -> list[FloatArray]:
    return [np.zeros(n) for _ in range(count)]


def run_event(
    m, c1, k, r, f0, y0, v0, last_dir, forcing: Forcing, times, t0, t_end, max_events, sigma=0.0
):
    """Run the exact event kernel; returns a dict of outputs."""
    u_t, u_val = forcing.pieces(t0, t_end)
    cap = REVERSAL_CAPACITY
    while True:
        f = f0.copy()
        o = _buffers(times.shape[0], 9)
        rev = _buffers(cap, 2)
        res = _event.run_events(m, c1, k, r, f, y0, v0, last_dir, u_t, u_val, times, t_end,
                                max_events, *o[:7], o[8], *rev, sigma, o[7])  # fmt: skip
        status, n, n_rev, stop, y, v, d, n_ev, _, _, t_last, _ = res
        if n_rev <= cap:
            break
        cap = n_rev
    y_o, v_o, a_o, fel_o, u_o, eel_o, dis_o, vis_o, work_o = (b[:n] for b in o)
    message = (
        "the motion was solved exactly"
        if status == 0
        else f"the event limit max_events = {max_events} was reached at t = {t_last:.6g}"
    )
    return {
        "n": n, "position": y_o, "velocity": v_o, "acceleration": a_o, "elastic": fel_o,
        "applied": u_o, "friction": u_o - m * a_o, "e_el": eel_o, "dissipated": dis_o,
        "viscous": vis_o, "work": work_o, "rev_t": rev[0][:n_rev], "rev_y": rev[1][:n_rev],
        "stop": stop,
        "y": y, "v": v, "dir": d, "f": f, "count": n_ev, "status": status, "message": message,
    }  # fmt: skip


def implicit_grid(t0: float, t_end: float, times: FloatArray, h: float):
    """Step grid through every sample time (equal substeps <= h); sample grid indices."""
    b = np.unique(np.concatenate(([t0], times, [t_end])))
    gaps = np.diff(b)
    # substeps of at most h (a relative 1e-9 forgives the rounding of gaps / h)
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
    m, c1, k, r, f0, y0, v0, last_dir, forcing: Forcing, times, t0, t_end, h, sigma=0.0
):
    """Run the implicit stepper on a grid through the sample times; a dict of outputs."""
    grid, out_idx = implicit_grid(t0, t_end, times, h)
    u_mid = forcing(0.5 * (grid[1:] + grid[:-1]))
    cap = REVERSAL_CAPACITY
    while True:
        f = f0.copy()
        o = _buffers(times.shape[0], 9)
        rev = _buffers(cap, 2)
        n_rev, stop, y, v, d, _, _, _ = _implicit.run_implicit(
            m,
            c1,
            k,
            r,
            f,
            y0,
            v0,
            last_dir,
            grid,
            u_mid,
            out_idx,
            *o[:7],
            o[8],
            *rev,
            sigma,
            o[7],
        )
        if n_rev <= cap:
            break
        cap = n_rev
    y_o, v_o, a_o, fric_o, fel_o, eel_o, dis_o, vis_o, work_o = o
    applied = forcing(times)
    at_start = out_idx == 0
    if at_start.any():
        u0 = applied[0]
        a_o[at_start] = initial_acceleration(m, c1, float(np.dot(k, f0)), v0, u0, sigma)
        fric_o[at_start] = u0 - m * a_o[at_start]
    return {
        "n": times.shape[0], "position": y_o, "velocity": v_o, "acceleration": a_o,
        "elastic": fel_o, "applied": applied,
        "friction": fric_o, "e_el": eel_o, "dissipated": dis_o, "viscous": vis_o,
        "work": work_o,
        "rev_t": rev[0][:n_rev], "rev_y": rev[1][:n_rev], "stop": stop, "y": y, "v": v,
        "dir": d, "f": f, "count": grid.shape[0] - 1, "status": 0,
        "message": f"{grid.shape[0] - 1} implicit steps of at most {h:.3g}",
    }  # fmt: skip


# ---------------------------------------------------------------------- batches
def single_bank(
    coulomb: Any, stiffness: Any, threshold: Any
) -> tuple[float, FloatArray, FloatArray]:
    """c1, k (N,), r (N,) of one model given by its parameter vectors, validated as PIFriction."""
    c1 = as_nonnegative_scalar("coulomb", coulomb)
    k = as_parameter_vector("stiffness", stiffness, allow_empty=True)
    r = as_parameter_vector("threshold", threshold, allow_empty=True)
    check_same_length(stiffness=k, threshold=r)
    with np.errstate(over="ignore", under="ignore"):  # reported by check_derived
        c = k * r
    check_derived(k, c, r)
    check_has_friction(np.array([c1]), k.shape[0])
    return c1, np.array(k), np.array(r)


def stack_models(models: Any) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """c1 (B,), σ (B,), k (B, N), r (B, N) from PIFriction models; shorter banks padded inertly."""
    seq = [models] if isinstance(models, PIFriction) else list(models)
    if not seq:
        raise ValueError("`models` must not be empty; got 0 models.")
    for i, model in enumerate(seq):
        if not isinstance(model, PIFriction):
            raise TypeError(f"`models` must hold PIFriction models; got {type(model).__name__} "
                            f"at index {i}.")  # fmt: skip
        check_model(model)
    n = max(mod.n_elements for mod in seq)
    # an inert element: no stiffness, never reaches its threshold
    k = np.zeros((len(seq), n))
    r = np.full((len(seq), n), np.inf)
    for i, mod in enumerate(seq):
        k[i, : mod.n_elements] = mod.stiffness
        r[i, : mod.n_elements] = mod.threshold
    sigma = np.array([mod.viscous for mod in seq], dtype=np.float64)
    return np.array([mod.coulomb for mod in seq]), sigma, k, r


def stack_parameters(
    coulomb: Any, stiffness: Any, breakaway: Any, threshold: Any, viscous: Any = 0.0
):
    """Validated parameter arrays of a batch, before broadcasting to the batch size.

    Returns c1 (Bc,), σ (Bv,), k (Bk, N), the given `breakaway` or `threshold`
    (Bo, N), its name, and the lengths {name: B} for `batch_size`.
    """
    if coulomb is None or stiffness is None:
        missing = " and ".join(
            f"`{n}`" for n, v in (("coulomb", coulomb), ("stiffness", stiffness)) if v is None
        )
        raise TypeError(
            "`coulomb` and `stiffness` (with `breakaway` or `threshold`) must be given when "
            f"`models` is not; got no {missing}."
        )
    if (breakaway is None) == (threshold is None):
        raise TypeError(
            "`breakaway` or `threshold` must be given, not both; got "
            + ("both." if breakaway is not None else "neither.")
        )
    c1 = np.array(as_parameter_vector("coulomb", coulomb, positive=False))
    sigma = np.array(as_parameter_vector("viscous", viscous, positive=False))
    k = as_parameter_matrix("stiffness", stiffness)
    name = "breakaway" if threshold is None else "threshold"
    raw = breakaway if threshold is None else threshold
    other = as_parameter_matrix(name, raw)
    if np.ndim(raw) == 0:  # one value for every element
        other = np.full((1, k.shape[1]), other[0, 0])
    if other.shape[1] != k.shape[1]:
        raise ValueError(
            f"`{name}` must have as many elements (columns) as `stiffness`; got {other.shape[1]} "
            f"and {k.shape[1]}."
        )
    sizes = {"coulomb": c1.shape[0], "viscous": sigma.shape[0], "stiffness": k.shape[0],
             name: other.shape[0]}  # fmt: skip
    return c1, sigma, k, other, name, sizes


def broadcast_parameters(c1, sigma, k, other, name: str, n_b: int):
    """c1 (B,), σ (B,), k (B, N), r (B, N) of a batch of size `n_b`, checked as PIFriction."""
    c1 = np.array(np.broadcast_to(c1, (n_b,)))
    sigma = np.array(np.broadcast_to(sigma, (n_b,)))
    k = np.array(np.broadcast_to(k, (n_b, k.shape[1])))
    other = np.array(np.broadcast_to(other, k.shape))
    with np.errstate(over="ignore", under="ignore"):  # reported by check_derived
        c, r = (other, other / k) if name == "breakaway" else (k * other, other)
    check_derived(k, c, r)
    check_has_friction(c1, k.shape[1])
    return c1, sigma, k, np.ascontiguousarray(r)


def as_batch_vector(name: str, value: Any, positive: bool = False) -> FloatArray:
    """A finite scalar or 1-D array (positive if asked), as a 1-D array."""
    if positive:
        return as_parameter_vector(name, value)
    return as_real_vector(name, value)


def batch_size(sizes: dict[str, int]) -> int:
    """The common batch size: every length is 1 or the same B."""
    big = {n for n in sizes.values() if n != 1}
    if len(big) > 1:
        long = {k: v for k, v in sizes.items() if v != 1}
        names = ", ".join(f"`{k}`" for k in long)
        got = ", ".join(f"{k} {v}" for k, v in long.items())
        raise ValueError(
            f"{names} must have length 1 or one common length B (the batch size); got "
            f"lengths {got}."
        )
    return big.pop() if big else 1


def batch_deformation(initial_state: Any, r: FloatArray, v0: FloatArray, u0: float):
    """Deformations (B, N) and last directions (B,) for "relaxed" or "saturated" starts."""
    if not isinstance(initial_state, str):
        raise TypeError(
            f"`initial_state` must be 'relaxed' or 'saturated'; got {type(initial_state).__name__}."
        )
    vdir = np.sign(v0)
    if initial_state == "relaxed":
        f = np.zeros(r.shape)
    elif initial_state == "saturated":
        vdir = saturation_direction(vdir, u0)
        f = np.where(np.isfinite(r), vdir[:, None] * r, 0.0)
    else:
        raise ValueError(
            f"`initial_state` must be 'relaxed' or 'saturated'; got {fmt(initial_state)}."
        )
    return np.ascontiguousarray(f), np.ascontiguousarray(vdir, dtype=np.float64)


def run_batch(m, c1, sigma, k, r, f0, y0, v0, last_dir, u_t, u_val, times, t_end, max_events):
    """Run the parallel batch kernel and wrap the outputs."""
    from presliding.motion._batch_events import batch_events
    from presliding.motion.results import MotionBatch

    n_b, n_t = m.shape[0], times.shape[0]
    o_y = np.full((n_b, n_t), np.nan)
    o_v = np.full((n_b, n_t), np.nan)
    stop = np.empty(n_b)
    n_rev = np.empty(n_b, dtype=np.int64)
    status = np.empty(n_b, dtype=np.int64)
    y_end = np.empty(n_b)
    v_end = np.empty(n_b)
    batch_events(m, c1, sigma, k, r, f0, y0, v0, last_dir, u_t, u_val, times, t_end, max_events,
                 o_y, o_v, stop, n_rev, status, y_end, v_end)  # fmt: skip
    stop = np.where(np.isnan(stop), np.inf, stop)
    failed = int(np.sum(status != 0))
    message = (
        "all motions solved exactly"
        if not failed
        else (f"{failed} of {n_b} motions reached the event limit max_events = {max_events}")
    )
    return MotionBatch(times, o_y, o_v, stop, n_rev, y_end, v_end, status, message)
