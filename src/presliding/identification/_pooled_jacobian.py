"""The structured finite-difference Jacobian of a pooled problem (`_pooled_problem`).

A free parameter that moves only per-record parameters touches only those
records' rows, so the columns of different records are perturbed together
(`PooledProblem.column_groups`): every trial point of a Jacobian is simulated
in one compiled call. Central differences for small problems; forward ones
from the residual the solver has just evaluated for large ones (one-sided
downwards at an upper bound).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

__all__ = ["assemble", "difference_columns", "difference_steps"]


def difference_steps(x: FloatArray, lo: FloatArray, hi: FloatArray, typical: FloatArray,
                     central: bool) -> tuple[FloatArray, FloatArray]:  # fmt: skip
    """The steps up and down of each free parameter, within its bounds; `typical` is the
    magnitude below which a step does not shrink."""
    eps = np.finfo(float).eps
    h = (np.cbrt(eps) if central else np.sqrt(eps)) * np.maximum(
        np.abs(x), typical * (1.0 if central else 1e-2)
    )
    up = np.minimum(h, hi - x)
    down = np.minimum(h, x - lo) if central else np.where(up > 0, 0.0, np.minimum(h, x - lo))
    return up, down


def difference_columns(
    problem: Any, pm: Any, x: FloatArray, up: FloatArray, down: FloatArray, groups: list,
    col_rows: list, rigid: bool, base: FloatArray | None,
) -> list:  # fmt: skip
    """Each free column's values on its rows: the groups perturbed together, every trial
    point simulated in one call; one-sided from `base` (the residual at x) when given."""
    sets = []
    for g in groups:
        xp, xm = x.copy(), x.copy()
        xp[g] += up[g]
        xm[g] -= down[g]
        sets.append(pm.full(xp))
        if base is None or np.any(down[g] > 0):
            sets.append(pm.full(xm))
    res = problem.residuals(np.array(sets), rigid)
    values: list = [None] * x.shape[0]
    k = 0
    for g in groups:
        plus = res[k]
        k += 1
        if base is None or np.any(down[g] > 0):
            minus = res[k]
            k += 1
        else:
            minus = base
        with np.errstate(invalid="ignore"):  # a trial point outside the model's range
            diff = plus - minus
        # (an infinite residual on both sides): no usable slope there, none assumed
        diff[~np.isfinite(diff)] = 0.0
        for j in g:
            span = up[j] + down[j]
            rows = col_rows[j]
            values[j] = diff[rows] / span if span > 0 else np.zeros(rows.shape[0])
    return values


def assemble(values: list, col_rows: list, n_res: int, n_free: int, sparse_output: bool) -> Any:
    """The Jacobian from its columns: dense, or CSC."""
    from scipy import sparse

    if not sparse_output:
        out = np.zeros((n_res, n_free))
        for j, rows in enumerate(col_rows):
            out[rows, j] = values[j]
        out[~np.isfinite(out)] = 0.0
        return out
    data = np.concatenate(values)
    data[~np.isfinite(data)] = 0.0
    indptr = np.concatenate([[0], np.cumsum([r.shape[0] for r in col_rows])])
    return sparse.csc_matrix((data, np.concatenate(col_rows), indptr), shape=(n_res, n_free))
