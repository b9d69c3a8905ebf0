"""The arguments of `fit_response`, checked on entry into one `ResponseRequest`.

`check_response` applies every rule of the entry checks in the order the
users' error messages have always followed (records and signals, choices,
element counts, parameter arguments against each other, model values), and
returns the arguments as the fit uses them: the model as a `ModelSpec`,
`fixed` completed with the known mass, F_c and (free records only) the unit
mass of a per-unit-mass fit. `order_options` gives the options of the
``n_elements="auto"`` search (`_model_order`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from presliding._validation import as_choice, as_count, as_positive_scalar, fmt
from presliding.identification.plans._response_setup import (
    MAX_BOOTSTRAP,
    check_model_values,
    check_records,
)
from presliding.identification.problem._fit_options import (
    check_constraints,
    check_options,
    element_count,
)
from presliding.identification.problem._model_spec import DENSITIES, ModelSpec
from presliding.identification.problem._parameters import (
    check_flag,
    check_levels,
    check_sides,
    resolve_parameters,
)
from presliding.measurement.measurement import Measurement

__all__ = ["SIGNALS", "STATES", "ResponseRequest", "check_response", "order_options"]

SIGNALS = ("velocity", "position", "both")
STATES = ("saturated", "preload", "relaxed")
#: the arguments `n_elements="auto"` passes on to each order's fit as given
_PASSED = ("records", "equal_breakaway", "mass", "coulomb_level", "min_coulomb_level",
           "viscous", "offset", "signal", "velocity", "weights", "initial_state", "fit_initial",
           "bounds", "bootstrap", "seed", "level", "max_evaluations", "tolerance", "multistart",
           "progress")  # fmt: skip


@dataclass(frozen=True)
class ResponseRequest:
    """The checked arguments of one `fit_response` call."""

    records: Any  # as given (a Measurement or a sequence of them)
    asymmetric: bool
    recs: list  # as `_pooled_problem.Record`
    single: bool
    spec: ModelSpec
    signal: str
    velocity: str
    initial_state: str
    mass: float | None
    coulomb_level: float | None  # None when n_elements=0 turned it into a fixed c1
    min_coulomb_level: float | None
    fmin: float | None
    viscous: bool
    offset: bool
    weights: Any
    fit_initial: bool
    multistart: bool
    prune: bool
    bootstrap: int
    seed: int | None
    level: float
    max_evaluations: int | None
    tolerance: float
    initial: dict
    bounds: dict
    fixed: dict  # completed (module notes)
    tied: dict
    given: dict  # the user's fixed, tied and bounds (for a refit without elements)
    forced: bool
    per_unit_mass: bool
    progress: Any


def order_options(request: dict[str, Any]) -> dict[str, Any]:
    """The options of each order's fit under ``n_elements="auto"`` (element names vary
    with N, so their entries of `initial`, `fixed` and `tied` are left out)."""
    if request["n_elements"] != "auto":
        raise ValueError(f"`n_elements` must be a count or 'auto'; got {request['n_elements']!r}.")
    if request["density"] is not None:
        raise ValueError("`n_elements='auto'` chooses a number of elements; got a density.")
    out = {x: request[x] for x in _PASSED}
    for label in ("initial", "fixed", "tied"):
        out[label] = {x: v for x, v in dict(request[label] or {}).items()
                      if not x.startswith(("stiffness_", "breakaway_"))}  # fmt: skip
    return out


def _model(request: dict[str, Any]) -> tuple[ModelSpec, dict[str, Any]]:
    """The model's arguments checked: the spec and the arguments as they now stand."""
    a = dict(request)
    if a["density"] is not None:
        a["density"] = as_choice("density", a["density"], DENSITIES)
    cells = as_count("density_cells", a["density_cells"], minimum=4)
    n = element_count(a["n_elements"], None, 4)
    if a["density"] == "piecewise_constant" and n < 1:
        raise ValueError(f"`n_elements` (the cells of the density) must be >= 1; got {n}.")
    if n == 0 and a["density"] is None:  # Coulomb (+ viscous) friction: F_c = c1, one parameter
        a["equal_breakaway"] = False
        if a["coulomb_level"] is not None:
            level = as_positive_scalar("coulomb_level", a["coulomb_level"])
            a["fixed"] = {**dict(a["fixed"] or {}), "coulomb": level}
            a["coulomb_level"] = None
    if a["coulomb_level"] is not None and (not a["equal_breakaway"] or a["density"] is not None):
        raise ValueError(
            "`coulomb_level` can be given only with equal_breakaway=True and elements; got "
            + ("a density." if a["density"] else "equal_breakaway=False.")
        )
    asymmetric = check_sides(a.get("asymmetric", False), a["offset"])
    return ModelSpec(n, a["equal_breakaway"], a["density"], cells, asymmetric), a


def _known(a: dict[str, Any], fixed: dict[str, float], recs: list) -> tuple[Any, bool, bool]:
    """`fixed` completed with the known mass and F_c; (F_min, forced, per unit mass)."""
    if a["mass"] is not None:
        fixed["mass"] = as_positive_scalar("mass", a["mass"])
    if a["coulomb_level"] is not None:
        fixed["coulomb_level"] = as_positive_scalar("coulomb_level", a["coulomb_level"])
    fmin = None if a["min_coulomb_level"] is None else as_positive_scalar(
        "min_coulomb_level", a["min_coulomb_level"])  # fmt: skip
    forced = any(r.forced for r in recs)
    per_unit_mass = not forced and not ({"mass", "coulomb_level"} & set(fixed))
    if per_unit_mass:
        fixed["mass"] = 1.0
    return fmin, forced, per_unit_mass


def check_response(request: dict[str, Any]) -> ResponseRequest:
    """Every argument of `fit_response` checked (module notes)."""
    recs = check_records(request["records"], request["signal"], SIGNALS, request["velocity"])
    signal = as_choice("signal", request["signal"], SIGNALS)
    initial_state = as_choice("initial_state", request["initial_state"], STATES)
    spec, a = _model(request)
    level, max_evaluations, tolerance = check_options(
        a["level"], a["max_evaluations"], a["tolerance"]
    )
    initial, bounds, fixed, tied = resolve_parameters(
        a["initial"], a["bounds"], a["fixed"], a["tied"],
        {"mass": a["mass"], "coulomb_level": a["coulomb_level"]},
    )  # fmt: skip
    check_levels(a["coulomb_level"], a["min_coulomb_level"], fixed)
    prune = check_flag("prune", a["prune"])
    fixed, tied = check_constraints(fixed, tied)
    given = {"fixed": dict(fixed), "tied": dict(tied), "bounds": bounds or {}}
    check_model_values(spec, fixed, tied, initial)
    bootstrap = as_count("bootstrap", a["bootstrap"], maximum=MAX_BOOTSTRAP)
    fmin, forced, per_unit_mass = _known(a, fixed, recs)
    fc = fixed.get("coulomb_level")
    if spec.has_level_parameter and spec.n and fc is not None and fixed.get("coulomb", 0.0) >= fc:
        raise ValueError(
            f"`fixed['coulomb']` must be less than the Coulomb level {fmt(fc)} (else no force is "
            f"left for the elements); got {fmt(fixed['coulomb'])}."
        )
    return ResponseRequest(
        records=a["records"], asymmetric=spec.negative is not None, recs=recs,
        single=isinstance(a["records"], Measurement),
        spec=spec, signal=signal, velocity=request["velocity"], initial_state=initial_state,
        mass=a["mass"],
        coulomb_level=a["coulomb_level"], min_coulomb_level=a["min_coulomb_level"], fmin=fmin,
        viscous=a["viscous"], offset=a["offset"], weights=a["weights"],
        fit_initial=a["fit_initial"], multistart=a["multistart"], prune=prune,
        bootstrap=bootstrap, seed=a["seed"], level=level, max_evaluations=max_evaluations,
        tolerance=tolerance, initial=initial, bounds=bounds, fixed=fixed, tied=tied,
        given=given, forced=forced, per_unit_mass=per_unit_mass, progress=a["progress"],
    )  # fmt: skip
