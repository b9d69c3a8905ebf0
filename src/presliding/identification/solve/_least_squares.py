"""The least-squares solver shared by the ``fit_*`` functions (scipy.optimize.least_squares).

`solve_least_squares` minimises a sum of squared residuals over named
parameters with the trust-region reflective method, bounds respected.
Parameters may be held *fixed* at a value or *tied* to another one
(p = factor·q); only the remaining *free* parameters are varied (`_Map`).

Uncertainty follows the usual linearisation at the optimum: with the Jacobian
J of the residuals with respect to the free parameters, n residuals and p free
parameters, the covariance is s²·(JᵀJ)⁻¹ with s² = ‖r‖²/(n − p); tied
parameters inherit it through their factor, fixed ones have zero error. The
confidence interval is value ± t_{n−p}·SE (Student t at the chosen level); where it would
cross a bound of the parameter (a nonnegative one below 0), the data do not exclude the
bound: the interval reaches it, and its far end is taken on a log scale from the bound
(`bounded_interval`), so it never leaves the parameter's range. It
is exact for parameters that enter linearly and Gaussian independent noise, a
first-order approximation otherwise. A direction of parameter space that the
data do not determine (a singular JᵀJ) makes the affected errors infinite and
the status ``"not_identifiable"``. The outcome is a `Solution`;
`fitting.FitResult` turns it into the public result.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import sparse

from presliding._validation import (
    as_bounds,
    as_choice,
    as_positive_scalar,
    as_real_scalar,
    fmt,
)
from presliding.identification.intervals._covariance import fit_covariance
from presliding.identification.intervals._profile import Profiler
from presliding.identification.judge._status import STATUSES as STATUSES
from presliding.identification.problem._fit_options import (  # noqa: F401 (their home before)
    check_budget,
    check_constraints,
    check_options,
)
from presliding.identification.problem._parameter_map import ParameterMap as _Map
from presliding.identification.problem._parameter_map import free_bounds as _free_bounds
from presliding.identification.problem._parameter_map import parameter_map as _parameter_map
from presliding.identification.solve._deferred import complete, deferred_solution, dense, verdict
from presliding.identification.solve._solution import Solution, name_list, solution_of
from presliding.identification.solve._structured_lm import (
    free_limit,
    levenberg_marquardt,
    one_blas_thread,
)
from presliding.identification.uncertainty import (
    bounded_interval,
    full_covariance,
)

FloatArray = NDArray[np.float64]
Tie = str | tuple[str, float] | tuple[str, float, float]
__all__ = [
    "LARGE_PROBLEM",
    "STATUSES",
    "Solution",
    "Tie",
    "complete",
    "name_list",
    "solve_least_squares",
]

#: residuals × free parameters² above which a structured problem takes `levenberg_marquardt`
LARGE_PROBLEM = 2e7


# ---------------------------------------------------------------------- solver
def solve_least_squares(
    residual: Callable[[FloatArray], FloatArray],
    initial: Mapping[str, float],
    *,
    jacobian: Callable[[FloatArray], FloatArray] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    fixed: Mapping[str, float] | None = None,
    tied: Mapping[str, Tie] | None = None,
    level: float = 0.95,
    max_evaluations: int | None = None,
    tolerance: float = 1e-8,
    difference: str = "3-point",
    gradient_tolerance: float | None = None,
    free_jacobian: Callable[..., FloatArray] | None = None,
    blocks: Any = None,
    clusters: Any = None,
    links: Any = None,
    residual_size: int = 0,
    step_limit: Callable[[FloatArray], FloatArray] | None = None,
    method: str = "auto",
    progress: Any = None,
    errors: bool = True,
) -> Solution:
    """Minimise ‖residual(p)‖² over named parameters, some fixed or tied.

    Parameters
    ----------
    residual : callable
        ``residual(p) -> r`` with p the vector of *all* parameters, in the
        order of `initial`.
    initial : mapping name -> float
        Start values, real numbers (fixed parameters take their `fixed` value
        instead; a non-finite start becomes 0, and a start outside the bounds
        is moved onto them).
    jacobian : callable, optional
        ``jacobian(p) -> (len(r), len(p))`` array; default: 3-point differences.
    bounds : mapping name -> (lower, upper), optional
    fixed : mapping name -> value, optional
    tied : mapping name -> target, (target, factor) or (target, factor, offset), optional
        ``{"b": "a"}`` keeps b = a; ``{"b": ("a", 0.5)}`` keeps b = 0.5·a;
        ``{"b": ("a", 0.5, 1.0)}`` keeps b = 0.5·a + 1.
    level : float
        Confidence level of the intervals, in (0, 1).
    max_evaluations : int, optional
        Most residual evaluations (an integer >= 1); default: scipy's choice
        (100 per free parameter). Reaching it gives the status
        ``"max_evaluations"``.
    tolerance : float
        ftol, xtol and gtol of scipy.optimize.least_squares (positive).
    difference : {"3-point", "2-point"}
        Finite-difference scheme when no `jacobian` is given.
    gradient_tolerance : float, optional
        gtol of scipy.optimize.least_squares (default `tolerance`). Its test is
        absolute in the residual's units, so a fit whose residual vanishes at
        the optimum (noise-free data) may want a much smaller value and stop on
        the relative step and cost tests instead.
    free_jacobian : callable, optional
        ``free_jacobian(pm, x, lower, upper)``: the Jacobian with respect to the
        free parameters x (of the map `pm`, within their bounds), for callers
        that exploit its structure (the pooled fits).
    blocks : sequence of index arrays or slices, optional
        Rows of independent blocks of serially correlated residuals: the
        covariance is then the HAC sandwich of `presliding.identification.uncertainty`
        instead of s²·(JᵀJ)⁻¹; `clusters` (the record of each block) adds the
        record-level sandwich (`_covariance.fit_covariance`).
    links : sequence of `_covariance.Link`, optional
        Velocity blocks that are the difference quotient of a position block
        (`_covariance.fit_covariance`): no error is then below that of
        independent noise in the position.
    progress : FitProgress, optional
        Counts the residual evaluations and shows them with the cost
        (`presliding.identification.result._fit_progress`); it does not change the result.
    errors : bool
        False defers the covariance (of blocks of residuals, the costly part of a large
        pooled solve) for a solve that may be discarded (a start of a search): the
        solution then has the values, residual, status and message it would have, no
        errors yet, and `complete` gives the complete one (the same as with True).

    Returns
    -------
    Solution
        Values, standard errors and intervals of every parameter, the residual
        at the optimum, `status` (one of `STATUSES`) and `message`.

    Raises
    ------
    ValueError, TypeError
        On entry, for a bad option, an unknown parameter name, a fixed value
        that is not a finite real inside its bounds, a malformed tie or a cycle
        of ties.
    """
    setup = _setup(
        initial, bounds, fixed, tied, level, max_evaluations, tolerance, difference,
        gradient_tolerance, method,
    )  # fmt: skip
    if not setup.pm.free:
        return _solution(setup, _nothing_free(setup, residual), residual, None, None, blocks,
                         clusters, links)  # fmt: skip
    fun, jac, large = _objective(setup, residual, jacobian, free_jacobian, progress, residual_size)
    try:
        res = _minimise(setup, fun, jac, large, step_limit)
    except (ValueError, np.linalg.LinAlgError, FloatingPointError) as exc:
        return _failed(setup, setup.x0, f"the optimiser failed: {exc}")
    found = _outcome(setup, res, fun)
    if isinstance(found, Solution):
        return found
    complete = partial(_solution, setup, found, residual, jac, step_limit, blocks, clusters, links)
    deferred = None if errors else deferred_solution(setup, found, blocks, complete)
    return complete() if deferred is None else deferred


# ---------------------------------------------------------------------- the steps
@dataclass(frozen=True)
class _Setup:
    """One solve's checked options: the parameter map, bounds, start and tolerances."""

    names: tuple[str, ...]
    pm: _Map
    fixed: dict[str, float]
    tied: dict[str, Tie]
    level: float
    max_evaluations: int | None
    tolerance: float
    gtol: float
    difference: str
    method: str
    lower: FloatArray  # of every parameter
    upper: FloatArray
    lo: FloatArray  # of the free ones
    hi: FloatArray
    x0: FloatArray


@dataclass(frozen=True)
class _Found:
    """Where the optimiser stopped: free values, residual, Jacobian and its verdict."""

    x: FloatArray
    r: FloatArray
    jac_free: Any
    evaluations: int
    on_bound: tuple[str, ...]
    status: str
    message: str


def _setup(
    initial: Mapping[str, float], bounds: Any, fixed: Any, tied: Any, level: Any,
    max_evaluations: Any, tolerance: Any, difference: str, gradient_tolerance: Any, method: str,
) -> _Setup:  # fmt: skip
    """Every option checked on entry; the parameter map, the bounds and the start."""
    level, max_evaluations, tolerance = check_options(level, max_evaluations, tolerance)
    difference = as_choice("difference", difference, ("3-point", "2-point"))
    method = as_choice("method", method, ("auto", "trf", "lm"))
    if gradient_tolerance is not None:
        gradient_tolerance = as_positive_scalar("gradient_tolerance", gradient_tolerance)
    fixed, tied = check_constraints(fixed, tied)
    names = tuple(initial)
    bounds = as_bounds("bounds", bounds, names)
    pm = _parameter_map(names, fixed, tied)
    lower = np.array([bounds.get(n, (-np.inf, np.inf))[0] for n in names], dtype=float)
    upper = np.array([bounds.get(n, (-np.inf, np.inf))[1] for n in names], dtype=float)
    for n, v in fixed.items():
        i = names.index(n)
        if not lower[i] <= v <= upper[i]:
            raise ValueError(
                f"`fixed[{n!r}]` must lie in [{fmt(lower[i])}, {fmt(upper[i])}] (its bounds); "
                f"got {fmt(v)}."
            )
    lo, hi = _free_bounds(pm, lower, upper)
    x0 = np.array([as_real_scalar(f"initial[{n!r}]", initial[n], finite=False) for n in pm.free])
    x0 = np.where(np.isfinite(x0), x0, 0.0)
    x0 = np.clip(x0, lo, hi)  # start values of the caller's default guesses only
    gtol = tolerance if gradient_tolerance is None else gradient_tolerance
    return _Setup(names, pm, fixed, tied, level, max_evaluations, tolerance, gtol, difference,
                  method, lower, upper, lo, hi, x0)  # fmt: skip


def _objective(
    setup: _Setup, residual: Callable, jacobian: Callable | None, free_jacobian: Callable | None,
    progress: Any, residual_size: int,
) -> tuple[Callable, Any, bool]:  # fmt: skip
    """The residual and Jacobian over the free parameters, and whether the problem is large.

    Large structured problems go to `levenberg_marquardt`: the trust-region method
    would factor the whole Jacobian every iteration; LM on the small normal equations
    does not (a sparse Jacobian is kept sparse for it).
    """
    pm = setup.pm
    evaluate = residual if progress is None else progress.counting(residual)
    large = free_jacobian is not None and (
        setup.method == "lm"
        or (setup.method == "auto" and residual_size * len(pm.free) ** 2 > LARGE_PROBLEM)
    )

    def fun(x: FloatArray) -> FloatArray:
        return evaluate(pm.full(x))

    jac: Any = setup.difference
    if jacobian is not None:

        def jac(x: FloatArray) -> FloatArray:
            return jacobian(pm.full(x)) @ pm.matrix

    elif free_jacobian is not None:

        def jac(x: FloatArray) -> Any:
            out = free_jacobian(pm, x, setup.lo, setup.hi)
            return out if large or not hasattr(out, "toarray") else out.toarray()

    return fun, jac, large


def _minimise(setup: _Setup, fun: Callable, jac: Any, large: bool, step_limit: Any) -> Any:
    """The optimiser's run: structured LM for large problems, else scipy's trust region."""
    from scipy import optimize

    tol = setup.tolerance
    with one_blas_thread():
        if large:
            return levenberg_marquardt(
                fun, jac, setup.x0, setup.lo, setup.hi, ftol=tol, xtol=tol, gtol=setup.gtol,
                max_nfev=setup.max_evaluations, step_limit=free_limit(setup.pm, step_limit),
            )  # fmt: skip
        return optimize.least_squares(
            fun, setup.x0, jac=jac, bounds=(setup.lo, setup.hi), method="trf", x_scale="jac",
            tr_solver="exact", ftol=tol, xtol=tol, gtol=setup.gtol,
            max_nfev=setup.max_evaluations,
        )  # fmt: skip


def _outcome(setup: _Setup, res: Any, fun: Callable) -> _Found | Solution:
    """The optimiser's result read: values on a bound snapped to it, status and message
    (a failed `Solution` when the residual is not finite or moves with nothing)."""
    x, r, jac_free, evaluations = res.x, res.fun, res.jac, int(res.nfev)
    lo, hi = setup.lo, setup.hi
    # a parameter the solver left on a bound is reported exactly there (0, not 1e-69)
    x = np.where(res.active_mask < 0, lo, np.where(res.active_mask > 0, hi, x))
    on_bound = tuple(n for n, a in zip(setup.pm.free, res.active_mask, strict=True) if a != 0)
    if on_bound:
        r = fun(x)
    status = "max_evaluations" if res.status == 0 else "converged"
    message = (
        "stopped at the evaluation limit before convergence"
        if res.status == 0
        else f"converged ({res.message.rstrip('.')})"
    )
    if not np.all(np.isfinite(r)):
        return _failed(setup, x, "the residual is not finite at the optimum")
    if not (jac_free.count_nonzero() if sparse.issparse(jac_free) else np.any(jac_free)):
        return _failed(
            setup, x,
            "the residual does not change with any parameter (insensitive or failed model)",
        )  # fmt: skip
    return _Found(x, r, jac_free, evaluations, on_bound, status, message)


def _nothing_free(setup: _Setup, residual: Callable) -> _Found:
    """Every parameter fixed: the residual at the given values."""
    x = setup.x0
    return _Found(x, residual(setup.pm.full(x)), np.zeros((0, 0)), 0, (), "converged",
                  "all parameters are fixed; nothing was fitted")  # fmt: skip


def _solution(
    setup: _Setup, found: _Found, residual: Callable, jac: Any, step_limit: Any, blocks: Any,
    clusters: Any, links: Any = None,
) -> Solution:  # fmt: skip
    """The result: covariance (HAC for blocks), errors, intervals and the profiler."""
    from scipy import stats

    pm, names, r = setup.pm, setup.names, found.r
    widths: tuple[int, ...] = ()
    with one_blas_thread():  # tall, thin factorisations
        cov, undetermined, got = fit_covariance(
            dense(found.jac_free), r, blocks if pm.free else None, clusters, links
        )
        widths = tuple(got)
    full = pm.full(found.x)
    var = np.einsum("ij,jk,ik->i", pm.matrix, cov, pm.matrix) if pm.free else np.zeros(len(names))
    se = np.sqrt(np.maximum(var, 0.0))
    for j in undetermined:
        se[pm.matrix[:, j] != 0] = np.inf
    status, message = verdict(setup, found, undetermined)
    dof = max(r.shape[0] - len(pm.free), 1)
    q = float(stats.t.ppf(0.5 + setup.level / 2, dof))
    profiler = None
    if pm.free:
        profiler = Profiler(
            lambda x: residual(pm.full(x)), jac if callable(jac) else None, pm.free, setup.lo,
            setup.hi, q, free_limit(pm, step_limit),
        )  # fmt: skip
    lower, upper = setup.lower, setup.upper
    return solution_of(
        setup, found, status, message, standard_error=dict(zip(names, se.tolist(), strict=True)),
        confidence_interval={
            n: bounded_interval(v, q * s, lower[i], upper[i])
            for i, (n, v, s) in enumerate(zip(names, full, se, strict=True))
        },
        covariance=full_covariance(pm.matrix, cov, se), bandwidths=widths, profiler=profiler,
    )  # fmt: skip


def _failed(setup: _Setup, x: FloatArray, msg: str) -> Solution:
    pm = setup.pm
    full = pm.full(x)
    inf = dict.fromkeys(pm.names, float("inf"))
    return Solution(
        values=dict(zip(pm.names, full.tolist(), strict=True)),
        standard_error=inf,
        confidence_interval={n: (-np.inf, np.inf) for n in pm.names},
        level=setup.level,
        fixed=tuple(setup.fixed),
        tied=tuple(setup.tied),
        residual=np.zeros(0),
        status="failed",
        message=msg,
        n_evaluations=0,
        free=pm.free,
    )
