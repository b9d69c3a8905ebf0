"""The fitting problem every ``fit_*`` builds: parameters, residual, Jacobian structure.

A `FitProblem` is what a fit minimises, frozen once the arguments are checked:
the named parameters (`names`) with their start values (`start`), `bounds`,
`fixed` values and `tied` parameters; the residual and its Jacobian; the model
(`spec`, a `_model_spec.ModelSpec`, for the pooled fits) and the records
(`records`, a `_pooled_problem.PooledProblem`: their layout in the residual,
the blocks of rows each record's own parameters touch, the trust box).

Two kinds share the one type:

* a *record-pooled* problem (`fit_response`, `fit_quasi_static`): `records`
  given; its residual and structured Jacobian come from the records'
  compiled simulation, with a hinge row for a lower bound on a derived F_c
  (`penalty`), a rigid variant of the stiffest element, and the HAC
  covariance over the records' blocks;
* a *direct* problem (the separable fits `fit_presliding`, `fit_motion`,
  `fit_virgin_curve`): `residual_function` and `jacobian_function` of the
  vector of every parameter.

`FitProblem.solve` runs the least-squares core (`_least_squares`) from a start;
`FitOptions` holds the options every solve of one fit shares. The steps every
fit runs (search, checks, judge, intervals, result) are in `_fit_engine`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding.identification.solve._least_squares import Solution, Tie, solve_least_squares

FloatArray = NDArray[np.float64]

__all__ = ["FitOptions", "FitProblem"]


@dataclass(frozen=True)
class FitOptions:
    """The options every solve of one fit shares (checked by the fit on entry)."""

    level: float
    max_evaluations: int | None
    tolerance: float
    gradient_tolerance: float | None = None  # None: `tolerance`
    progress: Any = None  # a `_fit_progress.FitProgress`, or None

    def solver(self) -> dict[str, Any]:
        """The keyword arguments of `solve_least_squares` they give."""
        return {"level": self.level, "max_evaluations": self.max_evaluations,
                "tolerance": self.tolerance, "gradient_tolerance": self.gradient_tolerance,
                "progress": self.progress}  # fmt: skip


@dataclass(frozen=True, eq=False)
class FitProblem:
    """What a fit minimises (module notes)."""

    names: tuple[str, ...]
    initial: Mapping[str, float]
    bounds: Mapping[str, tuple[float, float]]
    fixed: Mapping[str, float]
    tied: Mapping[str, Tie]
    residual_function: Callable[[FloatArray], FloatArray] | None = None
    jacobian_function: Callable[[FloatArray], FloatArray] | None = None
    records: Any = None  # a `PooledProblem` (record-pooled problems)
    spec: Any = None  # a `ModelSpec` (record-pooled problems)
    penalty: float | None = None  # lower bound on a derived F_c, as a hinge row
    method: str = "auto"  # of `solve_least_squares`

    def __post_init__(self) -> None:
        """Every start value finite, or an error naming the one that is not (a NaN start
        made every evaluation NaN: a fit ran minutes without ending)."""
        for x in self.names:
            value = self.initial.get(x, 0.0)
            if x not in self.fixed and not np.isfinite(value):
                raise ValueError(
                    f"the start value of `{x}` came out {value} from the data (too few "
                    "moving samples for a start of it?); give it in `initial`."
                )

    # ------------------------------------------------------------ what is minimised
    def start(self) -> dict[str, float]:
        """The start values of every parameter, in `names` order."""
        return {x: self.initial[x] for x in self.names}

    @property
    def free(self) -> tuple[str, ...]:
        """The parameters the fit varies (neither fixed nor tied)."""
        return tuple(x for x in self.names if x not in self.fixed and x not in self.tied)

    def objective(self, rigid: bool = False) -> tuple[Callable, Callable | None]:
        """``(residual, jacobian)``: of every parameter (direct), or the records' residual
        and their structured Jacobian over the free parameters (record-pooled)."""
        if self.records is None:
            assert self.residual_function is not None
            return self.residual_function, self.jacobian_function
        from presliding.identification.records._penalty import with_penalty

        return with_penalty(self.records, rigid, self.penalty)

    def residual(self, x: FloatArray) -> FloatArray:
        """The residual at the vector `x` of every parameter (`names` order)."""
        return self.objective()[0](np.asarray(x, dtype=float))

    def jacobian(self, x: FloatArray) -> Any:
        """The Jacobian of the residual over every parameter at `x` (a record-pooled
        problem's structured one, dense or sparse, with all parameters free)."""
        jac = self.objective()[1]
        x = np.asarray(x, dtype=float)
        if jac is None:
            raise ValueError("this problem has no Jacobian of its own (finite differences).")
        if self.records is None:
            return jac(x)
        from presliding.identification.problem._parameter_map import parameter_map

        pm = parameter_map(self.names, {}, {})
        inf = np.full(len(self.names), np.inf)
        return jac(pm, x, -inf, inf)

    # ------------------------------------------------------------ one local solve
    def solve(
        self,
        options: FitOptions,
        begin: Mapping[str, float] | None = None,
        *,
        rigid: bool = False,
        extra: Mapping[str, float] | None = None,
        **overrides: Any,
    ) -> Solution:
        """The least-squares solve from `begin` (default: the start), `extra` values held
        besides `fixed`, `overrides` of the options (``max_evaluations=...``)."""
        begin = self.start() if begin is None else begin
        kw = {**options.solver(), **overrides}
        fun, jac = self.objective(rigid)
        if self.records is None:
            return solve_least_squares(fun, begin, jacobian=jac, bounds=self.bounds,
                                       fixed=self.fixed, tied=self.tied, **kw)  # fmt: skip
        rec = self.records
        return solve_least_squares(
            fun, begin, fixed={**self.fixed, **(extra or {})}, tied=self.tied,
            bounds=self.bounds, free_jacobian=jac, blocks=[rows for _, rows in rec.rows],
            residual_size=rec.n_res, clusters=[i for i, _ in rec.rows],
            links=getattr(rec, "links", None),
            step_limit=rec.step_limit, method=self.method, **kw,
        )  # fmt: skip
