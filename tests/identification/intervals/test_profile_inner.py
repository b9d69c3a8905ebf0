"""The inner optimisation of a profile point (`identification._profile_inner`):
Levenberg–Marquardt with per-record steps and an absolute stopping tolerance."""

from __future__ import annotations

import numpy as np
from scipy import optimize, sparse

from presliding.identification.intervals._profile_inner import minimise


def _records(records=5, seed=2):
    """y_i = A_i·exp(−k·t_i·s_i): k shared, A_i and s_i each record's own (a nonlinear block)."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 3.0, 25)
    a, s = rng.uniform(1.0, 3.0, records), rng.uniform(0.5, 2.0, records)
    y = a[:, None] * np.exp(-1.3 * s[:, None] * t) + rng.normal(0.0, 0.02, (records, t.size))

    def fun(p):
        k, amp, sc = p[0], p[1::2], p[2::2]
        return (amp[:, None] * np.exp(-k * sc[:, None] * t) - y).ravel()

    def jac(p):
        k, amp, sc = p[0], p[1::2], p[2::2]
        out = np.zeros((records * t.size, 1 + 2 * records))
        for i in range(records):
            rows = slice(i * t.size, (i + 1) * t.size)
            e = np.exp(-k * sc[i] * t)
            out[rows, 0] = -amp[i] * sc[i] * t * e
            out[rows, 1 + 2 * i] = e
            out[rows, 2 + 2 * i] = -amp[i] * k * t * e
        return out

    start = np.concatenate([[1.0], np.ravel(np.column_stack([np.ones(records), s * 1.5]))])
    return fun, jac, start


def test_per_record_steps_reach_the_least_squares_optimum():
    """From a start far from the optimum, with a sparse Jacobian of record blocks (per-record
    steps) and a dense one (plain method): the cost of scipy's solution to 1e-9, and the
    result says it converged."""
    fun, jac, start = _records()
    lo, hi = np.full(start.shape, -np.inf), np.full(start.shape, np.inf)
    hi[0] = 10.0
    ref = optimize.least_squares(fun, start, jac=jac, xtol=1e-15, ftol=1e-15, gtol=1e-15)
    best = float(ref.fun @ ref.fun)
    for j in (jac, lambda p: sparse.csc_matrix(jac(p))):
        out = minimise(fun, j, start, lo, hi, tol=1e-12 * best, max_nfev=400)
        assert out.converged
        assert abs(out.cost - best) <= 1e-9 * best
        assert out.remaining <= 1e-12 * best


def test_the_evaluation_limit_is_honoured_and_reported():
    fun, jac, start = _records()
    lo, hi = np.full(start.shape, -np.inf), np.full(start.shape, np.inf)
    out = minimise(fun, jac, start, lo, hi, tol=0.0, max_nfev=4)
    assert out.nfev <= 5 and not out.converged
    assert out.cost <= float(fun(start) @ fun(start))
