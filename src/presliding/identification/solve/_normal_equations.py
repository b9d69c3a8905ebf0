"""The normal equations of a least-squares problem: JᵀJ and its scaled pseudo-inverse.

The profile walk (`_profile_walk`), the choice of the parameters to profile
(`_profile`), the far step along the least determined split (`_flat_probe`), the
comparison of second optima (`_alternatives`) and the quasi-static errors
(`_quasi_static_errors`) all read the curvature of the cost ‖r‖² from the
Jacobian J of the residual: A = JᵀJ (half the Gauss–Newton Hessian) and its
inverse h = A⁻¹, whose diagonal gives the Wald variances up to s².

The inverse is a pseudo-inverse of A scaled to a unit diagonal
(D⁻¹AD⁻¹, D = diag(√A_jj)): the parameters' scales differ by many orders
(a mass in kg, stiffnesses in N/m, initial positions in m), and an undetermined
direction shows as a small eigenvalue of the scaled matrix, cut at a relative
1e-12, not as a column scale.

`profile_thresholds` gives each free parameter's profile threshold
P_j = (t·SE_j)²/h_jj (`_profile`), the cost rise within which another point
is as good as the optimum for that parameter (the split check, second optima).

A parameter on a bound whose column vanishes there (`flat_on_bound`: a preload saturated
in the direction of the motion) has no such threshold: SE_p and h_pp both go to infinity,
each cut by a different rank tolerance. It and the parameters whose intervals its profile
widened (``interval_method`` "partner", `_profile_bound`) take the level of that profile,
`carried_threshold`: the largest P_j of the others outside the flat column's record (a
record's own errors carry that column in some share, each cut differently: one of them
had a threshold a thousand times the others'), h computed without those (a column small but
not zero would enter h through the pseudo-inverse's scaling), or t²·s² where every free
parameter is carried.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import sparse

__all__ = [
    "NEAR_FLAT",
    "carried_threshold",
    "flat_on_bound",
    "inverse_normal",
    "normal_matrix",
    "profile_thresholds",
    "record_of",
    "scaled_pinv",
    "thresholds",
]

FloatArray = NDArray[np.float64]


def normal_matrix(jac: Any) -> FloatArray:
    """JᵀJ, dense p × p (from a dense or a sparse Jacobian)."""
    a = (jac.T @ jac).toarray() if sparse.issparse(jac) else jac.T @ jac
    return np.asarray(a, dtype=float)


def scaled_pinv(a: FloatArray) -> FloatArray:
    """The inverse of a symmetric matrix by a pseudo-inverse of its unit-diagonal scaling."""
    d = np.sqrt(np.maximum(np.diag(a), 0.0))
    d[d == 0] = 1.0
    return np.linalg.pinv(a / np.outer(d, d), rcond=1e-12) / np.outer(d, d)


def inverse_normal(jac: Any) -> FloatArray:
    """(JᵀJ)⁻¹ by the scaled pseudo-inverse (dense p × p)."""
    return scaled_pinv(normal_matrix(jac))


def thresholds(hinv: FloatArray, standard_error: FloatArray, quantile: float) -> FloatArray:
    """P_j = (t·SE_j)²/h_jj for each parameter (h = (JᵀJ)⁻¹, t the `quantile`); NaN where the
    error is not finite and positive or h_jj is not positive."""
    diag = np.diag(hinv)
    usable = np.isfinite(standard_error) & (standard_error > 0) & (diag > 0)
    out = np.full(diag.shape[0], np.nan)
    out[usable] = (quantile * standard_error[usable]) ** 2 / diag[usable]
    return out


#: Distance from a bound, as a share of the range, within which a flat column counts as on it
#: (a solver stops a saturated preload at 1 − 3e-5 as well as on 1).
NEAR_FLAT = 1e-3


def flat_on_bound(lower: FloatArray, upper: FloatArray, x: FloatArray, standard_error: FloatArray,
                  quantile: float) -> list[int]:  # fmt: skip
    """The free parameters on (or within `NEAR_FLAT` of) a finite bound whose Wald half width
    t·SE spans their range: a column that vanishes there (an infinite error where it is
    exactly zero)."""
    out = []
    for i in range(x.shape[0]):
        lo, hi = lower[i], upper[i]
        if not (np.isfinite(lo) and np.isfinite(hi)):
            continue
        near = min(x[i] - lo, hi - x[i]) <= NEAR_FLAT * (hi - lo)
        if near and not quantile * standard_error[i] < hi - lo:  # an infinite error too
            out.append(i)
    return out


#: The names of a record's own parameters: ``<prefix>_<record>`` in a pooled fit, the
#: prefix alone in a fit of one record.
_OWN = re.compile(r"^(initial_position|initial_velocity|preload_fraction)(?:_(\d+))?$")


def record_of(name: str) -> str | None:
    """The record of a record's own parameter: its number in a pooled fit, "" in a fit of
    one record; None for the shared parameters."""
    m = _OWN.match(name)
    return (m.group(2) or "") if m else None


def _records(names: Sequence[str], among: list[int]) -> set[int]:
    """The columns of every record's own parameters of which one is in `among`."""
    tags = {record_of(names[i]) for i in among} - {None}
    return {i for i, n in enumerate(names) if record_of(n) in tags}


def carried_threshold(normal: FloatArray, standard_error: FloatArray, quantile: float,
                      exclude: list[int], names: Sequence[str] = ()) -> float:  # fmt: skip
    """The largest finite P_j of the free parameters not in `exclude` nor of the records of
    the parameters in `exclude` (`names`: their errors carry the flat column in some share),
    h the inverse of JᵀJ without those (module notes); NaN where there is none."""
    out = set(exclude) | (_records(names, exclude) if names else set())
    keep = np.array([i for i in range(normal.shape[0]) if i not in out], dtype=int)
    if keep.size == 0:
        return float("nan")
    limits = thresholds(scaled_pinv(normal[np.ix_(keep, keep)]), standard_error[keep], quantile)
    limits = limits[np.isfinite(limits) & (limits > 0)]
    return float(np.max(limits)) if limits.size else float("nan")


def profile_thresholds(sol: Any) -> dict[str, float]:
    """The profile's threshold P_j = (t·SE_j)²/h_jj of each free parameter of a solution
    (`_least_squares.Solution` with its profiler), from the Jacobian at its values; the
    carried level for a column flat on its bound and the parameters it widened (module
    notes). Only parameters with a finite, positive threshold (empty when JᵀJ is not
    finite)."""
    prof = sol.profiler
    x = np.array([sol.values[n] for n in prof.free], dtype=float)
    normal = normal_matrix(prof.jacobian(x))
    if not np.all(np.isfinite(normal)):
        return {}
    ses = np.array([sol.standard_error.get(n, np.inf) for n in prof.free], dtype=float)
    flat = flat_on_bound(prof.lower, prof.upper, x, ses, prof.quantile)
    crits = np.full(x.shape[0], np.nan)
    keep = np.array([i for i in range(x.shape[0]) if i not in flat], dtype=int)
    if keep.size:
        crits[keep] = thresholds(scaled_pinv(normal[np.ix_(keep, keep)]), ses[keep], prof.quantile)
    methods = getattr(sol, "interval_method", {}) or {}
    carried = [i for i, n in enumerate(prof.free) if i in flat or methods.get(n) == "partner"]
    if flat:
        level = carried_threshold(normal, ses, prof.quantile, carried, prof.free)
        if not np.isfinite(level):  # every free parameter carried: independent residuals'
            r = np.asarray(sol.residual, dtype=float)
            level = prof.quantile**2 * float(r @ r) / max(r.shape[0] - x.shape[0], 1)
        crits[carried] = level
    return {n: float(c) for n, c in zip(prof.free, crits, strict=True) if np.isfinite(c)}
