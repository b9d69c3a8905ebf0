"""Honest uncertainty for least-squares fits of time records: HAC covariance and correlations.

The textbook covariance s²·(JᵀJ)⁻¹ assumes independent residuals. Residuals of
an output-error fit are not: quantisation of an encoder, a velocity estimated
by differences, and unmodelled dynamics make neighbouring samples correlated,
and the intervals come out too narrow (the issue that motivated this module:
the truth outside the 95 % interval of a 0.3 %-noise fit). Here the
covariance is the heteroscedasticity-and-autocorrelation-consistent (HAC)
sandwich of Newey & West (1987),

    C = (JᵀJ)⁻¹ · Ω · (JᵀJ)⁻¹ · n/(n − p),
    Ω = Σ_blocks Σ_{|l| <= L} (1 − |l|/(L + 1)) Σ_t g_t g_{t−l}ᵀ,    g_t = J_t·r_t,

with the Bartlett kernel and, per block, the bandwidth L of Andrews (1991)
from AR(1) fits of the score columns g_t (`andrews_bandwidth`),
L = 1.1447·(α·n)^(1/3). Blocks are independent records (no lags across
them). With three or more records, each parameter's variance is the larger of
this and the record-level (cluster-robust) sandwich, whose meat is the outer
products of each record's summed scores (`hac_covariance`'s `clusters`).
The Bartlett sum is computed exactly through moving sums of g over
windows of L + 1 samples: Σ_t W_t W_tᵀ/(L + 1) (O(n·p²) per block, whatever L).
Within a block only the columns that touch it enter (a record's own nuisance
parameters and the shared ones), so a pooled fit of many records stays cheap.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from presliding._validation import as_count, as_real_array, fmt

__all__ = [
    "andrews_bandwidth",
    "bounded_interval",
    "correlation_matrix",
    "full_covariance",
    "hac_covariance",
    "ols_covariance",
]

FloatArray = NDArray[np.float64]
_RANK_TOL = 1e-7


def andrews_bandwidth(scores: FloatArray) -> int:
    """Bartlett bandwidth L of Andrews (1991) from AR(1) fits of the scores.

    For score columns a with lag-1 autocorrelation ρ_a and innovation variance
    σ_a² (equal weights), α = Σ 4ρ_a²σ_a⁴/((1 − ρ_a)⁶(1 + ρ_a)²) / Σ σ_a⁴/(1 − ρ_a)⁴
    and L = 1.1447·(α·n)^(1/3). A 1-D array is one column (the residuals).

    Parameters
    ----------
    scores : ndarray, shape (n,) or (n, p)
        g_t = J_t·r_t, or the residuals.

    Returns
    -------
    int
        L >= 0, at most n − 1 (each ρ capped at ±0.99).
    """
    g = np.asarray(scores, dtype=float)
    g = g[:, None] if g.ndim == 1 else g
    n = g.shape[0]
    power = np.sum(g * g, axis=0)
    g = g[:, power > 0]
    if n < 3 or g.shape[1] == 0:
        return 0
    rho = np.clip(np.sum(g[1:] * g[:-1], axis=0) / np.sum(g * g, axis=0), -0.99, 0.99)
    var = np.sum((g[1:] - rho * g[:-1]) ** 2, axis=0) / (n - 1)
    num = np.sum(4 * rho**2 * var**2 / ((1 - rho) ** 6 * (1 + rho) ** 2))
    den = np.sum(var**2 / (1 - rho) ** 4)
    alpha = num / den if den > 0 else 0.0
    return int(min(np.floor(1.1447 * (alpha * n) ** (1 / 3)), n - 1))


def _singular(mat: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Singular values (descending) and right singular vectors of a tall matrix.

    Large matrices go through the eigenvalues of the small Gram matrix (the
    column scaling keeps its condition moderate), which is much faster than
    factoring the tall matrix itself.
    """
    n, p = mat.shape
    if n * p * p <= 2e7:
        _, s, vt = np.linalg.svd(mat, full_matrices=False)
        return s, vt
    lam, vec = np.linalg.eigh(mat.T @ mat)
    order = np.argsort(lam)[::-1]
    return np.sqrt(np.maximum(lam[order], 0.0)), vec[:, order].T


def _bartlett_meat(g: FloatArray, lag: int) -> FloatArray:
    """Σ_{|l| <= L} (1 − |l|/(L+1)) Σ_t g_t g_{t−l}ᵀ through window sums (module notes)."""
    if lag == 0:
        return g.T @ g
    c = np.vstack([np.zeros((1, g.shape[1])), np.cumsum(g, axis=0)])
    n = g.shape[0]
    hi = np.minimum(np.arange(n + lag) + 1, n)  # window [t − L, t] ∩ [0, n)
    lo = np.maximum(np.arange(n + lag) - lag, 0)
    w = c[hi] - c[lo]
    return (w.T @ w) / (lag + 1)


def hac_covariance(
    jacobian: FloatArray,
    residual: FloatArray,
    blocks: Sequence[NDArray[np.intp] | slice] | None = None,
    *,
    bandwidth: int | None = None,
    clusters: Sequence[int] | None = None,
) -> tuple[FloatArray, list[int], list[int]]:
    """HAC (Newey–West) covariance of least-squares estimates from serially correlated blocks.

    Parameters
    ----------
    jacobian : ndarray, shape (n, p)
        ∂r/∂θ at the optimum.
    residual : ndarray, shape (n,)
    blocks : sequence of index arrays or slices, optional
        Rows of each independent block (a record, or one signal of a record);
        default one block of all rows.
    bandwidth : int, optional
        Bartlett bandwidth L for every block (default: Andrews' per block).
    clusters : sequence of int, optional
        The independent record each block belongs to. With three or more, the
        record-level (cluster-robust) sandwich Ω_c = G/(G − 1)·Σ_i s_i s_iᵀ,
        s_i the summed scores of record i, is computed too, and each
        parameter gets the larger of its two variances (correlations from the
        HAC sandwich): no bandwidth can then make the intervals optimistic.

    Returns
    -------
    covariance : ndarray, shape (p, p)
        Zero rows and columns for undetermined parameters.
    undetermined : list of int
        Columns the data do not determine (a singular JᵀJ).
    bandwidths : list of int
        L of each block.
    """
    jac = as_real_array("jacobian", jacobian)
    if jac.ndim != 2:
        raise ValueError(f"`jacobian` must be two-dimensional (n, p); got shape {jac.shape}.")
    r = as_real_array("residual", residual)
    if r.shape != jac.shape[:1]:
        raise ValueError(f"`residual` must have shape ({jac.shape[0]},); got shape {r.shape}.")
    if bandwidth is not None:
        bandwidth = as_count("bandwidth", bandwidth, maximum=max(jac.shape[0] - 1, 0))
    n, p = jac.shape
    if p == 0:
        return np.zeros((0, 0)), [], []
    if n <= p:
        return np.zeros((p, p)), list(range(p)), []
    norms = np.linalg.norm(jac, axis=0)
    dead = norms == 0
    scale = np.where(dead, 1.0, norms)
    s, vt = _singular(jac / scale)
    keep = s > _RANK_TOL * s[0] if s[0] > 0 else np.zeros_like(s, dtype=bool)
    bread = (vt[keep].T / s[keep] ** 2) @ vt[keep] / np.outer(scale, scale)  # (JᵀJ)⁺
    meat = np.zeros((p, p))
    widths = []
    for rows in blocks if blocks is not None else [slice(None)]:
        jb, rb = jac[rows], r[rows]
        cols = np.flatnonzero(np.any(jb != 0, axis=0))
        g = jb[:, cols] * rb[:, None]
        lag = andrews_bandwidth(g) if bandwidth is None else int(bandwidth)
        widths.append(lag)
        meat[np.ix_(cols, cols)] += _bartlett_meat(g, lag)
    cov = bread @ meat @ bread * (n / (n - p))
    if clusters is not None and blocks is not None and len(set(clusters)) >= 3:
        sums: dict[int, FloatArray] = {}
        for rows, c in zip(blocks, clusters, strict=True):
            sums[c] = sums.get(c, np.zeros(p)) + jac[rows].T @ r[rows]
        g = len(sums)
        omega = sum(np.outer(v, v) for v in sums.values()) * g / (g - 1)
        robust = bread @ omega @ bread * (n / (n - p))
        sd_h, sd_c = np.sqrt(np.maximum(np.diag(cov), 0)), np.sqrt(np.maximum(np.diag(robust), 0))
        with np.errstate(invalid="ignore", divide="ignore"):
            corr = np.where(np.outer(sd_h, sd_h) > 0, cov / np.outer(sd_h, sd_h), 0.0)
        sd = np.maximum(sd_h, sd_c)
        cov = corr * np.outer(sd, sd)
    undetermined = set(np.flatnonzero(dead).tolist())
    for row in vt[~keep]:
        undetermined |= set(np.flatnonzero(np.abs(row) > 1e-3).tolist())
    # A parameter whose scores vanish (its record's residuals are all 0, e.g. a quantised
    # record the model reproduces exactly, or scores summing to 0 in the record-level
    # sandwich) would get a variance of exactly 0; it is determined no better than the
    # pooled noise allows: it takes the ordinary variance s²·(JᵀJ)⁻¹ instead.
    s2 = float(r @ r) / (n - p)
    zero = np.flatnonzero((np.diag(cov) <= 0) & ~dead)
    zero = np.array([i for i in zero if i not in undetermined], dtype=int)
    if zero.size and s2 > 0:
        cov[zero, :] = 0.0
        cov[:, zero] = 0.0
        cov[zero, zero] = s2 * np.diag(bread)[zero]
    return cov, sorted(undetermined), widths


def ols_covariance(jac: FloatArray, r: FloatArray) -> tuple[FloatArray, list[int]]:
    """s²·(JᵀJ)⁻¹ on the determined subspace, and the undetermined parameters.

    The textbook covariance for independent residuals, s² = ‖r‖²/(n − p).

    Parameters
    ----------
    jac : ndarray, shape (n, p)
    r : ndarray, shape (n,)

    Returns
    -------
    covariance : ndarray, shape (p, p)
    undetermined : list of int
        Columns the data do not determine (a singular JᵀJ).
    """
    n, p = jac.shape
    if p == 0:
        return np.zeros((0, 0)), []
    if n <= p:
        return np.zeros((p, p)), list(range(p))
    norms = np.linalg.norm(jac, axis=0)
    dead = norms == 0
    scale = np.where(dead, 1.0, norms)
    _, s, vt = np.linalg.svd(jac / scale, full_matrices=False)
    keep = s > _RANK_TOL * s[0] if s[0] > 0 else np.zeros_like(s, dtype=bool)
    s2 = float(r @ r) / (n - p)
    inv = (vt[keep].T / s[keep] ** 2) @ vt[keep]
    cov = s2 * inv / np.outer(scale, scale)
    undetermined = set(np.flatnonzero(dead).tolist())
    for row in vt[~keep]:
        undetermined |= set(np.flatnonzero(np.abs(row) > 1e-3).tolist())
    return cov, sorted(undetermined)


def full_covariance(matrix: FloatArray, cov: FloatArray, se: FloatArray) -> FloatArray:
    """Covariance of every parameter from that of the free ones: M·C·Mᵀ.

    `matrix` maps the free parameters to all of them (fixed rows 0, tied rows
    their factor); a parameter whose standard error is inf (undetermined) gets
    an infinite variance.
    """
    full = matrix @ cov @ matrix.T if matrix.shape[1] else np.zeros((matrix.shape[0],) * 2)
    full[np.diag_indices_from(full)] = np.where(np.isinf(se), np.inf, np.diag(full))
    return full


def correlation_matrix(covariance: FloatArray) -> FloatArray:
    """Correlations C_ij/sqrt(C_ii·C_jj); 0 off the diagonal where a variance is 0 or inf.

    Parameters
    ----------
    covariance : ndarray, shape (p, p)

    Returns
    -------
    ndarray, shape (p, p)
        With ones on the diagonal where the variance is positive and finite.
    """
    c = as_real_array("covariance", covariance, finite=False)
    if c.ndim != 2 or c.shape[0] != c.shape[1]:
        raise ValueError(f"`covariance` must be a square matrix; got shape {c.shape}.")
    if np.any(np.diag(c) < 0):
        raise ValueError(f"`covariance` must have a nonnegative diagonal; got {fmt(np.diag(c))}.")
    d = np.sqrt(np.diag(c))
    ok = np.isfinite(d) & (d > 0)
    out = np.zeros_like(c)
    with np.errstate(invalid="ignore", divide="ignore"):
        out[np.ix_(ok, ok)] = c[np.ix_(ok, ok)] / np.outer(d[ok], d[ok])
    np.fill_diagonal(out, np.where(ok, 1.0, 0.0))
    return np.clip(out, -1.0, 1.0)


def bounded_interval(value: float, half: float, lo: float, hi: float) -> tuple[float, float]:
    """value ± half (Wald), unless that interval crosses a bound of the parameter: the data then
    do not exclude the bound, so the interval reaches it, and its far end is taken on a log
    scale from the bound, lo + d·exp(half/d) with d = value − lo (mirrored for hi), which agrees
    with the Wald end to first order in half/d and lies beyond it. It never leaves [lo, hi]; a
    value on its bound, or an infinite error, reaches out to the bound itself."""
    a, b = value - half, value + half
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        if a < lo:
            d = value - lo
            a, b = lo, (lo + d * np.exp(half / d) if d > 0 else b)
        if b > hi:
            d = hi - value
            a, b = (min(a, hi - d * np.exp(half / d)) if d > 0 else a), hi
    a, b = float(max(a, lo)), float(min(b, hi))
    if np.isfinite(half) and np.isfinite(value):  # beyond 6 decades: the data do not bound it
        far = 1e6 * max(abs(value), half)
        a = a if abs(a - value) <= far else -np.inf if lo == -np.inf else float(lo)
        b = b if abs(b - value) <= far else np.inf if hi == np.inf else float(hi)
    return (a if np.isfinite(half) else float(lo), b if np.isfinite(half) else float(hi))
