"""The covariance of a least-squares fit: one entry point for every fit kind.

`fit_covariance` is called where the solver has its optimum (Jacobian J of the
free parameters, residual r). Without blocks the residuals are taken as
independent: s²·(JᵀJ)⁻¹ (`uncertainty.ols_covariance`). With blocks (records,
or the signals of a record, whose residuals are serially correlated) it is the
HAC sandwich of `uncertainty.hac_covariance` (Newey–West, Andrews' bandwidth,
the record-level sandwich as a floor), computed from leverage-adjusted
residuals:

    r̃_t = r_t / (1 − h_t),    h_t = J_t (JᵀJ)⁻¹ J_tᵀ,

the HC3 form of MacKinnon & White (1985) inside the Bartlett sum, and without
the n/(n − p) factor (which the adjustment replaces). Why: a pooled fit has
parameters that only a few samples determine (a record's initial velocity is
fixed by its first samples, an element that slides only briefly by those
samples). The fit pulls the residuals at such samples towards zero (the
leverage h_t is close to 1 there), so the plain sandwich, built from those
residuals, sees almost no scatter and its standard errors come out too small
(95 % intervals holding the truth in about 75 % of fits). Dividing by 1 − h_t
restores the scatter those samples had before the fit absorbed it; where
every sample has a small leverage (the shared parameters of a long record)
nothing changes. Only the variances are taken from the adjusted residuals (never
below the plain ones); the correlations stay those of the plain sandwich: a few
rescaled samples would otherwise dominate the meat and make two parameters
look perfectly correlated. The leverage is capped at `MAX_LEVERAGE`: a parameter fixed by
a single sample is not estimated with a finite factor anyway (its variance falls
back to s²·(JᵀJ)⁻¹ in `hac_covariance`, or it is undetermined).

Velocity from the position (`links`). When a record's velocity is the
difference quotient of its position, v = D·y (`numpy.gradient`, compared as
such: `_pooled_problem`), its velocity residual is c·D times its position
residual (c = w_v/w_y, the ratio of the signal weights), and so is its
Jacobian: the two signals carry one noise, the position's. The score of the
record is then Σ_t J̃_t·r_y,t with

    J̃ = J_y + c·Dᵀ·J_v       (the velocity rows moved onto the position rows),

and with independent position noise of variance s_y² (estimated from the
position residuals, ‖r_y‖²/(m − p)) the covariance is exactly

    C_white = s_y² · (JᵀJ)⁻¹ · J̃ᵀJ̃ · (JᵀJ)⁻¹.

That is the least the data allow (quantisation and sensor noise are at least
that). The sandwich of such a fit is formed from the moved scores too
(`linked_sandwich`: per record the Bartlett sum of g_t = J̃_t·r_y,t, the
record-level sandwich as a floor), and each variance is the larger of the two
(correlations from the sandwich); the leverage adjustment is not needed then.
Why: with the velocity and position blocks apart, the velocity scores' noise
(a difference of position noise, negatively correlated at lag 2 for central
differences, its sum telescoping) enters the Bartlett sum as if it were
independent, and the cross terms with the position block are lost. In the
pooled-stops study the shared parameters' standard errors came out about four
times too large (z = (estimate − truth)/SE with a spread of 0.25), while the
records' initial velocities and preloads, fixed by their first few samples
where any sandwich sees only a handful of residuals already pulled towards zero,
came out too small (spread 1.4–1.6, 85–90 % coverage). With the moved scores
and the floor, over the 34 of 40 seeds whose fit is in the true valley: spreads
0.75–1.1 for the shared parameters, 1.05–1.15 for the initial positions and
preloads (1.9 for the initial velocities, from a few records), coverage 91–97 %.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding.identification.uncertainty import (
    _RANK_TOL,
    _singular,
    andrews_bandwidth,
    hac_covariance,
    ols_covariance,
)
from presliding.identification.uncertainty import (
    _bartlett_meat as bartlett_meat,
)

__all__ = [
    "MAX_LEVERAGE",
    "Link",
    "fit_covariance",
    "leverage",
    "linked_sandwich",
    "undetermined_columns",
    "white_floor",
]

FloatArray = NDArray[np.float64]

#: Largest leverage used in the adjustment (a residual is scaled by at most 1/(1 − 0.9)).
MAX_LEVERAGE = 0.9


def leverage(jac: FloatArray) -> FloatArray:
    """The diagonal h_t of the hat matrix J (JᵀJ)⁺ Jᵀ (columns scaled, rank-revealing).

    Parameters
    ----------
    jac : ndarray, shape (n, p)

    Returns
    -------
    ndarray, shape (n,)
        In [0, 1]; 0 for every row when J has no nonzero column.
    """
    n, p = jac.shape
    if p == 0 or n == 0:
        return np.zeros(n)
    norms = np.linalg.norm(jac, axis=0)
    scaled = jac / np.where(norms == 0, 1.0, norms)
    gram = scaled.T @ scaled
    inv = np.linalg.pinv(gram, rcond=1e-12, hermitian=True)
    h = np.sum((scaled @ inv) * scaled, axis=1)  # one matrix product (BLAS), not a triple loop
    return np.clip(h, 0.0, 1.0)


@dataclass(frozen=True)
class Link:
    """A velocity block that is c·D times a position block (module notes).

    ``velocity`` and ``position`` are the rows of the two blocks (of equal length),
    ``operator`` the difference matrix D (sparse or dense, n × n), ``ratio`` c.
    """

    velocity: slice
    position: slice
    operator: Any
    ratio: float


def _covered(n: int, p: int, links: Sequence[Link]) -> bool:
    """Every row belongs to a link, and the position rows outnumber the parameters."""
    covered = np.zeros(n, dtype=bool)
    for link in links:
        covered[link.velocity] = covered[link.position] = True
    m = sum(link.position.stop - link.position.start for link in links)
    return bool(links) and bool(np.all(covered)) and m > p


def _moved(jac: FloatArray, link: Link) -> FloatArray:
    """J̃ = J_y + c·DᵀJ_v of one link (module notes)."""
    return jac[link.position] + link.ratio * (link.operator.T @ jac[link.velocity])


def _bread(jac: FloatArray) -> tuple[FloatArray, FloatArray]:
    """(JᵀJ)⁺ in the coordinates of the columns scaled to unit norm, and the scales."""
    norms = np.linalg.norm(jac, axis=0)
    scale = np.where(norms == 0, 1.0, norms)
    scaled = jac / scale
    return np.linalg.pinv(scaled.T @ scaled, rcond=1e-12, hermitian=True), scale


def white_floor(jac: FloatArray, residual: FloatArray, links: Sequence[Link]) -> FloatArray | None:
    """The variances C_white of the free parameters (module notes), or None when some rows
    belong to no link (then there is no single position noise to refer to)."""
    n, p = jac.shape
    if not _covered(n, p, links):
        return None
    tilde = np.vstack([_moved(jac, link) for link in links])
    ss = sum(float(residual[link.position] @ residual[link.position]) for link in links)
    m = tilde.shape[0]
    bread, scale = _bread(jac)
    left = (tilde / scale) @ bread  # J̃·(JᵀJ)⁻¹, in the scaled coordinates
    return np.sum(left * left, axis=0) / scale**2 * ss / (m - p)


def linked_sandwich(jac: FloatArray, residual: FloatArray, links: Sequence[Link]) -> FloatArray:
    """The HAC sandwich of the moved scores g_t = J̃_t·r_y,t (module notes), one block per
    link (record), with the record-level sandwich as a floor for three or more records.

    The Bartlett bandwidth of a record is the larger of Andrews' for its moved scores and
    for its position scores alone (a record at rest after its stop keeps the quantisation
    error of its last position: the position scores are correlated over the rest).
    """
    n, p = jac.shape
    bread, scale = _bread(jac)
    meat, sums = np.zeros((p, p)), []
    for link in links:
        tilde, ry = _moved(jac, link) / scale, residual[link.position]
        cols = np.flatnonzero(np.any(tilde != 0, axis=0))
        g = tilde[:, cols] * ry[:, None]
        alone = (jac[link.position][:, cols] / scale[cols]) * ry[:, None]
        lag = max(andrews_bandwidth(g), andrews_bandwidth(alone))
        meat[np.ix_(cols, cols)] += bartlett_meat(g, lag)
        sums.append(tilde.T @ ry)
    cov = bread @ meat @ bread * (n / (n - p))
    if len(sums) >= 3:
        g_n = len(sums)
        omega = sum(np.outer(v, v) for v in sums) * g_n / (g_n - 1)
        robust = bread @ omega @ bread * (n / (n - p))
        sd_h, sd_c = np.sqrt(np.maximum(np.diag(cov), 0)), np.sqrt(np.maximum(np.diag(robust), 0))
        with np.errstate(invalid="ignore", divide="ignore"):
            corr = np.where(np.outer(sd_h, sd_h) > 0, cov / np.outer(sd_h, sd_h), 0.0)
        cov = corr * np.outer(np.maximum(sd_h, sd_c), np.maximum(sd_h, sd_c))
    return cov / np.outer(scale, scale)


def fit_covariance(
    jac: FloatArray,
    residual: FloatArray,
    blocks: Sequence[NDArray[np.intp] | slice] | None = None,
    clusters: Sequence[int] | None = None,
    links: Sequence[Link] | None = None,
) -> tuple[FloatArray, list[int], list[int]]:
    """Covariance of the free parameters at a least-squares optimum (module notes).

    Parameters
    ----------
    jac : ndarray, shape (n, p)
        ∂r/∂θ of the free parameters at the optimum.
    residual : ndarray, shape (n,)
    blocks : sequence of index arrays or slices, optional
        Rows of each serially correlated block; None: independent residuals.
    clusters : sequence of int, optional
        The independent record of each block (`uncertainty.hac_covariance`).
    links : sequence of Link, optional
        Velocity blocks that are the difference quotient of a position block: each
        variance is at least that of independent position noise (module notes).

    Returns
    -------
    covariance : ndarray, shape (p, p)
    undetermined : list of int
        Columns the data do not determine.
    bandwidths : list of int
        The Bartlett bandwidth of each block (empty without blocks).
    """
    if blocks is None:
        cov, undetermined = ols_covariance(jac, residual)
        return cov, undetermined, []
    n, p = jac.shape
    if n <= p or p == 0:
        return hac_covariance(jac, residual, blocks, clusters=clusters)
    plain, undetermined, widths = hac_covariance(jac, residual, blocks, clusters=clusters)
    floor = white_floor(jac, residual, links) if links else None
    if links and floor is not None:  # one noise, the position's (module notes)
        linked = linked_sandwich(jac, residual, links)
        var = np.where(np.diag(plain) > 0, np.maximum(np.diag(linked), floor), 0.0)
        sd, sd_l = np.sqrt(var), np.sqrt(np.maximum(np.diag(linked), 0.0))
        with np.errstate(invalid="ignore", divide="ignore"):
            corr = np.where(np.outer(sd_l, sd_l) > 0, linked / np.outer(sd_l, sd_l), 0.0)
        np.fill_diagonal(corr, 1.0)
        return corr * np.outer(sd, sd), undetermined, widths
    h = np.minimum(leverage(jac), MAX_LEVERAGE)
    adjusted = hac_covariance(jac, residual / (1.0 - h), blocks, clusters=clusters)[0]
    var = np.maximum(np.diag(adjusted) * ((n - p) / n), np.diag(plain))
    sd, sd_plain = np.sqrt(np.maximum(var, 0.0)), np.sqrt(np.maximum(np.diag(plain), 0.0))
    with np.errstate(invalid="ignore", divide="ignore"):
        scale = np.where(sd_plain > 0, sd / sd_plain, 0.0)
    return plain * np.outer(scale, scale), undetermined, widths


def undetermined_columns(jac: FloatArray, blocks: Any) -> list[int] | None:
    """The columns `fit_covariance` finds undetermined, without the covariance: the same
    scaled factorisation as `uncertainty.hac_covariance` (a dead column, or a large entry
    of a right singular vector below its rank tolerance). None where `fit_covariance`
    takes another route (no blocks, or no more rows than columns): the caller then
    computes the covariance itself."""
    n, p = jac.shape
    if blocks is None or n <= p or p == 0:
        return None
    jac = np.asarray(jac, dtype=float)
    norms = np.linalg.norm(jac, axis=0)
    dead = norms == 0
    s, vt = _singular(jac / np.where(dead, 1.0, norms))
    keep = s > _RANK_TOL * s[0] if s[0] > 0 else np.zeros_like(s, dtype=bool)
    undetermined = set(np.flatnonzero(dead).tolist())
    for row in vt[~keep]:
        undetermined |= set(np.flatnonzero(np.abs(row) > 1e-3).tolist())
    return sorted(undetermined)
