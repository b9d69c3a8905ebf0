"""Is an asymmetry supported by the data? The symmetric and the asymmetric fit compared.

A fit with ``asymmetric=True`` also fits the symmetric model, which is the asymmetric one with
every negative level equal to its positive one (q linear constraints: F_c⁻ = F_c⁺, and σ⁻ = σ
with a viscous term; c1⁻ = c1 and r_j⁻ = r_j for the two branches of a virgin curve). The
asymmetric fit starts from the symmetric optimum, so its residual sum of squares is never the
larger: the two are nested, and the test of the constraints is the least-squares
likelihood-ratio test in its F form,

    F = (RSS_sym − RSS_asym)/q / (κ·s²),      s² = RSS_asym/(n − p),

against F(q, n − p) (n residuals, p free parameters of the asymmetric fit). For independent
residuals κ = 1: F is the classical test, and n·ln(RSS_sym/RSS_asym) is asymptotically χ²_q.
Output-error residuals are serially correlated (`presliding.identification.uncertainty`), and
the classical test then rejects far more often than its level; κ is the ratio of the
constraints' HAC variance (the fit's covariance) to their ordinary one,

    κ = tr[(A V Aᵀ)(s² A h Aᵀ)⁻¹]/q,      h = (JᵀJ)⁻¹,

A the constraints' rows in the free parameters: the same scaling of the likelihood-ratio
threshold that the profile intervals use (`_profile`), so that the asymmetry is supported
exactly when the profile-likelihood region of the constraints excludes the symmetric model.
The verdict is "supported" when p < 1 − level, "not supported" otherwise, "undetermined" when
a fit failed, the constraints' variance is not finite, or the data do not determine the
difference of the levels (its interval, ±t·SE, wider than their mean: records that slide in
one direction only, a start the data cannot pin down). ΔAIC and ΔBIC (Gaussian least
squares, asymmetric minus symmetric: negative favours the asymmetry) are reported beside it;
they count every residual as independent.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["AsymmetryTest", "asymmetry_test", "hac_scale"]

#: The verdicts of the test.
VERDICTS = ("supported", "not supported", "undetermined")
#: Fits whose residual sum of squares is not an optimum the test can use.
_UNUSABLE = ("failed", "max_evaluations")


@dataclass(frozen=True, eq=False)
class AsymmetryTest:
    """The test of an asymmetric fit against its symmetric one (module notes).

    Attributes
    ----------
    verdict : {"supported", "not supported", "undetermined"}
        Whether the data support the asymmetry at `level`.
    statistic : float
        F = (RSS_sym − RSS_asym)/q / (κ·s²).
    p_value : float
        P(F(q, n − p) > statistic).
    degrees_of_freedom : (int, int)
        (q, n − p): the constraints and the asymmetric fit's residual degrees of freedom.
    scale : float
        κ, the HAC variance of the constraints over their ordinary variance (1: independent
        residuals).
    likelihood_ratio, likelihood_ratio_p_value : float
        n·ln(RSS_sym/RSS_asym) and its χ²_q p-value (the classical test, κ = 1).
    delta_aic, delta_bic : float
        AIC and BIC of the asymmetric fit minus the symmetric one's.
    rss : (float, float)
        The residual sums of squares (symmetric, asymmetric).
    constrained : tuple of str
        The asymmetric fit's parameters the constraints equal to their positive sides.
    level : float
        The confidence level (the test's level is 1 − level).
    message : str
    symmetric : FitResult
        The symmetric fit.
    """

    verdict: str
    statistic: float
    p_value: float
    degrees_of_freedom: tuple[int, int]
    scale: float
    likelihood_ratio: float
    likelihood_ratio_p_value: float
    delta_aic: float
    delta_bic: float
    rss: tuple[float, float]
    constrained: tuple[str, ...]
    level: float
    message: str
    symmetric: Any = field(default=None, repr=False)

    @property
    def supported(self) -> bool:
        """True when the data support the asymmetry at `level`."""
        return self.verdict == "supported"

    @property
    def status(self) -> str:
        """The verdict (one of `VERDICTS`)."""
        return self.verdict

    @property
    def success(self) -> bool:
        """True when the test could be decided ("supported" or "not supported")."""
        return self.verdict != "undetermined"

    def lines(self) -> list[str]:
        """The report's lines."""
        q, dof = self.degrees_of_freedom
        return [
            "", f"asymmetry: {self.verdict} — {self.message}",
            f"  F = {self.statistic:.4g} on ({q}, {dof}) degrees of freedom, p = "
            f"{self.p_value:.3g} (scaled by κ = {self.scale:.3g} for the residual's "
            "autocorrelation)",
            f"  likelihood ratio n·ln(RSS_sym/RSS_asym) = {self.likelihood_ratio:.4g}, "
            f"χ²_{q} p = {self.likelihood_ratio_p_value:.3g} (independent residuals)",
            f"  ΔAIC = {self.delta_aic:+.4g}, ΔBIC = {self.delta_bic:+.4g} (asymmetric − "
            f"symmetric); RSS {self.rss[0]:.6g} → {self.rss[1]:.6g}",
        ]  # fmt: skip

    def report(self) -> str:
        """The test as text."""
        return "\n".join(self.lines()[1:])

    def to_dict(self) -> dict[str, Any]:
        """The figures as plain values (the symmetric fit as its own dict)."""
        return {
            "verdict": self.verdict, "status": self.status, "success": self.success,
            "message": self.message, "statistic": self.statistic, "p_value": self.p_value,
            "degrees_of_freedom": list(self.degrees_of_freedom), "scale": self.scale,
            "likelihood_ratio": self.likelihood_ratio,
            "likelihood_ratio_p_value": self.likelihood_ratio_p_value,
            "delta_aic": self.delta_aic, "delta_bic": self.delta_bic, "rss": list(self.rss),
            "constrained": list(self.constrained), "level": self.level,
            "symmetric": None if self.symmetric is None else self.symmetric.to_dict(),
        }  # fmt: skip

    def __repr__(self) -> str:
        return (f"AsymmetryTest(verdict={self.verdict!r}, statistic={self.statistic:.4g}, "
                f"p_value={self.p_value:.3g}, delta_aic={self.delta_aic:.4g}, "
                f"delta_bic={self.delta_bic:.4g})")  # fmt: skip


def hac_scale(sol: Any, constraints: Sequence[Mapping[str, float]]) -> float:
    """κ of the module notes from the asymmetric fit's solution (its covariance and the
    Jacobian of its profiler at the optimum); nan where it cannot be formed."""
    from presliding.identification.solve._normal_equations import inverse_normal

    prof, cov = sol.profiler, sol.covariance
    if prof is None or cov is None or not sol.free:
        return float("nan")
    names, free = list(sol.values), list(sol.free)
    a_full = np.array([[c.get(n, 0.0) for n in names] for c in constraints])
    a_free = np.zeros((len(constraints), len(free)))
    for i, c in enumerate(constraints):
        for n, w in c.items():
            if n in free:
                a_free[i, free.index(n)] += w
            elif n in sol.ties:  # a tied parameter moves with its target
                target, factor, _ = sol.ties[n]
                if target in free:
                    a_free[i, free.index(target)] += w * factor
    x = np.array([sol.values[n] for n in free])
    with np.errstate(all="ignore"):
        h = inverse_normal(prof.jacobian(x))
        r = sol.residual
        s2 = float(r @ r) / max(r.shape[0] - len(free), 1)
        hac = a_full @ cov @ a_full.T
        ordinary = s2 * (a_free @ h @ a_free.T)
        if not (np.all(np.isfinite(hac)) and np.all(np.isfinite(ordinary))):
            return float("nan")
        kappa = float(np.trace(hac @ np.linalg.pinv(ordinary))) / len(constraints)
    return kappa if np.isfinite(kappa) and kappa > 0 else float("nan")


def _loose(fit: Any, row: Mapping[str, float], dof: int, level: float) -> list[str]:
    """Why the data do not determine the difference of the levels (empty when they do)."""
    from scipy import stats

    names = list(fit.parameters)
    if fit.covariance is None or any(x not in fit.parameters for x in row):
        return []
    a = np.array([row.get(n, 0.0) for n in names])
    with np.errstate(all="ignore"):
        se = float(np.sqrt(max(a @ fit.covariance @ a, 0.0)))
    mean = 0.5 * sum(fit.parameters[x] * (1.0 if w > 0 else -w) for x, w in row.items())
    half = float(stats.t.ppf(0.5 + level / 2, dof)) * se
    if np.isfinite(half) and half <= abs(mean):
        return []
    return [f"the data do not determine the difference of the levels (±{half:.3g} about a mean "
            f"level of {mean:.3g}; do the records slide both ways?)"]  # fmt: skip


def asymmetry_test(symmetric: Any, asymmetric: Any, constraints: Sequence[Mapping[str, float]],
                   scale: float, level: float) -> AsymmetryTest:  # fmt: skip
    """The test of two nested fits (`FitResult`), the symmetric one the constrained
    (module notes); `scale` is κ (`hac_scale`)."""
    from scipy import stats

    rss_s, rss_a = float(symmetric.chisqr), float(asymmetric.chisqr)
    n, p = int(asymmetric.ndata), int(asymmetric.nvarys)
    q, dof = len(constraints), max(n - p, 1)
    named = tuple(sorted({x for c in constraints for x, w in c.items() if w > 0}))
    drop = max(rss_s - rss_a, 0.0)
    s2 = rss_a / dof
    with np.errstate(all="ignore"):
        f = drop / max(q, 1) / (scale * s2) if s2 > 0 else (np.inf if drop > 0 else 0.0)
        lr = n * float(np.log(rss_s / rss_a)) if rss_a > 0 else np.inf
    pf = float(stats.f.sf(f, q, dof)) if np.isfinite(f) else (0.0 if f > 0 else float("nan"))
    plr = float(stats.chi2.sf(max(lr, 0.0), q)) if np.isfinite(lr) else 0.0
    daic, dbic = float(asymmetric.aic - symmetric.aic), float(asymmetric.bic - symmetric.bic)
    alpha = 1.0 - level
    bad = [f"the {w} fit's status is {r.status}" for w, r in (("symmetric", symmetric),
           ("asymmetric", asymmetric)) if r.status in _UNUSABLE]  # fmt: skip
    bad += _loose(asymmetric, constraints[0], dof, level) if q else []
    if bad or not (np.isfinite(scale) and np.isfinite(pf)) or q == 0:
        verdict = "undetermined"
        why = "; ".join(bad) or (
            "the constraints' variance is not finite (a side the data do not determine)"
            if q else "the negative sides are fixed or tied")  # fmt: skip
        message = f"the test cannot decide: {why}"
    elif pf < alpha:
        verdict = "supported"
        message = (f"the data support different levels by direction (p = {pf:.3g} < "
                   f"{alpha:.3g}); the asymmetric fit is the better model")  # fmt: skip
    else:
        verdict = "not supported"
        message = (f"the symmetric fit explains the data as well (p = {pf:.3g} >= {alpha:.3g}):"
                   " the two directions' levels differ by no more than the noise; prefer "
                   "asymmetric=False")  # fmt: skip
    if verdict != "undetermined" and symmetric.status == "local_minimum":
        message += " (the symmetric fit's status is local_minimum: its RSS may be too high)"
    return AsymmetryTest(verdict, float(f), pf, (q, dof), float(scale), float(lr), plr, daic,
                         dbic, (rss_s, rss_a), named, float(level), message, symmetric)  # fmt: skip
