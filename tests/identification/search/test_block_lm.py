"""Every record's own block polished at once (`identification._block_lm`)."""

from __future__ import annotations

import numpy as np

from presliding import Measurement, PIFriction
from presliding.identification.search._block_lm import polish_blocks
from presliding.identification.search._nuisance_search import record_costs
from tests.helpers import pooled_problem_at, stop_records

MODEL = PIFriction(0.3, [4000.0, 1000.0], breakaway=[0.35, 0.35])
SHARED = {"mass": 2.0, "coulomb_level": 1.0, "coulomb": 0.3, "stiffness_1": 4000.0,
          "stiffness_2": 1000.0}  # fmt: skip
MOVES = {"initial_position": 2e-5, "initial_velocity": 0.002, "preload_fraction": 0.04}


def _mirror(m: Measurement) -> Measurement:
    return Measurement(m.time, position=-m.position, velocity=-m.velocity,
                       applied_force=-m.applied_force)  # fmt: skip


def _setup(records, nuisance):
    problem, truth = pooled_problem_at(records, nuisance, SHARED)
    free = {x for x in problem.names if problem.record_of[x] is not None}
    bounds = {x: (-1.0, 1.0) for x in free if x.startswith("preload_fraction")}
    return problem, truth, free, bounds


def _moved(problem, truth, signs) -> np.ndarray:
    """Candidates (one a row): every record's block moved off the truth, each its own way."""
    out = []
    for s in signs:
        vec = np.array([truth[x] for x in problem.names])
        for i in range(problem.n_rec):
            for j, kind in enumerate(problem.kinds):
                vec[problem.index[problem.nuisance(kind, i)]] += s[i][j] * MOVES[kind]
        out.append(vec)
    return np.array(out)


def test_every_block_of_every_candidate_is_polished_to_its_record_s_optimum():
    """Noise-free stops: the shared values at the truth, two candidates whose records'
    blocks start off the truth in different directions (and by different amounts) all
    end near the truth, each record's cost a thousandth of its start or less (a block
    stops when its step gains less than `FTOL` of its candidate's cost); a block whose
    cost is not finite is left as it is."""
    records, nuisance = stop_records(4, 3, MODEL, samples=300)
    problem, truth, free, bounds = _setup(records, nuisance)
    signs = [[(1, 1, -1), (-1, 1, 1), (1, -1, 1)], [(-2, -1, 1), (1, -2, -1), (-1, 1, -2)]]
    vecs = _moved(problem, truth, signs)
    start = record_costs(problem, problem.residuals(vecs))
    assert np.all(start > 1e-6)  # every block starts well off its optimum
    costs = start.copy()
    costs[1, 2] = np.inf  # this block stays
    out, polished, sets = polish_blocks(problem, vecs, free, bounds, costs, 40)
    assert 0 < sets <= 2 * 41  # the trial points packed: two candidates a step at most
    moved = np.isfinite(costs)
    assert np.all(polished[moved] < 1e-3 * start[moved])
    assert np.all(polished <= costs)
    np.testing.assert_allclose(polished, record_costs(problem, problem.residuals(out)), rtol=1e-9)
    for k in range(2):
        for i in range(3):
            for kind in problem.kinds:
                j = problem.index[problem.nuisance(kind, i)]
                if moved[k, i] and kind != "preload_fraction":  # (one near saturation is
                    assert abs(out[k, j] - truth[problem.names[j]]) < 0.05 * MOVES[kind]
                elif not moved[k, i]:  # hardly seen: erased by the first slide)
                    assert out[k, j] == vecs[k, j]
    shared = [problem.index[x] for x in SHARED]
    assert np.array_equal(out[:, shared], vecs[:, shared])  # the shared values held


def test_a_record_and_its_mirror_image_are_polished_to_mirrored_blocks_to_the_last_bit():
    """Noisy quantised stops and their mirror images (y, v and u negated), the blocks
    started mirrored: the polished blocks are each other's negatives exactly (steps away
    from zero, per-record sums in the same order)."""
    records, nuisance = stop_records(7, 3, MODEL, samples=300, quantum=1e-6, noise=2e-7)
    a, truth, free, bounds = _setup(records, nuisance)
    flipped = [{k: -v for k, v in n.items()} for n in nuisance]
    b, truth_b, _, _ = _setup([_mirror(m) for m in records], flipped)
    signs = [[(1, 1, -1), (-1, 1, 1), (1, -1, 1)], [(-2, -1, 1), (1, -2, -1), (-1, 1, -2)]]
    va = _moved(a, truth, signs)
    vb = _moved(b, truth_b, [[tuple(-x for x in s) for s in c] for c in signs])
    own = [a.index[x] for x in sorted(free)]
    assert np.array_equal(vb[:, own], -va[:, own])
    ca = record_costs(a, a.residuals(va))
    out_a, cost_a, sets_a = polish_blocks(a, va, free, bounds, ca, 40)
    out_b, cost_b, sets_b = polish_blocks(b, vb, free, bounds, record_costs(b, b.residuals(vb)),
                                          40)  # fmt: skip
    assert np.all(cost_a < ca)  # the noisy optimum is below the moved starts
    assert np.array_equal(out_b[:, own], -out_a[:, own])
    assert np.array_equal(cost_a, cost_b) and sets_a == sets_b
