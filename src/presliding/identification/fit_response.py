"""Output-error fit: simulated against measured motion (the paper's experiments, section 4).

The paper identifies m, F_c, c1 and k_2..k_5 of eq. 17 with four elements of
equal break-away force c_j = (F_c − c1)/4 by fitting the simulated velocity
response to the measured one near a full stop. `fit_response` does this with
the exact event-driven simulator (`presliding.motion`), so the fitted response
has no numerical micro-oscillations and sticks exactly.

Scale. With u = 0 throughout, eq. 17 is homogeneous: multiplying the mass and
every force by the same factor leaves the motion unchanged, so only the ratios
F/m are identifiable. This is detected; unless the mass or the Coulomb level is
given, the parameters are reported per unit mass (mass = 1, forces in N/kg,
stiffnesses in N/(m·kg)).

Start. Unless `initial` is given, the start comes from the inverse model: eq. 17
as a linear regression (`presliding.identification.fit_motion`'s machinery) on the measured
velocity, its difference quotient and its integral, with the thresholds on a
grid, merged into the wanted number of elements.

Robustness. With equal break-away forces the stiffest element can trade places
with the Coulomb element: as k_1 → ∞ the element turns rigid-plastic and its
break-away force joins c1, a local minimum that fits almost as well (c1 → 0
and one very stiff element). So the fit (i) starts from the regression start
and from a spread start (c1/F_c between 1/4 and 3/5, the stiffest element at
most twice the next one), compared on at most `COARSE_SAMPLES` samples, and
refines the better on every sample; (ii) refits with that element rigid and
compares the costs S: if S_rigid − S ≤ s²·t²_{n−p}(level) (the profile
likelihood bound of the confidence level, s² = S/(n − p)), the data cannot
separate c1 from the stiffest element and the status is ``"not_identifiable"``
(the intervals then span both fits, and k_1's reaches infinity); (iii) a model
parameter on its bound 0 gives the status ``"at_bound"``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from presliding._validation import (
    as_choice,
    as_nonnegative_scalar,
    as_positive_scalar,
    as_real_scalar,
    fmt,
)
from presliding.friction.pi_friction import PIFriction
from presliding.identification import _response_tools as rt
from presliding.identification._least_squares import check_constraints, check_options
from presliding.identification._response_checks import (
    bound_check,
    cost,
    polish_initial_velocity,
    rigid_check,
    spread_start,
    stiffest_first,
)
from presliding.identification.fit_presliding import check_enough, check_varies, element_count
from presliding.identification.fit_result import FitResult, Tie, solve_least_squares
from presliding.identification.measurement import Measurement

__all__ = ["fit_response"]

FloatArray = NDArray[np.float64]
SIGNALS = ("velocity", "position", "both")
COARSE_SAMPLES = 2000  #: starts are compared on at most this many samples


def fit_response(
    measurement: Measurement,
    n_elements: int = 4,
    equal_breakaway: bool = True,
    mass: float | None = None,
    *,
    coulomb_level: float | None = None,
    signal: str = "velocity",
    initial_state: str = "saturated",
    initial: Mapping[str, float] | None = None,
    fit_initial: bool = True,
    fixed: Mapping[str, float] | None = None,
    tied: Mapping[str, Tie] | None = None,
    level: float = 0.95,
    max_evaluations: int | None = None,
    tolerance: float = 1e-8,
    multistart: bool = True,
) -> FitResult:
    """Fit eq. 17 by matching the simulated to the measured motion (output error).

    Parameters
    ----------
    measurement : Measurement
        Time and the measured `velocity` and/or `position`; `applied_force` u
        (held constant between samples, as a digital controller applies it;
        absent = 0). The motion starts at the first sample from the measured
        position (or 0) and velocity (or the difference quotient of the position).
    n_elements : int
        Number N of elasto-plastic elements (the paper: 4).
    equal_breakaway : bool
        Parameters ``mass``, ``coulomb_level`` F_c, ``coulomb`` c1, ``stiffness_j``
        with c_j = (F_c − c1)/N (the paper's choice); False: ``mass``, ``coulomb``,
        ``stiffness_j``, ``breakaway_j``.
    mass : float, optional
        Known mass [kg] (held fixed).
    coulomb_level : float, optional, keyword only
        Known F_c [N] (held fixed; needs ``equal_breakaway=True``).
    signal : {"velocity", "position", "both"}
        What is compared; "both" weighs each by the inverse of its RMS.
    initial_state : {"saturated", "relaxed"}
        Friction memory at the first sample ("saturated": steady sliding before).
    initial : mapping, optional
        Start values by parameter name (others from the default start).
    fit_initial : bool
        Also estimate the initial velocity (parameter ``initial_velocity``) and,
        when the position is compared, the initial position
        (``initial_position``); a noisy first sample would otherwise bias every
        other parameter. False holds them at the first measured sample.
    fixed, tied, level, max_evaluations, tolerance : as in `fit_presliding`
        A fixed (or start) mass, ``coulomb_level``, stiffness or break-away
        force must be positive, c1 nonnegative, every value a finite real; a
        tie of those parameters needs a positive factor. `max_evaluations`
        defaults to 50 per parameter for each start and check.
    multistart : bool, keyword only
        Also try the spread start and test the rigid limit of the stiffest
        element (see the module notes); only when c1 and the stiffnesses are
        neither fixed nor tied.

    Returns
    -------
    FitResult
        Against time; parameters per unit mass when u = 0 and neither `mass`
        nor `coulomb_level` is given (said in `message`). Status
        ``"not_identifiable"`` when the data cannot separate c1 from the
        stiffest element, ``"at_bound"`` when a model parameter sits on 0.
    """
    if not isinstance(measurement, Measurement):
        raise TypeError(f"`measurement` must be a Measurement; got {type(measurement).__name__}.")
    signal = as_choice("signal", signal, SIGNALS)
    initial_state = as_choice("initial_state", initial_state, ("saturated", "relaxed"))
    need = {"velocity": ("velocity",), "position": ("position",), "both": ("velocity", "position")}
    measurement.require(*need[signal], purpose=f"fit_response(signal={signal!r})")
    n = element_count(n_elements, None, 4)
    if coulomb_level is not None and not equal_breakaway:
        raise ValueError("`coulomb_level` can be given only with equal_breakaway=True.")
    level, max_evaluations, tolerance = check_options(level, max_evaluations, tolerance)
    fixed, tied = check_constraints(fixed, tied)
    _check_model_values(fixed, tied, initial)
    m = measurement
    t = m.time
    v = m.velocity if m.velocity is not None else np.gradient(m.position, t)
    y = m.position if m.position is not None else rt.integral(t, v)
    u = m.applied_force if m.applied_force is not None else np.zeros_like(t)
    check_varies("velocity" if m.velocity is not None else "position", v)
    if mass is not None:
        fixed["mass"] = as_positive_scalar("mass", mass)
    if coulomb_level is not None:
        fixed["coulomb_level"] = as_positive_scalar("coulomb_level", coulomb_level)
    fc = fixed.get("coulomb_level")
    if equal_breakaway and n and fc is not None and fixed.get("coulomb", 0.0) >= fc:
        raise ValueError(
            f"`fixed['coulomb']` must be less than the Coulomb level {fmt(fc)} (else no force is "
            f"left for the elements); got {fmt(fixed['coulomb'])}."
        )
    per_unit_mass = not np.any(u) and not ({"mass", "coulomb_level"} & set(fixed))
    if per_unit_mass:
        fixed["mass"] = 1.0
    k_names = [f"stiffness_{j + 1}" for j in range(n)]
    c_names = [f"breakaway_{j + 1}" for j in range(n)]
    names = ["mass", *(["coulomb_level"] if equal_breakaway else []), "coulomb", *k_names]
    names += [] if equal_breakaway else c_names
    names += ["initial_velocity", "initial_position"]
    direction = rt.initial_direction(v, u)
    if not fit_initial:
        fixed.setdefault("initial_velocity", float(v[0]))
    if not fit_initial or signal == "velocity":
        fixed.setdefault("initial_position", float(y[0]))
    check_enough(t.shape[0], len(names) - len(fixed))
    free_motion = not np.any(u)
    start = rt.default_start(
        t, y, v, u, n, fixed.get("mass", 1.0 if free_motion else None), equal_breakaway
    )
    if free_motion and "mass" not in fixed and "coulomb_level" in fixed:
        factor = fixed["coulomb_level"] / start["coulomb_level"]
        start = {key: val * factor for key, val in start.items()}
    start.update(initial_velocity=float(v[0]), initial_position=float(y[0]))
    for key, val in dict(initial or {}).items():
        if key not in names:
            raise ValueError(f"`initial` names unknown parameter {key!r}; known: {names}.")
        start[key] = float(val)
    start = {x: start[x] for x in names}
    problem = _Problem(names, n, equal_breakaway, rt.Simulator(m, u, initial_state, direction),
                       rt.weights(signal, m), v, y)  # fmt: skip
    bounds = dict.fromkeys(names, (0.0, np.inf))
    bounds["initial_position"] = (-np.inf, np.inf)
    saturated = initial_state == "saturated"
    bounds["initial_velocity"] = (
        (0.0, np.inf) if direction > 0 else (-np.inf, 0.0) if saturated else (-np.inf, np.inf)
    )
    if max_evaluations is None:
        max_evaluations = 50 * len(names)
    options = {"bounds": bounds, "tied": tied, "level": level, "max_evaluations": max_evaluations,
               "tolerance": tolerance, "gradient_tolerance": max(tolerance**2, 1e-15)}  # fmt: skip

    evaluations = [0]

    def solve(begin, rigid=False, idx=None, extra=None, **kw):
        opts = {**options, **kw}
        out = solve_least_squares(
            problem.residual(rigid, idx), begin, fixed={**fixed, **(extra or {})}, **opts
        )
        evaluations[0] += out.n_evaluations
        return out

    shaped = {"coulomb", *k_names, *c_names} & (set(fixed) | set(tied))
    search = multistart and n >= 1 and not shaped
    starts = [start] + ([spread_start(start, k_names)] if search and equal_breakaway else [])
    if len(starts) == 1:
        sol = solve(start)
    elif t.shape[0] > COARSE_SAMPLES:
        idx = np.unique(np.linspace(0, t.shape[0] - 1, COARSE_SAMPLES).round().astype(int))
        coarse = min((solve(s, idx=idx, tolerance=1e-6) for s in starts), key=cost)
        sol = solve(coarse.values if np.isfinite(cost(coarse)) else start)
    else:
        sol = min((solve(s) for s in starts), key=cost)
    sol = polish_initial_velocity(sol, solve, fixed, tied, v)
    if equal_breakaway and not (set(k_names) & (set(fixed) | set(tied))):
        sol = stiffest_first(sol, k_names)
    if search and sol.status == "converged":
        sol = rigid_check(sol, solve, problem, names, fixed, tied, level)
    sol = bound_check(sol, start, names, fixed, tied, equal_breakaway)
    sol = replace(sol, n_evaluations=evaluations[0])  # over every start and check
    mass_, c1, k, c, y0, v0 = problem.unpack(np.array([sol.values[x] for x in names]))
    ys, vs, ok = problem.sim(mass_, c1, k, c / k, y0, v0)
    model = PIFriction(c1, k, breakaway=c) if n else PIFriction(c1)
    note = ""
    if per_unit_mass:
        note = (
            "; the applied force is zero throughout, so mass and forces are determined only up "
            "to a common factor: they are reported per unit mass (mass = 1; forces in N/kg, "
            "stiffnesses in N/(m·kg)); give `mass` or `coulomb_level` to scale them"
        )
    if not ok and sol.status == "converged":
        sol = replace(sol, status="failed", message="the simulation failed at the optimum")
    sol = replace(sol, message=sol.message + note)
    derived = {"coulomb_level": model.coulomb_level} if not equal_breakaway else {}
    derived.update({f"threshold_{j + 1}": float(x) for j, x in enumerate(c / k)})
    if equal_breakaway and n:
        derived["breakaway_each"] = float(c[0])
    measured, fitted = (y, ys) if signal == "position" else (v, vs)
    return FitResult.from_solution(
        sol, model, t, measured, fitted, kind="output-error response",
        abscissa_label="time [s]", signal_label="position" if signal == "position" else "velocity",
        signal_unit="m" if signal == "position" else "m/s",
        units=_per_kg(names) if per_unit_mass else {},
        derived=derived,
    )  # fmt: skip


def _per_kg(names: list[str]) -> dict[str, str]:
    """Units of the parameters reported per unit mass."""
    per = {"mass": "1 (fixed)", "coulomb": "N/kg", "coulomb_level": "N/kg", "stiffness": "N/(m kg)",
           "breakaway": "N/kg"}  # fmt: skip
    return {x: per[x.split("_")[0] if x.startswith(("stiffness", "breakaway")) else x]
            for x in names if x.split("_")[0] in per or x in per}  # fmt: skip


def _check_model_values(
    fixed: dict[str, float], tied: dict[str, Tie], initial: Mapping[str, float] | None
) -> None:
    """Fixed and start values in the model's domain, ties of the model parameters positive.

    The mass, F_c, the stiffnesses and the break-away forces must be positive
    (the simulator has no element of zero stiffness or mass) and c1 >= 0.
    """

    def positive(x: object) -> bool:
        return x in ("mass", "coulomb_level") or (
            isinstance(x, str) and x.startswith(("stiffness_", "breakaway_"))
        )

    if initial is not None and not isinstance(initial, Mapping):
        raise TypeError(
            f"`initial` must be a mapping of parameter names to start values; "
            f"got {type(initial).__name__}."
        )
    for label, values in (("fixed", fixed), ("initial", initial or {})):
        for x, v in values.items():
            name = f"{label}[{x!r}]"
            if positive(x):
                as_positive_scalar(name, v)
            elif x == "coulomb":
                as_nonnegative_scalar(name, v)
            else:
                as_real_scalar(name, v)
    for x, spec in tied.items():
        if positive(x) and not isinstance(spec, str):
            as_positive_scalar(f"tied[{x!r}][1]", spec[1])


class _Problem:
    """Residual of the output-error fit for a parameter vector (all names, in order)."""

    def __init__(self, names, n, equal_breakaway, sim, weights, v, y):
        self.names, self.n, self.equal = names, n, equal_breakaway
        self.k_names = [f"stiffness_{j + 1}" for j in range(n)]
        self.c_names = [f"breakaway_{j + 1}" for j in range(n)]
        self.sim, self.weights, self.v, self.y = sim, weights, v, y

    def unpack(self, p: FloatArray, rigid: bool = False):
        """mass, c1, k, c, y0, v0; `rigid`: element 1 rigid-plastic (k_1 → ∞), c_1 joins c1."""
        tiny = np.finfo(float).tiny
        q = dict(zip(self.names, p, strict=True))
        c1 = max(q["coulomb"], 0.0)
        k = np.maximum([q[x] for x in self.k_names], tiny)
        if self.equal:
            c = np.full(self.n, max((q["coulomb_level"] - c1) / max(self.n, 1), tiny))
        else:
            c = np.maximum([q[x] for x in self.c_names], tiny)
        if rigid:
            c1, k, c = c1 + c[0], k[1:], c[1:]
        return max(q["mass"], tiny), c1, k, c, q["initial_position"], q["initial_velocity"]

    def residual(self, rigid: bool = False, idx=None):
        times = None if idx is None else self.sim.t[idx]
        data = (self.v, self.y) if idx is None else (self.v[idx], self.y[idx])

        def fun(p: FloatArray) -> FloatArray:
            mass, c1, k, c, y0, v0 = self.unpack(p, rigid)
            ys, vs, _ = self.sim(mass, c1, k, c / k, y0, v0, times)
            return np.concatenate(
                [w * (s - d) for w, s, d in zip(self.weights, (vs, ys), data, strict=True) if w]
            )

        return fun
