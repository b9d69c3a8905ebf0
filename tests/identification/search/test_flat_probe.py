"""The flat-direction probe of the stiffness split (`_flat_probe`)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from presliding.identification.search._flat_probe import flat_direction, flat_probe, flat_starts
from presliding.identification.solve._least_squares import solve_least_squares

X = np.linspace(0.0, 1.0, 50)
NAMES = ("stiffness_1", "stiffness_2", "offset")
K = NAMES[:2]
BOUNDS = {"stiffness_1": (0.0, np.inf), "stiffness_2": (0.0, np.inf)}


def _solve(model, data, begin, max_evaluations=None):
    def residual(p):
        return model(p) - data

    return solve_least_squares(residual, begin, bounds=BOUNDS, max_evaluations=max_evaluations,
                               tolerance=1e-12)  # fmt: skip


def _sum_and_split(eps):
    """y = (k1 + k2)·x + z + eps·(k1 − k2)·x²: the sum well determined, the split by eps."""
    return lambda p: (p[0] + p[1]) * X + p[2] + eps * (p[0] - p[1]) * X**2


def test_the_flat_direction_keeps_the_sum_and_moves_the_others_on_the_profile_path():
    model = _sum_and_split(1e-3)
    data = model(np.array([3.0, 1.0, 0.5]))
    sol = _solve(model, data, {"stiffness_1": 2.0, "stiffness_2": 2.0, "offset": 0.0})
    free, step = flat_direction(sol, K)
    assert free == NAMES
    assert abs(step[0] + step[1]) <= 1e-2 * abs(step[0])  # Σ k_j held (eq. 7)
    x = np.array([sol.values[n] for n in free])
    jac = sol.profiler.jacobian(x)
    held = step.copy()
    held[2] = 0.0  # the offset not re-optimised: the cost rises faster
    assert np.linalg.norm(jac @ step) < np.linalg.norm(jac @ held)


def test_coalesced_elements_have_their_split_as_the_flat_direction():
    """k1 and k2 enter alike (one column twice): the split is exactly flat, which the
    pseudo-inverse of JᵀJ would hide; the Schur complement shows it."""
    model = _sum_and_split(0.0)
    data = model(np.array([2.0, 2.0, 0.5]))
    sol = _solve(model, data, {"stiffness_1": 2.5, "stiffness_2": 2.5, "offset": 0.0})
    _, step = flat_direction(sol, K)
    assert abs(step[0] + step[1]) <= 1e-8 * abs(step[0]) and abs(step[0]) > 0
    assert abs(step[2]) <= 1e-8 * abs(step[0])


def test_the_starts_go_far_both_ways_and_stay_inside_the_bounds():
    model = _sum_and_split(1e-3)
    data = model(np.array([3.0, 1.0, 0.5]))
    sol = _solve(model, data, {"stiffness_1": 2.0, "stiffness_2": 2.0, "offset": 0.0})
    starts = flat_starts(sol, K, shares=(0.5,))
    assert len(starts) == 2
    for start in starts:
        ratios = [start[x] / sol.values[x] for x in K]
        assert all(r > 0 for r in ratios)
        # half-way to the first bound 0 (or the step that moves a stiffness by the largest)
        assert 0.5 - 1e-12 <= min(ratios) <= 0.55
    assert flat_starts(sol, ("stiffness_1",)) == []  # one stiffness: no split


def test_an_equal_cost_optimum_far_along_the_split_is_reached():
    """y = (k1 + k2)·x + z and a row c·(d − 1)(d − 3), d = k1 − k2: two optima of equal
    cost, d = 3 and d = 1, the curvature between them small. From the first, a tenth of a
    stiffness moved finds nothing; the far step along the flat direction does."""

    def model(p):
        d = p[0] - p[1]
        return np.concatenate([(p[0] + p[1]) * X + p[2], [1e-2 * (d - 1.0) * (d - 3.0)]])

    data = np.concatenate([4.0 * X + 0.5 + 1e-3 * np.sin(40 * X), [0.0]])
    solve = lambda begin, max_evaluations=None: _solve(model, data, begin, max_evaluations)  # noqa: E731
    best = solve({"stiffness_1": 3.4, "stiffness_2": 0.6, "offset": 0.5})
    assert best.values["stiffness_1"] - best.values["stiffness_2"] == pytest.approx(3.0, abs=1e-3)
    problem = SimpleNamespace(shared=NAMES)
    kept, probes = flat_probe(problem, solve, best, K, budget=20, interchangeable=False)
    c0 = float(best.residual @ best.residual)
    other = [t for t in probes if abs(t.values["stiffness_1"] - t.values["stiffness_2"] - 1) < 1e-3]
    assert other and float(other[0].residual @ other[0].residual) == pytest.approx(c0, rel=1e-6)
    assert other[0].status == "converged"
    assert kept is best or float(kept.residual @ kept.residual) < c0
