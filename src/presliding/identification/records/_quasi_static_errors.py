"""A floor on the standard errors of a pooled fit from the samples where the contact sticks.

Why. Where the contact sticks, the true position is constant over a stretch
of samples, and a quantised position (an encoder) reads one value there, up to
the noise that sometimes flips a sample to the next level: the quantisation
error is common to the stretch and does not average out over it. The
least-squares residual cannot show it where a parameter is fixed by such a
stretch alone: a record's initial position is the only parameter that moves
its first samples, before the force has overcome c1 (on the samples after them
it is collinear with the record's preload, which shifts the whole loop), so
the fit takes the stretch's value exactly, leaves residuals of 0 there, and
the sandwich (`_covariance.fit_covariance`), built from those residuals, gives
a standard error up to 10⁶ times too small (the leverage adjustment cannot
help: the residuals are 0, not merely shrunk). The preload inherits the error
through the collinearity.

The floor. The error covariance the noise alone implies: each sample's noise
variance σ_b² (`_noise_floor.noise_variance` of the block's signal:
quantisation q²/12 or the high-frequency noise) split into a part v_ind
independent from sample to sample, estimated as the pooled variance of the
residual within the stick stretches (the runs where the fitted signal is
constant), and a part v_com = σ_b² − v_ind common to the samples of one stick
stretch (independent elsewhere):

    Σ = v_ind·I + v_com·(blocks of ones over each stick stretch),
    Cov_floor = H⁻¹ Jᵀ Σ J H⁻¹,  H = JᵀJ.

It is the least covariance the data support for the records' own parameters,
which only a few stretches determine; their variance is the larger of the
fit's and this floor's (the shared parameters keep the fit's sandwich, which
sees their information spread over many samples and records). The
correlations stay the fit's, the Wald intervals are formed again from the
raised errors (the profile then uses them for its threshold). Without stick
stretches, Σ = σ_b²·I, the ordinary floor s²·H⁻¹, which the fit's own errors
exceed anyway.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import sparse

from presliding.identification.judge._noise_floor import noise_variance
from presliding.identification.solve._normal_equations import inverse_normal
from presliding.identification.solve._solution import Solution
from presliding.identification.uncertainty import bounded_interval

__all__ = ["floor_variances", "run_matrix", "with_run_floor"]

FloatArray = NDArray[np.float64]


def run_matrix(problem: Any, residual: FloatArray) -> sparse.csr_matrix:
    """G with GᵀG = Σ (module notes): rows √v_ind on every residual row, and √v_com over
    each stick stretch (consecutive rows of one block whose fitted signal is constant)."""
    fitted = problem.data + residual
    rows, cols, vals, n_out = [], [], [], 0
    for _, block in problem.rows:
        data, fit, r = problem.data[block], fitted[block], residual[block]
        n = data.shape[0]
        if n == 0:
            continue
        total = noise_variance(data)
        run = np.concatenate([[0], np.cumsum(np.diff(fit) != 0)])
        sizes = np.bincount(run)
        means = np.bincount(run, weights=r) / sizes
        spread = float(np.sum((r - means[run]) ** 2))
        dof = int(np.sum(sizes[sizes > 1] - 1))
        independent = min(spread / dof, total) if dof else total
        common = total - independent
        index = np.arange(block.start, block.stop)
        rows += [n_out + np.arange(n), n_out + n + run]
        cols += [index, index]
        vals += [np.full(n, np.sqrt(independent)), np.full(n, np.sqrt(common))]
        n_out += n + int(run[-1]) + 1
    if not rows:
        return sparse.csr_matrix((0, problem.n_res))
    return sparse.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
        shape=(n_out, problem.n_res),
    )


def floor_variances(jac: Any, runs: sparse.csr_matrix) -> FloatArray:
    """diag(H⁻¹ Jᵀ Σ J H⁻¹) with Σ = GᵀG (module notes); H⁻¹ as the profile forms it."""
    hinv = inverse_normal(jac)
    g = runs @ jac
    g = g.toarray() if sparse.issparse(g) else np.asarray(g, dtype=float)
    return np.diag(hinv @ (g.T @ g) @ hinv)


def with_run_floor(sol: Solution, problem: Any) -> Solution:
    """`sol` with the records' own parameters' variances raised to the floor (module notes).

    Tied parameters follow their target; fixed ones keep 0. A failed solve, or
    one without a profiler (nothing free), is returned as it is.
    """
    prof = sol.profiler
    if prof is None or sol.status == "failed" or sol.covariance is None or not prof.free:
        return sol
    x = np.array([sol.values[n] for n in prof.free], dtype=float)
    jac = prof.jacobian(x)[: problem.n_res]  # without a hinge row of a bound on F_c
    dense_ok = np.all(np.isfinite(jac.data if sparse.issparse(jac) else jac))
    if not dense_ok:
        return sol
    floor = floor_variances(jac, run_matrix(problem, sol.residual[: problem.n_res]))
    se = dict(sol.standard_error)
    for name, var in zip(prof.free, floor, strict=True):
        old = se[name]
        if problem.record_of.get(name) is None:  # a shared parameter: the sandwich holds
            continue
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
