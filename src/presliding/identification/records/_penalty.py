"""The hinge row that keeps a derived F_c (eq. 9) at or above `min_coulomb_level`.

A pooled fit whose model derives F_c = c1 + Σ c_j may be given a least level
F_min; its residual then gains one row, scale·max(0, F_min − F_c), steep
enough that the optimum never sits below the level, and zero above it.
"""

from __future__ import annotations

import numpy as np

from presliding.identification.records import _pooled_problem as pp

__all__ = ["with_penalty"]


def with_penalty(problem: pp.PooledProblem, rigid: bool, fmin: float | None):
    """Residual and Jacobian, with a hinge row max(0, F_min − F_c) when F_c is derived."""
    fun, jac = problem.residual(rigid), problem.free_jacobian(rigid)
    if fmin is None:
        return fun, jac
    names = problem.names
    scale = 10.0 * float(np.sqrt(max(problem.n_res, 1)) * np.max(np.abs(problem.data)) / fmin)

    def hinge(p):
        q = dict(zip(names, p, strict=True))
        return scale * max(0.0, fmin - problem.spec.coulomb_level(q))

    def fun_p(p):
        return np.append(fun(p), hinge(p))

    def jac_p(pm, x, lo, hi):
        base = jac(pm, x, lo, hi)
        row = np.zeros(x.shape[0])
        h0 = hinge(pm.full(x))
        for j in range(x.shape[0]):
            step = 1e-7 * max(abs(x[j]), 1e-12)
            xs = x.copy()
            xs[j] += step
            row[j] = (hinge(pm.full(xs)) - h0) / step
        return np.vstack([base, row])

    return fun_p, jac_p
