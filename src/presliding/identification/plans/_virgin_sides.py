"""``fit_virgin_curve(asymmetric=True)``: both branches of the virgin curve from the symmetric fit.

The samples of ramps in +y and in −y with their side (`fit_virgin`: the + branch first, each
sorted by s; the result's `records` are the two branches), the symmetric fit of the
same samples done: the problem of both branches (`problem._sided_virgin`) solved from the
symmetric fit lifted (c1⁻ = c1, r_j⁻ = r_j: the nested start) and from it with the − branch
scaled to its level (`SidedVirgin.side_ratio`), the better kept; the result carries F_c⁺ and
F_c⁻ and the test of the asymmetry (`judge._asymmetry`: the constraints c1⁻ = c1 and
r_j⁻ = r_j).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from presliding.identification._fit_engine import FitPlan, FitRun, Found, cost, run_fit
from presliding.identification.fit_result import FitResult
from presliding.identification.judge._asymmetry import asymmetry_test, hac_scale
from presliding.identification.problem._fit_options import (
    check_enough,
    check_fit_options,
    element_count,
)
from presliding.identification.problem._fit_problem import FitOptions
from presliding.identification.problem._parameters import resolve_parameters
from presliding.identification.problem._separable_adequacy import separable_adequacy
from presliding.identification.problem._sided_virgin import SidedVirgin
from presliding.identification.result._fit_progress import as_reporter

__all__ = ["fit_branches"]

FloatArray = NDArray[np.float64]


def fit_branches(request: dict[str, Any], symmetric: FitResult, s: FloatArray, fv: FloatArray,
                 side: FloatArray) -> FitResult:  # fmt: skip
    """The asymmetric virgin-curve fit of `request` (the arguments of `fit_virgin_curve`)
    from its `symmetric` fit (module notes)."""
    initial, bounds, fixed, tied = resolve_parameters(
        request["initial"], request["bounds"], request["fixed"], request["tied"])  # fmt: skip
    fixed, tied, level, _, max_evaluations, tolerance = check_fit_options(
        fixed, tied, request["level"], request["grid_size"], request["max_evaluations"],
        request["tolerance"])  # fmt: skip
    sided = SidedVirgin(s, fv, side, element_count(request["n_elements"],
                                                   request["thresholds"], 3))  # fmt: skip
    check_enough(s.shape[0], len(sided.names), "virgin-curve samples")
    problem = sided.problem(sided.lifted(symmetric.parameters), float(s[0]), fixed, tied,
                            bounds, initial)  # fmt: skip

    def search(run: FitRun) -> Found:
        tries = [run.solve(), run.solve(sided.lifted(symmetric.parameters, sided.side_ratio()))]
        best = min(tries, key=cost)
        return Found(best, 2, sum(1 for t in tries if cost(t) <= cost(best) * 1.001))

    def result(run: FitRun, sol: Any, boot: Any, found: Any) -> FitResult:
        model = sided.model(sol.values)
        levels = {} if model is None else dict(zip(("coulomb_level", "coulomb_level_negative"),
                                                   model.coulomb_levels, strict=True))  # fmt: skip
        out = FitResult.from_solution(
            sol, model, s, fv, sided.fitted(np.array([sol.values[x] for x in sided.names])),
            kind="virgin curve", abscissa_label="s = travel from rest",
            signal_label="virgin-curve force", signal_unit="N", derived=levels,
        )  # fmt: skip
        rows = [{"coulomb_negative": 1.0, "coulomb": -1.0}] + [
            {m: 1.0, p: -1.0} for p, m in zip(sided.r_names, sided.rn_names, strict=True)
        ]
        held = set(fixed) | set(tied)  # a negative side held: its constraint is not tested
        rows = [r for r in rows if not {x for x, w in r.items() if w > 0} & held]
        kappa = hac_scale(sol, rows) if rows else float("nan")
        test = asymmetry_test(symmetric, out, rows, kappa, level)
        ups = int(np.sum(side > 0))  # the two branches drawn apart, as two records
        return replace(out, asymmetry=test, records=((0, ups), (ups, int(s.shape[0]))),
                       n_evaluations=out.n_evaluations + symmetric.n_evaluations)  # fmt: skip

    options = FitOptions(
        level, max_evaluations, tolerance, progress=as_reporter(request["progress"])
    )
    plan = FitPlan(search=search, result=result, adequacy=lambda run, sol: separable_adequacy(
        cast(Any, _Branches(sided)), sol, {"s": s}, signal="virgin-curve force",
        span=float(s.max()) if sided.n else None))  # fmt: skip
    return run_fit(problem, options, plan)


class _Branches:
    """The two branches as the residual tests read a separable problem: every sample used,
    the force the target, the elements' columns min(s, r)."""

    def __init__(self, sided: SidedVirgin):
        self.sided, self.target = sided, sided.force
        self.used = np.arange(sided.s.shape[0])

    def _q(self, values: Any) -> FloatArray:
        return np.array([values[x] for x in self.sided.names] if isinstance(values, Mapping)
                        else values, dtype=float)  # fmt: skip

    def fitted(self, values: Any) -> FloatArray:
        return self.sided.fitted(self._q(values))

    def residual(self, values: Any) -> FloatArray:
        return self.sided.residual(self._q(values))

    def jacobian(self, values: Any) -> FloatArray:
        return self.sided.jacobian(self._q(values))

    def basis(self, thresholds: FloatArray) -> tuple[FloatArray]:
        return (np.minimum(self.sided.s[:, None], np.asarray(thresholds)[None, :]),)
