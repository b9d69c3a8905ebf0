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

Each end is found by a walk from the optimum (`_profile_walk`: continuation, secant
steps, regula falsi inside the bracket, every solved point kept and reused); an end
the profile never reaches is unbounded (±inf), and the fit is then not identifiable
(`_status`).

A profile is only as good as the inner optimisations that give each P(θ); an end decided
by where they happen to stop moves with any rounding, and is not an interval the data
support. So, before any walk: the parameters a hair inside a bound are put on it
(`NEAR_BOUND`; a saturated preload fraction at 1 − 5e-8 has a column near zero and a cost
that rises steeply away from the bound); every free parameter is re-optimised once from the
optimum, and where that lowers the cost by more than `SETTLE`·P_crit of a parameter, its
optimum is not a minimum on the scale of its interval and it keeps its Wald interval. P is
measured from the lowest cost known. During a walk, P at the first step and at each end
inside the bounds is solved from two starts; where they differ by more than
`SETTLE`·P_crit the profile is not resolved, the parameter keeps its Wald interval and no
further parameter is profiled (the same inner optimisations would decide them).

A parameter whose column vanishes on its bound (a preload fraction saturated in the
direction of the record's first motion: its Wald interval spans [−1, 1]) is profiled first,
inward from the bound (`_profile_bound`): its interval is [end, bound], and every other
parameter's interval is widened to the values it takes along that walk within the threshold
(``interval_method`` "partner", its standard error raised to match). Their Wald intervals,
read where the Jacobian does not see the partner move, are far too short, and so would be
their own profiles: with a zero column and gradient the inner optimisations never move the
partner off the bound. Those parameters are not profiled again.

`profile_solution` chooses the parameters ("auto"): every free parameter
whose Wald interval reaches a bound or is wide (half width above a quarter of
the value) is profiled. For the others the cost along the linearised path is
compared with the quadratic at both Wald ends; where it departs by more than
10 %, the profile is solved at the two Wald ends, and the Wald interval is kept
only if √P is within 2 % of √P_crit at both (the profile goes on from those
points otherwise). `which` may
name the parameters instead. The shared parameters go before the records' own,
and among each those whose Wald interval a bound cuts go first: the budget of
inner optimisations (`BUDGET`) is spent where the Wald interval says least.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from presliding.identification.intervals._profile_bound import ACCURACY as BOUND_ACCURACY
from presliding.identification.intervals._profile_bound import partner_intervals, widen
from presliding.identification.intervals._profile_inner import cost, minimise
from presliding.identification.intervals._profile_walk import (
    FIRST_STEP,
    INNER_EVALUATIONS,
    INNER_SHARE,
    FloatArray,
    Profiler,
    Walker,
    interval_end,
)
from presliding.identification.solve._normal_equations import (
    carried_threshold,
    flat_on_bound,
    normal_matrix,
    record_of,
    scaled_pinv,
    thresholds,
)
from presliding.identification.solve._structured_lm import on_one_blas_thread

# `Profiler` (defined with the walk that uses it) is named here too: the solver builds it
# for this module
__all__ = ["Profiler", "profile_solution", "wants_profile"]

#: Relative departure of the cost from its quadratic model that asks for a check.
NONLINEAR = 0.1
#: Wald half width, as a share of the value, above which an interval is profiled.
WIDE = 0.25
#: Relative agreement of √P with √P_crit at both Wald ends that keeps a Wald interval.
AGREE = 0.02
#: Wald half width, as a multiple of the value, beyond which no profile is tried (the data
#: do not determine the parameter: the judge says so from the Wald interval).
HOPELESS = 100.0
#: Distance from a bound, relative to max(1, |bound|), within which a parameter is put on it.
NEAR_BOUND = 1e-6
#: Fall of the cost below the optimum's, as a share of P_crit, beyond which a parameter keeps
#: its Wald interval: the optimum is not a minimum on the scale of its interval, and a
#: profile measured from it would be decided by where the inner optimisations stop.
SETTLE = 0.1
#: Inner optimisations a profile step may spend, the second solves of its checks included (the
#: rest keep their Wald interval).
BUDGET = 40


def wants_profile(walk: Walker, half: float, wald: tuple[float, float]) -> str | None:
    """The "auto" choice (module notes): "profile" (a bound reached, or wide), "check" (the
    cost along the linearised path departs from the quadratic), or None (Wald holds)."""
    prof, x, j = walk.prof, walk.x, walk.j
    v = float(x[j])
    if wald[0] > v - half or wald[1] < v + half or v in (prof.lower[j], prof.upper[j]):
        return "profile"
    if half > WIDE * abs(v):
        return "profile"
    expected = walk.root**2
    for s in (-1.0, 1.0):
        theta = v + s * half
        z = x[walk.keep] + s * half * walk.path
        if np.any(z < prof.lower[walk.keep]) or np.any(z > prof.upper[walk.keep]):
            return "check"
        rise = cost(prof.fun(walk.full(z, theta))) - walk.c0
        if not abs(rise - expected) <= NONLINEAR * expected:
            return "check"
    return None


def _wald_holds(walk: Walker, half: float) -> bool:
    """Whether the profile meets the Wald ends: √P within `AGREE` of √P_crit at both."""
    v = float(walk.x[walk.j])
    return all(abs(walk.g(v + s * half)) <= AGREE * walk.root for s in (-1.0, 1.0))


@on_one_blas_thread
def profile_solution(sol: Any, which: str | Sequence[str] = "auto", budget: int = BUDGET) -> Any:
    """`sol` (a `Solution`) with profile intervals for the chosen free parameters.

    `which` is "auto" (module notes), "all", or the names to profile. The
    intervals of tied parameters follow their target's. `interval_method` names
    each free parameter's method ("profile", "partner" or "wald").
    """
    prof: Profiler | None = sol.profiler
    methods = dict.fromkeys(sol.free, "wald")
    if prof is None or sol.status == "failed" or not prof.free:
        return replace(sol, interval_method=methods)
    x = np.array([sol.values[n] for n in prof.free], dtype=float)
    c0 = cost(prof.fun(x))
    if not np.isfinite(c0):
        return replace(sol, interval_method=methods)
    x, c0 = _onto_bounds(prof, x, c0)
    q = prof.quantile
    ses = np.array([sol.standard_error.get(n, np.inf) for n in prof.free], dtype=float)
    x, c0 = _flat_onto_bounds(prof, x, c0, ses)
    normal = normal_matrix(prof.jacobian(x))
    hinv = scaled_pinv(normal)
    limits = thresholds(hinv, ses, q)
    crits = limits[np.isfinite(limits)]
    drop = _settled(prof, x, c0, SETTLE * INNER_SHARE * float(np.min(crits))) if crits.size else 0.0
    ci = dict(sol.confidence_interval)
    spent = 1 if drop > 0 else 0
    se = dict(sol.standard_error)
    done: set[int] = set()
    flat = flat_on_bound(prof.lower, prof.upper, x, ses, q)
    for p in flat:  # a column that vanishes on its bound (module notes)
        crit = carried_threshold(normal, ses, q, flat, prof.free)
        if spent >= budget or not np.isfinite(crit) or drop > SETTLE * crit:
            continue
        if which not in ("auto", "all") and prof.free[p] not in which:
            continue
        walk = Walker(prof, x, c0, normal, p, crit, -drop, accuracy=BOUND_ACCURACY)
        ci[prof.free[p]], ranges = partner_intervals(walk)
        methods[prof.free[p]] = "profile"
        done.add(p)
        spent += walk.solves
        for i, rng in ranges.items():
            if widen(sol.values[prof.free[i]], prof.free[i], rng, ci, se, q):
                methods[prof.free[i]] = "partner"
                done.add(i)
    order = sorted(
        range(len(prof.free)),
        key=lambda i: (_per_record(prof.free[i]), not _at_bound(prof, x, i, ci[prof.free[i]])),
    )
    unresolved: tuple[str, ...] = ()  # their profiles stopped where P was not resolved
    for j in order:
        name = prof.free[j]
        if j in done:
            continue
        se_j = float(sol.standard_error.get(name, np.inf))
        if not (np.isfinite(se_j) and se_j > 0 and hinv[j, j] > 0):
            continue
        half = q * se_j
        if half <= 1e-9 * abs(x[j]):  # noise-free data: the Wald interval is a point
            continue
        if half > HOPELESS * abs(x[j]):  # undetermined already: its Wald interval stays
            continue
        if which != "auto" and which != "all" and name not in which:
            continue
        if spent >= budget:
            break
        crit = half * half / hinv[j, j]
        if drop > SETTLE * crit:  # a lower cost is known: not a minimum on this scale
            continue
        walk = Walker(prof, x, c0, normal, j, crit, -drop)
        need = wants_profile(walk, half, ci[name]) if which == "auto" else "profile"
        if need is None:
            continue
        ends = _resolved_ends(walk, half, need)
        if isinstance(ends, tuple):
            lo, hi = ends
            if sol.status == "not_identifiable":  # a check widened it: never narrow it
                lo, hi = min(lo, ci[name][0]), max(hi, ci[name][1])
            ci[name] = (lo, hi)
            methods[name] = "profile"
        spent += walk.solves
        if ends is None:  # the inner optimisations do not resolve P here: stop profiling
            unresolved = tuple(prof.free[i] for i in order[order.index(j) :] if i not in done)
            break
    ci.update(_tied_intervals(sol, ci))
    if done:
        return replace(sol, confidence_interval=ci, interval_method=methods,
                       standard_error=se, covariance=_rescaled(sol, se),
                       unresolved=unresolved)  # fmt: skip
    return replace(sol, confidence_interval=ci, interval_method=methods, unresolved=unresolved)


def _rescaled(sol: Any, se: dict) -> Any:
    """The covariance with the rows and columns of the parameters whose error was raised
    (`_profile_bound.widen`) scaled by the ratio of the errors: their correlations kept."""
    cov = sol.covariance
    if cov is None:
        return None
    scale = np.ones(cov.shape[0])
    for i, name in enumerate(sol.values):
        old = float(sol.standard_error.get(name, np.nan))
        if np.isfinite(old) and old > 0 and np.isfinite(se.get(name, np.nan)):
            scale[i] = se[name] / old
    return cov * np.outer(scale, scale)


def _settled(prof: Profiler, x: FloatArray, c0: float, tol: float) -> float:
    """How far the cost falls below c0 when every free parameter is re-optimised from x (one
    inner optimisation): 0 at a minimum; above `SETTLE`·P_crit of a parameter, its profile
    is not measured (module notes)."""
    if x.shape[0] < 2:
        return 0.0
    out = minimise(
        prof.fun, prof.jacobian, x, prof.lower, prof.upper, tol=tol,
        max_nfev=INNER_EVALUATIONS, step_limit=prof.step_limit,
    )  # fmt: skip
    return max(c0 - out.cost, 0.0)


def _resolved_ends(walk: Walker, half: float, need: str) -> tuple[float, float] | str | None:
    """The profile ends, "wald" where the profile meets the Wald ends ("check"), or None where
    the profile is not resolved on the scale of P_crit (module notes): P at the first points
    solved (the Wald ends for a check, else the first steps) or at an end differs by more
    than `SETTLE`·P_crit when solved from two starts."""
    v = float(walk.x[walk.j])
    first = 1.0 if need == "check" else FIRST_STEP
    for side in (-1.0, 1.0):
        if not walk.repeatable(v + side * first * half, SETTLE):
            return None
    if need == "check" and _wald_holds(walk, half):
        return "wald"
    ends = []
    for side in (-1, 1):
        end = interval_end(walk, side, half)
        inside = np.isfinite(end) and end not in (walk.prof.lower[walk.j], walk.prof.upper[walk.j])
        if inside and not walk.repeatable(end, SETTLE):
            return None
        ends.append(end)
    return ends[0], ends[1]


def _onto_bounds(prof: Profiler, x: FloatArray, c0: float) -> tuple[FloatArray, float]:
    """x with the parameters a hair inside a bound (`NEAR_BOUND`) put on it, where that does
    not raise the cost.

    A solver stops such a parameter just inside its bound (a preload fraction at 1 − 5e-8,
    saturated): its column is nearly zero there and the cost rises steeply away from the
    bound, so the linearised path would move it far, and every inner step would try to.
    On the bound it is held while its gradient pushes outward.
    """
    lo, hi = prof.lower, prof.upper
    near_lo = np.isfinite(lo) & (x - lo <= NEAR_BOUND * np.maximum(1.0, np.abs(lo)))
    near_hi = np.isfinite(hi) & (hi - x <= NEAR_BOUND * np.maximum(1.0, np.abs(hi)))
    if not (near_lo.any() or near_hi.any()):
        return x, c0
    y = np.where(near_lo, lo, np.where(near_hi, hi, x))
    c = cost(prof.fun(y))
    return (y, c) if c <= c0 * (1.0 + 1e-12) else (x, c0)


def _flat_onto_bounds(prof: Profiler, x: FloatArray, c0: float,
                      ses: FloatArray) -> tuple[FloatArray, float]:  # fmt: skip
    """x with the flat columns near a bound (`flat_on_bound`) put on it, where that raises
    the cost by no more than 1e-6 of it (a few thousandths of a profile threshold): the
    walk inward starts on the bound, and the interval reaches it."""
    flat = flat_on_bound(prof.lower, prof.upper, x, ses, prof.quantile)
    y = x.copy()
    for i in flat:
        y[i] = prof.upper[i] if prof.upper[i] - x[i] <= x[i] - prof.lower[i] else prof.lower[i]
    if np.array_equal(y, x):
        return x, c0
    c = cost(prof.fun(y))
    return (y, c) if c <= c0 * (1.0 + 1e-6) else (x, c0)


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
    return record_of(name) is not None


def _tied_intervals(sol: Any, ci: dict) -> dict:
    """A tied parameter p = a·q + b takes q's interval through its tie."""
    out = {}
    for n, (target, a, b) in getattr(sol, "ties", {}).items():
        if target in ci:
            lo, hi = a * ci[target][0] + b, a * ci[target][1] + b
            out[n] = (min(lo, hi), max(lo, hi))
    return out
