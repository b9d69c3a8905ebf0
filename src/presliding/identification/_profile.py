"""Profile-likelihood confidence intervals on top of the least-squares core.

The approach of lmfit's ``conf_interval``: for a parameter θ_j, hold it at a
value θ and re-optimise every other free parameter; the profile
P(θ) = χ²(θ) − χ²_min rises from 0 at the optimum, and the interval at level
α is where it stays below

    P_crit = t²_{n−p}(α) · SE_j² / h_jj,    h = (JᵀJ)⁻¹,

which is t²·s² (the F-test of lmfit, F_{1,n−p} = t²) for the ordinary
covariance s²·h, and keeps the HAC scaling (`uncertainty.hac_covariance`)
where the residuals are autocorrelated: the threshold is raised by the ratio of
the HAC variance to the ordinary one. For a model linear in its parameters the
profile is the quadratic (θ − θ̂)²/h_jj and the interval is exactly the Wald
(F) interval; otherwise it follows the data: asymmetric, or reaching a bound.

Each end is found by walking out from the optimum in steps of the Wald half
width, doubling, until the profile crosses P_crit, and then by Brent's method on
√P − √P_crit. An end past a bound the profile stays below is the bound (the
data do not exclude it); an end the profile never reaches within 2⁸ Wald
half widths, with no bound there, is unbounded (±inf), and the fit is then not
identifiable (`_status`). The inner optimisations use the structured
Levenberg–Marquardt of `_structured_lm` (dense or pooled sparse Jacobians),
warm-started on the linearised profile path x̂ + (θ − θ̂)·h[:, j]/h_jj.

`profile_solution` chooses the parameters ("auto"): every free parameter
whose Wald interval reaches a bound, is wide (half width above a quarter of the
value), or whose cost along the linearised path departs from the quadratic by
more than 10 % at either Wald end; `which` may name them instead. The shared
parameters go before the records' own, and among each those whose Wald interval a
bound cuts go first: the budget of inner optimisations (`BUDGET`) is spent where the
Wald interval says least.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import sparse

from presliding.identification._structured_lm import levenberg_marquardt

FloatArray = NDArray[np.float64]

#: Doublings of the Wald half width tried before an end is called unbounded.
MAX_DOUBLINGS = 8
#: Relative departure of the cost from its quadratic model that asks for a profile.
NONLINEAR = 0.1
#: Wald half width, as a share of the value, above which an interval is profiled.
WIDE = 0.25
#: Relative accuracy of √P at an interval end (1e-5: the end to about 1e-5 of the half width).
ROOT_TOL = 1e-5
#: Wald half width, as a multiple of the value, beyond which no profile is tried (the data
#: do not determine the parameter: the judge says so from the Wald interval).
HOPELESS = 100.0
#: Inner optimisations a profile step may spend (the rest keep their Wald interval).
BUDGET = 30


@dataclass(frozen=True, eq=False)
class Profiler:
    """What the profile needs of a solved problem, in the free coordinates."""

    fun: Callable[[FloatArray], FloatArray]
    jac: Callable[[FloatArray], Any] | None  # None: central differences
    free: tuple[str, ...]
    lower: FloatArray
    upper: FloatArray
    quantile: float  # t_{n−p} at the level
    step_limit: Callable[[FloatArray], FloatArray] | None = None

    def jacobian(self, x: FloatArray) -> Any:
        if self.jac is not None:
            return self.jac(x)
        r0 = self.fun(x)
        out = np.empty((r0.shape[0], x.shape[0]))
        for j in range(x.shape[0]):
            h = 1e-6 * max(abs(x[j]), 1e-8)
            a, b = x.copy(), x.copy()
            a[j] = min(x[j] + h, self.upper[j])
            b[j] = max(x[j] - h, self.lower[j])
            out[:, j] = (self.fun(a) - self.fun(b)) / (a[j] - b[j])
        return out


def _cost(r: FloatArray) -> float:
    return float(r @ r) if np.all(np.isfinite(r)) else np.inf


def _inverse_normal(jac: Any) -> FloatArray:
    """(JᵀJ)⁻¹ by a scaled pseudo-inverse (dense p × p)."""
    a = (jac.T @ jac).toarray() if sparse.issparse(jac) else jac.T @ jac
    a = np.asarray(a, dtype=float)
    d = np.sqrt(np.maximum(np.diag(a), 0.0))
    d[d == 0] = 1.0
    return np.linalg.pinv(a / np.outer(d, d), rcond=1e-12) / np.outer(d, d)


class _Walker:
    """Profile of one parameter: inner optimisations with a shared budget."""

    def __init__(self, prof: Profiler, x: FloatArray, c0: float, hinv: FloatArray, j: int):
        self.prof, self.x, self.c0, self.j = prof, x, c0, j
        self.keep = np.array([i for i in range(x.shape[0]) if i != j], dtype=int)
        self.path = hinv[self.keep, j] / hinv[j, j] if hinv[j, j] > 0 else np.zeros(len(self.keep))
        self.solves = 0

    def full(self, z: FloatArray, theta: float) -> FloatArray:
        out = self.x.copy()
        out[self.keep] = z
        out[self.j] = theta
        return out

    def __call__(self, theta: float, warm: tuple[float, FloatArray] | None) -> tuple:
        """(P(θ), the others at the optimum) for the parameter held at θ."""
        prof, keep = self.prof, self.keep
        lo, hi = prof.lower[keep], prof.upper[keep]
        base_t, base_z = warm if warm is not None else (self.x[self.j], self.x[keep])
        z0 = np.clip(base_z + (theta - base_t) * self.path, lo, hi)
        self.solves += 1
        if keep.size == 0:
            return _cost(prof.fun(self.full(z0, theta))) - self.c0, z0

        def fun(z: FloatArray) -> FloatArray:
            return prof.fun(self.full(z, theta))

        def jac(z: FloatArray) -> Any:
            out = prof.jacobian(self.full(z, theta))
            return out.tocsc()[:, keep] if sparse.issparse(out) else out[:, keep]

        limit = None
        if prof.step_limit is not None:
            step_limit = prof.step_limit

            def limit(z: FloatArray) -> FloatArray:
                return step_limit(self.full(z, theta))[keep]

        try:
            res = levenberg_marquardt(
                fun, jac, z0, lo, hi, ftol=1e-10, xtol=1e-9, gtol=1e-9,
                max_nfev=5 + keep.size, step_limit=limit,
            )  # fmt: skip
        except (ValueError, np.linalg.LinAlgError, FloatingPointError):
            return np.inf, z0
        return _cost(res.fun) - self.c0, res.x


def _end(walk: _Walker, side: int, half: float, threshold: float) -> float:
    """The interval end on `side` (±1): where P crosses `threshold`, a bound, or ±inf.

    Secant steps on g(θ) = √P(θ) − √P_crit (linear in θ for a linear model, so
    the first step, to the Wald end, is exact there) until the crossing is
    bracketed, then regula falsi with the Illinois rule.
    """
    prof, j = walk.prof, walk.j
    theta0 = float(walk.x[j])
    limit = float(prof.upper[j] if side > 0 else prof.lower[j])
    if theta0 == limit:
        return limit
    root = float(np.sqrt(threshold))

    def g_at(theta: float, warm: tuple) -> tuple[float, FloatArray]:
        p, z = walk(theta, warm)
        return (float(np.sqrt(max(p, 0.0))) - root if np.isfinite(p) else np.inf), z

    warm: tuple[float, FloatArray] = (theta0, walk.x[walk.keep])
    a, ga = theta0, -root
    theta = theta0 + side * half
    for _ in range(3 * MAX_DOUBLINGS):
        if (theta - limit) * side >= 0:
            theta = limit
        g, z = g_at(theta, warm)
        if g >= 0:
            break
        if theta == limit:
            return limit
        if theta == a:  # a step below the resolution of θ
            return theta
        slope = (g - ga) / (theta - a)
        a, ga, warm = theta, g, (theta, z)
        reach = abs(theta - theta0)
        if reach > 2.0**MAX_DOUBLINGS * half:
            return side * np.inf
        guess = -g / slope * side if slope * side > 0 else np.inf  # distance still to go
        theta += side * min(max(1.2 * guess, 0.25 * reach), reach)
    else:
        return side * np.inf
    if g > 1.0 * root:  # far past the threshold: a jump to another valley? try the linear path
        g2, _ = g_at(theta, (theta0, walk.x[walk.keep]))
        g = min(g, g2)
        if g < 0:
            return _end_from(walk, side, theta, g_at, threshold)
    if g <= ROOT_TOL * root:
        return theta
    state = {"warm": warm}

    def g_root(t: float) -> float:
        gt, zt = g_at(t, state["warm"])
        if gt < 0:
            state["warm"] = (t, zt)
        return gt

    from scipy.optimize import brentq

    try:
        return float(brentq(g_root, a, theta, xtol=1e-7 * abs(theta - theta0), rtol=1e-12,
                            maxiter=10))  # fmt: skip
    except (ValueError, RuntimeError):
        return float(theta)


def _end_from(walk: _Walker, side: int, theta: float, g_at: Any, threshold: float) -> float:
    """Continue the walk past `theta` (found inside the interval after a second start)."""
    return _end(walk, side, abs(theta - float(walk.x[walk.j])), threshold)


def wants_profile(
    prof: Profiler, x: FloatArray, c0: float, hinv: FloatArray, j: int, half: float,
    wald: tuple[float, float],
) -> bool:  # fmt: skip
    """The "auto" choice: bound reached, wide, or a cost that is not quadratic (module notes)."""
    v = float(x[j])
    if wald[0] > v - half or wald[1] < v + half or v in (prof.lower[j], prof.upper[j]):
        return True
    if half > WIDE * abs(v):
        return True
    step = half * hinv[:, j] / hinv[j, j]
    expected = half * half / hinv[j, j]
    for s in (-1.0, 1.0):
        xs = x + s * step
        if np.any(xs < prof.lower) or np.any(xs > prof.upper):
            return True
        rise = _cost(prof.fun(xs)) - c0
        if not abs(rise - expected) <= NONLINEAR * expected:
            return True
    return False


def profile_solution(sol: Any, which: str | Sequence[str] = "auto", budget: int = BUDGET) -> Any:
    """`sol` (a `Solution`) with profile intervals for the chosen free parameters.

    `which` is "auto" (module notes), "all", or the names to profile. The
    intervals of tied parameters follow their target's. `interval_method` names
    each free parameter's method ("profile" or "wald").
    """
    prof: Profiler | None = sol.profiler
    methods = dict.fromkeys(sol.free, "wald")
    if prof is None or sol.status == "failed" or not prof.free:
        return replace(sol, interval_method=methods)
    x = np.array([sol.values[n] for n in prof.free], dtype=float)
    r = prof.fun(x)
    c0 = _cost(r)
    if not np.isfinite(c0):
        return replace(sol, interval_method=methods)
    hinv = _inverse_normal(prof.jacobian(x))
    q = prof.quantile
    ci = dict(sol.confidence_interval)
    spent = 0
    order = sorted(
        range(len(prof.free)),
        key=lambda i: (_per_record(prof.free[i]), not _at_bound(prof, x, i, ci[prof.free[i]])),
    )
    for j in order:
        name = prof.free[j]
        se = float(sol.standard_error.get(name, np.inf))
        if not (np.isfinite(se) and se > 0 and hinv[j, j] > 0):
            continue
        half = q * se
        if half <= 1e-9 * abs(x[j]):  # noise-free data: the Wald interval is a point
            continue
        if half > HOPELESS * abs(x[j]):  # undetermined already: its Wald interval stays
            continue
        if which == "auto":
            if not wants_profile(prof, x, c0, hinv, j, half, ci[name]):
                continue
        elif which != "all" and name not in which:
            continue
        if spent >= budget:
            break
        threshold = half * half / hinv[j, j]
        walk = _Walker(prof, x, c0, hinv, j)
        lo, hi = _end(walk, -1, half, threshold), _end(walk, +1, half, threshold)
        if sol.status == "not_identifiable":  # a check widened the interval: never narrow it
            lo, hi = min(lo, ci[name][0]), max(hi, ci[name][1])
        ci[name] = (lo, hi)
        methods[name] = "profile"
        spent += walk.solves
    ci.update(_tied_intervals(sol, ci))
    return replace(sol, confidence_interval=ci, interval_method=methods)


def _at_bound(prof: Profiler, x: FloatArray, j: int, wald: tuple[float, float]) -> bool:
    """Whether the Wald interval of free parameter `j` was cut by a bound (or x is on one).

    Such parameters are profiled first: their Wald interval says least about the data, and
    the budget must not be spent on well-determined ones before them.
    """
    v = float(x[j])
    return bool(
        v in (prof.lower[j], prof.upper[j]) or wald[0] <= prof.lower[j] or wald[1] >= prof.upper[j]
    )


def _per_record(name: str) -> bool:
    return name.startswith(("initial_velocity", "initial_position", "preload_fraction"))


def _tied_intervals(sol: Any, ci: dict) -> dict:
    """A tied parameter p = a·q + b takes q's interval through its tie."""
    out = {}
    for n, (target, a, b) in getattr(sol, "ties", {}).items():
        if target in ci:
            lo, hi = a * ci[target][0] + b, a * ci[target][1] + b
            out[n] = (min(lo, hi), max(lo, hi))
    return out
