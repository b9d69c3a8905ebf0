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
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._validation import (
    as_bounds,
    as_choice,
    as_positive_scalar,
    as_real_scalar,
    fmt,
)
from presliding.identification._covariance import fit_covariance
from presliding.identification._fit_options import (  # noqa: F401 (their home before)
    check_budget,
    check_constraints,
    check_options,
)
from presliding.identification._profile import Profiler
from presliding.identification._status import STATUSES as STATUSES
from presliding.identification._structured_lm import free_limit, levenberg_marquardt
from presliding.identification.uncertainty import (
    bounded_interval,
    full_covariance,
)

FloatArray = NDArray[np.float64]
Tie = str | tuple[str, float] | tuple[str, float, float]

_LISTED = 6  # names listed in a message before "and N more"
#: residuals × free parameters² above which a structured problem takes `levenberg_marquardt`
LARGE_PROBLEM = 2e7


# ---------------------------------------------------------------------- parameters
@dataclass(frozen=True)
class _Map:
    """full = T @ free + const, for the free/fixed/tied split of named parameters."""

    names: tuple[str, ...]
    free: tuple[str, ...]
    matrix: FloatArray
    const: FloatArray

    def full(self, free: FloatArray) -> FloatArray:
        return self.matrix @ free + self.const


def _parameter_map(
    names: tuple[str, ...],
    fixed: Mapping[str, float],
    tied: Mapping[str, Tie],
) -> _Map:
    for label, spec in (("fixed", fixed), ("tied", tied)):
        for n in spec:
            if n not in names:
                raise ValueError(
                    f"`{label}` must name parameters of the fit ({fmt(list(names))}); got {n!r}."
                )
    both = set(fixed) & set(tied)
    if both:
        raise ValueError(f"a parameter cannot be both fixed and tied; got {sorted(both)}.")
    free = tuple(n for n in names if n not in fixed and n not in tied)
    col = {n: i for i, n in enumerate(free)}
    matrix = np.zeros((len(names), len(free)))
    const = np.zeros(len(names))

    def resolve(n: str, seen: tuple[str, ...]) -> tuple[FloatArray, float]:
        if n in seen:
            raise ValueError(f"`tied` must not form a cycle; got {' -> '.join((*seen, n))}.")
        if n in fixed:
            return np.zeros(len(free)), float(fixed[n])
        if n not in tied:
            row: FloatArray = np.zeros(len(free))
            row[col[n]] = 1.0
            return row, 0.0
        spec = tied[n]
        target, factor, shift = (spec, 1.0, 0.0) if isinstance(spec, str) else (*spec, 0.0)[:3]
        if target not in names:
            raise ValueError(f"`tied` target of {n!r} must be a parameter; got {target!r}.")
        row, c = resolve(target, (*seen, n))
        return float(factor) * row, float(factor) * c + float(shift)

    for i, n in enumerate(names):
        matrix[i], const[i] = resolve(n, ())
    return _Map(names, free, matrix, const)


def _free_bounds(pm: _Map, lower: FloatArray, upper: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Bounds on the free parameters implied by the bounds of every parameter."""
    lo = np.full(len(pm.free), -np.inf)
    hi = np.full(len(pm.free), np.inf)
    for i in range(len(pm.names)):
        row = pm.matrix[i]
        nz = np.flatnonzero(row)
        if nz.size != 1:
            continue
        j, f = int(nz[0]), row[nz[0]]
        a, b = (lower[i] - pm.const[i]) / f, (upper[i] - pm.const[i]) / f
        lo[j], hi[j] = max(lo[j], min(a, b)), min(hi[j], max(a, b))
    return lo, hi


# ---------------------------------------------------------------------- solver
@dataclass(frozen=True)
class Solution:
    """Outcome of `solve_least_squares` (values and errors of every parameter)."""

    values: dict[str, float]
    standard_error: dict[str, float]
    confidence_interval: dict[str, tuple[float, float]]
    level: float
    fixed: tuple[str, ...]
    tied: tuple[str, ...]
    residual: FloatArray
    status: str
    message: str
    n_evaluations: int
    covariance: FloatArray | None = None  # over every parameter, in the order of `values`
    bandwidths: tuple[int, ...] = ()  # HAC bandwidth of each block (empty: independent)
    at_bounds: tuple[str, ...] = ()
    free: tuple[str, ...] = ()
    bounds: dict[str, tuple[float, float]] = field(default_factory=dict)  # the finite ones
    #: how each free parameter's interval was formed ("profile" or "wald"; empty: not yet)
    interval_method: dict[str, str] = field(default_factory=dict)
    #: tied name -> (target, factor, offset)
    ties: dict[str, tuple[str, float, float]] = field(default_factory=dict)
    profiler: Any = field(default=None, repr=False, compare=False)  # `_profile.Profiler`


def name_list(names: Any, order: tuple[str, ...]) -> str:
    """Names in parameter order, at most a few, then "and N more"."""
    rank = {n: i for i, n in enumerate(order)}
    ordered = sorted(set(names), key=lambda n: (rank.get(n, len(rank)), n))
    shown = ", ".join(ordered[:_LISTED])
    return shown + (f" and {len(ordered) - _LISTED} more" if len(ordered) > _LISTED else "")


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
    residual_size: int = 0,
    step_limit: Callable[[FloatArray], FloatArray] | None = None,
    method: str = "auto",
    progress: Any = None,
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
        record-level sandwich (`hac_covariance`).
    progress : FitProgress, optional
        Counts the residual evaluations and shows them with the cost
        (`presliding.identification._fit_progress`); it does not change the result.

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
    from scipy import optimize, stats
    from threadpoolctl import threadpool_limits

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
    evaluations = 0
    if pm.free:
        evaluate = residual if progress is None else progress.counting(residual)

        def fun(x: FloatArray) -> FloatArray:
            return evaluate(pm.full(x))

        jac: Any = difference
        if jacobian is not None:

            def jac(x: FloatArray) -> FloatArray:
                return jacobian(pm.full(x)) @ pm.matrix

        elif free_jacobian is not None:

            def jac(x: FloatArray) -> Any:
                out = free_jacobian(pm, x, lo, hi)
                return out if large or not hasattr(out, "toarray") else out.toarray()

        # Large structured problems: the trust-region method would factor the
        # whole Jacobian every iteration; LM on the small normal equations does not.
        large = free_jacobian is not None and (
            method == "lm"
            or (method == "auto" and residual_size * len(pm.free) ** 2 > LARGE_PROBLEM)
        )
        gtol = tolerance if gradient_tolerance is None else gradient_tolerance
        try:
            with threadpool_limits(limits=1, user_api="blas"):
                if large:
                    res = levenberg_marquardt(
                        fun, jac, x0, lo, hi, ftol=tolerance, xtol=tolerance, gtol=gtol,
                        max_nfev=max_evaluations, step_limit=free_limit(pm, step_limit),
                    )  # fmt: skip
                else:
                    res = optimize.least_squares(
                        fun, x0, jac=jac, bounds=(lo, hi), method="trf", x_scale="jac",
                        tr_solver="exact", ftol=tolerance, xtol=tolerance, gtol=gtol,
                        max_nfev=max_evaluations,
                    )  # fmt: skip
        except (ValueError, np.linalg.LinAlgError, FloatingPointError) as exc:
            return _failed(pm, x0, fixed, tied, level, f"the optimiser failed: {exc}")
        x, r, jac_free, evaluations = res.x, res.fun, res.jac, int(res.nfev)
        # a parameter the solver left on a bound is reported exactly there (0, not 1e-69)
        x = np.where(res.active_mask < 0, lo, np.where(res.active_mask > 0, hi, x))
        on_bound = tuple(n for n, a in zip(pm.free, res.active_mask, strict=True) if a != 0)
        if on_bound:
            r = fun(x)
        status = "max_evaluations" if res.status == 0 else "converged"
        message = (
            "stopped at the evaluation limit before convergence"
            if res.status == 0
            else f"converged ({res.message.rstrip('.')})"
        )
        if not np.all(np.isfinite(r)):
            return _failed(pm, x, fixed, tied, level, "the residual is not finite at the optimum")
        if not np.any(jac_free):
            return _failed(
                pm, x, fixed, tied, level,
                "the residual does not change with any parameter (insensitive or failed model)",
            )  # fmt: skip
    else:
        x, r, jac_free, on_bound = x0, residual(pm.full(x0)), np.zeros((0, 0)), ()
        status, message = "converged", "all parameters are fixed; nothing was fitted"
    widths: tuple[int, ...] = ()
    with threadpool_limits(limits=1, user_api="blas"):  # tall, thin factorisations
        cov, undetermined, found = fit_covariance(
            jac_free, r, blocks if pm.free else None, clusters
        )
        widths = tuple(found)
    full = pm.full(x)
    var = np.einsum("ij,jk,ik->i", pm.matrix, cov, pm.matrix) if pm.free else np.zeros(len(names))
    se = np.sqrt(np.maximum(var, 0.0))
    for j in undetermined:
        se[pm.matrix[:, j] != 0] = np.inf
    if undetermined and status == "converged":
        status = "not_identifiable"
        which = {names[i] for j in undetermined for i in np.flatnonzero(pm.matrix[:, j])}
        message = f"the data do not determine {name_list(which, names)} (singular Jacobian)"
    dof = max(r.shape[0] - len(pm.free), 1)
    q = float(stats.t.ppf(0.5 + level / 2, dof))
    profiler = None
    if pm.free:
        profiler = Profiler(
            lambda x: residual(pm.full(x)), jac if callable(jac) else None, pm.free, lo, hi, q,
            free_limit(pm, step_limit),
        )  # fmt: skip
    return Solution(
        values=dict(zip(names, full.tolist(), strict=True)),
        standard_error=dict(zip(names, se.tolist(), strict=True)),
        confidence_interval={
            n: bounded_interval(v, q * s, lower[i], upper[i])
            for i, (n, v, s) in enumerate(zip(names, full, se, strict=True))
        },
        level=level,
        fixed=tuple(fixed),
        tied=tuple(tied),
        residual=r,
        status=status,
        message=message,
        n_evaluations=evaluations,
        covariance=full_covariance(pm.matrix, cov, se),
        bandwidths=widths,
        at_bounds=on_bound,
        free=pm.free,
        bounds={
            n: (float(a), float(b))
            for n, a, b in zip(names, lower, upper, strict=True)
            if np.isfinite(a) or np.isfinite(b)
        },
        ties=_ties(tied),
        profiler=profiler,
    )


def _ties(tied: Mapping[str, Tie]) -> dict[str, tuple[str, float, float]]:
    """Each tie as (target, factor, offset): p = factor·target + offset."""
    out = {}
    for n, spec in tied.items():
        target, factor, shift = (spec, 1.0, 0.0) if isinstance(spec, str) else (*spec, 0.0)[:3]
        out[n] = (str(target), float(factor), float(shift))
    return out


def _failed(pm: _Map, x: FloatArray, fixed: Any, tied: Any, level: float, msg: str) -> Solution:
    full = pm.full(x)
    inf = dict.fromkeys(pm.names, float("inf"))
    return Solution(
        values=dict(zip(pm.names, full.tolist(), strict=True)),
        standard_error=inf,
        confidence_interval={n: (-np.inf, np.inf) for n in pm.names},
        level=level,
        fixed=tuple(fixed),
        tied=tuple(tied),
        residual=np.zeros(0),
        status="failed",
        message=msg,
        n_evaluations=0,
        free=pm.free,
    )
