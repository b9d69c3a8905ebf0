"""python-control interface: friction models and the friction-loaded mass as discrete-time systems.

``to_iosys(model, dt=...)`` is the friction law alone, input displacement y_k,
output friction force F_k; its update is the exact operator (the play update of
eq. 3, rate independent), so a path through it gives ``model.force`` bit for bit.

``to_iosys(model, mass=m, dt=...)`` is the plant of eq. 17, input applied force
u_k held constant over [t_k, t_k + dt) (zero-order hold, as a digital controller
applies it), outputs position y_k and velocity v_k; its update is the exact
event-driven simulation over one period (`presliding.motion.simulation`,
method "event"), with exact stiction. python-control's continuous-time
simulation has no events, so the discrete-time system is the one to close loops
with (``control.interconnect``, ``control.input_output_response``).

State vectors (``X0`` of ``input_output_response``; see `iosys_state`):

* friction: ``[y_last, x_1, …, x_N, direction]`` (PI; Coulomb has N = 0) or
  ``[y_last, force]`` (Dahl);
* mass: ``[y, v, x_1, …, x_N, direction]``.

The zero vector is the relaxed model at rest at 0. python-control is an optional
dependency: ``pip install presliding[control]``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._validation import as_positive_scalar, as_real_scalar, fmt
from presliding.friction.baselines import CoulombFriction, DahlFriction, DahlState
from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis.operators import PIState

__all__ = ["iosys_state", "to_iosys"]

# the Dahl model has no motion form here (its state is the force, not the elements)
_DAHL_WITH_MASS = (
    "`model` must be a PIFriction or CoulombFriction when a `mass` is given; got DahlFriction."
)

FloatArray = NDArray[np.float64]


def _control() -> Any:
    try:
        import control
    except ImportError as exc:
        raise ImportError(
            "to_iosys needs the optional `control` package (python-control); "
            "install it with `pip install presliding[control]`."
        ) from exc
    return control


def _pi_model(model: Any) -> PIFriction | DahlFriction:
    if isinstance(model, CoulombFriction):
        return model.as_pi_friction
    if isinstance(model, (PIFriction, DahlFriction)):
        return model
    raise TypeError(
        "`model` must be a PIFriction, CoulombFriction or DahlFriction; "
        f"got {type(model).__name__}."
    )


def iosys_state(
    model: Any,
    state: PIState | DahlState | None = None,
    *,
    mass: float | None = None,
    position: float = 0.0,
    velocity: float = 0.0,
) -> FloatArray:
    """The state vector of ``to_iosys(model, mass)`` for a given friction memory.

    Parameters
    ----------
    model : PIFriction, CoulombFriction or DahlFriction
    state : PIState or DahlState, optional
        Friction memory; default relaxed at `position`.
    mass : float, optional
        Give it (any value) for the mass system's layout ``[y, v, memory]``.
    position, velocity : float
        Used when `state` is None (position) and for the mass system (velocity).
    """
    model = _pi_model(model)
    y0 = as_real_scalar("position", position)
    v0 = as_real_scalar("velocity", velocity)
    if isinstance(model, DahlFriction):
        if mass is not None:
            raise TypeError(_DAHL_WITH_MASS)
        state = model.relaxed_state(y0) if state is None else state
        if not isinstance(state, DahlState):
            raise TypeError(f"`state` must be a DahlState; got {type(state).__name__}.")
        return np.array([state.last_input, state.force])
    state = model.relaxed_state(y0) if state is None else state
    if not isinstance(state, PIState):
        raise TypeError(f"`state` must be a PIState; got {type(state).__name__}.")
    state.check_against(model.threshold)
    memory = np.concatenate(([state.last_input], state.play, [state.direction]))
    return memory if mass is None else np.concatenate(([state.last_input, v0], memory[1:]))


def to_iosys(
    model: Any,
    mass: float | None = None,
    dt: float = 1e-3,
    *,
    name: str | None = None,
) -> Any:
    """A discrete-time ``control.NonlinearIOSystem`` with the exact friction update.

    Parameters
    ----------
    model : PIFriction, CoulombFriction or DahlFriction
        Dahl only without `mass`.
    mass : float, optional
        m > 0 [kg]. None: the friction law alone (input ``displacement``, output
        ``friction``). Given: the mass of eq. 17 (input ``force``, outputs
        ``position`` and ``velocity``), exact over each period with u held; each
        update is one exact `simulate` call (about a millisecond per step).
    dt : float
        Sample period [s] (> 0).
    name : str, optional
        System name for ``control.interconnect``.

    Returns
    -------
    control.NonlinearIOSystem
        Start it from `iosys_state` (zeros: relaxed at rest at 0).

    Examples
    --------
    >>> import numpy as np, control
    >>> model = PIFriction(coulomb=0.5, stiffness=[100.0], breakaway=[1.0])
    >>> sys = to_iosys(model, dt=0.01)
    >>> y = np.array([0.0, 0.004, 0.03, 0.01])
    >>> resp = control.input_output_response(sys, np.arange(4) * 0.01, y, iosys_state(model))
    >>> bool(np.array_equal(resp.outputs, model.force(y, model.relaxed_state(0.0))[0]))
    True
    """
    control = _control()
    model = _pi_model(model)
    h = as_positive_scalar("dt", dt)
    if name is not None and not isinstance(name, str):
        raise TypeError(f"`name` must be a string or None; got {fmt(name)}.")
    if mass is None:
        return _friction_system(control, model, h, name)
    if isinstance(model, DahlFriction):
        raise TypeError(_DAHL_WITH_MASS)
    m = as_positive_scalar("mass", mass)
    return _mass_system(control, model, m, h, name)


def _friction_system(control: Any, model: Any, dt: float, name: str | None) -> Any:
    if isinstance(model, DahlFriction):

        def dahl(x: FloatArray, u: FloatArray) -> tuple[FloatArray, DahlState]:
            return model.force(np.atleast_1d(u)[:1], DahlState(x[0], x[1]))

        def update(t, x, u, params):
            st = dahl(x, u)[1]
            return np.array([st.last_input, st.force])

        def output(t, x, u, params):
            return dahl(x, u)[0]

        states = ["y_last", "force"]
    else:
        n = model.n_elements

        def pi(x: FloatArray, u: FloatArray) -> tuple[FloatArray, PIState]:
            return model.force(np.atleast_1d(u)[:1], PIState(x[0], x[1 : n + 1], x[n + 1]))

        def update(t, x, u, params):
            st = pi(x, u)[1]
            return np.concatenate(([st.last_input], st.play, [st.direction]))

        def output(t, x, u, params):
            return pi(x, u)[0]

        states = ["y_last", *[f"play_{j}" for j in range(n)], "direction"]
    return control.NonlinearIOSystem(
        update, output, inputs=["displacement"], outputs=["friction"], states=states,
        dt=dt, name=name,
    )  # fmt: skip


def _mass_system(control: Any, model: PIFriction, mass: float, dt: float, name: str | None):
    from presliding.motion.simulation import simulate

    n = model.n_elements

    def update(t, x, u, params):
        y, v = float(x[0]), float(x[1])
        state = PIState(y, x[2 : n + 2], x[n + 2])
        res = simulate(
            model, mass, applied_force=float(np.atleast_1d(u)[0]), initial_position=y,
            initial_velocity=v, initial_state=state, t_start=float(t), t_end=float(t) + dt,
            t_eval=[float(t), float(t) + dt], method="event",
        )  # fmt: skip
        if not res.success:
            raise RuntimeError(f"the plant step at t = {t!r} failed: {res.message}")
        st = res.final_state
        return np.concatenate(([st.last_input, res.final_velocity], st.play, [st.direction]))

    def output(t, x, u, params):
        return np.array([x[0], x[1]])

    states = ["position", "velocity", *[f"play_{j}" for j in range(n)], "direction"]
    return control.NonlinearIOSystem(
        update, output, inputs=["force"], outputs=["position", "velocity"], states=states,
        dt=dt, name=name,
    )  # fmt: skip
