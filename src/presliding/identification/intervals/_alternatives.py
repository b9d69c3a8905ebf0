"""Second optima the search found: never hidden behind the best one.

The search runs several starts (`_search`, the fits' own plans); every local
optimum a solve reached is kept on the run (`_fit_engine.FitRun.optima`). A
profile interval is found by walking outward from the best optimum
(`_profile`), so a second valley at almost the same cost, further out, is
missed: the interval excludes it although the data do not.

The rule, with the profile's own likelihood-ratio threshold, each optimum's
cost χ²(θ') evaluated again with the best's objective (`_cost_now`: a solve of
the search may have compared another velocity). For a free
parameter θ_j the profile interval at level α is where the profile
P(θ) = χ²(θ) − χ²_min stays below P_j = t²·SE_j²/h_jj (h = (JᵀJ)⁻¹, the HAC
scaling included through SE_j). Another optimum θ' with χ²(θ') − χ²_min ≤ P_j
has P(θ'_j) ≤ χ²(θ') − χ²_min ≤ P_j: its value θ'_j belongs to the confidence
set of θ_j. When it lies outside the reported interval (and apart from the
best by more than the solver's resolution), that parameter

* has its interval widened to the union of the interval and the other optimum's
  own interval at the level left to it, θ'_j ± t·SE_j·√(1 − ρ/P_j) for a rise
  ρ = χ²(θ') − χ²_min (the second valley's profile, with the best's curvature,
  crosses P_j there; ``interval_method`` "union"),
* makes the fit ``not_identifiable`` (rule ``optima`` of `_status`), the
  message naming the parameter and both values,

and the other optimum is kept on the result (`FitResult.alternatives`:
its parameters, cost, rise over the best and the parameters that differ).
A fit that is already not a success (a local minimum, the budget) keeps its
status; its intervals are widened all the same.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from presliding.identification.solve._normal_equations import profile_thresholds
from presliding.identification.solve._solution import Solution, name_list

__all__ = ["RESOLUTION", "Alternative", "canonical", "hidden_optima"]

#: Relative difference below which two optima's values are one (the solver's resolution).
RESOLUTION = 1e-4
#: Statuses of a solve that ended at a local optimum.
OPTIMUM = ("converged", "not_identifiable", "at_bound")


@dataclass(frozen=True)
class Alternative:
    """Another local optimum within the profile threshold of the best (module notes)."""

    parameters: dict[str, float]
    cost: float  # ‖r‖² at it
    rise: float  # its cost minus the best's
    differs: tuple[str, ...]  # the parameters it puts outside the best's intervals

    def to_dict(self) -> dict[str, Any]:
        return {"parameters": dict(self.parameters), "cost": self.cost, "rise": self.rise,
                "differs": list(self.differs)}  # fmt: skip

    def text(self, best: Mapping[str, float], order: tuple[str, ...]) -> str:
        shown = [x for x in order if x in self.differs][:4]
        pairs = ", ".join(f"{x} {best[x]:.6g} against {self.parameters[x]:.6g}" for x in shown)
        more = len(self.differs) - len(shown)
        return pairs + (f" and {more} more" if more > 0 else "")


def canonical(values: Mapping[str, float], best: Mapping[str, float],
              interchangeable: Sequence[str]) -> dict[str, float]:  # fmt: skip
    """`values` with interchangeable elements relabelled in the order of `best`'s
    (elements of equal break-away force: only the sorted set is meaningful)."""
    out = dict(values)
    if len(interchangeable) > 1:
        ranks = np.argsort(np.argsort([-best[x] for x in interchangeable], kind="stable"))
        ordered = sorted((values[x] for x in interchangeable), reverse=True)
        out.update({x: ordered[int(r)] for x, r in zip(interchangeable, ranks, strict=True)})
    return out


def _cost_now(sol: Solution, values: Mapping[str, float]) -> float:
    """‖r‖² of `values` under `sol`'s own objective (its profiler's residual). An optimum
    reached under another comparison (the search compares the exact simulated velocity,
    the polish then the difference quotient of the position, `_response_plan`) has its
    cost from that comparison: compared as it is, a rise would mix two objectives."""
    prof = sol.profiler
    r = prof.fun(np.array([values[n] for n in prof.free], dtype=float))
    return float(r @ r) if np.all(np.isfinite(r)) else np.inf


def _apart(a: float, b: float) -> bool:
    return abs(a - b) > RESOLUTION * max(abs(a), abs(b), 1e-300)


def _valley(sol: Solution, name: str, v: float, rise: float, limit: float) -> tuple[float, float]:
    """The other optimum's own interval of `name` at the level left to it (module notes),
    held inside the parameter's bounds; its value alone where the error is not finite."""
    se = float(sol.standard_error.get(name, np.nan))
    if not (np.isfinite(se) and se > 0):
        return v, v
    half = sol.profiler.quantile * se * float(np.sqrt(max(0.0, 1.0 - rise / limit)))
    i = sol.profiler.free.index(name)
    return max(v - half, float(sol.profiler.lower[i])), min(v + half, float(sol.profiler.upper[i]))


def hidden_optima(sol: Solution) -> tuple[Solution, tuple[Alternative, ...]]:
    """`sol` with the intervals widened to the other optima within the profile threshold,
    its status and message by rule ``optima``, and those optima (module notes)."""
    if not sol.others or sol.profiler is None or sol.status == "failed":
        return sol, ()
    c0 = float(sol.residual @ sol.residual)
    thresholds = profile_thresholds(sol)
    ci, methods = dict(sol.confidence_interval), dict(sol.interval_method)
    found = []
    for values, _ in sol.others:
        outside = [name for name in thresholds
                   if not sol.confidence_interval[name][0] <= values[name]
                   <= sol.confidence_interval[name][1]
                   and _apart(values[name], sol.values[name])]  # fmt: skip
        if not outside:
            continue
        c = _cost_now(sol, values)
        rise = c - c0
        if not np.isfinite(rise):
            continue
        differs = [name for name in outside if rise <= thresholds[name]]
        for name in differs:
            lo, hi = _valley(sol, name, values[name], rise, thresholds[name])
            ci[name] = (min(ci[name][0], lo), max(ci[name][1], hi))
            methods[name] = "union"
        if differs:
            found.append(Alternative(dict(values), float(c), float(rise), tuple(differs)))
    if not found:
        return sol, ()
    for name, (target, a, b) in sol.ties.items():  # a tied parameter follows its target
        if methods.get(target) == "union":
            lo, hi = a * ci[target][0] + b, a * ci[target][1] + b
            ci[name] = (min(lo, hi), max(lo, hi))
    found.sort(key=lambda alt: alt.cost)
    status, message = sol.status, sol.message
    if status in ("converged", "at_bound", "not_identifiable"):
        names = {x for alt in found for x in alt.differs}
        text = (
            f"rule optima: {len(found)} other local optim{'um' if len(found) == 1 else 'a'} "
            f"within the profile's likelihood-ratio threshold of the best put "
            f"{name_list(names, tuple(sol.values))} outside the intervals (best against "
            f"other: {found[0].text(sol.values, tuple(sol.values))}); the intervals hold both"
        )
        old = message if status == "not_identifiable" else ""
        status, message = "not_identifiable", "; ".join(x for x in (text, old) if x)
    out = replace(sol, confidence_interval=ci, interval_method=methods, status=status,
                  message=message)  # fmt: skip
    return out, tuple(found)
