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
that); it is used as a floor on each variance (correlations from the sandwich).
Why: a record's initial velocity and preload are fixed by its first few
samples, where any sandwich sees only a handful of residuals, already pulled
towards zero by the fit, and the velocity rows' noise (a difference of position
noise, negatively correlated at lag 2 for central differences) makes the
Bartlett sum smaller still: their standard errors came out half of C_white's,
and 95 % intervals held the truth in about 85 % of records. C_white uses the
noise level of every sample instead.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding.identification.uncertainty import hac_covariance, ols_covariance

__all__ = ["MAX_LEVERAGE", "Link", "fit_covariance", "leverage", "white_floor"]

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


def white_floor(jac: FloatArray, residual: FloatArray, links: Sequence[Link]) -> FloatArray | None:
    """The variances C_white of the free parameters (module notes), or None when some rows
    belong to no link (then there is no single position noise to refer to)."""
    n, p = jac.shape
    covered = np.zeros(n, dtype=bool)
    for link in links:
        covered[link.velocity] = covered[link.position] = True
    m = sum(link.position.stop - link.position.start for link in links)
    if not links or not np.all(covered) or m <= p:
        return None
    moved = []
    ss = 0.0
    for link in links:
        jy, jv = jac[link.position], jac[link.velocity]
        moved.append(jy + link.ratio * (link.operator.T @ jv))
        ss += float(residual[link.position] @ residual[link.position])
    tilde = np.vstack(moved)
    norms = np.linalg.norm(jac, axis=0)
    scale = np.where(norms == 0, 1.0, norms)
    scaled = jac / scale
    bread = np.linalg.pinv(scaled.T @ scaled, rcond=1e-12, hermitian=True)
    left = (tilde / scale) @ bread  # J̃·(JᵀJ)⁻¹, in the scaled coordinates
    var = np.sum(left * left, axis=0) / scale**2
    return var * ss / (m - p)


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
    h = np.minimum(leverage(jac), MAX_LEVERAGE)
    adjusted = hac_covariance(jac, residual / (1.0 - h), blocks, clusters=clusters)[0]
    var = np.maximum(np.diag(adjusted) * ((n - p) / n), np.diag(plain))
    floor = white_floor(jac, residual, links) if links else None
    if floor is not None:
        var = np.where(np.diag(plain) > 0, np.maximum(var, floor), var)
    sd, sd_plain = np.sqrt(np.maximum(var, 0.0)), np.sqrt(np.maximum(np.diag(plain), 0.0))
    with np.errstate(invalid="ignore", divide="ignore"):
        scale = np.where(sd_plain > 0, sd / sd_plain, 0.0)
    return plain * np.outer(scale, scale), undetermined, widths
