"""`fit_quasi_static` as a `FitProblem` and its parts of the pipeline (`_fit_engine`).

`check_quasi_static` applies the entry checks; `quasi_static_problem` builds
the record-pooled problem (`QuasiStaticProblem`) with the regression start
(`_quasi_static_start`), each record's start, F_c bounded below by the largest
applied force, and the user's `initial` and `bounds`. `quasi_static_plan`
gives the fit's own steps:

* search: the residual is far from convex in the records' preloads, in c1
  against the stiffest element, in the element split and in a density's length
  scale (its further starts move it by `DENSITY_SCALES` with F_m kept). The cheapest route
  first: the regression start solved once (the records' own starts fitted one
  by one first, `record_starts`); when it converged with every record within
  the floor rule (`_search.at_floor`) no further start runs. Otherwise the
  spread starts and the best of the global search, a few steps each; the best
  is refined, the records' own starts fitted again, then searched on the grid
  of the fit engine (`_nuisance_search`); a start whose short solve ended
  within `REFINE_WITHIN` of the best's cost in another basin is solved on to
  its own optimum (a second valley is reported, never hidden: `_alternatives`);
  then the element split is probed: from the best, a tenth of the smaller
  stiffness moved between neighbouring elements, both ways, each solved (the
  split is the least determined direction of the loops; another optimum that
  the profile's threshold does not exclude is reported, `_alternatives`), and
  so is its flattest direction, stepped far both ways (`_flat_probe`);
* refit: a preload fit far above the noise floor is fitted again from relaxed
  records and replaced where that fits clearly better (`_relaxed`: a relaxed
  memory is not on the branch of the preloads);
* checks: coalesced elements split, elements relabelled stiffest first, then a
  split of neighbouring elements the records do not determine made
  ``not_identifiable`` with its plateau in the intervals (`_split_check`: an
  element that never slides leaves only the sum of the stiffnesses);
* ``asymmetric=True``: the symmetric fit first, the asymmetric one from it
  (`_asymmetric_plan`; the parts it keeps: `asymmetric_parts`);
* result: the errors raised to the floor that runs of equal quantised samples
  imply (`_quasi_static_errors`: a record's initial position is fixed by its
  first samples alone), the model, the preloads as forces, the note of an F_c
  on its floor and the predictor.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import partial
from typing import Any

import numpy as np

from presliding._validation import as_bounds, as_choice, as_count, as_positive_scalar
from presliding.identification._fit_engine import FitPlan, FitRun, Found
from presliding.identification.checks._response_checks import (
    coalesced_split,
    cost,
    split_coalesced,
    spread_start,
    stiffest_first,
)
from presliding.identification.checks._split_check import undetermined_split
from presliding.identification.plans._asymmetric_plan import Parts
from presliding.identification.plans._quasi_static_result import level_floor, quasi_static_result
from presliding.identification.plans._response_setup import (
    MAX_BOOTSTRAP,
    check_model_values,
    check_quasi_static_records,
    record_starts,
)
from presliding.identification.problem._fit_options import (
    check_constraints,
    check_enough,
    check_options,
    element_count,
)
from presliding.identification.problem._fit_problem import FitOptions, FitProblem
from presliding.identification.problem._model_spec import DENSITIES, ModelSpec
from presliding.identification.problem._parameters import (
    check_flag,
    check_levels,
    check_sides,
    resolve_parameters,
)
from presliding.identification.records._creep_problem import CREEP, CreepQuasiStaticProblem
from presliding.identification.records._quasi_static_problem import QuasiStaticProblem
from presliding.identification.records._quasi_static_start import (
    CREEP_TIMES,
    creep_start,
    lift_density,
    quasi_static_start,
)
from presliding.identification.records._residual_blocks import pooled_adequacy
from presliding.identification.search._flat_probe import flat_probe
from presliding.identification.search._nuisance_search import search_nuisance
from presliding.identification.search._probes import other_valley, solve_probes, split_starts
from presliding.identification.search._search import (
    SAME_OPTIMUM,
    TIE,
    at_floor,
    global_start,
    same_point,
)
from presliding.identification.solve._least_squares import Solution
from presliding.measurement.measurement import Measurement

__all__ = ["STATES", "asymmetric_parts", "check_quasi_static", "quasi_static_plan",
           "quasi_static_problem"]  # fmt: skip

STATES = ("preload", "continuing", "relaxed")


@dataclass(frozen=True)
class QuasiStaticRequest:
    """The checked arguments of one `fit_quasi_static` call."""

    records: Any  # as given
    recs: list
    single: bool
    spec: ModelSpec
    initial_state: str
    offset: bool
    fmin: float
    initial: dict
    bounds: dict
    fixed: dict
    tied: dict
    bootstrap: int
    seed: int | None
    options: FitOptions
    creep: bool = False


def check_quasi_static(request: dict[str, Any]) -> QuasiStaticRequest:
    """Every argument of `fit_quasi_static` checked, in the order of its messages."""
    a = request
    recs = check_quasi_static_records(a["records"])
    initial_state = as_choice("initial_state", a["initial_state"], STATES)
    density = None if a["density"] is None else as_choice("density", a["density"], DENSITIES)
    n = element_count(a["n_elements"], None, 3)
    if n < 1:
        raise ValueError(f"`n_elements` must be at least 1 (the position needs elements); got {n}.")
    cells = as_count("density_cells", a["density_cells"], minimum=4)
    level, max_evaluations, tolerance = check_options(
        a["level"], a["max_evaluations"], a["tolerance"]
    )
    initial, bounds, fixed, tied = resolve_parameters(a["initial"], a["bounds"], a["fixed"],
                                                      a["tied"])  # fmt: skip
    check_levels(None, a["min_coulomb_level"], fixed)
    fixed, tied = check_constraints(fixed, tied)
    asymmetric = check_sides(a.get("asymmetric", False), a["offset"])
    spec = ModelSpec(n, a["equal_breakaway"], density, cells, asymmetric)
    check_model_values(spec, fixed, tied, initial)
    bootstrap = as_count("bootstrap", a["bootstrap"], maximum=MAX_BOOTSTRAP)
    fmin = 0.0 if a["min_coulomb_level"] is None else as_positive_scalar(
        "min_coulomb_level", a["min_coulomb_level"])  # fmt: skip
    options = FitOptions(level, max_evaluations, tolerance, max(tolerance**2, 1e-15),
                         a["progress"])  # fmt: skip
    return QuasiStaticRequest(
        a["records"], recs, isinstance(a["records"], Measurement), spec, initial_state,
        a["offset"], fmin, initial, bounds, fixed, tied, bootstrap, a["seed"], options,
        check_flag("creep", a.get("creep", False)),
    )  # fmt: skip


def _start_and_box(req: QuasiStaticRequest, records: QuasiStaticProblem) -> tuple[dict, dict]:
    """Start values and bounds of every parameter, in the order of the names."""
    names, spec, preload = records.names, req.spec, req.initial_state == "preload"
    start = quasi_static_start(req.recs, spec, req.offset)
    floor = level_floor(req, records)
    for i, rec in enumerate(req.recs):
        start[records.nuisance("initial_position", i)] = float(rec.position[0])
        if preload:
            start[records.nuisance("preload_fraction", i)] = 0.0
    for key, val in dict(req.initial or {}).items():
        if key not in names:
            raise ValueError(f"`initial` must name parameters of the fit; got {key!r}.")
        start[key] = float(val)
    if req.creep:
        start = {**creep_start(req.recs, spec, start), **start}
    start = {x: start[x] for x in names}
    box = {**spec.bounds(), "offset": (-np.inf, np.inf), **dict.fromkeys(CREEP, (0.0, np.inf))}
    for i in range(records.n_rec):
        box[records.nuisance("initial_position", i)] = (-np.inf, np.inf)
        if preload:
            box[records.nuisance("preload_fraction", i)] = (-1.0, 1.0)
    if spec.has_level_parameter and floor > 0:
        box["coulomb_level"] = (floor, np.inf)
        start["coulomb_level"] = max(start["coulomb_level"], floor * 1.01)
    if spec.negative is not None:  # F_c⁻ above the largest −u (and `min_coulomb_level`)
        below = max(req.fmin, records.u_sides[1] * (1 + 1e-9))
        box[spec.negative] = (below, np.inf)
        start[spec.negative] = max(start[spec.negative], below * 1.01)
    elif floor > 0:  # a density: F_c = c1 + F_m is derived; F_m is linear in the heights
        start = lift_density(spec, start, 1.2 * floor, req.fixed)
    for key, (lo, hi) in as_bounds("bounds", req.bounds, names).items():  # the user's, within
        old = box.get(key, (-np.inf, np.inf))
        box[key] = (max(old[0], lo), min(old[1], hi))
    return start, {x: box.get(x, (-np.inf, np.inf)) for x in names}


def quasi_static_problem(req: QuasiStaticRequest) -> tuple[FitProblem, FitOptions]:
    """The pooled quasi-static problem of a checked request, and its solves' options."""
    kind = CreepQuasiStaticProblem if req.creep else QuasiStaticProblem
    records = kind(req.recs, req.spec, req.initial_state, offset=req.offset,
                   suffix=not req.single)  # fmt: skip
    names = records.names
    check_enough(records.n_res, len(names) - len(req.fixed))
    start, box = _start_and_box(req, records)
    records.set_typical(start)
    options = req.options
    if options.max_evaluations is None:
        options = replace(options, max_evaluations=50 * len(names))
    problem = FitProblem(tuple(names), start, box, req.fixed, req.tied, records=records,
                         spec=req.spec, method="lm")  # fmt: skip
    return problem, options


def quasi_static_plan(req: QuasiStaticRequest) -> FitPlan:
    """The quasi-static fit's own steps (module notes)."""
    return FitPlan(
        search=partial(_search, req), checks=(partial(_split, req), partial(_plateau, req)),
        refit=partial(_relaxed, req), result=partial(quasi_static_result, req),
        bootstrap=req.bootstrap, seed=req.seed,
        adequacy=lambda run, sol: pooled_adequacy(run.problem, sol),
    )  # fmt: skip


def asymmetric_parts(req: QuasiStaticRequest) -> Parts:
    """The parts an asymmetric quasi-static fit keeps (`_asymmetric_plan`): the problem, its
    search, the elements relabelled stiffest first, and the result."""
    problem, options = quasi_static_problem(req)
    own = req.initial_state == "preload" and not any(
        x in problem.fixed or x in problem.tied for x in problem.names)  # fmt: skip
    prepare = partial(record_starts, problem.records) if own else None
    return Parts(problem, options, (partial(_relabel, req),), partial(quasi_static_result, req),
                 req.bootstrap, req.seed, prepare, partial(_search, req))  # fmt: skip


def _relabel(req: QuasiStaticRequest, run: FitRun, sol: Solution) -> Solution:
    """Elements of equal break-away force relabelled stiffest first."""
    spec = req.spec
    if spec.density is None and spec.equal and not _shaped(req) and sol.status != "failed":
        return stiffest_first(sol, spec.k_names)
    return sol


#: a relaxed start is kept where its cost is below this share of the best preload's
RELAXED_BETTER = 0.5


def _relaxed(req: QuasiStaticRequest, run: FitRun, sol: Solution) -> Any:
    """A preload fit far above the noise floor, fitted again from relaxed records; kept when
    it fits clearly better (`RELAXED_BETTER`), with a note.

    The preloads are memories on the branch from saturation (the record reverses at its
    preload): a record that starts relaxed (a new contact, its first loading on the virgin
    curve) is none of them, and its fit ended 38 times above the noise floor with a preload
    of −0.6 and an initial position 0.37 mm off where the truth is relaxed at 0 (torque loops
    of a uniform density)."""
    from presliding.identification._fit_engine import run_fit

    if req.initial_state != "preload" or at_floor(run.problem.records, sol):
        return None
    if not np.isfinite(cost(sol)):
        return None

    def own(given: dict) -> dict:
        return {x: v for x, v in given.items() if not x.startswith("preload_fraction")}

    other = replace(req, initial_state="relaxed", initial=own(req.initial),
                    bounds=own(req.bounds), fixed=own(req.fixed), tied=own(req.tied))  # fmt: skip
    run.stage("refit: the records started relaxed")
    problem, options = quasi_static_problem(other)
    result = run_fit(problem, options, quasi_static_plan(other))
    if not result.chisqr < RELAXED_BETTER * cost(sol):
        return None
    note = (f"the records start relaxed: that memory fits them {cost(sol) / result.chisqr:.3g} "
            "times better (in cost) than any preload on the branch from saturation, so the "
            "fit is that of initial_state='relaxed'")  # fmt: skip
    return replace(result, notes=(*result.notes, note),
                   n_evaluations=result.n_evaluations + run.evaluations)  # fmt: skip


def _shaped(req: QuasiStaticRequest) -> bool:
    """Whether an element's stiffness is fixed or tied (the element split is given)."""
    return bool(set(req.spec.k_names) & (set(req.fixed) | set(req.tied)))


def _starts(req: QuasiStaticRequest, run: FitRun) -> list[dict[str, float]]:
    """The further starts: spread ones (c1 against the stiffest element), the global one."""
    p, spec = run.problem, req.spec
    start = dict(p.initial)
    starts = [start]
    if spec.density is None and spec.equal and spec.n > 1 and not _shaped(req):
        spread = spread_start(start, spec.k_names)
        starts.append(spread)
        if "coulomb" not in p.fixed and "coulomb" not in p.tied:
            starts += [
                {**spread, "coulomb": share * spread["coulomb_level"]} for share in (0.1, 0.4)
            ]
    if spec.density is not None and not _density_shaped(req):
        starts += _density_starts(spec, start)
    if not p.tied:
        extra, count = global_start(p.records, start, p.fixed, p.bounds, keep=1)
        run.evaluations += count
        starts += [{x: e[x] for x in p.names} for e in extra]
    if req.creep and "creep_time" not in p.fixed and "creep_time" not in p.tied:
        starts += [{**start, "creep_time": start["creep_time"] * f} for f in CREEP_TIMES]
    return starts


#: factors of a density's length scale in its further starts (its F_m kept)
DENSITY_SCALES = (0.5, 2.0)


def _density_shaped(req: QuasiStaticRequest) -> bool:
    """Whether the density's length or heights are fixed or tied (its shape is given)."""
    return bool({x for x in req.spec.names if x != "coulomb"} & (set(req.fixed) | set(req.tied)))


def _density_starts(spec: ModelSpec, start: dict[str, float]) -> list[dict[str, float]]:
    """Starts along a density's length scale with its F_m kept (heights × 1/f²): the loops
    determine the virgin curve's reach poorly where the data do not reach the density's
    end, and the regression's start sat in the wrong valley of it."""
    length = "length" if spec.density == "exponential" else "max_threshold"
    heights = [x for x in spec.names if x.startswith("height")]
    out = []
    for f in DENSITY_SCALES:
        cand = dict(start)
        cand[length] = start[length] * f
        cand.update({x: start[x] / f**2 for x in heights})
        out.append(cand)
    return out


def _search(req: QuasiStaticRequest, run: FitRun) -> Found:
    """The starts (`_starts_search`), then the element split probed (module notes)."""
    found = _starts_search(req, run)
    spec, sol = req.spec, found.solution
    if spec.density is not None or not spec.equal or spec.n < 2 or _shaped(req):
        return found
    if not np.isfinite(cost(sol)):
        return found
    best, probes = solve_probes(run.problem.records, run.solve,
                                split_starts(sol.values, spec.k_names), sol)  # fmt: skip
    assert run.options.max_evaluations is not None
    best, flat = flat_probe(run.problem.records, run.solve, best, spec.k_names,
                            min(run.options.max_evaluations, 40))  # fmt: skip
    probes += flat
    at_best = sum(1 for t in probes if same_point(run.problem.records, t.values, best.values)
                  or cost(t) <= cost(best) * (1.0 + SAME_OPTIMUM))  # fmt: skip
    if best is sol:  # a probe that found a lower optimum leaves the starts' best behind
        at_best += found.n_starts_at_best
    return Found(best, found.n_starts + len(probes), at_best, found.search_evaluations)


def _starts_search(req: QuasiStaticRequest, run: FitRun) -> Found:
    """The cheapest route first, then further starts (module notes)."""
    p = run.problem
    own = req.initial_state == "preload" and not any(x in p.fixed or x in p.tied for x in p.names)

    def prepared(begin: dict[str, float]) -> dict[str, float]:
        return record_starts(p.records, begin) if own else begin

    first = run.solve(prepared(dict(p.initial)))
    if at_floor(p.records, first):
        return Found(first)
    starts = _starts(req, run)
    assert run.options.max_evaluations is not None
    short = min(run.options.max_evaluations, 40)
    tries = [first] + [run.solve(prepared(s), max_evaluations=short) for s in starts[1:]]
    best = min(tries, key=cost)
    sol = run.solve(prepared(best.values if np.isfinite(cost(best)) else dict(p.initial)))
    values, found, count = search_nuisance(p.records, sol.values, p.fixed, p.bounds)  # the grid
    if found < cost(sol) * (1.0 - SAME_OPTIMUM):
        again = run.solve(values)
        sol = again if cost(again) < cost(sol) else sol
    run.evaluations += count
    tries = [other_valley(p.records, run.solve, t, sol) for t in tries]
    best = min(tries, key=cost)
    sol = best if cost(best) < cost(sol) * (1.0 - TIE) else sol
    at_best = sum(1 for t in tries if same_point(p.records, t.values, sol.values)
                  or cost(t) <= cost(sol) * (1.0 + SAME_OPTIMUM))  # fmt: skip
    return Found(sol, len(tries), at_best, count)


def _split(req: QuasiStaticRequest, run: FitRun, sol: Solution) -> Solution:
    """Coalesced elements split, then relabelled stiffest first."""
    spec = req.spec
    if spec.density is None and spec.equal and not _shaped(req):
        sol = split_coalesced(sol, run.solve, spec.k_names)
        sol = stiffest_first(sol, spec.k_names)
        sol = coalesced_split(sol, run.solve, spec.k_names, run.options.level)
    return sol


def _plateau(req: QuasiStaticRequest, run: FitRun, sol: Solution) -> Solution:
    """A split of neighbouring elements the records do not determine (`_split_check`)."""
    spec = req.spec
    if spec.density is not None or not spec.equal or spec.n < 2 or _shaped(req):
        return sol
    return undetermined_split(sol, run.solve, spec.k_names)
