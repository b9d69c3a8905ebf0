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
#: a first motion is a displacement beyond this many times the noise and quantum
FIRST_MOTION = 3.0


def initial_direction(v: FloatArray, u: FloatArray, y: FloatArray | None = None) -> float:
    """Direction of the first motion (for a saturated or preloaded start): the sign of the
    first displacement from the first sample beyond `FIRST_MOTION` times the position's
    noise and quantum; without a measured position `y`, of the first velocity beyond that
    many times its noise; at rest throughout, of the first applied force, else of the
    first nonzero velocity.

    Not the sign of the first velocity sample: a record that starts at rest has a first
    difference quotient of noise (two rotary records got −1 while moving positive, and
    their preloads' intervals missed by z −237).
    """
    from presliding.identification.judge._noise_floor import quantum, white_variance

    if y is not None and y.shape[0] > 1:
        tol = FIRST_MOTION * max(quantum(y), float(np.sqrt(white_variance(y))))
        big = np.flatnonzero(np.abs(y - y[0]) > tol)
        if big.size:
            return float(np.sign(y[big[0]] - y[0]))
    elif v.shape[0] > 1:
        big = np.flatnonzero(np.abs(v) > FIRST_MOTION * float(np.sqrt(white_variance(v))))
        if big.size:
            return float(np.sign(v[big[0]]))
    for sig in (u, v):
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

    # log k_j relative to its start, in units of c, with the exact Jacobian: every step of
    # the solve is then the same in any consistent units (a finite-difference step relative
    # to log k, whose value shifts with the units, moved k_1 by 5e-4 between mm, g and SI)
    log0 = np.log(c / r0)

    def slopes(u: FloatArray) -> FloatArray:
        return np.exp(np.clip(log0 + u, -700.0, 700.0))[None, :] * s[:, None]

    def res(u: FloatArray) -> FloatArray:
        return (np.minimum(slopes(u), c).sum(axis=1) - target) / c

    def jac(u: FloatArray) -> FloatArray:
        ks = slopes(u)
        return np.where(ks < c, ks, 0.0) / c

    fit = least_squares(res, np.zeros(n), jac=jac, method="lm", xtol=1e-10)
    # an element the curve does not want goes soft without end: it starts as one carrying
    # 1e-3 of c over the grid's widest swing (finite, so a start is never log 0)
    k = np.maximum(np.exp(log0 + fit.x), 1e-3 * c / s[-1])
    return np.sort(k)[::-1]
