"""The end search of a profile-likelihood interval: the walk from the optimum to one end.

`_profile` chooses the parameters and the threshold P_crit; here P(θ) = χ²(θ) − χ²_min
(the parameter held at θ, every other free parameter re-optimised) is walked out to where it
reaches P_crit. Each end is a root of g(θ) = √P(θ) − √P_crit, which is linear in θ for a
linear model. The walk to an end solves at half the Wald half width, then takes
secant steps on the two farthest points inside (no step longer than the
distance already walked: a continuation), until the root is bracketed, and
regula falsi (Illinois rule) inside the bracket. Every solved point is kept and
reused, and each inner optimisation starts from the lowest-cost extrapolation
from the nearest solved points: along the secant of the two nearest, along the
linearised profile path dz/dθ = −A_zz⁻¹A_zj (A = JᵀJ, the parameters on a bound
held), each step within the solver's trust box, and the nearest solution
itself. The residual of a fit with stiction is only piecewise smooth: where
the solver cannot lower the cost from a start at all, the next start is tried
(`RETRIES`), and P(θ) is the
lowest cost found. An end is known to `END_ACCURACY` of the Wald half width
(far below the sampling error of any interval end): the search stops when its
next correction, or the bracket, is smaller than that, or after `ROOT_STEPS`
(a profile rough on the scale of P_crit), and the inner optimisations stop
when the decrease the Gauss–Newton model still predicts is below a matching share of
P_crit, or after `INNER_EVALUATIONS`. An end within
that accuracy of a bound, or past a bound the profile stays below, is the bound
(the data do not exclude it); an end the profile never reaches within 2⁸ Wald
half widths, with no bound there, is unbounded (±inf), and the fit is then not
identifiable (`_status`). The inner optimisations are `_profile_inner.minimise`
(Levenberg–Marquardt whose records' own parameters also step per record, stopped by an
absolute tolerance of the cost in units of P_crit). P is measured from the lowest cost
known (`Walker.low`, set by `_profile`), and `Walker.repeatable` solves a point from a
second start to tell whether P there depends on where the solver stops.

`Profiler` is what the walk needs of a solved problem (`_least_squares` builds it),
`Walker` the profile of one parameter with its solved points, `interval_end` one end.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import sparse

from presliding.identification.intervals._profile_inner import cost, minimise
from presliding.identification.solve._normal_equations import scaled_pinv

FloatArray = NDArray[np.float64]

__all__ = ["Profiler", "Walker", "interval_end"]

#: Doublings of the Wald half width tried before an end is called unbounded.
MAX_DOUBLINGS = 8
#: Accuracy of an interval end, as a share of the Wald half width.
END_ACCURACY = 1e-3
#: Share of END_ACCURACY·P_crit the inner optimisations may leave in the cost (their absolute
#: tolerance: the decrease the Gauss–Newton model still predicts).
INNER_SHARE = 0.5
#: Residual evaluations of one inner optimisation (from a start next to a solved point it
#: needs a few; one that runs on is in a rough valley, and its cost stays an upper bound).
INNER_EVALUATIONS = 15
#: First step of the walk to an end, as a share of the Wald half width; no step is longer
#: than this or the distance already walked (a continuation: a far extrapolation of the
#: records' own parameters can land in another valley of their cost).
FIRST_STEP = 0.5
#: Starts an inner optimisation may take: the next start is tried only when the solver
#: could not lower the cost from the previous one at all (a kink of the residual there).
RETRIES = 2
#: Excess of g at a bracket's outside end over the line through its inside points, as a
#: share of √P_crit, that asks for that end to be solved again.
OUTLIER = 0.25
#: Decrease of the cost, as a share of P_crit, below which a start counts as stuck.
STALL = 1e-3
#: Steps of the root search inside a bracket (more go into chasing a profile that is rough on
#: the scale of P_crit, where the records' own parameters jump between valleys).
ROOT_STEPS = 6


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


class Walker:
    """Profile of one parameter: P(θ) by inner optimisations, every solved point kept."""

    def __init__(self, prof: Profiler, x: FloatArray, c0: float, normal: FloatArray, j: int,
                 threshold: float, low: float = 0.0,
                 accuracy: float = END_ACCURACY):  # fmt: skip
        self.prof, self.x, self.c0, self.j = prof, x, c0, j
        self.keep = np.array([i for i in range(x.shape[0]) if i != j], dtype=int)
        self.path = _path(prof, x, normal, j, self.keep)
        self.root = float(np.sqrt(threshold))
        self.solved: dict[float, tuple[float, FloatArray]] = {float(x[j]): (0.0, x[self.keep])}
        self.refined: set[float] = set()
        self.solves = 0
        # the cost left by an inner optimisation moves an end by about δP/(2·P_crit) of the
        # half width: a share of the accuracy the walk's ends are found to
        self.accuracy = accuracy
        self.tol = INNER_SHARE * accuracy * threshold
        #: the lowest P found (below 0 where the fit's optimum is not a minimum on the scale
        #: of P_crit: the profile is then measured from it)
        self.low = low

    def full(self, z: FloatArray, theta: float) -> FloatArray:
        out = self.x.copy()
        out[self.keep] = z
        out[self.j] = theta
        return out

    def g(self, theta: float) -> float:
        """√P(θ) − √P_crit (inf where the model fails)."""
        p = self(theta) - self.low
        return float(np.sqrt(max(p, 0.0))) - self.root if np.isfinite(p) else np.inf

    def centre(self) -> float:
        """g at the optimum (P measured from the lowest cost known, `low`)."""
        return min(self.g(float(self.x[self.j])), 0.0)

    def repeatable(self, theta: float, share: float) -> bool:
        """Whether P(θ) solved from two different starts agrees to `share` of P_crit (the
        lower value is kept). Where it does not, P depends on where the inner
        optimisations stop, and an end found from it would move with any rounding."""
        theta = float(theta)
        first = self(theta)
        starts = self._starts(theta, exclude=theta)
        if self.keep.size == 0 or len(starts) < 2:
            return True
        self.solves += 1
        p, z, _ = self._solve(theta, starts[-1][0])
        if p < first:
            self.solved[theta] = (p, z)
        return bool(abs(p - first) <= share * self.root**2)

    def __call__(self, theta: float) -> float:
        """P(θ): the cost with the parameter held at θ and the others re-optimised."""
        theta = float(theta)
        if theta not in self.solved:
            self.solved[theta] = self._run(theta, self._starts(theta))
        return self.solved[theta][0]

    def refine(self, theta: float) -> float:
        """P(θ) solved again from the nearest other solved point; the lower of the two."""
        theta = float(theta)
        if theta not in self.refined:
            self.refined.add(theta)
            again = self._run(theta, self._starts(theta, exclude=theta))
            if again[0] < self.solved[theta][0]:
                self.solved[theta] = again
        return self.solved[theta][0]

    def _run(self, theta: float, starts: list) -> tuple[float, FloatArray]:
        """The inner optimisation from the first start, and from the next where the solver
        took no step, or stayed above 2·P_crit lowering the cost by less than a share
        `STALL` of P_crit (a kink there, or another valley)."""
        if self.keep.size == 0:
            return starts[0][1], starts[0][0]
        best = (np.inf, starts[0][0])
        crit = self.root**2
        for z0, p0 in starts[:RETRIES]:
            self.solves += 1
            p, z, stuck = self._solve(theta, z0)
            if p < best[0]:
                best = (p, z)
            if not stuck and (p < p0 - STALL * crit or p < 2.0 * crit):
                break
        return best

    def _starts(self, theta: float, exclude: float | None = None) -> list:
        """The extrapolations from the nearest solved points, lowest cost first (module
        notes)."""
        prof, keep = self.prof, self.keep
        known = sorted(
            (t for t, (p, _) in self.solved.items() if np.isfinite(p) and t != exclude),
            key=lambda t: abs(t - theta),
        )
        tn = known[0]
        zn = self.solved[tn][1]
        steps = [(theta - tn) * self.path]
        if len(known) > 1:
            t2 = known[1]
            steps.insert(0, (theta - tn) * (zn - self.solved[t2][1]) / (tn - t2))
        if prof.step_limit is not None:  # within the solver's trust box: a start far out
            limit = prof.step_limit(self.full(zn, tn))[keep]  # can take long to simulate
            steps = [np.clip(d, -limit, limit) for d in steps]
        cands = [zn + d for d in steps] + [zn]
        lo, hi = prof.lower[keep], prof.upper[keep]
        out = []
        for c in cands:
            c = np.clip(c, lo, hi)
            out.append((c, cost(prof.fun(self.full(c, theta))) - self.c0))
        return sorted(out, key=lambda s: s[1])

    def _solve(self, theta: float, z0: FloatArray) -> tuple[float, FloatArray, bool]:
        prof, keep = self.prof, self.keep

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
            res = minimise(
                fun, jac, z0, prof.lower[keep], prof.upper[keep], tol=self.tol,
                max_nfev=INNER_EVALUATIONS, step_limit=limit,
            )  # fmt: skip
        except (ValueError, np.linalg.LinAlgError, FloatingPointError):
            return np.inf, z0, True
        p = res.cost - self.c0
        self.low = min(self.low, p)
        # stuck: no step accepted from the start
        return p, res.x, not res.converged and np.array_equal(res.x, z0)


def _path(prof: Profiler, x: FloatArray, normal: FloatArray, j: int,
          keep: NDArray[np.int_]) -> FloatArray:  # fmt: skip
    """dz/dθ of the linearised profile: −A_zz⁻¹A_zj over the others not on a bound (a
    parameter on a bound stays there: its column says nothing about moving past it)."""
    out = np.zeros(keep.shape[0])
    inside = (x[keep] > prof.lower[keep]) & (x[keep] < prof.upper[keep])
    inner = keep[inside]
    if inner.size:
        out[inside] = -scaled_pinv(normal[np.ix_(inner, inner)]) @ normal[inner, j]
    return out


def interval_end(walk: Walker, side: int, half: float) -> float:
    """The interval end on `side` (±1): where g = √P − √P_crit crosses 0, a bound, or ±inf.

    The walk: a first step of `FIRST_STEP` half widths, then secant steps on the
    two farthest points inside, a little past the predicted root, until it is
    bracketed (module notes); the end to the walk's accuracy (`Walker.accuracy`, in half
    widths: `END_ACCURACY` unless the walk was made for another).
    """
    prof, j, accuracy = walk.prof, walk.j, walk.accuracy
    theta0 = float(walk.x[j])
    limit = float(prof.upper[j] if side > 0 else prof.lower[j])
    if theta0 == limit:
        return limit
    tol = accuracy * half
    prev, (a, ga) = None, (theta0, walk.centre())
    theta = theta0 + side * FIRST_STEP * half
    for _ in range(3 * MAX_DOUBLINGS):
        if (theta - limit) * side >= 0:
            theta = limit
        g = walk.g(theta)
        if g >= 0:
            end, inside = _bracketed(walk, (a, ga), (theta, g), tol)
            if end is not None:
                # within the accuracy of a bound is the bound (where the model may fail)
                return limit if abs(end - limit) <= tol else end
            (theta, g), (a, ga) = inside  # the outside end, solved again, is inside
        if theta == limit:
            return limit
        if theta == a:  # a step below the resolution of θ
            return theta
        prev, (a, ga) = (a, ga), (theta, g)
        reach = abs(a - theta0)
        if reach > 2.0**MAX_DOUBLINGS * half:
            return side * np.inf
        rise = (ga - prev[1]) / abs(a - prev[0])  # of g per unit of distance outwards
        dist = -ga / rise if rise > 0 else np.inf
        if dist <= tol:
            return a + side * dist
        theta = a + side * min(dist + tol, max(reach, FIRST_STEP * half))
    return side * np.inf


def _bracketed(walk: Walker, inside: tuple[float, float], outside: tuple[float, float],
               tol: float) -> tuple[float | None, Any]:  # fmt: skip
    """The root of g between a point inside (g < 0) and one outside (g ≥ 0): regula falsi
    with the Illinois rule, until the next correction or the bracket is below `tol`.

    An outside end far above the line through the two inside ends nearest it is solved
    again from the nearer one (a start far away can end in another valley); if it is then
    inside, returns (None, (that end, the inside point before it)) for the walk to go on.
    """
    (a, ga), (b, gb) = inside, outside
    last, kept = b, 0
    t = b
    for _ in range(ROOT_STEPS):
        t = a - ga * (b - a) / (gb - ga) if np.isfinite(gb) else 0.5 * (a + b)
        if abs(t - last) <= tol or abs(b - a) <= 2.0 * tol:
            return float(t), None
        g = walk.g(t)
        last = t
        if g >= 0:
            b, gb = t, g
            kept = kept + 1 if kept > 0 else 1  # the inside end kept again
            if kept > 1:
                ga *= 0.5
            continue
        trend = g + (g - ga) / (t - a) * (b - t)  # g at b on the line through a and t
        a, ga = t, g
        kept = kept - 1 if kept < 0 else -1  # the outside end kept again
        if kept < -1:
            gb *= 0.5
        if b not in walk.refined and not gb <= trend + OUTLIER * walk.root:
            walk.refine(b)
            gb = walk.g(b)
            if gb < 0:
                return None, ((b, gb), (a, ga))
            kept = 0
    return float(t), None
