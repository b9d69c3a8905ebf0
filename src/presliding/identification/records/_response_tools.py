"""Small helpers of the response fits: a record's first direction, integrals, stiffnesses.

`initial_direction` gives the direction of the motion before a record's first
sample (for a saturated or preloaded start), `integral` the cumulative
trapezoid, and `equal_breakaway_stiffness` the N stiffnesses of equal break-away
force whose virgin curve is closest to a nonparametric one (the start).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


def initial_direction(v: FloatArray, u: FloatArray, y: FloatArray | None = None) -> float:
    """Direction of the first motion (for a saturated start): the sign of the first
    velocity; at rest, of the first displacement from the first position, else of
    the first applied force, else of the first nonzero velocity."""
    moved = None if y is None else y - y[0]
    for sig in (v[:1], moved, u[:1], v):
        if sig is None:
            continue
        nz = np.flatnonzero(sig)
        if nz.size:
            return float(np.sign(sig[nz[0]]))
    return 1.0  # pragma: no cover - a constant zero velocity is rejected before


def integral(t: FloatArray, v: FloatArray) -> FloatArray:
    """Cumulative trapezoid integral from 0."""
    return np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(t))])


def equal_breakaway_stiffness(grid: FloatArray, weight: FloatArray, c: float, n: int) -> FloatArray:
    """Stiffnesses k_j (descending) with Σ_j min(k_j·s, c) closest to G(s) = Σ_g w_g·min(s, r_g)."""
    from scipy.optimize import least_squares

    s = np.geomspace(grid[0] / 4, grid[-1] * 2, 200)
    target = np.minimum(s[:, None], grid[None, :]) @ weight
    # start: element j saturates where G reaches (j + 1/2)·c
    levels = (np.arange(n) + 0.5) * c
    r0 = np.interp(levels, target, s) if np.ptp(target) > 0 else np.geomspace(s[0], s[-1], n)
    r0 = np.maximum(r0, s[0])

    def res(logk: FloatArray) -> FloatArray:
        k = np.exp(np.clip(logk, -700.0, 700.0))
        return np.minimum(k[None, :] * s[:, None], c).sum(axis=1) - target

    fit = least_squares(res, np.log(c / r0), method="lm", xtol=1e-10)
    return np.sort(np.exp(fit.x))[::-1]
