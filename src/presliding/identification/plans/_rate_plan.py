"""`fit_response(family=...)`: the pooled fit of GMS, LuGre or Dahl friction, as a `FitPlan`.

`check_rate` checks the arguments as for the PI model (`check_response`), refuses
those the family has no use for, and takes the family's parameters
(`_family_spec`); `rate_problem` builds the record-pooled problem (`RateProblem`:
the implicit step, ``substeps`` steps per sample interval) with its start and
bounds; `rate_plan` gives the fit's own steps:

* search: the PI model's fit of the same records, a batched grid of the rate
  parameters around it, and the adaptive multistart from the best candidates
  (`_rate_search`); the problem's own start (the PI regression start of
  `_pooled_start`, a drop of a fifth of F_C at a third of the records' typical speed, a
  lag of two sample intervals) stands in for the PI fit where the caller holds the
  elements' shape or turns the multistart off; v_s is bounded below by a thousandth of the
  records' typical speed (`SLOWEST`);
* checks: the engine's shared ones (bounds, records' own undetermined starts);
* result: the family's model (`GMSFriction`, `LuGreFriction`, `DahlFriction`), its
  static level as a derived value, and the predictor of held-out records.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from functools import partial
from typing import Any

import numpy as np

from presliding._validation import as_bounds, as_choice, as_count, as_nonnegative_scalar, fmt
from presliding.identification._fit_engine import FitPlan, FitRun, Found
from presliding.identification.plans._response_plan import held_starts
from presliding.identification.plans._response_request import ResponseRequest, check_response
from presliding.identification.plans._response_result import PER_UNIT_MASS, _per_kg
from presliding.identification.plans._response_setup import (
    check_model_values,
    initial_bounds,
    signal_weights,
)
from presliding.identification.problem._family_spec import FAMILIES, NONNEGATIVE, FamilySpec
from presliding.identification.problem._fit_options import check_enough
from presliding.identification.problem._fit_problem import FitOptions, FitProblem
from presliding.identification.problem._model_spec import ModelSpec
from presliding.identification.records._pooled_start import pooled_start
from presliding.identification.records._rate_problem import RateProblem
from presliding.identification.records._residual_blocks import pooled_adequacy
from presliding.identification.search._rate_search import (
    base_values,
    rate_search,
    sample_interval,
    typical_speed,
)
from presliding.identification.solve._least_squares import Solution, complete
from presliding.measurement.measurement import common_axis

__all__ = ["check_rate", "rate_plan", "rate_problem"]

#: steps of the implicit method per sample interval (`RateProblem`), unless given
SUBSTEPS = 4
#: the natural lower bound of v_s, over the records' typical speed: a Stribeck curve that
#: falls within a thousandth of the speeds measured is a step at rest, which its drop and
#: v_s cannot tell apart (v_s → 0 left both without a gradient, and the Jacobian garbage)
SLOWEST = 1e-3
#: the further preloads a held-out record's own start is solved from (`ResponsePredictor`)
PRELOADS = (-0.6, 0.0, 0.6)
#: options of `fit_response` the rate families refuse unless at their defaults
_PI_ONLY = {"density": None, "prune": False, "min_coulomb_level": None, "n_elements": 4,
            "equal_breakaway": True, "coulomb_level": None}  # fmt: skip
_ELEMENTS = ("n_elements", "equal_breakaway", "coulomb_level")  # GMS has elements
_PER_KG = {"stribeck_drop": "N/kg", "static_level": "N/kg", "static": "N/kg",
           "damping": "N s/(m kg)"}  # fmt: skip


def check_rate(request: dict[str, Any]) -> tuple[ResponseRequest, FamilySpec, int]:
    """Every argument of `fit_response(family=...)` checked; (the request as for the PI model,
    the family's parameters, substeps)."""
    family = as_choice("family", request["family"], ("pi", *FAMILIES))
    substeps = SUBSTEPS if request["substeps"] is None else as_count(
        "substeps", request["substeps"], minimum=1, maximum=1000)  # fmt: skip
    for name, default in _PI_ONLY.items():
        if family == "gms" and name in _ELEMENTS:
            continue
        value = request[name]
        if value is not default and value != default:
            raise ValueError(
                f"`{name}` is an option of the PI model's fit (family 'pi'"
                f"{', gms' if name in _ELEMENTS else ''}); got {fmt(value)} with family "
                f"{family!r}."
            )
    checked = check_response(request)
    spec = FamilySpec(family, checked.spec)
    check_model_values(spec, checked.fixed, checked.tied, checked.initial)
    for label, values in (("fixed", checked.fixed), ("initial", checked.initial)):
        for x in NONNEGATIVE:
            if x in values and x in spec.names:
                as_nonnegative_scalar(f"{label}[{x!r}]", values[x])
    return checked, spec, substeps


def rate_problem(req: ResponseRequest, spec: FamilySpec,
                 substeps: int) -> tuple[FitProblem, FitOptions]:  # fmt: skip
    """The pooled problem of a checked request, and the options of its solves."""
    recs = req.recs
    records = RateProblem(
        recs, spec, signal_weights(req.signal, recs, req.weights), req.initial_state,
        offset=req.offset, suffix=not req.single, viscous=req.viscous, velocity=req.velocity,
        substeps=substeps,
    )  # fmt: skip
    names, fixed = records.names, held_starts(req, records)
    check_enough(records.n_res, len(names) - len(fixed))
    pi_spec = spec.pi if spec.family == "gms" else ModelSpec(2, True, None, spec.cells)
    pi = pooled_start(recs, pi_spec, fixed.get("mass", None if req.forced else 1.0), req.offset,
                      req.viscous)  # fmt: skip
    fc = pi_spec.coulomb_level(pi)
    start = {**dict.fromkeys(names, 0.0), "stribeck_drop": 0.2 * fc,
             "stribeck_velocity": 0.3 * typical_speed(recs),
             "lag_time": 2.0 * sample_interval(recs)}  # fmt: skip
    start = base_values(spec, start, pi, pi_spec, set(names))
    for i, rec in enumerate(recs):
        start[records.nuisance("initial_position", i)] = float(rec.position[0])
        start[records.nuisance("initial_velocity", i)] = float(rec.velocity[0])
        if req.initial_state == "preload":
            start[records.nuisance("preload_fraction", i)] = (
                float(records.direction[i]) if rec.velocity[0] else 0.0)  # fmt: skip
    for key, val in req.initial.items():
        if key not in names:
            raise ValueError(f"`initial` must name parameters of the fit; got {key!r}.")
        start[key] = float(val)
    start.update({x: v for x, v in fixed.items() if x in names})
    box = {**spec.bounds(), "mass": (0.0, np.inf), "offset": (-np.inf, np.inf),
           "viscous": (0.0, np.inf), **initial_bounds(records, req.initial_state),
           "stribeck_velocity": (SLOWEST * typical_speed(recs), np.inf)}  # fmt: skip
    for key, (lo, hi) in as_bounds("bounds", req.bounds, names).items():
        old = box.get(key, (-np.inf, np.inf))
        box[key] = (max(old[0], float(lo)), min(old[1], float(hi)))
    start = {x: float(np.clip(start[x], *box.get(x, (-np.inf, np.inf)))) for x in names}
    records.set_typical(start)
    budget = 50 * len(names) if req.max_evaluations is None else req.max_evaluations
    options = FitOptions(req.level, budget, req.tolerance, max(req.tolerance**2, 1e-15),
                         req.progress)  # fmt: skip
    problem = FitProblem(
        tuple(names), start, {x: box.get(x, (-np.inf, np.inf)) for x in names}, fixed,
        req.tied, records=records, spec=spec, method="lm" if records.n_rec > 1 else "auto",
    )  # fmt: skip
    return problem, options


def rate_plan(req: ResponseRequest, spec: FamilySpec, pi_fit: Callable[..., Any]) -> FitPlan:
    """The rate family fit's own steps (module notes); `pi_fit` is `fit_response` (the PI
    model's fit that starts a GMS fit's elements)."""
    return FitPlan(search=partial(_search, req, spec, pi_fit),
                   result=partial(_result, req, spec), bootstrap=req.bootstrap,
                   seed=req.seed,
                   adequacy=lambda run, sol: pooled_adequacy(run.problem, sol))  # fmt: skip


def _search(req: ResponseRequest, spec: FamilySpec, pi_fit: Callable[..., Any],
            run: FitRun) -> Found:  # fmt: skip
    """The PI fit, the grid of the rate parameters, the adaptive multistart (`_rate_search`)."""
    p = run.problem
    run.stage(f"least squares ({spec.family}): {p.records.n_rec} record(s), "
              f"{len(p.names) - len(p.fixed)} free parameters")  # fmt: skip
    sol, n_starts, at_best, count = rate_search(req, spec, pi_fit, run)
    run.evaluations += count
    return Found(complete(sol), n_starts, at_best, count)


def _result(req: ResponseRequest, spec: FamilySpec, run: FitRun, sol: Solution, boot: Any,
            summary: Any) -> Any:  # fmt: skip
    """The public result: the family's model, derived values, notes, predictor."""
    from presliding.identification.fit_result import FitResult
    from presliding.identification.plans._predictors import ResponsePredictor

    problem = run.problem.records
    values = sol.values
    o_y, o_v, status, _ = problem.simulate(np.array([values[x] for x in problem.names]))
    if not (np.all(status == 0) and np.all(np.isfinite(o_v))) and sol.status == "converged":
        sol = replace(sol, status="failed", message="the simulation failed at the optimum")
    if req.per_unit_mass:
        sol = replace(sol, message=f"{sol.message}; {PER_UNIT_MASS}")
    derived = spec.derived(values)
    position = req.signal == "position"
    measured = np.concatenate([(r.position if position else r.velocity) for r in problem.records])
    units = {x: "1" for x in problem.names if x.startswith("preload_fraction")}
    if req.per_unit_mass:
        units.update(_per_kg([*problem.names, *derived]))
        units.update({x: u for x, u in _PER_KG.items() if x in values or x in derived})
    result = FitResult.from_solution(
        sol, spec.model(values), problem.t_all, measured, o_y[0] if position else o_v[0],
        kind=f"output-error response ({spec.family})", abscissa_label="time [s]",
        signal_label="position" if position else "velocity",
        signal_unit="m" if position else "m/s", units=units, derived=derived,
    )  # fmt: skip
    spans = tuple(zip(problem.t_off[:-1].tolist(), problem.t_off[1:].tolist(), strict=True))
    notes = (PER_UNIT_MASS,) if req.per_unit_mass else ()
    return replace(
        result, records=spans if problem.n_rec > 1 else (), bootstrap=boot, notes=notes,
        predictor=ResponsePredictor(problem, values, PRELOADS), search=summary,
    ).on_axis(common_axis(req.records))  # fmt: skip
