"""`simulate` for the state-variable friction models: GMS, LuGre and Dahl with a mass.

The models' parameters are packed for the one compiled step (`_rate_step`), the
initial state is taken from a name ("relaxed", "saturated") or the model's own
state object, and the implicit loop (`_rate_loop`) runs; `simulate` assembles the
`MotionResult` from the outputs as for the PI model's implicit method. Only the
implicit method applies: these models have no closed-form pieces (a GMS model
without Stribeck drop and lag is the PI model, `GMSFriction.pi_friction`, whose
event method is exact).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._validation import fmt
from presliding.friction._baseline_kernels import lugre_output
from presliding.friction.baselines import DahlFriction, DahlState, LuGreFriction, LuGreState
from presliding.friction.gms import GMSFriction, GMSState
from presliding.motion import _rate_loop, _rate_step
from presliding.motion._forcing import Forcing
from presliding.motion._run import REVERSAL_CAPACITY, _buffers, applied_force_at

__all__ = ["MAX_REFINED", "RATE_MODELS", "family_arrays", "initial_rate_state", "run_rate"]

FloatArray = NDArray[np.float64]
RATE_MODELS = (GMSFriction, LuGreFriction, DahlFriction)
#: implicit steps at most of an accuracy target's step doubling (`simulate(rtol=...)`): each
#: step solves a scalar root, several times the PI model's piecewise-linear step
MAX_REFINED = 2_000_000
STATE_TYPES = {GMSFriction: GMSState, LuGreFriction: LuGreState, DahlFriction: DahlState}


def family_arrays(model: Any) -> tuple[int, FloatArray, FloatArray, FloatArray]:
    """(family code, parameter vector, k, c) of a model for the compiled step (`_rate_step`)."""
    par = np.zeros(_rate_step.N_PARAMETERS)
    empty = np.empty(0)
    if isinstance(model, GMSFriction):
        vs = 1.0 if model.stribeck_velocity is None else float(model.stribeck_velocity)
        par[:] = (model.coulomb, model.static_ratio, vs, model.stribeck_exponent,
                  model.lag_time, model.viscous)  # fmt: skip
        return _rate_step.GMS, par, np.ascontiguousarray(model.stiffness), np.ascontiguousarray(
            model.breakaway)  # fmt: skip
    if isinstance(model, LuGreFriction):
        par[:] = (model.coulomb, model.static, model.stiffness, model.damping, model.viscous,
                  model.stribeck_velocity)  # fmt: skip
        return _rate_step.LUGRE, par, empty, empty
    par[:4] = (model.coulomb, model.stiffness, model.exponent, model.viscous)
    return _rate_step.DAHL, par, empty, empty


def force_scale(model: Any) -> float:
    """The largest friction force at rest of a model [N] (GMS: F_S; LuGre: F_s; Dahl: F_c)."""
    if isinstance(model, GMSFriction):
        return float(model.static_level)  # type: ignore[arg-type]
    return float(model.static if isinstance(model, LuGreFriction) else model.coulomb)


def _saturation_direction(v0: float, u0: float, rest: float) -> float:
    """The direction of steady sliding before the start: of v0, else of u0 − F."""
    if v0 != 0.0:
        return float(np.sign(v0))
    return 1.0 if u0 - rest >= 0.0 else -1.0


def initial_rate_state(model: Any, initial_state: Any, y0: float, v0: float,
                       u0: float) -> tuple[FloatArray, FloatArray, float]:  # fmt: skip
    """(z, e, direction of the last motion) at the start, from a name or a state object."""
    n = model.n_elements if isinstance(model, GMSFriction) else 1
    if isinstance(initial_state, str):
        if initial_state == "relaxed":
            return np.zeros(n), np.zeros(n), float(np.sign(v0))
        if initial_state == "saturated":
            s = _saturation_direction(v0, u0, 0.0)
            if isinstance(model, GMSFriction):
                st = model.saturated_state(y0, 0.0, s, abs(v0))
                return np.array(st.forces), np.array(st.slipping), s
            if isinstance(model, LuGreFriction):
                g = float(model.stribeck(v0)) if v0 != 0.0 else model.static
                return np.array([s * g / model.stiffness]), np.zeros(1), s
            return np.array([s * model.coulomb]), np.zeros(1), s
        raise ValueError(
            "`initial_state` must be 'relaxed', 'saturated' or a "
            f"{STATE_TYPES[type(model)].__name__}; got {fmt(initial_state)}."
        )
    expected: Any = STATE_TYPES[type(model)]
    if not isinstance(initial_state, expected):
        raise TypeError(
            f"`initial_state` must be 'relaxed', 'saturated' or a {expected.__name__}; got "
            f"{type(initial_state).__name__}."
        )
    state: Any = initial_state
    if state.last_input != y0:
        raise ValueError(
            "`initial_state.last_input` must equal `initial_position`; got "
            f"{fmt(state.last_input)} and {fmt(y0)}."
        )
    vdir = float(np.sign(v0))
    if isinstance(initial_state, GMSState):
        model._check_state(initial_state)
        return (np.array(initial_state.forces), np.array(initial_state.slipping),
                vdir if vdir else initial_state.direction)  # fmt: skip
    if isinstance(initial_state, LuGreState):
        zmax = model.static / model.stiffness
        if abs(initial_state.bristle) > zmax * (1 + 1e-12):
            raise ValueError(
                f"`initial_state.bristle` must satisfy |z| <= static/stiffness {fmt(zmax)}; got "
                f"{fmt(initial_state.bristle)}."
            )
        return np.array([initial_state.bristle]), np.zeros(1), vdir
    if abs(state.force) > model.coulomb:
        raise ValueError(
            f"`initial_state.force` must satisfy |force| <= coulomb {fmt(model.coulomb)}; got "
            f"{fmt(state.force)}."
        )
    return np.array([state.force]), np.zeros(1), vdir


def initial_force(model: Any, z: FloatArray, v0: float, u0: float) -> float:
    """The friction force at the start (at rest: what balances u0, up to the band)."""
    family, par, _, _ = family_arrays(model)
    if family == _rate_step.GMS:
        rest = float(np.sum(z))
        shat = float(model.stribeck(v0)) / model.coulomb_level
        if v0 != 0.0:
            return model.coulomb * shat * float(np.sign(v0)) + rest + model.viscous * v0
        band = model.coulomb * model.static_ratio
        return rest + float(np.clip(u0 - rest, -band, band))
    if family == _rate_step.LUGRE:
        return float(lugre_output(z[0], v0, par[2], par[3], par[4], par[0], par[1], par[5]))
    return float(z[0])


def run_rate(model: Any, m: float, z0: FloatArray, e0: FloatArray, y0: float, v0: float,
             last_dir: float, forcing: Forcing, times: FloatArray, t0: float, t_end: float,
             n_steps: int) -> tuple[dict[str, Any], float, Any]:  # fmt: skip
    """The implicit run; returns (outputs for `simulate`'s result, initial energy, final state)."""
    family, par, k, c = family_arrays(model)
    u_kind, u_t, u_val, u_mid = forcing.loop_form(t0, t_end, n_steps)
    e_start = 0.5 * m * v0 * v0 + float(_rate_step.stored_energy(family, par, k, z0))
    cap = REVERSAL_CAPACITY
    while True:
        z, e = z0.copy(), e0.copy()
        o = _buffers(times.shape[0], 9)
        rev = _buffers(cap, 2)
        n_rev, stop, y, v, d, status = _rate_loop.run_rate(
            family, par, k, c, z, e, m, y0, v0, last_dir, t0, t_end, n_steps, u_kind, u_t,
            u_val, u_mid, times, *o, *rev,
        )  # fmt: skip
        if n_rev <= cap:
            break
        cap = n_rev
    y_o, v_o, a_o, fric_o, fel_o, eel_o, dis_o, vis_o, work_o = o
    applied = applied_force_at(forcing, u_kind, u_t, u_val, times)
    n0 = int(np.searchsorted(times, t0, side="right"))
    if n0:
        f0 = initial_force(model, z0, v0, float(applied[0]))
        a_o[:n0] = (applied[0] - f0) / m
        fric_o[:n0] = f0
    h = (t_end - t0) / n_steps
    out = {
        "n": times.shape[0], "time": times, "position": y_o, "velocity": v_o, "acceleration": a_o,
        "elastic": fel_o, "applied": applied, "friction": fric_o, "e_el": eel_o,
        "dissipated": dis_o, "viscous": vis_o, "work": work_o,
        "rev_t": rev[0][:n_rev], "rev_y": rev[1][:n_rev], "stop": stop, "y": y, "v": v,
        "dir": d, "count": n_steps, "status": status, "t_end": t_end,
        "message": f"{n_steps} implicit steps of {h:.3g}",
    }  # fmt: skip
    return out, e_start, _final_state(model, y, t_end, z, e, v, d)


def _final_state(model: Any, y: float, t: float, z: FloatArray, e: FloatArray, v: float,
                 d: float) -> Any:  # fmt: skip
    if isinstance(model, GMSFriction):
        return GMSState(y, t, z, e, v, d)
    if isinstance(model, LuGreFriction):
        return LuGreState(y, t, float(z[0]), v)
    return DahlState(y, float(z[0]))
