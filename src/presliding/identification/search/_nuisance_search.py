"""Global search of every record's own parameters, the shared ones held (issue: local minima).

Records are independent given the shared parameters (mass, friction model,
σ, offset): the cost is a sum of per-record costs, each depending only on the
shared parameters and that record's nuisance block (initial position, initial
velocity, preload fraction in [−1, 1]). The residual is far from convex in the
preload (a preload on the wrong side of the branch family changes the first
reversal), so a local solver started from one guess ends in a local minimum
for some records. `search_nuisance` therefore

1. evaluates a grid of candidates for every record at once: one candidate is
   one full parameter vector in which every record takes the same grid point
   (preload fraction on a grid over [−1, 1], the initial velocity as measured
   and with its sign flipped, and the current values), all candidates in one
   batched compiled call (`PooledProblem.residuals`); the initial position,
   which shifts a record's positions only, is set in closed form per candidate
   (the mean of the position residual);
2. ranks, per record, the candidates by that record's cost;
3. polishes the best three ranks, the shared parameters held: every block of
   every rank a Levenberg–Marquardt iterate of its own, all in lockstep
   (`_block_lm`: each block's damping and stopping its own, the trial points
   packed into few parameter sets, one compiled call a step), and keeps, per
   record, the best polished block. One iterate over all blocks of a rank (one
   damping, one accept test for the sum) held every record back to the slowest:
   on the 20-record benchmark's scale probe its three ranks mostly ran to the
   cap of 40 steps each; the blocks stop after 20–30 steps at the same costs
   (to 1e-4), the search 1.5–2 times faster.

The result is never worse than the values it started from.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from presliding.identification.records._pooled_problem import PooledProblem
from presliding.identification.search._block_lm import polish_blocks
from presliding.identification.solve._structured_lm import (
    on_one_blas_thread,
)

FloatArray = NDArray[np.float64]

#: preload fractions of the grid (both ends: saturated in either direction), symmetric to
#: the last bit so that a record and its mirror image see mirrored candidates (the zero
#: takes the sign of the record's first motion: +0 and −0 step apart in a forward difference)
FRACTIONS = np.concatenate((-np.linspace(0.0, 1.0, 6)[:0:-1], np.linspace(0.0, 1.0, 6)))
#: candidates of each record polished (the best ranks of the grid)
POLISHED = 3
#: steps of the polish at most (per call, all records and ranks together)
POLISH_EVALUATIONS = 40


def record_costs(problem: PooledProblem, res: FloatArray) -> FloatArray:
    """Sum of squares of each record's rows, per parameter set (P, R)."""
    out = np.empty((res.shape[0], problem.n_rec))
    for i in range(problem.n_rec):
        out[:, i] = np.sum(res[:, problem.record_rows(i)] ** 2, axis=1)
    return out


def _position_rows(problem: PooledProblem, i: int) -> NDArray[np.intp] | None:
    """Record i's rows comparing positions (None when positions are not compared)."""
    rows = problem.record_rows(i)
    pos = rows[problem._wy[rows] > 0]
    return pos if pos.size else None


def _shift_positions(problem: PooledProblem, sets: FloatArray, res: FloatArray,
                     free_y0: list[bool]) -> None:  # fmt: skip
    """Move each free initial position by the mean position residual (in place, both arrays)."""
    for i in range(problem.n_rec):
        rows = _position_rows(problem, i)
        if rows is None or not free_y0[i]:
            continue
        mean = np.mean(res[:, rows], axis=1)
        ok = np.isfinite(mean)
        res[np.ix_(ok, rows)] -= mean[ok, None]
        w = problem._wy[rows[0]]
        sets[ok, problem.index[problem.nuisance("initial_position", i)]] -= mean[ok] / w


def _candidates(problem: PooledProblem, values: Mapping[str, float],
                free: set[str]) -> FloatArray:  # fmt: skip
    """Full parameter vectors: the current one first, then the grid (module notes)."""
    base = np.array([values[x] for x in problem.names])
    out = [base]
    kinds = problem.kinds
    fractions = FRACTIONS if "preload_fraction" in kinds else [None]
    signs = (1.0, -1.0) if "initial_velocity" in kinds else (1.0,)
    for frac in fractions:
        for sign in signs:
            cand = base.copy()
            for i, rec in enumerate(problem.records):
                if frac is not None:
                    name = problem.nuisance("preload_fraction", i)
                    if name in free:  # zero signed as the record's motion: mirrored steps
                        cand[problem.index[name]] = frac or np.copysign(0.0, rec.direction)
                if "initial_velocity" in kinds:
                    name = problem.nuisance("initial_velocity", i)
                    if name in free:
                        cand[problem.index[name]] = sign * float(rec.velocity[0])
                if "initial_position" in kinds:
                    name = problem.nuisance("initial_position", i)
                    if name in free:
                        cand[problem.index[name]] = float(rec.position[0])
            out.append(cand)
    return np.array(out)


@on_one_blas_thread
def search_nuisance(
    problem: PooledProblem,
    values: Mapping[str, float],
    fixed: Mapping[str, float],
    bounds: Mapping[str, tuple[float, float]],
    *,
    polish: bool = True,
) -> tuple[dict[str, float], float, int]:
    """The best nuisance blocks for `values`' shared parameters (module notes).

    Returns the values (shared ones unchanged), their cost ‖r‖² and the number
    of residual evaluations.
    """
    free = {x for x in problem.names if problem.record_of[x] is not None and x not in fixed}
    values = dict(values)
    if not free:
        r = problem.residuals(np.array([[values[x] for x in problem.names]]))[0]
        return values, float(r @ r), 1
    sets = _candidates(problem, values, free)
    lo = np.array([bounds.get(x, (-np.inf, np.inf))[0] for x in problem.names])
    hi = np.array([bounds.get(x, (-np.inf, np.inf))[1] for x in problem.names])
    sets = np.clip(sets, lo, hi)
    res = problem.residuals(sets)
    free_y0 = [problem.nuisance("initial_position", i) in free for i in range(problem.n_rec)]
    _shift_positions(problem, sets, res, free_y0)
    costs = record_costs(problem, res)
    costs[~np.isfinite(costs)] = np.inf
    ranked = np.argsort(costs, axis=0, kind="stable")[: min(POLISHED, costs.shape[0])]
    per, width = len(problem.shared), len(problem.kinds)
    evaluations = sets.shape[0]
    ranks = ranked.shape[0] if polish else 1
    chosen = np.repeat(sets[:1], ranks, axis=0)  # each rank's blocks, one rank a row
    rec_costs = np.empty((ranks, problem.n_rec))
    for i in range(problem.n_rec):
        cols = slice(per + i * width, per + (i + 1) * width)
        chosen[:, cols] = sets[ranked[:ranks, i], cols]
        rec_costs[:, i] = costs[ranked[:ranks, i], i]
    if polish:
        chosen, rec_costs, ev = polish_blocks(problem, chosen, free, bounds, rec_costs,
                                              POLISH_EVALUATIONS)  # fmt: skip
        evaluations += ev
    m = np.argmin(rec_costs, axis=0)  # per record, the best polished rank (the first on ties)
    out_vec = chosen[0].copy()
    for i in range(problem.n_rec):
        cols = slice(per + i * width, per + (i + 1) * width)
        out_vec[cols] = chosen[m[i], cols]
    total = float(np.sum(rec_costs[m, np.arange(problem.n_rec)]))
    base = _cost(res[0])
    if not np.isfinite(total) or total > base:
        return values, base, evaluations
    return dict(zip(problem.names, out_vec.tolist(), strict=True)), total, evaluations


def _cost(r: FloatArray) -> float:
    c = float(r @ r)
    return c if np.isfinite(c) else np.inf
