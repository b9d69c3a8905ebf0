"""The structured finite-difference Jacobian of a pooled problem (`_pooled_problem`).

A free parameter that moves only per-record parameters touches only those
records' rows, so the columns of different records are perturbed together
(`PooledProblem.column_groups`): every trial point of a Jacobian is simulated
in one compiled call. Central differences for small problems; forward ones
from the residual the solver has just evaluated for large ones, each step away
from zero (up for a value ≥ +0, down for a value ≤ −0; the other way at a
bound), so a record and its mirror image (positions, velocities and forces
negated: the records' own parameters change sign, the shared ones do not) take
mirrored steps and give the same parameters to rounding. The forward trial
point of a group moves each of its columns in its own direction: one
simulation per group.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding.identification.records import _pooled_kernel as pk

FloatArray = NDArray[np.float64]

__all__ = [
    "ForwardLayout",
    "assemble",
    "difference_columns",
    "difference_steps",
    "forward_jacobian",
]


def difference_steps(x: FloatArray, lo: FloatArray, hi: FloatArray, typical: FloatArray,
                     central: bool) -> tuple[FloatArray, FloatArray]:  # fmt: skip
    """The steps up and down of each free parameter, within its bounds; `typical` is the
    magnitude below which a step does not shrink. Forward steps go away from zero (module
    notes): exactly one of the two is nonzero, unless both bounds pin the parameter."""
    eps = np.finfo(float).eps
    h = (np.cbrt(eps) if central else np.sqrt(eps)) * np.maximum(
        np.abs(x), typical * (1.0 if central else 1e-2)
    )
    up, down = np.minimum(h, hi - x), np.minimum(h, x - lo)
    if central:
        return up, down
    go_down = np.where(np.signbit(x), down > 0, ~(up > 0))
    return np.where(go_down, 0.0, up), np.where(go_down, down, 0.0)


def difference_columns(
    problem: Any, pm: Any, x: FloatArray, up: FloatArray, down: FloatArray, groups: list,
    col_rows: list, rigid: bool, base: FloatArray | None,
) -> list:  # fmt: skip
    """Each free column's values on its rows: the groups perturbed together, every trial
    point simulated in one call; one-sided from `base` (the residual at x) when given,
    each column of a group stepping in its own direction (module notes)."""
    sets = []
    for g in groups:
        if base is not None:
            xt = x.copy()
            xt[g] += up[g] - down[g]
            sets.append(pm.full(xt))
            continue
        xp, xm = x.copy(), x.copy()
        xp[g] += up[g]
        xm[g] -= down[g]
        sets.extend((pm.full(xp), pm.full(xm)))
    res = problem.residuals(np.array(sets), rigid)
    values: list = [None] * x.shape[0]
    for k, g in enumerate(groups):
        if base is not None:
            plus, minus = res[k], base
        else:
            plus, minus = res[2 * k], res[2 * k + 1]
        with np.errstate(invalid="ignore"):  # a trial point outside the model's range
            diff = plus - minus
        # (an infinite residual on both sides): no usable slope there, none assumed
        diff[~np.isfinite(diff)] = 0.0
        for j in g:
            rows = col_rows[j]
            if base is not None:
                step = up[j] - down[j]  # signed: the one nonzero side
                values[j] = diff[rows] / step if step != 0 else np.zeros(rows.shape[0])
                continue
            span = up[j] + down[j]
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


class ForwardLayout:
    """Where each free column's values sit in a CSC Jacobian's data (`forward_jacobian`):
    for every stored entry, the flat index of its value in the (groups, rows) array of
    residual differences, and the column it divides by; the CSC indices and pointers."""

    def __init__(self, groups: list, col_rows: list, n_res: int):
        group_of = np.empty(len(col_rows), dtype=np.intp)
        for k, g in enumerate(groups):
            group_of[g] = k
        counts = np.array([r.shape[0] for r in col_rows], dtype=np.intp)
        # the index type scipy would choose, so that the matrices share these arrays
        kind = np.int32 if max(int(counts.sum()), n_res) < np.iinfo(np.int32).max else np.int64
        self.gather = np.concatenate(
            [group_of[j] * n_res + rows for j, rows in enumerate(col_rows)]
        ) if col_rows else np.zeros(0, dtype=np.intp)  # fmt: skip
        self.column = np.repeat(np.arange(len(col_rows)), counts)
        self.indices = (np.concatenate(col_rows) if col_rows else np.zeros(0)).astype(kind)
        self.indptr = np.concatenate([[0], np.cumsum(counts)]).astype(kind)
        self.shape = (n_res, len(col_rows))


def forward_jacobian(
    problem: Any, pm: Any, x: FloatArray, up: FloatArray, down: FloatArray, groups: list,
    layout: ForwardLayout, rigid: bool, base: FloatArray,
) -> Any:  # fmt: skip
    """The CSC Jacobian by forward differences from `base` (the residual at x): the values
    of `difference_columns` and `assemble` to the last bit, gathered in one pass."""
    from scipy import sparse

    sets = []
    for g in groups:
        xt = x.copy()
        xt[g] += up[g] - down[g]
        sets.append(pm.full(xt))
    res = problem.residuals(np.array(sets), rigid)
    data = np.empty(layout.gather.shape[0])
    pk.forward_columns(res, base, layout.gather, layout.column, layout.indices, up - down, data)
    return sparse.csc_matrix((data, layout.indices, layout.indptr), shape=layout.shape)
