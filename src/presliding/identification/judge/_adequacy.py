"""Model adequacy: whether a fit's residuals are what its noise model says (Ljung's tests).

System identification calls a model adequate when its residuals look like the
noise of the measurement (L. Ljung, *System Identification*, ch. 16.6; MATLAB's
``resid``): of the right size, white, and independent of the input. A fit of a
model that lacks a mechanism of the data (an asymmetry, a viscous force, a delay,
an element) leaves structure that these tests see even where the residual is
only a little above the noise. Each record's residual in each compared signal is
a `Block`, with the noise model `_noise_floor` estimates from the data (the
variance σ² of a white noise and the quantum q of a quantised signal; a velocity
that is the difference quotient D of a quantised position carries D times that
position's noise). Per block:

* **level**: the residual's RMS over the noise's, √(mean r² / (σ²·mean‖D_t‖²)),
  at most `LEVEL`;
* **whiteness**: the semivariogram of the residual in the position's domain,
  γ(k) = ½·mean (e_{t+k} − e_t)², stays at σ² at every lag for white noise and
  grows with the lag where the model leaves slow structure; the statistic is its
  largest growth over the lag window, (γ(k) − γ(1))/σ² for 1 < k ≤ `LAGS` (a
  portmanteau of the autocorrelations 1 − ρ_k weighted by the lag, in the units
  of the noise). Its null spread is about √(6/n); the rounding of a signal that
  stands still or creeps (its error then no longer white) may add at most q²/12
  on the samples that do not move a quantum, which the limit allows;
* **independence**: the cross-correlation S_k = Σ_t r_t·x_{t−k} of the residual
  with the input u, the velocity v and its sign at lags −`LAGS` … `LAGS`, in
  units of its exact standard deviation under the noise model
  (σ·‖Dᵀx_k‖), less the most the rounding of still samples can add
  ((q/2)·‖Dᵀx_k‖₁ over them); at most the Bonferroni quantile of `ALPHA`.

A residual whose noise has a colour the data do not tell (an equation error of derivatives
estimated through a filter: `fit_motion`) is a `Block` marked ``colored``: only the
independence test runs, with the variance its own autocovariance gives (Bartlett weights
to lag 2·`LAGS`), the level and whiteness having no noise model to be measured against.

The fitted parameters' own error Δθ (covariance C, the fit's) moves the
residual by J·Δθ, a slow signal that follows the motion: the whiteness limit
adds its variogram ½·E((J_{t+k} − J_t)·Δθ)², and the independence test its
standard deviation √(gᵀCg), g = Σ_t J_t·x_{t−k} (a sum of the two deviations:
they may correlate).

A fit fails when a block fails one of them. The likely cause is named when a
diagnostic points to it (`score_causes`): the fit's own Jacobian J at the
optimum and the residual's direction j_c of each candidate mechanism (a force
offset in one direction of motion, a viscous force, the force a sample late,
one element more) give Rao's score statistic (j̃ᵀr)²/(s²·j̃ᵀj̃), j̃ = j_c
projected off the columns of J: how much the cost would fall with that
mechanism added and the other parameters refitted, to first order (χ²₁ under the
model), with the mechanism's estimate −j̃ᵀr/j̃ᵀj̃ (the delay in samples, σ in
N·s/m, ...). The cause is named when its statistic exceeds `SCORE` and it
explains at least `SHARE` of the cost above the noise floor.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import stats

FloatArray = NDArray[np.float64]

__all__ = ["ALPHA", "LAGS", "LEVEL", "Adequacy", "Block", "Cause", "Finding", "assess",
           "score_causes"]  # fmt: skip

#: lag window of the whiteness and independence tests [samples]
LAGS = 20
#: family-wise false-alarm rate of one fit's independence tests (Bonferroni)
ALPHA = 1e-3
#: residual RMS over the noise's above which a block is not at its noise floor
LEVEL = 1.5
#: standard deviations of the null spread the whiteness statistic may reach
SPREAD = 5.0
#: rounding allowance of the whiteness statistic, in q²/12 per still sample share
ROUNDING = 2.0
#: score statistic (χ²₁ under the model) above which a candidate mechanism is significant
SCORE = 25.0
#: least share of the cost above the noise floor a named cause must explain
SHARE = 0.1
#: fewest samples a block needs for the whiteness and independence tests
MIN_SAMPLES = 2 * LAGS + 2


@dataclass(frozen=True, eq=False)
class Block:
    """One record's residual in one compared signal, with its noise model (module notes).

    `residual` is fitted − measured in the signal's units; `noise` the variance σ² of
    the white noise it is made of, `quotient` the sparse operator D when that noise is
    the difference quotient of a white signal (None: white itself), `quantum` the
    white signal's quantum and `still` its samples that do not move by a quantum.
    `path` is the residual in the domain of that white signal (the position of a
    velocity that is its quotient; default `residual`), read by the whiteness test;
    `regressors` the signals the independence test correlates it with.
    A velocity block that is the quotient of a position compared too leaves its
    whiteness to that position's block (`whiteness` False). With `sensitivity` (the
    fit's Jacobian on the block's rows) and `covariance` (of the parameters), the
    residual's share of the fitted parameters' error, J·Δθ, is allowed for.
    """

    record: int
    signal: str
    residual: FloatArray
    noise: float
    quotient: Any = None
    quantum: float = 0.0
    still: NDArray[np.bool_] | None = None
    path: FloatArray | None = None
    regressors: Mapping[str, FloatArray] = field(default_factory=dict)
    whiteness: bool = True  # False: another block of the record reads the same path
    #: ∂r/∂θ of the block's rows (its own units) and of its path, and the covariance of θ:
    #: the fitted parameters' own error moves the residual by J·Δθ, which the tests allow
    sensitivity: FloatArray | None = None
    path_sensitivity: FloatArray | None = None
    covariance: FloatArray | None = None
    #: noise of unknown colour (an equation error of estimated derivatives): only the
    #: independence test runs, its variance from the residual's own autocovariance
    colored: bool = False

    def noise_scale(self) -> float:
        """mean ‖H_t‖² of the noise's operator (1 for white noise)."""
        if self.quotient is None:
            return 1.0
        d = self.quotient
        return float(d.multiply(d).sum()) / d.shape[0]


@dataclass(frozen=True)
class Finding:
    """A test a block failed: which, where, how far."""

    test: str  # "level", "whiteness" or "independence"
    record: int
    signal: str
    statistic: float
    limit: float
    lag: int | None = None
    regressor: str = ""

    def text(self) -> str:
        where = f"record {self.record + 1} ({self.signal})"
        if self.test == "level":
            return (f"{where}: residual RMS {self.statistic:.3g} × the noise's (at most "
                    f"{self.limit:.3g})")  # fmt: skip
        if self.test == "whiteness":
            return (f"{where}: the residual is not white, its variogram grows by "
                    f"{self.statistic:.3g} noise variances by lag {self.lag} (at most "
                    f"{self.limit:.3g})")  # fmt: skip
        return (f"{where}: the residual correlates with {self.regressor} at lag {self.lag:+d} "
                f"({self.statistic:.3g} standard deviations, at most "
                f"{self.limit:.3g})")  # fmt: skip

    def to_dict(self) -> dict[str, Any]:
        return {"test": self.test, "record": self.record, "signal": self.signal,
                "statistic": self.statistic, "limit": self.limit, "lag": self.lag,
                "regressor": self.regressor}  # fmt: skip


@dataclass(frozen=True)
class Cause:
    """A candidate mechanism the residual points to (`score_causes`)."""

    name: str
    statistic: float  # Rao's score statistic (χ²₁ under the model)
    share: float  # of the cost above the noise floor it explains, to first order
    estimate: float
    text: str

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "statistic": self.statistic, "share": self.share,
                "estimate": self.estimate, "text": self.text}  # fmt: skip


@dataclass(frozen=True)
class Adequacy:
    """The residual tests of one fit: what failed, the levels, the likely cause."""

    findings: tuple[Finding, ...]
    levels: tuple[float, ...]  # per record: the largest block level
    n_blocks: int = 0
    cause: Cause | None = None

    @property
    def passed(self) -> bool:
        return not self.findings

    @property
    def failing_records(self) -> tuple[int, ...]:
        return tuple(sorted({f.record for f in self.findings}))

    def text(self) -> str:
        """What failed, worst first (at most three), and the likely cause."""
        if self.passed:
            return "the residuals pass the level, whiteness and independence tests"
        order = sorted(self.findings, key=lambda f: -f.statistic / max(f.limit, 1e-300))
        shown = "; ".join(f"{f.test} test, {f.text()}" for f in order[:3])
        more = f" and {len(order) - 3} more" if len(order) > 3 else ""
        cause = f". Likely cause: {self.cause.text}" if self.cause is not None else (
            ". No single mechanism explains it (an asymmetry, a viscous force, a delay and "
            "one element more were tried)")  # fmt: skip
        return f"the residuals are not what the noise model says: {shown}{more}{cause}"

    def with_cause(self, cause: Cause | None) -> Adequacy:
        return Adequacy(self.findings, self.levels, self.n_blocks, cause)

    def to_dict(self) -> dict[str, Any]:
        return {"passed": self.passed, "findings": [f.to_dict() for f in self.findings],
                "levels": list(self.levels),
                "cause": None if self.cause is None else self.cause.to_dict()}  # fmt: skip


# ---------------------------------------------------------------------- the tests
def level(block: Block) -> float:
    """The block's residual RMS over its noise's."""
    r = block.residual
    scale = block.noise * block.noise_scale()
    if not r.size or not scale > 0:
        return 0.0
    return float(np.sqrt(np.mean(r * r) / scale))


def whiteness(block: Block) -> tuple[float, int, float]:
    """(largest growth of the semivariogram over the lag window in noise variances, its lag,
    the limit) of the block's position-domain residual (module notes)."""
    e = block.residual if block.path is None else block.path
    n = e.shape[0]
    if n < MIN_SAMPLES or not block.noise > 0 or not block.whiteness:
        return 0.0, 0, np.inf
    lags = np.arange(1, LAGS + 1)
    half = np.array([0.5 * float(np.mean((e[k:] - e[:-k]) ** 2)) for k in lags])
    drift = np.zeros(LAGS)
    jac, cov = block.path_sensitivity, _finite(block.covariance)
    if jac is not None and cov is not None and jac.shape[0] == n:
        used = np.flatnonzero(np.any(jac != 0.0, axis=0))  # a record's own and the shared
        jac, cov = jac[:, used], cov[np.ix_(used, used)]  # (the other records' add nothing)
        for i, lag in enumerate(lags.tolist()):  # E ½·((J_{t+k} − J_t)·Δθ)² over t
            d = jac[lag:] - jac[:-lag]
            drift[i] = 0.5 * float(np.sum((d.T @ d) * cov)) / (n - lag)
    growth = (half[1:] - half[0] - drift[1:]) / block.noise
    k = int(np.argmax(growth))
    still = 0.0 if block.still is None else float(np.mean(block.still))
    allowance = ROUNDING * still * block.quantum**2 / 12.0 / block.noise
    limit = allowance + SPREAD * np.sqrt(6.0 / n)
    return float(growth[k]), int(lags[k + 1]), float(limit)


def _finite(cov: FloatArray | None) -> FloatArray | None:
    """The covariance with the rows and columns of undetermined parameters set to 0."""
    if cov is None:
        return None
    cov = np.array(cov, dtype=float)
    bad = ~np.isfinite(np.diag(cov))
    cov[bad, :] = 0.0
    cov[:, bad] = 0.0
    return np.where(np.isfinite(cov), cov, 0.0)


def lagged(x: FloatArray, lags: int) -> FloatArray:
    """(n, 2·lags + 1): column k + lags holds x_{t−k} − mean(x), zero beyond the record."""
    n = x.shape[0]
    xc = x - float(np.mean(x))
    out = np.zeros((n, 2 * lags + 1))
    for k in range(-lags, lags + 1):
        if k >= 0:
            out[k:, k + lags] = xc[: n - k]
        else:
            out[:k, k + lags] = xc[-k:]
    return out


def independence(block: Block, z_limit: float) -> Finding | None:
    """The largest standardised cross-correlation of the residual with each regressor over
    the lag window, beyond the rounding allowance (module notes); a Finding above
    `z_limit`."""
    r = block.residual
    n = r.shape[0]
    if n < MIN_SAMPLES or not block.noise > 0:
        return None
    sigma = float(np.sqrt(block.noise))
    still = np.zeros(n, dtype=bool) if block.still is None else block.still
    cov = _finite(block.covariance)
    sens = block.sensitivity
    if sens is not None and cov is not None:  # the block's own columns (the others are 0)
        used = np.flatnonzero(np.any(sens != 0.0, axis=0))
        sens, cov = np.ascontiguousarray(sens[:, used]), cov[np.ix_(used, used)]
    best: tuple[float, int, str] = (0.0, 0, "")
    for name, x in block.regressors.items():
        x = np.asarray(x, dtype=float)
        if x.shape[0] != n or not np.ptp(x) > 0:
            continue
        shifted = lagged(x, LAGS)
        a = shifted if block.quotient is None else np.asarray(block.quotient.T @ shifted)
        sd = _colored_sd(r, shifted) if block.colored else sigma * np.linalg.norm(a, axis=0)
        if sens is not None and cov is not None:  # and J·Δθ's share: Σ_t J_t·x_t
            g = sens.T @ shifted
            sd = sd + np.sqrt(np.maximum(np.sum(g * (cov @ g), axis=0), 0.0))
        allowance = 0.5 * block.quantum * np.abs(a[still]).sum(axis=0)
        with np.errstate(divide="ignore", invalid="ignore"):
            z = np.where(sd > 0, (np.abs(r @ shifted) - allowance) / sd, 0.0)
        k = int(np.argmax(z))
        if z[k] > best[0]:
            best = (float(z[k]), k - LAGS, name)
    if best[0] > z_limit:
        return Finding("independence", block.record, block.signal, best[0], z_limit,
                       best[1], best[2])  # fmt: skip
    return None


def _colored_sd(r: FloatArray, shifted: FloatArray) -> FloatArray:
    """Standard deviations of Σ_t r_t·x_{t−k} (columns of `shifted`) for a noise of the
    residual's own autocovariance γ_r (Bartlett weights to lag 2·`LAGS`): Σ_j w_j γ_r(j)
    Σ_t x_t x_{t+j} (a residual correlated over a filter's memory makes these sums vary
    more than white noise would)."""
    n = r.shape[0]
    rc = r - float(np.mean(r))
    out = np.zeros(shifted.shape[1])
    for j in range(2 * LAGS + 1):
        w = 1.0 - j / (2 * LAGS + 1)
        gamma = float(rc[j:] @ rc[: n - j]) / n
        cross = np.einsum("ij,ij->j", shifted[j:], shifted[: n - j])
        out += (1.0 if j == 0 else 2.0 * w) * gamma * cross
    return np.sqrt(np.maximum(out, 0.0))


def assess(blocks: Sequence[Block], n_records: int) -> Adequacy:
    """The three tests on every block (module notes)."""
    findings: list[Finding] = []
    levels = np.zeros(n_records)
    tests = sum(3 * (2 * LAGS + 1) for b in blocks if b.regressors) or 1
    z_limit = float(stats.norm.isf(ALPHA / (2 * tests)))
    for b in blocks:
        lv = level(b)
        levels[b.record] = max(levels[b.record], lv)
        if lv > LEVEL and not b.colored:
            findings.append(Finding("level", b.record, b.signal, lv, LEVEL))
        g, lag, limit = whiteness(b) if not b.colored else (0.0, 0, np.inf)
        if g > limit:
            findings.append(Finding("whiteness", b.record, b.signal, g, limit, lag))
        found = independence(b, z_limit)
        if found is not None:
            findings.append(found)
    return Adequacy(tuple(findings), tuple(float(x) for x in levels), len(blocks))


# ---------------------------------------------------------------------- the causes
@dataclass(frozen=True)
class Candidate:
    """A mechanism the model lacks, as the residual's direction of a small amount of it.

    `direction` is ∂r/∂θ_c (rows of the fit's residual) at θ_c = 0; `describe` turns
    the first-order estimate of θ_c into the text naming the cause."""

    name: str
    direction: FloatArray
    describe: Callable[[float], str]


def score_causes(residual: FloatArray, jacobian: Any, candidates: Sequence[Candidate],
                 floor_cost: float) -> Cause | None:  # fmt: skip
    """The candidate with the largest score statistic, when it is significant and explains
    `SHARE` of the cost above `floor_cost` (module notes); None otherwise."""
    r = np.asarray(residual, dtype=float)
    if not candidates or not r.size:
        return None
    jac = np.asarray(jacobian.toarray() if hasattr(jacobian, "toarray") else jacobian, float)
    jac = jac[:, np.all(np.isfinite(jac), axis=0) & np.any(jac != 0, axis=0)]
    basis = np.linalg.qr(jac)[0] if jac.size else np.zeros((r.shape[0], 0))
    cost = float(r @ r)
    s2 = cost / max(r.shape[0] - basis.shape[1], 1)
    excess = max(cost - floor_cost, 1e-300)
    best: Cause | None = None
    for c in candidates:
        j = np.asarray(c.direction, dtype=float)
        if j.shape != r.shape or not np.all(np.isfinite(j)):
            continue
        jt = j - basis @ (basis.T @ j)
        size = float(jt @ jt)
        if not size > 1e-20 * float(j @ j) or not size > 0:
            continue
        drop = float(jt @ r) ** 2 / size
        stat = drop / s2
        cause = Cause(c.name, stat, drop / excess, -float(jt @ r) / size, "")
        if best is None or stat > best.statistic:
            best = Cause(c.name, stat, cause.share, cause.estimate, c.describe(cause.estimate))
    if best is None or best.statistic < SCORE or best.share < SHARE:
        return None
    return best
