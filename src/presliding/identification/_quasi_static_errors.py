"""A floor on the standard errors of a pooled fit from runs of equal quantised samples.

Why. A quantised position (an encoder) that stands still over a run of
samples, while the contact sticks, repeats one value: the quantisation error
of those samples is one and the same, it does not average out over the run.
The least-squares residual cannot show it where a parameter is fixed by such
a run alone: a record's initial position is the only parameter that moves its
first samples, before the force has overcome c1 (on the samples after them it
is collinear with the record's preload, which shifts the whole loop), so the
fit takes the run's value exactly, leaves residuals of 0 there, and the
sandwich (`_covariance.fit_covariance`), built from those residuals, gives a
standard error up to 10⁶ times too small (the leverage adjustment cannot help:
the run's residuals are 0, not merely shrunk). The preload inherits the error
through the collinearity.

The floor. The error covariance the noise alone implies, with the samples of
each run of equal values perfectly correlated and independent otherwise,

    Σ = σ_b² · (blocks of ones over each run),    Cov_floor = H⁻¹ Jᵀ Σ J H⁻¹,  H = JᵀJ,

σ_b² the noise variance of the block's signal estimated from the data
(`_noise_floor.noise_variance`: quantisation q²/12 or the high-frequency
noise), is the least covariance the data support. Every free parameter's
variance is the larger of the fit's and this floor's; the correlations stay
the fit's, the Wald intervals are formed again from the raised errors (the
profile then uses them for its threshold). Unquantised data have runs of one
sample: the floor is then the ordinary s²·H⁻¹ with the noise floor for s², which the
fit's own covariance exceeds anyway.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import sparse

from presliding.identification._noise_floor import noise_variance
from presliding.identification._solution import Solution
from presliding.identification.uncertainty import bounded_interval

__all__ = ["floor_variances", "run_matrix", "with_run_floor"]

FloatArray = NDArray[np.float64]


def run_matrix(problem: Any) -> sparse.csr_matrix:
    """S (runs × residual rows): σ_b on the rows of each run of equal measured values.

    Runs are taken within each residual block (a record's signal), so that
    SᵀS = Σ, the error covariance of the module notes.
    """
    rows, cols, vals, n_runs = [], [], [], 0
    for _, block in problem.rows:
        data = problem.data[block]
        if data.shape[0] == 0:
            continue
        sigma = float(np.sqrt(noise_variance(data)))
        run = np.concatenate([[0], np.cumsum(np.diff(data) != 0)])
        rows.append(n_runs + run)
        cols.append(np.arange(block.start, block.stop))
        vals.append(np.full(data.shape[0], sigma))
        n_runs += int(run[-1]) + 1
    if not rows:
        return sparse.csr_matrix((0, problem.n_res))
    return sparse.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
        shape=(n_runs, problem.n_res),
    )


def floor_variances(jac: Any, runs: sparse.csr_matrix) -> FloatArray:
    """diag(H⁻¹ Jᵀ Σ J H⁻¹) with Σ = SᵀS (module notes); columns scaled, pseudo-inverse."""
    dense = jac.toarray() if sparse.issparse(jac) else np.asarray(jac, dtype=float)
    norms = np.linalg.norm(dense, axis=0)
    norms[norms == 0] = 1.0
    scaled = dense / norms
    hinv = np.linalg.pinv(scaled.T @ scaled, rcond=1e-12, hermitian=True)
    g = np.asarray(runs @ scaled)
    meat = g.T @ g
    return np.diag(hinv @ meat @ hinv) / norms**2


def with_run_floor(sol: Solution, problem: Any) -> Solution:
    """`sol` with every free parameter's variance raised to the floor (module notes).

    Tied parameters follow their target; fixed ones keep 0. A failed solve, or
    one without a profiler (nothing free), is returned as it is.
    """
    prof = sol.profiler
    if prof is None or sol.status == "failed" or sol.covariance is None or not prof.free:
        return sol
    x = np.array([sol.values[n] for n in prof.free], dtype=float)
    jac = prof.jacobian(x)
    dense_ok = np.all(np.isfinite(jac.data if sparse.issparse(jac) else jac))
    if not dense_ok:
        return sol
    floor = floor_variances(jac, run_matrix(problem))
    se = dict(sol.standard_error)
    for name, var in zip(prof.free, floor, strict=True):
        old = se[name]
        if np.isfinite(old) and np.isfinite(var) and var > old * old:
            se[name] = float(np.sqrt(var))
    for name, (target, factor, _) in sol.ties.items():
        if target in se:
            se[name] = abs(factor) * se[target]
    grown = [n for n in se if se[n] > sol.standard_error[n]]
    if not grown:
        return sol
    names = list(sol.values)
    scale = np.array([se[n] / sol.standard_error[n] if n in grown else 1.0 for n in names])
    cov = np.array(sol.covariance, dtype=float)
    with np.errstate(invalid="ignore"):
        cov = cov * np.outer(scale, scale)
    ci = dict(sol.confidence_interval)
    for n in grown:
        lo, hi = sol.bounds.get(n, (-np.inf, np.inf))
        ci[n] = bounded_interval(sol.values[n], prof.quantile * se[n], lo, hi)
    return replace(sol, standard_error=se, covariance=cov, confidence_interval=ci)
