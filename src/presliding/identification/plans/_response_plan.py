"""`fit_response` as a `FitProblem` and its parts of the pipeline (`_fit_engine`).

`response_problem` builds the record-pooled problem of a checked
`ResponseRequest`: the records' layout (`PooledProblem`), the start values and
bounds (`_response_box`), each record's start held where it is not fitted, and
the options. `response_plan` gives the fit's own steps:

* search: the adaptive multistart of `_search` (the regression start, the
  records that do not fit, then the spread start and the best of the cheap
  global search, made only when reached), on the exact simulated velocity;
  where a record's velocity is the difference quotient of its position the
  optimum is then polished comparing that quotient (`_pooled_problem`). The
  search's floor rule and starts were set on the exact comparison: with the
  quotient it stopped in a basin 5–7 % above the optimum (the rule allows
  3 × the floor) on seeds where the exact one went on to the optimum;
  the polish moves the parameters only by the quotient's bias. A pooled fit
  then probes the neighbouring valleys from the best optimum (`_probes`: the
  elements coalesced, where the best is above the floor or holds elements that never
  slide; an element that never engaged re-engaged and the rigid corner left, where the
  best has such an element; each a short solve of `PROBE_EVALUATIONS`, solved on when
  it ends near the best). Where the best is not known to be the optimum
  (`_probe_gate`: above the noise floor, starts that ended apart, or a search
  whose solve stopped short of a minimum), it moves the element split, steps
  along eq. 17's scale, the mass and every force scaled together with every
  record's block searched again (`_scale_probe`), and last takes a far step
  both ways along the least determined split of the stiffnesses
  (`_flat_probe`): the starts all derive from one regression start and can
  miss a valley next to the one they reach. The probes' solves defer their
  covariance (`_deferred`); the best one's is computed once;
* checks: the rigid corner, the Coulomb corner (c1 ≥ F_c: the elements carry
  nothing) and coalesced elements, the start from rest of a single record,
  interchangeable elements relabelled, the rigid limit of the smallest-threshold
  element, and two elements still coalesced after all that
  (their split checked, `coalesced_split`) (`_response_checks`);
* refit: with ``prune=True``, the fit again without the elements that never
  slide (one refit, from this optimum);
* result: the model, derived values, notes and predictor
  (`_response_result`).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import nullcontext
from dataclasses import dataclass, replace
from functools import partial
from typing import Any

import numpy as np

from presliding.identification._fit_engine import FitPlan, FitRun, Found
from presliding.identification.checks._response_checks import (
    coalesced_split,
    escape_corner,
    escape_coulomb,
    polish_initial_velocity,
    rigid_check,
    smallest_threshold_first,
    split_coalesced,
    spread_start,
    stiffest_first,
)
from presliding.identification.judge._adequacy import LEVEL
from presliding.identification.judge._noise_floor import floor_ratios
from presliding.identification.judge._status import OPTIMUM
from presliding.identification.plans._asymmetric_plan import Parts
from presliding.identification.plans._response_box import start_and_box
from presliding.identification.plans._response_request import ResponseRequest
from presliding.identification.plans._response_result import PER_UNIT_MASS, response_result
from presliding.identification.plans._response_setup import (
    DROPS,
    LEFT,
    prune_elements,
    signal_weights,
)
from presliding.identification.problem._fit_options import check_enough
from presliding.identification.problem._fit_problem import FitOptions, FitProblem
from presliding.identification.problem._parameters import kept_parameters
from presliding.identification.records import _pooled_problem as pp
from presliding.identification.records._residual_blocks import pooled_adequacy
from presliding.identification.search._flat_probe import flat_probe
from presliding.identification.search._probe_gate import needs_probes, predicted_decrease
from presliding.identification.search._probes import (
    corner_starts,
    engage_starts,
    merge_starts,
    solve_probes,
    split_starts,
)
from presliding.identification.search._scale_probe import scale_probe, scaled_names
from presliding.identification.search._search import (
    FLOOR_FACTOR,
    SAME_OPTIMUM,
    adaptive_search,
    cost,
    exact_velocity_stands_in,
    global_start,
    same_point,
)
from presliding.identification.solve._least_squares import LARGE_PROBLEM, Solution, complete
from presliding.identification.solve._structured_lm import on_one_blas_thread
from presliding.measurement.measurement import common_axis

__all__ = ["asymmetric_parts", "held_starts", "response_plan", "response_problem"]

#: evaluations of a probe's short solve (`_probes`; solved on when it ends near the best)
PROBE_EVALUATIONS = 40
#: evaluations of the rigid-limit refit of a large pooled problem (an upper bound of its
#: cost suffices to flag the rigid corner; the refit starts at the optimum)
RIGID_EVALUATIONS = 30
#: evaluations after which that refit is judged: one still far above the optimum ends there
#: (`_response_checks.CLEAR`)
RIGID_JUDGE = 10


def held_starts(req: ResponseRequest, records: Any) -> dict[str, float]:
    """`fixed` with each record's start held at its first sample where it is not fitted
    (``fit_initial=False``; the position when only the velocity is compared)."""
    fixed = dict(req.fixed)
    for i, rec in enumerate(req.recs):
        if not req.fit_initial:
            fixed.setdefault(records.nuisance("initial_velocity", i), float(rec.velocity[0]))
        if not req.fit_initial or req.signal == "velocity":
            fixed.setdefault(records.nuisance("initial_position", i), float(rec.position[0]))
    return fixed


def response_problem(req: ResponseRequest) -> tuple[FitProblem, FitOptions]:
    """The pooled problem of a checked request, and the options of its solves."""
    spec, recs = req.spec, req.recs
    records = pp.PooledProblem(
        recs, spec, signal_weights(req.signal, recs, req.weights), req.initial_state,
        offset=req.offset, suffix=not req.single, viscous=req.viscous, velocity=req.velocity,
    )  # fmt: skip
    names, fixed = records.names, held_starts(req, records)
    check_enough(records.n_res, len(names) - len(fixed))
    start, box = start_and_box(records, spec, recs, fixed, req.forced, req.offset, req.viscous,
                               req.initial_state, req.initial, req.bounds, req.fmin)  # fmt: skip
    records.set_typical(start)
    penalty = None if req.fmin is None or spec.has_level_parameter else req.fmin
    budget = 50 * len(names) if req.max_evaluations is None else req.max_evaluations
    options = FitOptions(req.level, budget, req.tolerance, max(req.tolerance**2, 1e-15),
                         req.progress)  # fmt: skip
    problem = FitProblem(
        tuple(names), start, box, fixed, req.tied, records=records, spec=spec, penalty=penalty,
        method="lm" if records.n_rec > 1 else "auto",
    )  # fmt: skip
    return problem, options


def asymmetric_parts(req: ResponseRequest) -> Parts:
    """The parts an asymmetric response fit keeps (`_asymmetric_plan`): the problem, its
    search, the relabelling of interchangeable elements and the result."""
    problem, options = response_problem(req)
    assert options.max_evaluations is not None
    search = partial(_search, req, _flags(req, problem, options.max_evaluations))
    return Parts(problem, options, (partial(_relabel, req),), partial(_result, req),
                 req.bootstrap, req.seed, search=search)  # fmt: skip


@dataclass(frozen=True)
class _Flags:
    """Which searches and checks a response fit runs."""

    discrete_equal: bool  # elements of equal break-away force
    search: bool  # multistart, with c1 and the elements free
    large: bool  # rigid refits capped
    short: int  # evaluations of a further start's short solves


def _flags(req: ResponseRequest, p: FitProblem, budget: int) -> _Flags:
    spec, rec = req.spec, p.records
    shaped = set(spec.names) & (set(p.fixed) | set(p.tied))
    discrete_equal = spec.density is None and spec.equal and spec.n >= 1
    search = req.multistart and spec.density is None and spec.n >= 1 and not (
        {"coulomb", *spec.k_names, *spec.c_names} & shaped)  # fmt: skip
    free = len(p.names) - len(p.fixed)
    large = rec.n_rec > 1 or rec.n_res * free**2 > LARGE_PROBLEM
    return _Flags(discrete_equal, search, large, min(budget, 12 + 2 * len(rec.shared)))


def response_plan(req: ResponseRequest, problem: FitProblem, options: FitOptions,
                  refit_with: Callable[..., Any]) -> FitPlan:  # fmt: skip
    """The response fit's own steps (module notes); `refit_with` is `fit_response`."""
    assert options.max_evaluations is not None
    flags = _flags(req, problem, options.max_evaluations)
    return FitPlan(
        search=partial(_search, req, flags),
        checks=(partial(_corner_checks, req, flags), partial(_relabel, req),
                partial(_rigid_limit, flags), partial(_coalesced, req, flags)),
        refit=partial(_prune, req, refit_with), result=partial(_result, req),
        bootstrap=req.bootstrap, seed=req.seed,
        adequacy=lambda run, sol: pooled_adequacy(run.problem, sol),
    )  # fmt: skip


@on_one_blas_thread
def _search(req: ResponseRequest, flags: _Flags, run: FitRun) -> Found:
    """The adaptive multistart (`_search.adaptive_search`)."""
    p = run.problem
    rec, start, k_names = p.records, p.initial, req.spec.k_names
    run.stage(f"least squares: {rec.n_rec} record(s), {len(p.names) - len(p.fixed)} free "
              "parameters")  # fmt: skip

    def more_starts() -> Iterator[tuple[dict[str, float], int]]:
        """The further shared starts, made only when the search reaches them."""
        if flags.search and flags.discrete_equal:
            yield spread_start(dict(start), k_names), 0
        if req.multistart and not p.tied:
            run.stage("search: the shared parameters' global start")
            extra, spent = global_start(rec, start, p.fixed, p.bounds)
            for j, e in enumerate(extra):
                yield {x: e[x] for x in p.names}, spent if j == 0 else 0

    run.stage("search: the regression start, then the records that do not fit")
    polish = bool(rec.w_v and any(r.difference for r in rec.records))
    polish = polish and exact_velocity_stands_in(rec, start)
    with rec.exact_velocity_compared() if polish else nullcontext():  # no errors if polished
        sol, n_starts, at_best, count = adaptive_search(rec, run.solve, start, more_starts,
                                                        p.fixed, p.bounds, flags.short,
                                                        errors=not polish)  # fmt: skip
    run.evaluations += count
    searched = sol
    if polish and sol.status != "failed":
        run.stage("search: the optimum polished with the velocity's difference quotient")
        polished = run.solve(sol.values)
        sol = polished if polished.status != "failed" else sol
    sol = complete(sol)
    if flags.search and flags.discrete_equal and rec.n_rec > 1 and _elements_carry(sol):
        run.stage("search: probes of the neighbouring valleys from the best optimum")
        with rec.exact_velocity_compared() if polish else nullcontext():  # the search's own
            decrease = predicted_decrease(sol, searched.values)  # cost, where its solve ended
        sol, n_starts, at_best, short = _probe(req, run, sol, n_starts, at_best, decrease)
        return Found(sol, n_starts, at_best, count, lower_unsolved=short)
    return Found(sol, n_starts, at_best, count)


def _elements_carry(sol: Solution) -> bool:
    """Whether the search ended at an optimum (not on the evaluation cap) where the elements
    carry force (c1 below F_c): otherwise their stiffnesses do not enter the residual and
    the probes' moves have no meaning."""
    v = sol.values
    at_optimum = sol.status in ("converged", "not_identifiable", "at_bound")  # not a cap
    return at_optimum and v.get("coulomb", 0.0) < v.get("coulomb_level", np.inf)


def _probe(req: ResponseRequest, run: FitRun, sol: Solution, n_starts: int, at_best: int,
           decrease: float) -> tuple[Solution, int, int, bool]:  # fmt: skip
    """The probes of `_probes` from the best optimum: an element that never engaged
    re-engaged and the rigid corner left (each solved on when it ends near the best); then,
    where the best is not known to be the optimum (`_probe_gate.needs_probes`, `decrease`
    the Gauss–Newton decrease where the search's solve ended), the valleys' probes
    (`_valley_probes`); then, where the best still fails the residual tests or sits far
    above the floor, the elements coalesced (`_merged`; from a lower optimum there, the
    engage and corner probes again). Last: whether a coalesced start went below the best
    but its solve stopped short of an optimum (the best is then kept, and a better optimum
    of this model is known to exist: ``local_minimum``)."""
    p, k_names = run.problem, req.spec.k_names
    assert run.options.max_evaluations is not None
    budget = min(PROBE_EVALUATIONS, run.options.max_evaluations)  # the user's cap holds
    solve = partial(run.solve, errors=False)  # errors only for the best (`complete`)
    moved = engage_starts(sol.values, k_names) + corner_starts(sol.values, k_names)
    best, probes = solve_probes(p.records, solve, moved, sol, budget)
    best = complete(best)
    if needs_probes(p.records, best, best is sol and at_best == n_starts, decrease):
        best, probes = _valley_probes(req, run, solve, sol, best, probes, budget)
    merged, more = solve_probes(p.records, solve, _merged(req, run, best), best, budget)
    probes += more
    short = merged is not best and merged.status not in OPTIMUM
    if merged is not best and not short:  # the coalesced valley: its dead elements engaged
        moved = engage_starts(merged.values, k_names) + corner_starts(merged.values, k_names)
        best, again = solve_probes(p.records, solve, moved, merged, budget)
        probes += again
    at = sum(1 for t in probes if same_point(p.records, t.values, best.values)
             or cost(t) <= cost(best) * (1.0 + SAME_OPTIMUM))  # fmt: skip
    return complete(best), n_starts + len(probes), at + (at_best if best is sol else 0), short


def _merged(req: ResponseRequest, run: FitRun, sol: Solution) -> list[dict[str, float]]:
    """The coalesced elements' starts (`_probes.merge_starts`), where the best is above the
    noise floor, or holds elements that never slide in the data (break-away force that may
    never act) with a record above `_adequacy.LEVEL` times its floor (the level test's
    bound) and residuals that fail the tests (`pooled_adequacy`; a best that passes them is
    left alone: its probes would cost more than its search): a model with more elements
    than the data need contains the coalesced one."""
    rec = run.problem.records
    ratios, pooled = floor_ratios(rec, sol.residual)  # whatever the solve's status said
    if pooled <= FLOOR_FACTOR and np.all(ratios <= LEVEL):
        return []
    pruned = prune_elements(rec, sol, req.spec)
    if not pruned.dead and pooled <= FLOOR_FACTOR and np.all(ratios <= FLOOR_FACTOR):
        return []
    if pooled <= FLOOR_FACTOR and np.all(ratios <= FLOOR_FACTOR):  # near the floor: only
        tested = pooled_adequacy(run.problem, sol)  # where the residual tests would fail
        if tested is None or tested.passed:
            return []
    live = [j for j in range(req.spec.n) if j not in pruned.dead]
    return merge_starts(sol.values, req.spec.k_names, live, pruned.reachable)


def _valley_probes(req: ResponseRequest, run: FitRun, solve: Callable[..., Solution],
                   sol: Solution, best: Solution, probes: list[Solution],
                   budget: int) -> tuple[Solution, list[Solution]]:  # fmt: skip
    """The probes a best that is not known to be the optimum needs (`_probe_gate`): the
    element split moved, the steps along eq. 17's scale, the far step along the least
    determined split."""
    p, k_names = run.problem, req.spec.k_names
    best, split = solve_probes(p.records, solve, split_starts(sol.values, k_names), best,
                               budget, within=1.0)  # fmt: skip
    probes += split
    names = scaled_names(p.records, p.fixed, p.tied)
    if names:  # along eq. 17's scale, every record's block searched again (`_scale_probe`)
        before = best
        best, steps, spent = scale_probe(p.records, solve, best, names, p.fixed, p.bounds,
                                         budget, tied=p.tied)  # fmt: skip
        run.evaluations += spent
        probes += steps
        if best is not before:  # the true scale's valley can hold an element not engaged
            moved = engage_starts(best.values, k_names) + corner_starts(best.values, k_names)
            best, again = solve_probes(p.records, solve, moved, best, budget)
            probes += again
    best, flat = flat_probe(p.records, solve, complete(best), k_names, budget)  # needs H
    return best, probes + flat


def _corner_checks(req: ResponseRequest, flags: _Flags, run: FitRun, sol: Solution) -> Solution:
    """The rigid corner and coalesced elements; a single record's start from rest."""
    k_names = req.spec.k_names
    if flags.search and flags.discrete_equal:
        run.stage("checks: a rigid stiffest element, coalesced elements")
        sol = escape_corner(sol, run.solve, k_names)
        sol = escape_coulomb(sol, run.solve, k_names)
        sol = split_coalesced(sol, run.solve, k_names)
    if req.single:
        p = run.problem
        sol = polish_initial_velocity(sol, run.solve, p.fixed, p.tied, req.recs[0].velocity)
    return sol


def _relabel(req: ResponseRequest, run: FitRun, sol: Solution) -> Solution:
    """Interchangeable elements in their order (stiffest, or smallest threshold, first)."""
    spec, p = req.spec, run.problem
    labelled = (set(spec.k_names) | set(spec.c_names)) & (set(p.fixed) | set(p.tied))
    if spec.density is None and spec.equal and spec.n >= 1 and not labelled:
        return stiffest_first(sol, spec.k_names)
    if spec.density is None and not spec.equal and not labelled and sol.status != "failed":
        return smallest_threshold_first(sol, spec.k_names, spec.c_names)
    return sol


def _rigid_limit(flags: _Flags, run: FitRun, sol: Solution) -> Solution:
    """The rigid limit of the smallest-threshold element (`rigid_check`)."""
    if not (flags.search and sol.status == "converged"):
        return sol
    run.stage("check: the rigid limit of the smallest-threshold element")
    p = run.problem
    # the capped refits' covariance only where they flag the corner (`rigid_check`)
    capped = (lambda *a, **k: run.solve(*a, max_evaluations=RIGID_EVALUATIONS, errors=False,
                                        **k)) if flags.large else run.solve  # fmt: skip
    judge = (lambda *a, **k: run.solve(*a, max_evaluations=RIGID_JUDGE, errors=False, **k)) \
        if flags.large and RIGID_JUDGE < RIGID_EVALUATIONS else None  # fmt: skip
    return rigid_check(sol, capped, p.records, p.names, p.fixed, p.tied, run.options.level,
                       refine=run.solve if flags.large else None, judge=judge)  # fmt: skip


def _coalesced(req: ResponseRequest, flags: _Flags, run: FitRun, sol: Solution) -> Solution:
    """Two elements of equal break-away force still coalesced: their split checked
    (`_response_checks.coalesced_split`)."""
    if not (flags.search and flags.discrete_equal):
        return sol
    return coalesced_split(sol, run.solve, req.spec.k_names, run.options.level)


def _prune(req: ResponseRequest, refit_with: Callable[..., Any], run: FitRun,
           sol: Solution) -> Any:  # fmt: skip
    """With ``prune=True``: the fit again without the elements that never slide.

    One refit, from this optimum without them (`Pruning.start`: the model's force while
    sliding kept), whose search stops at the floor where this fit was. An element that
    never slides at the refit's optimum in turn is kept and its note says so (`LEFT`): the
    model returned has exactly the elements the notes leave. The fit's evaluations are the
    sum of both.
    """
    spec, rec = req.spec, run.problem.records
    pruned = prune_elements(rec, sol, spec)
    kept = spec.n - len(pruned.dead)
    if not (req.prune and pruned.dead and spec.density is None and kept >= 0):
        return None
    options = run.options
    run.stage(f"refit without {len(pruned.dead)} element(s) that never slide")
    refit = refit_with(
        req.records, n_elements=kept, equal_breakaway=spec.equal, mass=req.mass,
        coulomb_level=req.coulomb_level, min_coulomb_level=req.min_coulomb_level,
        offset=req.offset, viscous=req.viscous, signal=req.signal, weights=req.weights,
        initial_state=req.initial_state, fit_initial=req.fit_initial, level=options.level,
        max_evaluations=options.max_evaluations, tolerance=options.tolerance,
        multistart=req.multistart, bootstrap=req.bootstrap, seed=req.seed,
        initial=pruned.start(sol.values, rec), progress=options.progress,
        **kept_parameters(req.given, kept),
    )  # fmt: skip
    note = pruned.note(spec) + "; refitted without them"
    left = tuple(n.replace(DROPS, LEFT) for n in refit.notes)  # the refit's own: kept
    return replace(refit, notes=(note, *left),
                   n_evaluations=refit.n_evaluations + run.evaluations)  # fmt: skip


def _result(req: ResponseRequest, run: FitRun, sol: Solution, boot: Any,
            summary: Any) -> Any:  # fmt: skip
    """The public result: model, derived values, notes, predictor, search summary."""
    rec, spec = run.problem.records, req.spec
    pruned = prune_elements(rec, sol, spec)
    notes = [PER_UNIT_MASS] if req.per_unit_mass else []
    if pruned.dead:
        notes.append(pruned.note(spec) + DROPS)
    result = response_result(sol, rec, spec, pruned, notes, boot, req.per_unit_mass, req.signal)
    return replace(result, search=summary).on_axis(common_axis(req.records))
