"""Levenberg–Marquardt on every record's own block at once, the shared parameters held.

Given the shared parameters the records are independent: record i's rows
depend only on its own block (initial position, velocity, preload fraction).
`polish_blocks` runs one Levenberg–Marquardt iterate per block (each with its
own damping, Nielsen's rule, and MINPACK's column scaling and stopping tests, as
`_structured_lm`), on the block's normal equations (a few columns, solved in one
batched call for all blocks), instead of one iterate over all blocks together
whose single damping and single accept test hold every record back to the
slowest one. Several candidate blocks of each record (the ranks of the nuisance
grid, `_nuisance_search`) are polished together.

Evaluations are packed: one parameter set carries one block of each record, so
the trial points of all the blocks still moving take as many sets as the record
with the most moving candidates, and a Jacobian (forward differences away from
zero, as `_pooled_jacobian`: a record and its mirror image take mirrored steps)
one set more per column; each is one compiled call. A block stops when its step
lowers the cost by less than `FTOL` times its candidate's total (the other
records' share of the cost dwarfs it), when its step is negligible, or when its
gradient vanishes.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from presliding.identification.problem._parameter_map import parameter_map
from presliding.identification.records import _pooled_jacobian as pj
from presliding.identification.records._pooled_problem import PooledProblem

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

__all__ = ["FTOL", "polish_blocks"]

#: a block whose accepted step lowers the cost by less than this share of its candidate's
#: total cost (all records) stops
FTOL = 1e-6
#: relative step below which a block stops (MINPACK's xtol)
XTOL = 1e-10
#: largest cosine between a block's residual and its columns below which it stops (gtol)
GTOL = 1e-12


def polish_blocks(problem: PooledProblem, vecs: FloatArray, free: set[str],
                  bounds: Mapping[str, tuple[float, float]], costs: FloatArray,
                  steps: int) -> tuple[FloatArray, FloatArray, int]:  # fmt: skip
    """Every record's block of each candidate (`vecs`, one a row, the shared values
    equal) polished for at most `steps` steps (module notes). `costs` (candidates,
    records) are the blocks' costs ‖r_i‖² at the start; a block whose cost is not finite
    stays. Returns the polished candidates, their per-record costs (never above `costs`)
    and the number of parameter sets of the trial steps."""
    lm = _Blocks(problem, vecs, free, bounds)
    evaluations = lm.sets
    moving = lm.free_blocks & np.isfinite(lm.cost) & np.isfinite(costs)
    for _ in range(steps):
        moving &= lm.moving()
        if not moving.any():
            break
        evaluations += lm.step(moving)
    better = 2.0 * lm.cost < costs
    out = vecs.copy()
    for k, i in zip(*np.nonzero(better), strict=True):
        out[k, lm.cols[i]] = lm.x[k, lm.cols[i]]
    return out, np.where(better, 2.0 * lm.cost, costs), evaluations


class _Blocks:
    """The iterates of `polish_blocks`: per (candidate, record) block its values, cost,
    normal equations, damping and column scales (arrays over candidates × records)."""

    def __init__(self, problem: PooledProblem, vecs: FloatArray, free: set[str],
                 bounds: Mapping[str, tuple[float, float]]) -> None:  # fmt: skip
        self.problem = problem
        names, n_rec = problem.names, problem.n_rec
        per, width = len(problem.shared), len(problem.kinds)
        self.cols = per + np.arange(n_rec)[:, None] * width + np.arange(width)[None, :]
        self.is_free: BoolArray = np.array([[names[c] in free for c in row] for row in self.cols])
        self.free_blocks: BoolArray = np.any(self.is_free, axis=1)[None, :]
        lo = np.array([bounds.get(x, (-np.inf, np.inf))[0] for x in names])
        hi = np.array([bounds.get(x, (-np.inf, np.inf))[1] for x in names])
        self.lo, self.hi = lo[self.cols], hi[self.cols]
        pm = parameter_map(tuple(names), {x: 0.0 for x in names if x not in free}, {})
        typical = dict(zip(pm.free, problem.typical(pm), strict=True))
        self.typ = np.array([[typical.get(names[c], 1.0) for c in row] for row in self.cols])
        self.limit = problem.step_limit(vecs[0])[self.cols]  # the blocks' limits are constant
        rows = [problem.record_rows(i) for i in range(n_rec)]
        self.rows = rows
        order = np.concatenate(rows)
        self.owner = np.empty(problem.n_res, dtype=np.intp)
        self.owner[order] = np.repeat(np.arange(n_rec), [r.shape[0] for r in rows])
        # each record's rows one stretch in the layout's order: sums without a gather
        self.order = None if np.array_equal(order, np.arange(problem.n_res)) else order
        self.starts = np.concatenate([[0], np.cumsum([r.shape[0] for r in rows])[:-1]])
        self.x = vecs.copy()
        self.r = problem.residuals(self.x)
        self.sets = self.x.shape[0]
        self.cost = self._half_costs(self.r)
        shape = (*self.cost.shape, width)
        self.lam = np.full(self.cost.shape, 1e-3)
        self.nu = np.full(self.cost.shape, 2.0)
        self.A = np.zeros((*shape, width))
        self.g = np.zeros(shape)
        self.norms = np.zeros(shape)
        self.d = np.zeros(shape)
        self.done = ~np.isfinite(self.cost)
        self.due = np.ones(self.cost.shape, dtype=bool)  # blocks whose Jacobian is due

    # ------------------------------------------------------------ packing
    def _sums(self, m: FloatArray) -> FloatArray:
        """Each record's sum of the rows of `m` (..., n_res) -> (..., R)."""
        if self.order is not None:
            m = m[..., self.order]
        return np.add.reduceat(m, self.starts, axis=-1)

    def _half_costs(self, r: FloatArray) -> FloatArray:
        with np.errstate(invalid="ignore", over="ignore"):
            c = 0.5 * self._sums(r * r)
        return np.where(np.isfinite(c), c, np.inf)

    @staticmethod
    def _slots(mask: BoolArray) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
        """The packing of the blocks `mask` (K, R): each block's set (−1: none), and the
        candidate each set takes each record's block from (0 where it takes none)."""
        slot = np.where(mask, np.cumsum(mask, axis=0) - 1, -1)
        taken = np.zeros((int(mask.sum(axis=0).max()), mask.shape[1]), dtype=np.intp)
        k, i = np.nonzero(mask)
        taken[slot[k, i], i] = k
        return slot, taken

    def _packed(self, blocks: FloatArray, taken: NDArray[np.intp]) -> FloatArray:
        """Parameter sets carrying the blocks (K, R, width) that `taken` names."""
        sets = np.repeat(self.x[:1], taken.shape[0], axis=0)
        sets[:, self.cols] = blocks[taken, np.arange(taken.shape[1])]
        return sets

    def _unpacked(self, sums: FloatArray, slot: NDArray[np.intp]) -> FloatArray:
        """Per-record sums of packed sets (S, R, ...) back to the blocks (K, R, ...)."""
        return sums[np.maximum(slot, 0), np.arange(slot.shape[1])]

    # ------------------------------------------------------------ the iterate
    def _normal(self, mask: BoolArray) -> None:
        """The normal equations of the blocks `mask` at their values (forward differences
        away from zero, one packed set per column and slot)."""
        slot, taken = self._slots(mask)
        x = self.x[:, self.cols]
        width = self.cols.shape[1]
        sets, steps = [], []
        for j in range(width):
            up, down = pj.difference_steps(x[..., j], self.lo[:, j], self.hi[:, j],
                                           self.typ[:, j], central=False)  # fmt: skip
            h = (up - down) * self.is_free[:, j]
            moved = x.copy()
            moved[..., j] += h
            sets.append(self._packed(moved, taken))
            steps.append(h)
        n_sets = taken.shape[0]
        res = self.problem.residuals(np.concatenate(sets)).reshape(width, n_sets, -1)
        base = self.r[taken[:, self.owner], np.arange(self.problem.n_res)]  # (S, n_res)
        with np.errstate(invalid="ignore"):
            res -= base[None]
        res[~np.isfinite(res)] = 0.0  # no usable slope where a trial point failed
        h = np.array(steps)  # (width, K, R), 0 for a held column
        with np.errstate(divide="ignore"):
            inv = np.where(h != 0, 1.0 / np.where(h != 0, h, 1.0), 0.0)
        A = np.empty((*mask.shape, width, width))
        g = np.empty((*mask.shape, width))
        for a in range(width):
            g[..., a] = self._unpacked(self._sums(res[a] * base), slot) * inv[a]
            for b in range(a, width):
                s = self._unpacked(self._sums(res[a] * res[b]), slot) * inv[a] * inv[b]
                A[..., a, b] = A[..., b, a] = s
        self.A[mask], self.g[mask] = A[mask], g[mask]
        self.norms[mask] = np.sqrt(np.maximum(np.einsum("...aa->...a", A[mask]), 0.0))
        self.d[mask] = np.maximum(self.d[mask], self.norms[mask])
        self.due[mask] = False

    def _free(self) -> BoolArray:
        """Free columns of each block: a bound holds one the gradient pushes outward."""
        x = self.x[:, self.cols]
        held = ((x <= self.lo) & (self.g > 0)) | ((x >= self.hi) & (self.g < 0))
        return self.is_free[None] & ~held

    def moving(self) -> BoolArray:
        """The blocks not yet stopped (their normal equations brought up to date first)."""
        due = self.due & ~self.done
        if due.any():
            self._normal(due)
        rn = np.sqrt(2.0 * self.cost)
        free = self._free()
        cos = np.where(free, np.abs(self.g) / (self.norms * rn[..., None] + 1e-300), 0.0)
        self.done |= (rn == 0.0) | ~free.any(axis=2) | (cos.max(axis=2) <= GTOL)
        return ~self.done

    def _damped(self, free: BoolArray) -> FloatArray:
        """The solutions of (A + λ·D²) δ = −g of every block on its free columns."""
        width = free.shape[-1]
        eye = np.eye(width)
        d2 = np.where(self.d > 0, self.d, 1.0) ** 2
        mat = self.A + self.lam[..., None, None] * eye * d2[..., None, :]
        mat = np.where(free[..., :, None] & free[..., None, :], mat, eye)
        rhs = np.where(free, -self.g, 0.0)
        try:
            delta = np.linalg.solve(mat, rhs[..., None])[..., 0]
        except np.linalg.LinAlgError:
            flat = [np.linalg.lstsq(m, b, rcond=None)[0]
                    for m, b in zip(mat.reshape(-1, width, width), rhs.reshape(-1, width),
                                    strict=True)]  # fmt: skip
            delta = np.reshape(flat, rhs.shape)
        return np.where(free, delta, 0.0)

    def step(self, moving: BoolArray) -> int:
        """One damped step of every moving block, all tried in one packed call; returns
        the number of parameter sets."""
        delta = np.clip(self._damped(self._free() & moving[..., None]), -self.limit, self.limit)
        x0 = self.x[:, self.cols]
        x1 = np.clip(x0 + delta, self.lo, self.hi)
        delta = x1 - x0
        d = self.d
        small = np.linalg.norm(d * delta, axis=2) <= XTOL * (np.linalg.norm(d * x0, axis=2) + XTOL)
        predicted = -(np.einsum("kia,kia->ki", self.g, delta)
                      + 0.5 * np.einsum("kia,kiab,kib->ki", delta, self.A, delta))  # fmt: skip
        slot, taken = self._slots(moving)
        r_new = self.problem.residuals(self._packed(x1, taken))
        cost_new = np.where(moving, self._unpacked(self._half_costs(r_new), slot), np.inf)
        with np.errstate(invalid="ignore", divide="ignore"):
            rho = np.where(predicted > 0, (self.cost - cost_new) / predicted, -1.0)
        accept = moving & (rho > 0) & (cost_new < self.cost)
        reject = moving & ~accept
        self.done |= reject & small
        self.lam = np.where(reject, self.lam * self.nu, self.lam)
        self.nu = np.where(reject, 2.0 * self.nu, self.nu)
        total = np.sum(self.cost, axis=1, keepdims=True)  # each candidate's, before the step
        for k, i in zip(*np.nonzero(accept), strict=True):
            self.x[k, self.cols[i]] = x1[k, i]
            self.r[k, self.rows[i]] = r_new[slot[k, i], self.rows[i]]
        with np.errstate(invalid="ignore"):
            negligible = (self.cost - cost_new <= FTOL * total) & (rho > 0.25)
        self.done |= accept & (negligible | small)
        self.cost = np.where(accept, cost_new, self.cost)
        factor = np.maximum(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3)
        self.lam = np.where(accept, self.lam * factor, self.lam)
        self.nu = np.where(accept, 2.0, self.nu)
        self.due |= accept
        return int(taken.shape[0])
