"""The element split the records do not determine: a check of the fits with elements of
equal break-away force (`fit_quasi_static`).

Why. With equal break-away forces c_j = (F_c − c1)/N the elements differ only in
their thresholds r_j = c_j/k_j (eq. 6), and an element shows its own stiffness
only where a record's swing crosses its threshold (2·r_j after a reversal). When
two elements never slide in any record, only their sum k_a + k_b is seen (eq. 7):
the cost is flat along their split over the whole range where neither slides.
The least-squares optimum then sits at the edge of that plateau, where the
stiffer of the two just begins to slide at one record's extreme swing and takes
up a quantum of noise there: the Jacobian of that one-sided kink is steep, its
covariance gives a standard error some 10⁻⁵ of the value, and the truth lies
hundreds or thousands of those errors away, on the plateau, at the same cost to
within the profile's threshold (torque loops with preload, `benchmarks/
identification_search.py loops`: z of −8000 with the fit's own interval missing
the truth). The linearised error of a kink does not describe the data, and the
profile walk from it may stop anywhere on the plateau.

The check (`undetermined_split`), for each pair of neighbouring free elements
(a stiffer than b, labels stiffest first): their sum S held, both set to S/2
(the two merged; every split between the fit's and its mirror image lies on the
segment through it; a pair whose intervals hold S/2 already is skipped) and every
other free parameter refitted, a short solve
(`BUDGET` evaluations: it can only overstate the profile there). If the cost
rises by no more than the profile's threshold P = t²·SE²/h (h = (JᵀJ)⁻¹; the
smaller of the pair's, `_profile`), the data do not determine the split: the
fit is ``not_identifiable`` (a flat profile, rule ``profile`` of `_status`),
both standard errors and variances are infinite (no curvature describes a
plateau; as for a singular Jacobian, `uncertainty.full_covariance`), and the
intervals hold the fit and the merged point: k_a ∈ [S/2, k̂_a] and k_b ∈ [k̂_b,
S/2], with their own ends kept where they reach further. A split the records
determine (an element that slides) rises far above P at the merged point and
is left as it is.

Its cost: one short solve per pair of neighbouring elements.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from dataclasses import replace

import numpy as np

from presliding.identification.search._search import cost
from presliding.identification.solve._deferred import complete
from presliding.identification.solve._normal_equations import profile_thresholds
from presliding.identification.solve._solution import Solution

__all__ = ["BUDGET", "undetermined_split"]

#: Evaluations of the refit at the merged point of a pair.
BUDGET = 20
_OPTIMUM = ("converged", "not_identifiable", "at_bound")


def undetermined_split(
    sol: Solution, solve: Callable[..., Solution], k_names: Sequence[str], budget: int = BUDGET
) -> Solution:
    """`sol` with every pair of neighbouring elements whose split the data do not determine
    made ``not_identifiable`` (module notes); `solve(begin, extra=held, max_evaluations=n)`
    refits with the `held` values fixed. Elements labelled stiffest first."""
    if sol.status not in _OPTIMUM or sol.profiler is None:
        return sol
    sol = complete(sol)
    free = [x for x in k_names if x in sol.free and sol.values[x] > 0]
    if len(free) < 2 or not np.isfinite(cost(sol)):
        return sol
    limits = profile_thresholds(sol)
    c0 = cost(sol)
    ranked = sorted(free, key=lambda x: -sol.values[x])
    found = []
    for a, b in itertools.pairwise(ranked):
        if a not in limits or b not in limits:
            continue
        half = 0.5 * (sol.values[a] + sol.values[b])
        if sol.confidence_interval[a][0] <= half or half <= sol.confidence_interval[b][1]:
            continue  # the merged point inside an interval already: nothing to widen
        merged = solve({**sol.values, a: half, b: half}, extra={a: half, b: half},
                       max_evaluations=budget)  # fmt: skip
        rise = cost(merged) - c0
        limit = min(limits[a], limits[b])
        if rise <= limit:
            found.append((a, b, half, rise / limit))
    if not found:
        return sol
    se, ci = dict(sol.standard_error), dict(sol.confidence_interval)
    names = list(sol.values)
    cov = None if sol.covariance is None else np.array(sol.covariance, dtype=float)
    parts = []
    for a, b, half, share in found:
        se[a] = se[b] = np.inf
        if cov is not None:  # an undetermined parameter's variance is infinite (as a
            for x in (a, b):  # singular Jacobian's, `uncertainty.full_covariance`)
                cov[names.index(x), names.index(x)] = np.inf
        ci[a] = (min(ci[a][0], half), max(ci[a][1], sol.values[a]))
        ci[b] = (min(ci[b][0], sol.values[b]), max(ci[b][1], half))
        parts.append(
            f"{a} + {b} = {2 * half:.6g} is determined, their split is not: with the two "
            f"equal ({half:.6g} each) and every other parameter refitted the cost rises by "
            f"only {share:.3g} of the profile's threshold (an element the records hardly "
            "make slide: its threshold lies beyond their swings)"
        )
    message = (
        "the data do not determine the split of the stiffnesses (a flat profile): "
        + "; ".join(parts)
        + "; the intervals span the fit and the merged elements"
    )
    old = sol.message if sol.status == "not_identifiable" else ""
    return replace(sol, status="not_identifiable", standard_error=se, confidence_interval=ci,
                   covariance=cov, message="; ".join(x for x in (message, old) if x))  # fmt: skip
