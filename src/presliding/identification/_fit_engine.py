"""The steps every fit runs on its `FitProblem`: search, checks, judge, intervals, result.

`run_fit(problem, options, plan)` is the one pipeline of the ``fit_*``
functions (lmfit's single Minimizer, scipy's result conventions):

1. **search** — the fit's starts and their solves (`FitPlan.search`: the
   adaptive multistart of `_search` for the pooled fits, the threshold grid
   and the global or envelope starts for the separable ones), giving a
   `Found`: the best solution, the starts run and how many reached it;
2. **checks** — the fit's own refinements of that optimum (`FitPlan.checks`:
   relabelling interchangeable elements, the rigid corner, coalesced
   elements), then, for record-pooled problems, the shared `settle`: a model
   parameter on its bound 0 (`at_bound`), F_c equal to the model's, records
   whose own start the data cannot pin down;
3. **refit** — a fit may end here with another fit (`FitPlan.refit`: the
   refit without elements that never slide);
4. **judge** — the residual tests of the optimum (`FitPlan.adequacy`,
   `_adequacy`: level, whiteness and independence per record, the likely cause
   when they fail), the noise-floor rule of record-pooled problems
   (`_search.floor_test`: ``local_minimum``), then rule ``adequacy`` of
   `_status` (``model_inadequate``) and the search summary (a direct
   problem's summary is its `Found`);
5. **intervals** — the record bootstrap when asked (its intervals joined
   with the profile-likelihood ones, `_response_setup.record_bootstrap`);
6. **result** — `FitPlan.result` assembles the `FitResult`, whose
   `FitResult.from_solution` computes the profile-likelihood intervals that
   are still missing (`_profile`) and passes the status through the one
   status judge (`_status.judge`).

`FitRun` carries one fit's explicit state along the way: the problem, the
options, the residual evaluations spent so far (every solve goes through
`FitRun.solve`, which counts them) and the local optima its solves reached,
handed on with the solution (`Solution.others`) so that one the intervals
exclude while the profile's threshold does not is reported (`_alternatives`).
A record-pooled fit reports every evaluation (every start and check); a
direct one those of the solve it kept.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from presliding.identification.intervals._alternatives import OPTIMUM, canonical
from presliding.identification.problem._fit_problem import FitOptions, FitProblem
from presliding.identification.solve._least_squares import Solution

__all__ = ["FitPlan", "FitRun", "Found", "cost", "run_fit"]


def cost(sol: Solution) -> float:
    """‖r‖² of a solution (inf for a failed one or a residual that is not finite)."""
    c = float(sol.residual @ sol.residual) if sol.status != "failed" else np.inf
    return c if np.isfinite(c) else np.inf


class FitRun:
    """One fit's run through the steps: its problem, options and evaluations so far."""

    def __init__(self, problem: FitProblem, options: FitOptions):
        self.problem, self.options = problem, options
        self.evaluations = 0
        self.optima: list[Solution] = []  # the local optima of the full problem's solves

    def solve(self, begin: Any = None, rigid: bool = False, extra: Any = None,
              **overrides: Any) -> Solution:  # fmt: skip
        """`FitProblem.solve` with the run's options, its evaluations counted."""
        out = self.problem.solve(self.options, begin, rigid=rigid, extra=extra, **overrides)
        self.evaluations += out.n_evaluations
        if not rigid and not extra and out.status in OPTIMUM:
            self.optima.append(out)
        return out

    def stage(self, text: str) -> None:
        """Say which stage runs (through the fit's progress, when shown)."""
        if self.options.progress is not None:
            self.options.progress.stage(text)


@dataclass(frozen=True)
class Found:
    """What the search step found: the best solution and how the starts went."""

    solution: Solution
    n_starts: int = 1
    n_starts_at_best: int = 1
    search_evaluations: int = 0  # residual evaluations of the nuisance searches
    note: str = ""  # what the search says of the starts it compared (direct problems)
    lower_unsolved: bool = False  # a start went below the best, its solve stopped short


Step = Callable[[FitRun, Solution], Solution]


@dataclass(frozen=True)
class FitPlan:
    """A fit's own parts of the pipeline (module notes)."""

    search: Callable[[FitRun], Found]
    result: Callable[[FitRun, Solution, Any, Any], Any]  # (run, sol, bootstrap, summary)
    checks: tuple[Step, ...] = ()
    refit: Callable[[FitRun, Solution], Any] | None = None  # a FitResult ends the fit
    bootstrap: int = 0
    seed: int | None = None
    #: the residual tests of an optimum (`_adequacy.Adequacy`; None: not tested)
    adequacy: Callable[[FitRun, Solution], Any] | None = None


def run_fit(problem: FitProblem, options: FitOptions, plan: FitPlan) -> Any:
    """search → checks → (refit) → judge → intervals → result (module notes)."""
    run = FitRun(problem, options)
    found = plan.search(run)
    sol = found.solution
    for step in plan.checks:
        sol = step(run, sol)
    sol = settle(run, sol)
    if plan.refit is not None:
        other = plan.refit(run, sol)
        if other is not None:
            return other
    sol, summary = judge(run, sol, found, plan.adequacy)
    sol, boot = intervals(run, sol, plan.bootstrap, plan.seed)
    sol = replace(sol, others=other_optima(run, sol))
    if problem.records is not None:  # every start and check counted; a direct problem
        sol = replace(sol, n_evaluations=run.evaluations)  # counts the solve it kept
    return plan.result(run, sol, boot, summary)


def other_optima(run: FitRun, sol: Solution) -> tuple[tuple[dict[str, float], float], ...]:
    """The local optima of the run's solves with the same free parameters as `sol`, as
    (values, cost), interchangeable elements relabelled in `sol`'s order (`_alternatives`)."""
    p = run.problem
    k_names: list[str] = []
    if p.spec is not None and p.spec.equal and p.spec.density is None:
        k_names = [x for x in p.spec.k_names if x not in p.fixed and x not in p.tied]
        k_names = k_names if len(k_names) == len(p.spec.k_names) else []
    out = []
    for other in run.optima:
        if other.free != sol.free or set(other.values) != set(sol.values):
            continue
        c = cost(other)
        if np.isfinite(c):
            out.append((canonical(other.values, sol.values, k_names), c))
    return tuple(out)


def settle(run: FitRun, sol: Solution) -> Solution:
    """A record-pooled optimum's bounds, F_c and the records' own undetermined starts."""
    from presliding.identification.checks._response_checks import bound_check, consistent_level
    from presliding.identification.plans._response_setup import nuisance_only

    p = run.problem
    if p.records is None:
        return sol
    equal = p.spec.equal and p.spec.density is None
    sol = bound_check(sol, {"mass": 1.0, **p.initial}, p.names, p.fixed, p.tied, equal)
    return consistent_level(nuisance_only(sol, p.records, p.fixed), p.spec)


def judge(
    run: FitRun,
    sol: Solution,
    found: Found,
    adequacy: Callable[[FitRun, Solution], Any] | None = None,
) -> tuple[Solution, Any]:
    """The residual tests, the noise-floor rule of a record-pooled fit, rule ``adequacy``
    and the search summary (`_search`); a direct problem has no floor of its own but its
    tests' level: its summary is what the search found."""
    from presliding.identification.judge._status import OPTIMUM, adequacy_verdict
    from presliding.identification.search._search import SearchSummary, floor_test

    tested = adequacy(run, sol) if adequacy is not None and sol.status in OPTIMUM else None
    agree = found.n_starts_at_best == found.n_starts
    records = run.problem.records
    if records is None:  # its search is global (every start a threshold set by projection):
        # residual tests that fail are the model's, wherever the other starts ended
        status, message = adequacy_verdict(sol.status, sol.message, tested)
        return replace(sol, status=status, message=message, adequacy=tested), found
    failing = 0 if tested is None or tested.passed else len(tested.failing_records)
    cause = failing > 0 and tested is not None and tested.cause is not None
    every = failing == records.n_rec  # no record fits
    named = cause or 2 * failing >= records.n_rec > 0 < failing
    sol, ratios, floor, over = floor_test(records, sol, agree or cause or every, named)
    # failing tests are the model's whatever the starts, unless a start is known to go lower
    apart = found.lower_unsolved or not (agree or every)
    status, message = adequacy_verdict(
        sol.status, sol.message, tested, not apart, some_fit=0 < failing < records.n_rec
    )
    sol = replace(sol, status=status, message=message, adequacy=tested)
    summary = SearchSummary(found.n_starts, found.n_starts_at_best, floor, over, ratios,
                            found.search_evaluations)  # fmt: skip
    return sol, summary


def intervals(run: FitRun, sol: Solution, n_resamples: int, seed: int | None) -> tuple:
    """The record bootstrap (three or more records), its intervals joined with the profile."""
    from presliding.identification.plans._response_setup import record_bootstrap

    p = run.problem
    if not n_resamples or p.records is None or p.records.n_rec < 3 or not np.isfinite(cost(sol)):
        return sol, None
    settings = {**run.options.solver(), "fixed": p.fixed, "tied": p.tied, "bounds": p.bounds}
    sol, boot, count = record_bootstrap(sol, p.records, settings, n_resamples, seed)
    run.evaluations += count
    return sol, boot
