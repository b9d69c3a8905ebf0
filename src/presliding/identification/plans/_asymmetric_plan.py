"""``asymmetric=True`` of the pooled fits: the symmetric fit, then the asymmetric one from it.

The symmetric fit runs first, as the fit would without `asymmetric` (every start, probe,
check and, with ``n_elements="auto"`` or ``prune=True``, its choice of elements). The
asymmetric problem (`ModelSpec` with its negative side: ``coulomb_level_negative`` F_c⁻, or
``coulomb_negative`` without elements, and ``viscous_negative`` σ⁻ with a viscous term) then
has the same records, parameters and options plus those, and its search solves from

* the symmetric optimum with every negative level equal to its positive one (the symmetric
  model exactly: the nested start, from which the solver only descends, so the asymmetric
  residual is never the larger);
* the symmetric optimum with the mean levels kept and the ratio ρ = F_c⁻/F_c⁺ (and σ⁻) of the
  per-direction regression start (`_pooled_start`);
* and runs the fit's own search on the asymmetric problem (its regression start, further
  starts and probes): a symmetric optimum can sit in another valley than the asymmetric one
  (the symmetric model bends its elements to mimic a difference of the levels);

each start's records' own parameters prepared as the fit prepares them (the quasi-static
fit's preloads fitted record by record), keeping the best; then each record's own parameters
are searched on the nuisance grid with the shared ones held (`_nuisance_search`) and the fit
solved again where that found a better block. The fit's other steps are those of every
pooled fit (relabelling, the shared settle, the noise floor, intervals, the bootstrap), and
the result carries the test of the asymmetry against the symmetric fit (`judge._asymmetry`).
The user's `initial`, `fixed`, `tied` and `bounds` entries that name a negative side go to the
asymmetric fit only.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from functools import partial
from typing import Any

import numpy as np

from presliding.identification._fit_engine import FitPlan, FitRun, Found, cost, run_fit
from presliding.identification.judge._asymmetry import asymmetry_test, hac_scale
from presliding.identification.problem._parameters import check_flag, resolve_parameters
from presliding.identification.records._residual_blocks import pooled_adequacy
from presliding.identification.search._search import SAME_OPTIMUM
from presliding.identification.solve._least_squares import Solution, complete

__all__ = ["NEGATIVE", "Parts", "constraints", "fit_asymmetric", "fit_nested", "lifted",
           "split_negative"]  # fmt: skip

#: The parameters of the negative side.
NEGATIVE = ("coulomb_level_negative", "coulomb_negative", "viscous_negative")


def _negative(name: Any) -> bool:
    return isinstance(name, str) and (name in NEGATIVE or name.startswith("threshold_negative"))


def split_negative(request: dict[str, Any]) -> dict[str, Any]:
    """The request of the symmetric fit: `initial`, `fixed`, `tied` and `bounds` without the
    entries naming a negative side (a tie to one included), an lmfit.Parameters resolved."""
    initial, bounds, fixed, tied = resolve_parameters(
        request.get("initial"), request.get("bounds"), request.get("fixed"),
        request.get("tied"),
    )  # fmt: skip
    out = dict(request)
    for label, values in (("initial", initial), ("bounds", bounds), ("fixed", fixed)):
        out[label] = {x: v for x, v in (values or {}).items() if not _negative(x)} or None
    out["tied"] = {
        x: v
        for x, v in (tied or {}).items()
        if not _negative(x) and not _negative(v if isinstance(v, str) else v[0])
    }
    out["tied"] = out["tied"] or None  # fmt: skip
    return out


def _elements(result: Any, requested: Any) -> Any:
    """The number of elements of the symmetric fit's model (the requested one without it)."""
    model = result.model
    if model is not None and model.is_discrete:
        return int(np.asarray(model.stiffness).shape[0])
    return 4 if requested == "auto" else requested


@dataclass(frozen=True)
class Parts:
    """What a pooled fit gives its asymmetric fit: the checked problem and options, the
    checks it keeps (relabelling), its result step and its bootstrap."""

    problem: Any
    options: Any
    checks: tuple[Callable[..., Any], ...]
    result: Callable[..., Any]
    bootstrap: int = 0
    seed: int | None = None
    #: a start's records' own parameters prepared (None: taken as they are)
    prepare: Callable[[dict[str, float]], dict[str, float]] | None = None
    #: the fit's own search on the asymmetric problem (None: its start solved)
    search: Callable[[FitRun], Found] | None = None


def fit_asymmetric(fit: Callable[..., Any], request: dict[str, Any], check: Callable[..., Any],
                   build: Callable[[Any], Parts]) -> Any:  # fmt: skip
    """The symmetric fit by `fit`, then the asymmetric one (module notes).

    `check` turns a request into the fit's checked request (raising on a bad argument before
    anything runs), `build` a checked request into its `Parts`.
    """
    check_flag("asymmetric", request["asymmetric"])
    count = request["n_elements"]
    check({**request, "n_elements": 4 if count == "auto" else count})
    symmetric = fit(**{**split_negative(request), "asymmetric": False})
    n = _elements(symmetric, count)
    parts = build(check({**request, "n_elements": n}))
    problem, options = parts.problem, parts.options
    if options.progress is not None:
        options.progress.stage(f"asymmetric fit from the symmetric optimum ({n} element(s))")
    plan = FitPlan(
        search=partial(_search, symmetric, parts), checks=parts.checks,
        result=partial(_result, parts.result, symmetric, constraints(problem.spec,
                                                                     problem.names)),
        bootstrap=parts.bootstrap, seed=parts.seed,
        adequacy=lambda run, sol: pooled_adequacy(run.problem, sol),
    )  # fmt: skip
    out = run_fit(problem, options, plan)
    if n != count:  # the symmetric fit chose the elements (n_elements="auto", prune=True)
        note = f"{n} element(s), as the symmetric fit chose them (n_elements={count!r})"
        out = replace(out, notes=(*out.notes, note))
    return out


def constraints(spec: Any, names: Any) -> list[dict[str, float]]:
    """The rows of the symmetric model's constraints (negative minus positive side = 0)."""
    rows: list[dict[str, float]] = []
    if spec.n == 0:
        rows.append({"coulomb_negative": 1.0, "coulomb": -1.0})
    elif spec.equal:
        rows.append({"coulomb_level_negative": 1.0, "coulomb_level": -1.0})
    else:
        rows.append({"coulomb_level_negative": 1.0, "coulomb": -1.0,
                     **dict.fromkeys(spec.c_names, -1.0)})  # fmt: skip
    if "viscous_negative" in names:
        rows.append({"viscous_negative": 1.0, "viscous": -1.0})
    return rows


def lifted(spec: Any, values: Mapping[str, float], names: Any, ratio: float = 1.0,
           sigma: tuple[float, float] | None = None) -> dict[str, float]:  # fmt: skip
    """A symmetric fit's values as the asymmetric problem's: the mean levels kept and the
    negative side ρ = `ratio` times the positive one (1: the symmetric model exactly); with a
    viscous term σ⁺, σ⁻ = `sigma` (default: the symmetric σ on both sides)."""
    out = spec.sided({x: float(values[x]) for x in names if x in values}, ratio)
    if "viscous_negative" in names:
        out["viscous"], out["viscous_negative"] = sigma or (out["viscous"], out["viscous"])
    return {x: out[x] for x in names}


def _search(symmetric: Any, parts: Parts, run: FitRun) -> Found:
    """The nested and the ratio start, the fit's own search, then the records' own parameters
    searched (module notes)."""
    from presliding.identification.search._nuisance_search import search_nuisance

    p, prepare = run.problem, parts.prepare or (lambda s: s)
    spec, begin = p.spec, p.start()
    sigma = (begin["viscous"], begin["viscous_negative"]) if "viscous" in begin else None
    run.stage("search: from the symmetric optimum, and with the regression's ratio")
    solved = [run.solve(prepare(lifted(spec, symmetric.parameters, p.names))),
              run.solve(prepare(lifted(spec, symmetric.parameters, p.names, spec.ratio(begin),
                                       sigma)))]  # fmt: skip
    own = parts.search(run) if parts.search is not None else Found(run.solve(prepare(begin)))
    solved.append(own.solution)
    best = min(solved, key=cost)
    values, found, count = search_nuisance(p.records, best.values, p.fixed, p.bounds)
    if found < cost(best) * (1.0 - SAME_OPTIMUM):  # a better block for some record
        again = run.solve(values)
        solved.append(again)
        best = again if cost(again) < cost(best) else best
    low = cost(best)
    at = sum(1 for s in solved if cost(s) <= low * (1.0 + SAME_OPTIMUM))
    return Found(complete(best), len(solved) + own.n_starts - 1, at,
                 count + own.search_evaluations)  # fmt: skip


def fit_nested(
    problem_of: Callable[..., Any],
    thresholds: Any,
    symmetric: Any,
    result: Callable[..., Any],
    rows: list[dict[str, float]],
    options: Any,
    adequacy: Callable[..., Any] | None = None,
) -> Any:
    """The asymmetric fit of a separable problem (`fit_presliding`, `fit_motion`: c1⁻ and σ⁻
    beside c1 and σ, the elements shared) from its grid start (or the caller's `thresholds`)
    and from the `symmetric` fit's thresholds, the better kept; the linear stage at those
    thresholds contains the symmetric optimum, so the asymmetric residual is never the
    larger. `problem_of(thresholds=...)` builds the problem, `result` is the fit's result
    step, `rows` the constraints of the symmetric model, `adequacy` the fit's residual tests."""
    from presliding.identification.problem._pi_regression import element_names

    r_names = element_names(sum(1 for x in symmetric.parameters if x.startswith("threshold_")))[1]
    nested = [symmetric.parameters[x] for x in r_names] if r_names else None

    def search(run: FitRun) -> Found:
        tries = [run.solve()]
        if nested is not None:
            run.stage("least squares from the symmetric fit's thresholds")
            tries.append(problem_of(thresholds=nested).solve(run.options))
        best = min(tries, key=cost)
        return Found(best, len(tries), sum(1 for t in tries if cost(t) <= cost(best) * 1.001))

    plan = FitPlan(search=search, result=partial(_result, result, symmetric, rows),
                   adequacy=adequacy)  # fmt: skip
    return run_fit(problem_of(thresholds=thresholds), options, plan)


def _result(result: Callable[..., Any], symmetric: Any, rows: list[dict[str, float]],
            run: FitRun, sol: Solution, boot: Any, summary: Any) -> Any:  # fmt: skip
    """The fit's own result with the test of the asymmetry and every evaluation counted."""
    out = result(run, sol, boot, summary)
    p = run.problem
    held = set(p.fixed) | set(p.tied)
    free = [r for r in rows if not {x for x, w in r.items() if w > 0} & held]
    kappa = hac_scale(sol, free) if free and np.isfinite(cost(sol)) else float("nan")
    test = asymmetry_test(symmetric, out, free, kappa, run.options.level)
    return replace(out, asymmetry=test,
                   n_evaluations=out.n_evaluations + symmetric.n_evaluations)  # fmt: skip
