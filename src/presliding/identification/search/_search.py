"""The search step of the pooled fits: several starts, nuisance search, the noise-floor test.

`adaptive_search` (the pooled fits' search) runs the cheapest route first: the
regression start solved once; when every record then fits within the floor
rule it stops (one start). Otherwise only the records that do not fit get the
nuisance grid search (one batched compiled call on those records alone) and
everything is solved again; only while the fit stays above the floor do the
further shared starts run (a spread start, the best of the cheap global
search, made only when reached), each through the stages below, stopping as
soon as one reaches the floor or the best optimum again. A 20-record fit
whose records all fit after the first solve costs one solve.

Each further start runs through the same stages: each record's own parameters
searched globally with the shared ones held (`_nuisance_search`), a short solve
of everything, the nuisance search again (alternation) and, when it found better
blocks, another short solve. The best is the answer, and the number of starts
that reached it (cost within 0.1 %, or the same basin) is reported.

The starts: the regression start and the spread start the caller gives, and
the best two of a cheap global search (`global_start`): the regression
start with its mass alone or its forces alone scaled (eq. 17's scale is the
least determined direction), and random log-normal perturbations of all its
shared parameters, each scored by the nuisance grid alone (one batched
compiled call per candidate).

Noise floor (`_noise_floor`). The rule: a fit at an optimum (converged, or
not identifiable or at a bound by the checks: `_status` applies this rule
before theirs, and keeps their message after its own) whose pooled residual
RMS is more than `FLOOR_FACTOR` times the floor estimated from the data,
while at least one record is fitted within that factor of its own floor (so
the model family reaches the floor on these data) or the starts did not all
reach the best optimum (the cost has several minima there), is a
``"local_minimum"``; the message names the records furthest above their
floors. Records within the floor are no such sign when the residual tests
point to a mechanism the model lacks or fail on most records (`_adequacy`):
such a fit, like any other far above the floor, is judged by the residual tests
(``"model_inadequate"``, rule ``adequacy`` of `_status`).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from presliding.identification.judge._noise_floor import floor_ratios, record_floors
from presliding.identification.records._pooled_problem import PooledProblem
from presliding.identification.search._nuisance_search import search_nuisance
from presliding.identification.solve._least_squares import Solution, complete
from presliding.identification.solve._structured_lm import on_one_blas_thread

#: residual RMS over the noise floor above which a fit is not at the floor
FLOOR_FACTOR = 3.0
#: relative cost difference below which two solutions tie (round-off)
TIE = 1e-10
#: relative cost within which two starts reached the same optimum
SAME_OPTIMUM = 1e-3
#: shared parameters within this relative distance after the short solves: one basin
SAME_POINT = 0.01
#: evaluations of another start's solve on, in short budgets (the best is solved fully)
OTHER_BUDGET = 3
#: starts whose short solve ends within this factor of the best are solved to convergence
REFINE_WITHIN = 1.2
#: candidates of the cheap global search of the shared parameters
GLOBAL_CANDIDATES = 12
#: spread (log-normal σ) of those candidates around the regression start
GLOBAL_SPREAD = 0.6
#: factors of the structured candidates
GLOBAL_SCALES = (0.5, 0.7, 1.4, 2.0, 2.8)
#: the exact velocity stands in for a difference quotient while they differ by less than
#: this factor times a record's noise floor (`exact_velocity_stands_in`)
PROXY_FACTOR = 1.0


@dataclass(frozen=True)
class SearchSummary:
    """What the search did and how the best residual compares with the noise floor."""

    n_starts: int
    n_starts_at_best: int
    noise_floor: float  # RMS of the weighted residual that the noise alone leaves
    residual_over_floor: float  # pooled residual RMS / noise floor
    record_ratios: tuple[float, ...]  # each record's residual RMS over its floor
    search_evaluations: int = 0  # residual evaluations of the nuisance searches
    order_table: tuple[tuple[int, float, float, str], ...] = ()  # (N, cost, BIC, note)
    chosen_order: int | None = None

    def lines(self) -> list[str]:
        """Report lines."""
        out = [
            f"search: {self.n_starts_at_best} of {self.n_starts} start(s) reached the best "
            f"optimum; residual RMS {self.residual_over_floor:.3g} × the noise floor estimated "
            f"from the data",
        ]
        if self.order_table:
            out.append("model order (n_elements='auto', by BIC):")
            out.append(f"  {'N':>3} {'cost ‖r‖²':>14} {'BIC':>14}")
            for n, c, bic, note in self.order_table:
                mark = "  <- chosen" if n == self.chosen_order else ""
                out.append(f"  {n:>3} {c:>14.6g} {bic:>14.6g}{mark}{'  ' + note if note else ''}")
        return out

    def to_dict(self) -> dict[str, Any]:
        return {
            "n_starts": self.n_starts,
            "n_starts_at_best": self.n_starts_at_best,
            "noise_floor": self.noise_floor,
            "residual_over_floor": self.residual_over_floor,
            "record_ratios": list(self.record_ratios),
            "order_table": [list(row) for row in self.order_table],
            "chosen_order": self.chosen_order,
        }


def cost(sol: Solution) -> float:
    c = float(sol.residual @ sol.residual) if sol.status != "failed" else np.inf
    return c if np.isfinite(c) else np.inf


@on_one_blas_thread
def global_start(
    problem: PooledProblem,
    start: Mapping[str, float],
    fixed: Mapping[str, float],
    bounds: Mapping[str, tuple[float, float]],
    seed: int = 0,
    keep: int = 2,
) -> tuple[list[dict[str, float]], int]:
    """The `keep` best of random perturbations of the start's shared parameters (module notes)."""
    rng = np.random.default_rng(seed)
    scored: list[tuple[float, dict[str, float]]] = []
    count = 0
    movable = [x for x in problem.shared if x not in fixed and x != "offset" and start[x] > 0]
    forces = [x for x in movable if x != "mass"]
    factors = []  # structured: the mass alone, the forces alone (the scale of eq. 17)
    for scale in GLOBAL_SCALES:
        factors.append({"mass": scale} if "mass" in movable else {})
        factors.append(dict.fromkeys(forces, scale))
    for _ in range(GLOBAL_CANDIDATES):  # and random log-normal ones
        factors.append({x: float(np.exp(GLOBAL_SPREAD * rng.standard_normal())) for x in movable})
    for factor in factors:
        if not factor:
            continue
        cand = dict(start)
        for x, f in factor.items():
            lo, hi = bounds.get(x, (-np.inf, np.inf))
            cand[x] = float(np.clip(start[x] * f, lo, hi))
        if problem.spec.has_level_parameter and "coulomb" in cand:
            cand["coulomb"] = min(cand["coulomb"], 0.95 * cand["coulomb_level"])
        values, c, ev = search_nuisance(problem, cand, fixed, bounds, polish=False)
        count += ev
        if np.isfinite(c):
            scored.append((c, values))
    scored.sort(key=lambda item: item[0])
    return [v for _, v in scored[:keep]], count


def at_floor(problem: PooledProblem, sol: Solution, record_factor: float = FLOOR_FACTOR) -> bool:
    """Whether a solve converged within the floor rule: the pooled residual RMS within
    `FLOOR_FACTOR` times the floor and every record within `record_factor` times its own."""
    if sol.status != "converged" or not np.isfinite(cost(sol)):
        return False
    ratios, pooled = floor_ratios(problem, sol.residual)
    return bool(pooled <= FLOOR_FACTOR and np.all(ratios <= record_factor))


def unfit_records(problem: PooledProblem, sol: Solution) -> list[int]:
    """The records whose residual RMS is above `FLOOR_FACTOR` times their own floor."""
    ratios, _ = floor_ratios(problem, sol.residual)
    return [i for i in range(problem.n_rec) if not ratios[i] <= FLOOR_FACTOR]


def search_records(
    problem: PooledProblem,
    values: Mapping[str, float],
    fixed: Mapping[str, float],
    bounds: Mapping[str, tuple[float, float]],
    chosen: list[int],
) -> tuple[dict[str, float], float, int]:
    """The nuisance search on the `chosen` records only (the others' blocks kept).

    The chosen records form a sub-problem (`PooledProblem.subset`) so that the
    batched compiled call simulates them alone. Returns the values, the full
    cost ‖r‖² (estimated: the others' rows unchanged) and the evaluations.
    """
    if not chosen:
        return dict(values), np.inf, 0
    if len(chosen) == problem.n_rec:
        return search_nuisance(problem, values, fixed, bounds)
    sub = problem.subset([problem.records[i] for i in chosen])
    rename = {sub.nuisance(k, j): problem.nuisance(k, i)
              for j, i in enumerate(chosen) for k in problem.kinds}  # fmt: skip
    back = {x: rename.get(x, x) for x in sub.names}
    sub_values = {x: values[back[x]] for x in sub.names}
    sub_fixed = {x: fixed[back[x]] for x in sub.names if back[x] in fixed}
    sub_bounds = {x: bounds[back[x]] for x in sub.names if back[x] in bounds}
    sub.set_typical(sub_values)
    found, c, ev = search_nuisance(sub, sub_values, sub_fixed, sub_bounds)
    out = dict(values)
    out.update({back[x]: v for x, v in found.items()})
    return out, c, ev


@on_one_blas_thread
def adaptive_search(
    problem: PooledProblem,
    solve: Callable[..., Solution],
    start: Mapping[str, float],
    more_starts: Callable[[], Iterator[tuple[dict[str, float], int]]],
    fixed: Mapping[str, float],
    bounds: Mapping[str, tuple[float, float]],
    short: int,
    prepare: Callable[[dict[str, float]], dict[str, float]] | None = None,
    errors: bool = True,
) -> tuple[Solution, int, int, int]:
    """The cheapest route first, further starts only while the fit is above the floor.

    1. The regression start solved once (`prepare` may first set the records'
       own starts). If it converged with every record within the floor rule
       (`at_floor`), that is the answer: one start.
    2. Otherwise the records that do not fit (`unfit_records`) are searched on
       the nuisance grid (`search_records`, one batched compiled call on those
       records alone) and everything is solved again, twice at most.
    3. Only while the fit is still above the floor, the further starts
       (`more_starts`: produced lazily, with the evaluations they cost) run
       through the stages above (every record's grid search, a short solve,
       alternation); one that ends within `REFINE_WITHIN` of the best
       in another basin is solved on and its unfit records searched again. The
       search stops as soon as the best reaches the floor, or as soon as a
       further start reaches the best optimum again (two starts agree: the
       records still above their floors are not a matter of the start).

    The solves defer their errors (``errors=False``): only the best one's are
    computed (the covariance of a 20-record fit costs as much as several
    evaluations), and with ``errors=False`` not even its (for a caller that solves
    on from it, `_deferred.complete` computes them when needed). Returns the best
    solution, the number of starts run, how many reached the best optimum (cost
    within `SAME_OPTIMUM` or the same basin), and the residual evaluations of the
    searches.
    """
    evaluations = 0
    prep = prepare or (lambda v: dict(v))

    def deferred(begin: Any, **kw: Any) -> Solution:  # errors only for the one kept (`complete`)
        return solve(begin, errors=False, **kw)

    def repair(sol: Solution) -> Solution:
        nonlocal evaluations
        for _ in range(2):
            if sol.status == "failed" or at_floor(problem, sol):
                return sol
            bad = unfit_records(problem, sol)
            if not bad:
                return sol
            values, _, ev = search_records(problem, sol.values, fixed, bounds, bad)
            evaluations += ev
            again = deferred(values)
            if not cost(again) < cost(sol) * (1.0 - SAME_OPTIMUM):
                return again if cost(again) < cost(sol) else sol
            sol = again
        return sol

    def alternate(sol: Solution) -> Solution:
        nonlocal evaluations
        for _ in range(2):
            if sol.status == "failed":
                return sol
            values, c, ev = search_nuisance(problem, sol.values, fixed, bounds, polish=False)
            evaluations += ev
            if not c < cost(sol) * (1.0 - SAME_OPTIMUM):
                break
            sol = deferred(values, max_evaluations=short)
        return sol

    best = repair(deferred(prep(dict(start))))
    if at_floor(problem, best):  # every record's grid at once, unpolished: a cheap last check
        values, c, ev = search_nuisance(problem, best.values, fixed, bounds, polish=False)
        evaluations += ev
        if c < cost(best) * (1.0 - SAME_OPTIMUM):
            again = repair(deferred(values))
            best = again if cost(again) < cost(best) * (1.0 - TIE) else best
    finals = [best]
    if not at_floor(problem, best):
        for s, ev in more_starts():
            evaluations += ev
            values, _, ev = search_nuisance(problem, prep(dict(s)), fixed, bounds)
            evaluations += ev
            t = alternate(deferred(values, max_evaluations=short))
            if (
                np.isfinite(cost(t))
                and cost(t) <= REFINE_WITHIN * cost(best)
                and not same_point(problem, t.values, best.values)
            ):
                t = repair(deferred(t.values))
            finals.append(t)
            agree = cost(t) <= cost(best) * (1.0 + SAME_OPTIMUM) or same_point(
                problem, t.values, best.values
            )
            if cost(t) < cost(best) * (1.0 - TIE):  # a tie keeps the earlier (mirror images agree)
                best = t
            if at_floor(problem, best) or (agree and best.status == "converged"):
                break
    target = cost(best)
    at_best = sum(1 for f in finals if cost(f) <= target * (1.0 + SAME_OPTIMUM) + 1e-300
                  or same_point(problem, f.values, best.values))  # fmt: skip
    return complete(best) if errors else best, len(finals), at_best, evaluations


def exact_velocity_stands_in(problem: PooledProblem, values: Mapping[str, float]) -> bool:
    """Whether the exact simulated velocity may stand in for the records' difference
    quotients in the search (the cheaper comparison, the optimum polished after): at
    `values`, no record's velocity rows change by more than `PROXY_FACTOR` times its
    noise floor when the one replaces the other.

    The two differ by O(a·Δt) at events, well within the floor at a drive's sampling
    rate; but a stiff stage rings in presliding at a good share of the sampling rate
    (142 Hz at 1 kHz: the quotient is 13 % smaller), and the search then ends in a
    valley of the exact velocity that the polish cannot leave (a fit started at the
    truth ended 4–5 times above the floor).
    """
    p = np.array([values[x] for x in problem.names], dtype=float)[None]
    quotient = problem.residuals(p)[0]
    with problem.exact_velocity_compared():
        exact = problem.residuals(p)[0]
    if not (np.all(np.isfinite(quotient)) and np.all(np.isfinite(exact))):
        return True  # judged by the solves
    floors = record_floors(problem)
    for i in range(problem.n_rec):
        rows = problem.record_rows(i)
        gap = float(np.mean((exact[rows] - quotient[rows]) ** 2))
        if gap > PROXY_FACTOR**2 * floors[i]:
            return False
    return True


def same_point(problem: PooledProblem, a: Mapping[str, float], b: Mapping[str, float]) -> bool:
    """Whether two solutions' shared parameters agree to `SAME_POINT` (one basin)."""
    for x in problem.shared:
        scale = max(abs(a[x]), abs(b[x]), 1e-300)
        if abs(a[x] - b[x]) > SAME_POINT * scale:
            return False
    return True


def floor_test(problem: PooledProblem, sol: Solution, starts_agree: bool = True,
               model_named: bool = False) -> tuple[Solution, tuple, float, float]:  # fmt: skip
    """The noise-floor rule (module notes): the status, and the ratios it rests on. With
    `model_named` (the residual tests point to a mechanism the model lacks, or most records
    fail them: `_adequacy`) records within the floor are no sign of a better optimum."""
    ratios, pooled = floor_ratios(problem, sol.residual)
    sizes = np.array([problem.record_rows(i).shape[0] for i in range(problem.n_rec)])
    floor = float(np.sqrt(np.sum(record_floors(problem) * sizes) / np.sum(sizes)))
    reach = (bool(np.any(ratios <= FLOOR_FACTOR)) and not model_named) or not starts_agree
    optimum = sol.status in ("converged", "not_identifiable", "at_bound")  # rules after it
    if optimum and pooled > FLOOR_FACTOR and reach:
        worst = [int(i) for i in np.argsort(-ratios) if ratios[i] > FLOOR_FACTOR]
        named = ", ".join(f"{i + 1} ({ratios[i]:.3g}×)" for i in worst[:5])
        more = f" and {len(worst) - 5} more" if len(worst) > 5 else ""
        message = (
            f"local minimum: the residual RMS is {pooled:.3g} times the noise floor estimated "
            f"from the data (rule: more than {FLOOR_FACTOR:g} times while some records are "
            f"fitted within it or the starts ended apart); record(s) {named}{more} fit worst"
        )
        old = "" if sol.status == "converged" else sol.message
        sol = replace(
            sol, status="local_minimum", message="; ".join(x for x in (message, old) if x)
        )
    return sol, tuple(float(r) for r in ratios), floor, pooled
