"""python-control interface: friction, the friction-loaded mass and controllers as systems.

Signal names follow one convention, so that ``control.interconnect`` connects
the blocks by name with no wiring: ``position`` and ``velocity`` [m, m/s] are
what the mass puts out and what friction and controllers read, ``u`` [N] is
the force a controller puts out and the mass takes (rename with ``inputs=``,
e.g. ``inputs="force"``), and ``friction`` [N] is the friction force.

``to_iosys(model, dt=...)``
    The friction law alone: input ``position`` y_k, output ``friction`` F_k. Its
    update is the exact operator (the play update of eq. 3, rate independent),
    so a path through it gives ``model.force`` bit for bit; ``dt=True`` (a
    discrete system with an unspecified period) is accepted, the law having no
    time scale. A model with a viscous term σ has a second input ``velocity``
    and adds σ·ẏ_k.
``to_iosys(model, mass=m, dt=h)``
    The mass of eq. 17 with its friction: input ``u`` held constant over
    [t_k, t_k + h) (zero-order hold), outputs ``position`` and ``velocity``. Its
    update is the exact event-driven motion over one period, with exact stiction
    (the kernel `simulate_loop` runs too, `presliding.control._loop`), so it
    needs the period h in seconds.
``to_iosys(PID(...))``, ``to_iosys(DiscreteController(...))``
    Inputs ``reference`` and ``position``, output ``u``; the same arithmetic as
    `simulate_loop`. A loop ``control.interconnect([to_iosys(pid),
    to_iosys(model, mass=m, dt=pid.dt)], inputs="reference",
    outputs=["position", "velocity", "u"])``
    equals `simulate_loop` to rounding.

Parameters (``params`` of python-control, e.g. of ``input_output_response``)
are honoured: ``coulomb``, ``viscous``, ``stiffness``, ``breakaway`` or ``threshold`` (the
friction and the mass; as many elements as the model has; a new ``stiffness``
keeps the break-away forces), ``mass`` (the mass), ``kp``, ``ki``, ``kd`` (a
PID). A bad value is a ValueError naming the key, and a Dahl block refuses the
friction keys. python-control hands one dictionary to every block of an
interconnection, so keys that a block does not read are left to the others;
the blocks keep their values as the model they were built from, not as
``sys.params`` defaults, which an interconnection would merge across blocks.

State vectors (``X0``; see `iosys_state`; zeros: relaxed at rest at 0):

* friction: ``[y_last, x_1, …, x_N, direction]`` (PI; Coulomb has N = 0) or
  ``[y_last, force]`` (Dahl);
* mass: ``[y, v, f_1, …, f_N, direction]`` with the element deformations
  f_j = y − x_j (kept as such, so that no rounding of y − x_j enters);
* PID: ``[I, D, s_prev, started]``; DiscreteController: its state x.

python-control is a core dependency, imported only when one of these is called.
"""

from __future__ import annotations

import itertools
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._validation import as_list, as_positive_scalar, as_real_scalar, fmt
from presliding.control import _loop
from presliding.control._optional import python_control as _control
from presliding.control.controllers import PID, DiscreteController
from presliding.friction._sides import require_symmetric
from presliding.friction.baselines import CoulombFriction, DahlFriction, DahlState
from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis.operators import PIState
from presliding.motion import _run

__all__ = ["iosys_state", "to_iosys"]

_DAHL_WITH_MASS = (
    "`model` must be a PIFriction or CoulombFriction when a `mass` is given; got DahlFriction."
)
MODEL_KEYS = ("coulomb", "stiffness", "breakaway", "threshold", "viscous")
_COUNTER = itertools.count(1)
FloatArray = NDArray[np.float64]


def _pi_model(model: Any) -> PIFriction | DahlFriction:
    if isinstance(model, CoulombFriction):
        return model.as_pi_friction
    if isinstance(model, PIFriction):
        require_symmetric(model, "to_iosys")
    if isinstance(model, (PIFriction, DahlFriction)):
        return model
    raise TypeError(
        "`model` must be a PIFriction, CoulombFriction or DahlFriction (or a PID or "
        f"DiscreteController); got {type(model).__name__}."
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
    model : PIFriction, CoulombFriction, DahlFriction, PID or DiscreteController
        For a controller: its state before the first sample (nothing else is read).
    state : PIState or DahlState, optional
        Friction memory; default relaxed at `position`. For the mass system its
        ``last_input`` is the position.
    mass : float, optional
        Give it (any value) for the mass system's layout ``[y, v, f, direction]``.
    position, velocity : float
        Used when `state` is None (position) and for the mass system (velocity).
    """
    if isinstance(model, PID):
        return np.zeros(4)
    if isinstance(model, DiscreteController):
        return np.zeros(model.n_states)
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
    if not model.is_discrete:
        raise TypeError("`model` must have finite elements for a python-control system; got a "
                        f"continuous density {type(model.density).__name__}.")  # fmt: skip
    if state is not None and not isinstance(state, PIState):
        raise TypeError(f"`state` must be a PIState; got {type(state).__name__}.")
    if mass is None:
        state = model.relaxed_state(y0) if state is None else state
        state.check_against(model.threshold)
        return np.concatenate(([state.last_input], state.play, [state.direction]))
    if state is None:
        f, d = _run.initial_deformation(model, "relaxed", y0, v0, 0.0)
    else:
        y0 = state.last_input
        f, d = _run.initial_deformation(model, state, y0, v0, 0.0)
    return np.concatenate(([y0, v0], f, [d]))


def _key(value: Any) -> Any:
    arr = np.asarray(value)
    if arr.dtype.kind not in "iuf":
        raise TypeError(f"a friction parameter must be a number or array; got {fmt(value)}.")
    return arr.shape, arr.astype(np.float64).tobytes()


def _model_for(base: PIFriction, params: dict, cache: dict) -> PIFriction:
    """`base` with the model keys of `params` replaced (validated, cached by value)."""
    given = {k: params[k] for k in MODEL_KEYS if k in params}
    if not given:
        return base
    key = tuple((k, _key(v)) for k, v in sorted(given.items()))
    if key not in cache:
        if "breakaway" in given and "threshold" in given:
            raise ValueError("`params` must give `breakaway` or `threshold`, not both.")
        k = given.get("stiffness", base.stiffness)
        kw = {"threshold": given["threshold"]} if "threshold" in given else {
            "breakaway": given.get("breakaway", base.breakaway)}  # fmt: skip
        model = PIFriction(given.get("coulomb", base.coulomb), k, **kw,
                           viscous=given.get("viscous", base.viscous))  # fmt: skip
        if model.n_elements != base.n_elements:
            raise ValueError(
                f"`params` must keep the number of elements ({base.n_elements}) of the system's "
                f"state; got {model.n_elements}."
            )
        cache[key] = model
    return cache[key]


def _name(name: Any, kind: str) -> str:
    if name is None:
        return f"{kind}[{next(_COUNTER)}]"
    if not isinstance(name, str):
        raise TypeError(f"`name` must be a string or None; got {fmt(name)}.")
    if not name.strip():  # python-control refers to signals as "name.signal"
        raise ValueError(f"`name` must be a non-empty string or None; got {fmt(name)}.")
    return name


def _signals(arg: str, value: Any, default: list[str]) -> list[str]:
    if value is None:
        return default
    names = [value] if isinstance(value, str) else as_list(arg, value)
    if len(names) != len(default) or not all(isinstance(n, str) and n.strip() for n in names):
        raise ValueError(f"`{arg}` must be {len(default)} signal name(s) like {default!r}; got "
                         f"{fmt(value)}.")  # fmt: skip
    return names


def _period(dt: Any, allow_true: bool) -> float | bool:
    if dt is True:
        if not allow_true:
            raise ValueError(
                "`dt` must be the sample period in seconds for the mass system (its exact "
                "update integrates over one period); got True."
            )
        return True
    return as_positive_scalar("dt", dt)


def to_iosys(
    model: Any,
    mass: float | None = None,
    dt: float | bool | None = None,
    *,
    name: str | None = None,
    inputs: Any = None,
    outputs: Any = None,
) -> Any:
    """A discrete-time ``control.NonlinearIOSystem``: friction, the mass with friction, or a
    controller (see the module notes for names, parameters and states).

    Parameters
    ----------
    model : PIFriction, CoulombFriction, DahlFriction, PID or DiscreteController
        Dahl only without `mass`; a friction model needs finite elements.
    mass : float, optional
        m > 0 [kg]. None: the friction law alone. Given: the mass of eq. 17.
    dt : float or True
        Sample period [s] (> 0); default 1e-3 for friction, the controller's own
        ``dt`` for a controller (another value is an error). True (unspecified
        period) for the friction law alone.
    name : str, optional
        System name; default a readable one such as ``"mass[3]"``.
    inputs, outputs : str or list of str, optional
        Other signal names (as many as the defaults).

    Returns
    -------
    control.NonlinearIOSystem
        Start it from `iosys_state` (zeros: relaxed at rest at 0).

    Examples
    --------
    >>> import numpy as np, control
    >>> model = PIFriction(coulomb=0.5, stiffness=[100.0], breakaway=[1.0])
    >>> sys = to_iosys(model, dt=0.01)
    >>> sys.input_labels, sys.output_labels
    (['position'], ['friction'])
    >>> y = np.array([0.0, 0.004, 0.03, 0.01])
    >>> resp = control.input_output_response(sys, np.arange(4) * 0.01, y, iosys_state(model))
    >>> bool(np.array_equal(resp.outputs, model.force(y, model.relaxed_state(0.0))[0]))
    True
    """
    control = _control()
    if isinstance(model, (PID, DiscreteController)):
        from presliding.control._controller_iosys import controller_system

        if mass is not None:
            raise TypeError(f"`mass` must be None for a controller; got {fmt(mass)}.")
        if dt is not None and (dt is True or as_positive_scalar("dt", dt) != model.dt):
            raise ValueError(f"`dt` must be None or the controller's dt = {fmt(model.dt)}; got "
                             f"{fmt(dt)}.")  # fmt: skip
        ins = _signals("inputs", inputs, ["reference", "position"])
        outs = _signals("outputs", outputs, ["u"])
        return controller_system(control, model, _name(name, "pid" if isinstance(model, PID)
                                                       else "controller"), ins, outs)  # fmt: skip
    model = _pi_model(model)
    if isinstance(model, PIFriction) and not model.is_discrete:
        raise TypeError("`model` must have finite elements for a python-control system; got a "
                        f"continuous density {type(model.density).__name__}.")  # fmt: skip
    h = _period(1e-3 if dt is None else dt, allow_true=mass is None)
    if mass is None:
        viscous = isinstance(model, PIFriction) and model.viscous > 0
        ins = _signals("inputs", inputs, ["position", "velocity"] if viscous else ["position"])
        outs = _signals("outputs", outputs, ["friction"])
        return _friction_system(control, model, h, _name(name, "friction"), ins, outs)
    if isinstance(model, DahlFriction):
        raise TypeError(_DAHL_WITH_MASS)
    m = as_positive_scalar("mass", mass)
    ins = _signals("inputs", inputs, ["u"])
    outs = _signals("outputs", outputs, ["position", "velocity"])
    return _mass_system(control, model, m, h, _name(name, "mass"), ins, outs)


def _friction_system(control, model, dt, name, ins, outs) -> Any:
    if isinstance(model, DahlFriction):

        def dahl(x: FloatArray, u: FloatArray, params: dict) -> tuple[FloatArray, DahlState]:
            bad = sorted(set(params) & set(MODEL_KEYS))
            if bad:
                raise ValueError(f"`params` key `{bad[0]}` does not apply to a DahlFriction "
                                 "system (it reads no parameters).")  # fmt: skip
            return model.force(np.atleast_1d(u)[:1], DahlState(x[0], x[1]))

        def update(t, x, u, params):
            st = dahl(x, u, params)[1]
            return np.array([st.last_input, st.force])

        def output(t, x, u, params):
            return dahl(x, u, params)[0]

        states = ["y_last", "force"]
    else:
        n = model.n_elements
        cache: dict = {}

        def pi(x: FloatArray, u: FloatArray, params: dict) -> tuple[FloatArray, PIState]:
            mod = _model_for(model, params, cache)
            u = np.atleast_1d(u)
            force, st = mod.force(u[:1], PIState(x[0], x[1 : n + 1], x[n + 1]))
            assert isinstance(st, PIState)  # a finite-element model
            if u.shape[0] > 1:  # the velocity input of a model with a viscous term
                force = force + mod.viscous * u[1]
            return force, st

        def update(t, x, u, params):
            st = pi(x, u, params)[1]
            return np.concatenate(([st.last_input], st.play, [st.direction]))

        def output(t, x, u, params):
            return pi(x, u, params)[0]

        states = ["y_last", *[f"play_{j}" for j in range(n)], "direction"]
    return control.NonlinearIOSystem(
        update, output, inputs=ins, outputs=outs, states=states, dt=dt, name=name
    )


def _mass_system(control, model: PIFriction, mass: float, dt: float, name, ins, outs) -> Any:
    n = model.n_elements
    cache: dict = {}

    def update(t, x, u, params):
        mod = _model_for(model, params, cache)
        m = as_positive_scalar("mass", params.get("mass", mass))
        f = np.array(x[2 : n + 2], dtype=np.float64)
        k = np.array(mod.stiffness, dtype=np.float64)  # writable: one kernel type
        r = np.array(mod.threshold, dtype=np.float64)
        t0 = float(t)
        st, y, v, d, _ = _loop.plant_period(m, float(mod.coulomb), float(mod.viscous), k, r, f,
                                            float(x[0]),
                                            float(x[1]), float(x[n + 2]),
                                            float(np.atleast_1d(u)[0]), t0, t0 + dt,
                                            10_000_000,
                                            _loop.damped_flag(float(mod.viscous)))  # fmt: skip
        if st != 0:
            raise RuntimeError(f"the plant step at t = {t!r} reached the event limit.")
        return np.concatenate(([y, v], f, [d]))

    def output(t, x, u, params):
        return np.array([x[0], x[1]])

    states = ["position", "velocity", *[f"deformation_{j}" for j in range(n)], "direction"]
    return control.NonlinearIOSystem(
        update, output, inputs=ins, outputs=outs, states=states, dt=dt, name=name
    )
