"""Motion of a mass with PI friction and exact stiction (eqs. 12, 17).

    m·ÿ + c1·Sign(ẏ) + σ·ẏ + Σ_j k_j (y − x_j(y, r_j)) = u(t)       (eq. 17 with σ·ẏ)

with the set-valued sign Sign(0) = [−1, 1]: at zero velocity the Coulomb element
c1 carries any force up to c1, so the mass *sticks* iff |u − F_el| <= c1 (equality
sticks; the viscous force σ·0 vanishes) and stays exactly put, bit for bit, until
that fails. The viscous coefficient σ = ``model.viscous`` is 0 by default (the
paper's assumption (i)). Two methods:

``"event"``
    Exact for finite elements and a piecewise-constant u (a constant, or samples
    with ``hold="zoh"``): the motion is solved in closed form between events and
    the events (an element starting to slide, the velocity vanishing, a change of
    u) are located analytically or, with σ > 0, by a bracketed Newton iteration on
    the closed form (see `presliding.motion._event` and `presliding.motion._damped`).
    Results are exact to rounding at every time of `t_eval`.
``"implicit"``
    Any u(t) (callable, or samples with ``hold="linear"``): an implicit step that
    solves the inclusion exactly (see `presliding.motion._implicit`); first order in the
    step, stable for any step, no chatter and no creep at rest. A model with a
    continuous density (eq. 10) always uses it, with the exact general PI
    operator as the elastic force (see `presliding.motion._implicit_density`).

``"auto"`` picks "event" whenever it applies.

Reversals. A reversal is a change of sign of the trajectory's velocity: the
mass moved one way, and now moves the other way (through a stop or not). A
start from rest is never a reversal, whatever direction the friction memory
remembers; ``reversal_times`` are the turning points, as in
`presliding.analysis.turning_points`, `simulate_batch` and `free_response`.

Implicit steps. The step sequence depends only on t_start, t_end and `step`
(equal steps), never on `t_eval`: samples between two steps are read off the
step that contains them (see `presliding.motion._implicit_loop`).

Continuation. The `final_state` of an event run remembers (privately) the
exact deformations and the closed-form piece in progress: a run started from
it at ``t_start`` = the first run's ``t_end``, with ``initial_position`` =
``final_state.last_input``, ``initial_velocity`` = ``final_velocity`` and the
same model, mass and applied force, reproduces the whole run bit for bit.
A given memory is used as it is (nothing is snapped to the thresholds), so a
mass that never moves returns its initial memory unchanged.

Stop. The mass *stops* when its velocity vanishes while |u − F_el| <= c1. For
free motion (u constant) it then stays exactly at rest forever after:
nothing changes any more, so the simulation ends there and the remaining
samples repeat the rest state. ``stop_time`` is the start of the rest that lasts
until ``t_end`` (None if the mass moves at ``t_end``); with a varying u a later
change of u may set it in motion again. With σ > 0 an over-damped piece (σ² >=
4·m·K, K the stiffness of the sticking elements) that creeps towards the edge
of the stick band reaches it only as t → ∞: the mass then has no stop time,
its velocity decays exponentially.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_choice,
    as_count,
    as_positive_scalar,
    as_real_scalar,
    as_si,
    check_finite_derived,
)
from presliding.friction import _sides
from presliding.friction._model_checks import check_finite_stiffness
from presliding.friction.gms import GMSState
from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis.general_pi import MemoryState
from presliding.hysteresis.operators import PIState
from presliding.motion import _implicit_density as _density
from presliding.motion import _implicit_loop as _loop
from presliding.motion import _rate_run, _run
from presliding.motion._forcing import as_forcing
from presliding.motion.batch import free_response, simulate_batch
from presliding.motion.results import (
    FreeResponse,
    MotionBatch,
    MotionEnergy,
    MotionResult,
    motion_status,
)

__all__ = [
    "FreeResponse",
    "MotionBatch",
    "MotionEnergy",
    "MotionResult",
    "free_response",
    "simulate",
    "simulate_batch",
]

FloatArray = NDArray[np.float64]
METHODS = ("auto", "event", "implicit")


def simulate(
    model: PIFriction,
    mass: float,
    applied_force: float | ArrayLike | Any = 0.0,
    initial_position: float = 0.0,
    initial_velocity: float = 0.0,
    initial_state: str | PIState | MemoryState = "relaxed",
    t_end: float | None = None,
    t_eval: ArrayLike | None = None,
    method: str = "auto",
    hold: str = "zoh",
    step: float | None = None,
    *,
    t_start: float = 0.0,
    max_events: int = 10_000_000,
    rtol: float | None = None,
    atol: float = 0.0,
) -> MotionResult:
    """Simulate m·ÿ + c1·Sign(ẏ) + σ·ẏ + F_el(y) ∋ u(t) (eq. 17) with exact stiction.

    Parameters
    ----------
    model : PIFriction
        The friction model: finite elements (eq. 8) or a density (eq. 10; only
        the implicit method applies, with the exact continuous operator), with
        its viscous coefficient σ = ``model.viscous`` (0: the paper's eq. 17).
    mass : float
        m > 0 [kg].
    applied_force : float, callable or (time, value) pair
        u [N]: a constant; a function u(t) (called with an array of times; a
        scalar function is vectorised); or samples held as `hold` says.
    initial_position, initial_velocity : float
        y(t_start) [m], ẏ(t_start) [m/s].
    initial_state : "relaxed", "saturated", PIState or MemoryState
        Friction memory at the start. "relaxed": no elastic deformation.
        "saturated": every element at its threshold after sliding in the
        direction of the initial velocity, or of u(t_start) when the velocity is
        zero (steady sliding before t_start). A PIState (finite elements) or a
        MemoryState (a density) must have ``last_input == initial_position``.
    t_end : float
        End time (> t_start); default ``t_eval[-1]``.
    t_eval : array_like, optional
        Strictly increasing sample times in [t_start, t_end]; default 1001
        uniform samples.
    method : "auto", "event" or "implicit"
        "auto" picks "event" for finite elements with a piecewise-constant u,
        otherwise "implicit"; "event" with a density is an error.
    hold : "zoh" or "linear"
        How samples of u are held between sample times.
    step : float, optional
        Largest step of the implicit method; the span is divided into equal
        steps no longer than it (default 10⁴ steps), independent of `t_eval`.
    t_start : float, keyword only
        Start time [s] (default 0): the initial conditions hold at t_start, the
        motion is solved on [t_start, t_end] and a sampled `applied_force` must
        start at or before it.
    max_events : int, keyword only
        Event limit of the event method (status "event_limit" when reached).
    rtol, atol : float, keyword only
        Accuracy target of the implicit method: when `rtol` is given (or `atol`
        > 0) the step is halved, from `step` (default (t_end − t_start)/10⁴),
        until the step-doubling estimate max|y_h − y_h/2| of the position
        error at the samples is at most atol + rtol·max|y − y0| [m]; the result
        carries the estimate as ``error_estimate`` (and says so in its
        message). The scheme is first order, so each halving about halves the
        error; the step count is limited as for `step`.

    Returns
    -------
    MotionResult

    Examples
    --------
    >>> import presliding as ps
    >>> model = ps.PIFriction(coulomb=1.0, stiffness=[100.0], breakaway=[2.0])
    >>> res = ps.simulate(model, mass=1.0, initial_velocity=1.0,
    ...                   initial_state="saturated", t_end=2.0)
    >>> round(res.stop_time, 12), res.n_reversals        # 1/3 + π·sqrt(m/k)/1: one reversal
    (0.647492598692, 1)

    With a viscous term σ = 2 N·s/m and no elements, the stop of the
    Coulomb–viscous decay, (m/σ)·ln(1 + σ·v0/c1) = ln(7)/2:

    >>> res = ps.simulate(ps.PIFriction(coulomb=1.0, viscous=2.0), mass=1.0,
    ...                   initial_velocity=3.0, t_end=2.0)
    >>> round(res.stop_time, 12), round(float(res.energy.viscous[-1]), 6)
    (0.972955074528, 3.486478)
    """
    if isinstance(model, _rate_run.RATE_MODELS):
        return _simulate_rate(model, mass, applied_force, initial_position, initial_velocity,
                              initial_state, t_end, t_eval, method, hold, step, t_start, rtol,
                              atol)  # fmt: skip
    _run.check_model(model, density_ok=True, asymmetric_ok=True)
    check_finite_stiffness(model.initial_stiffness, "`simulate`", model.density)
    m = as_positive_scalar("mass", mass, kind="mass")
    y0 = as_real_scalar("initial_position", initial_position, kind="position")
    v0 = as_real_scalar("initial_velocity", initial_velocity, kind="velocity")
    t0 = as_real_scalar("t_start", t_start, kind="time")
    applied_force = as_si("applied_force", applied_force, "force")  # pint Quantities in SI
    t_end = None if t_end is None else as_si("t_end", t_end, "time")
    forcing = as_forcing(applied_force, hold, t0)
    method = as_choice("method", method, METHODS)
    t_end, times = _run.time_grid(t0, t_end, t_eval)
    max_events = as_count("max_events", max_events, minimum=1)
    step = None if step is None else as_positive_scalar("step", step)
    target = _run.accuracy_target(rtol, atol)
    if method == "event" and not model.is_discrete:
        raise ValueError(
            "`method` 'event' needs a finite-element model (the closed-form pieces need "
            "finitely many elements); got a continuous density "
            f"{type(model.density).__name__}: use method='implicit' or 'auto'."
        )
    if method == "auto":
        method = "event" if forcing.piecewise_constant and model.is_discrete else "implicit"
    if method == "event" and not forcing.piecewise_constant:
        raise ValueError(
            "`method` 'event' needs a piecewise-constant `applied_force` (a constant, or "
            f"samples with hold={'zoh'!r}); got a {forcing.kind} force with hold={forcing.hold!r}."
        )
    n_steps = _run.step_count(t0, t_end, step) if method == "implicit" else 0
    if target is not None and method == "implicit":
        kw: dict[str, Any] = dict(applied_force=applied_force, initial_position=initial_position,
                  initial_velocity=initial_velocity, initial_state=initial_state, t_end=t_end,
                  t_eval=times, method="implicit", hold=hold, t_start=t_start)  # fmt: skip
        return _run.refine(lambda h: simulate(model, mass, step=h, **kw), t0, t_end, n_steps,
                           *target)  # fmt: skip
    u0 = float(forcing(np.array([t0]))[0])
    sigma = float(model.viscous)
    traj_dir = float(np.sign(v0))  # a start from rest is never a reversal
    resume = None
    if not model.is_discrete:
        state, mem_dir = _density.initial_memory(model, initial_state, y0, v0, u0)
        _run.check_energy(m, v0, 0.5 * m * v0 * v0)
        out = _density.run(model.density, float(model.coulomb), m, state, v0, traj_dir,
                           forcing, times, t0, t_end, n_steps, sigma)  # fmt: skip
        e0, final_state = out["e0"], out["final_state"]
    else:
        f0, mem_dir = _run.initial_deformation(model, initial_state, y0, v0, u0)
        if method == "event":
            resume = _run.continuation_of(initial_state, model, m, y0, v0, t0)
        if resume is not None:
            f0, traj_dir = resume.f.copy(), resume.direction
        k = np.ascontiguousarray(model.stiffness, dtype=np.float64)
        r = np.ascontiguousarray(model.threshold, dtype=np.float64)
        c1 = float(model.coulomb)
        e0 = 0.5 * m * v0 * v0 + 0.5 * float(np.dot(k * f0, f0))
        _run.check_energy(m, v0, e0)
        sides = None if model.is_symmetric else _sides.sides_of(model)
        if method == "event":
            out = _run.run_event(m, c1, k, r, f0, y0, v0, traj_dir, forcing, times, t0, t_end,
                                 max_events, sigma, resume, sides)  # fmt: skip
        else:
            out = _run.run_implicit(m, c1, k, r, f0, y0, v0, traj_dir, forcing, times, t0,
                                    t_end, n_steps, sigma, sides)  # fmt: skip
        if not (np.isfinite(out["y"]) and np.isfinite(out["v"])):
            _run.motion_overflow(t_end)
        y_end = float(out["y"])
        direction = out["dir"] if out["dir"] != 0.0 else mem_dir
        final_state = _run.final_state(y_end, out["f"], direction, initial_state, y0, f0)
        if method == "event":
            stop_at = out["stop"] if out["v"] == 0.0 else np.nan
            if resume is not None and stop_at == t0 and not np.isnan(resume.rest_start):
                out["stop"] = stop_at = resume.rest_start  # the rest began before t_start
            object.__setattr__(final_state, "_continuation", _run.Continuation(
                t_end, y_end, float(out["v"]), out["f"].copy(), float(out["dir"]), stop_at,
                out["piece"], _run.model_key(model, m)))  # fmt: skip
    return _result(out, m, e0, final_state, method, model)


def _simulate_rate(
    model: Any,
    mass: Any,
    applied_force: Any,
    initial_position: Any,
    initial_velocity: Any,
    initial_state: Any,
    t_end: Any,
    t_eval: Any,
    method: Any,
    hold: Any,
    step: Any,
    t_start: Any,
    rtol: Any,
    atol: Any,
) -> MotionResult:
    """`simulate` for GMS, LuGre and Dahl friction: the implicit method (`_rate_run`)."""
    m = as_positive_scalar("mass", mass, kind="mass")
    y0 = as_real_scalar("initial_position", initial_position, kind="position")
    v0 = as_real_scalar("initial_velocity", initial_velocity, kind="velocity")
    t0 = as_real_scalar("t_start", t_start, kind="time")
    applied_force = as_si("applied_force", applied_force, "force")
    t_end = None if t_end is None else as_si("t_end", t_end, "time")
    forcing = as_forcing(applied_force, hold, t0)
    if as_choice("method", method, METHODS) == "event":
        raise ValueError(
            f"`method` 'event' needs the PI model's closed-form pieces; got a "
            f"{type(model).__name__}, a rate-dependent model: use method='implicit' or 'auto'."
        )
    t_end, times = _run.time_grid(t0, t_end, t_eval)
    step = None if step is None else as_positive_scalar("step", step)
    n_steps = _run.step_count(t0, t_end, step)
    target = _run.accuracy_target(rtol, atol)
    if target is not None:
        kw: dict[str, Any] = dict(applied_force=applied_force, initial_position=y0,
                  initial_velocity=v0, initial_state=initial_state, t_end=t_end, t_eval=times,
                  method="implicit", hold=hold, t_start=t0)  # fmt: skip
        return _run.refine(lambda h: simulate(model, m, step=h, **kw), t0, t_end, n_steps,
                           *target, max_steps=_rate_run.MAX_REFINED)  # fmt: skip
    h = np.float64((t_end - t0) / n_steps)
    with np.errstate(over="ignore", divide="ignore"):  # refused here, by name
        scales = (1.0 / h, m / (h * h), _rate_run.force_scale(model) / np.float64(m))
    check_finite_derived("step 1/h", scales[0], ("t_end", "step"))
    check_finite_derived("implicit inertia m/h²", scales[1], ("mass", "step"))
    check_finite_derived("acceleration F/m", scales[2], "mass")
    u0 = float(forcing(np.array([t0]))[0])
    z0, e0, last = _rate_run.initial_rate_state(model, initial_state, y0, v0, u0)
    out, energy0, final_state = _rate_run.run_rate(
        model, m, z0, e0, y0, v0, float(np.sign(v0)), forcing, times, t0, t_end, n_steps
    )
    if out["status"] != 0 or not (np.isfinite(out["y"]) and np.isfinite(out["v"])):
        _run.motion_overflow(t_end)
    if out["dir"] == 0.0 and isinstance(final_state, GMSState):  # never moved: the memory's
        final_state = GMSState(
            final_state.last_input,
            final_state.last_time,
            final_state.forces,
            final_state.slipping,
            0.0,
            last,
        )
    return _result(out, m, energy0, final_state, "implicit", model)


def _result(out: dict, m: float, e0: float, final_state: Any, method: str, model: PIFriction):
    """The MotionResult of a run's outputs (energies assembled here, O(samples))."""
    kinetic, residual, finite = _loop.energy_terms(
        m, e0, out["position"], out["velocity"], out["e_el"], out["dissipated"], out["viscous"],
        out["work"],
    )  # fmt: skip
    if not (finite and np.isfinite(out["y"]) and np.isfinite(out["v"])):
        _run.motion_overflow(out["t_end"])
    energy = MotionEnergy(
        kinetic=kinetic,
        elastic=out["e_el"],
        dissipated=out["dissipated"],
        work=out["work"],
        residual=residual,
        initial=e0,
        viscous=out["viscous"],
    )
    stop = None if np.isnan(out["stop"]) else float(out["stop"])
    y_end = float(out["y"])
    return MotionResult(
        time=out["time"],
        position=out["position"],
        velocity=out["velocity"],
        acceleration=out["acceleration"],
        friction_force=out["friction"],
        elastic_force=out["elastic"],
        applied_force=out["applied"],
        reversal_times=out["rev_t"],
        reversal_positions=out["rev_y"],
        stop_time=stop,
        rest_position=None if stop is None else y_end,
        energy=energy,
        final_state=final_state,
        final_velocity=float(out["v"]),
        status=motion_status(int(out["status"])),
        message=out["message"],
        method=method,
        n_events=int(out["count"]),
        mass=m,
        model=model,
    )
