"""The end search of a profile interval (`identification._profile_walk`): the walk from
the optimum to where the profile reaches its threshold."""

from __future__ import annotations

import numpy as np

from presliding.identification.intervals._profile_walk import Walker, interval_end
from presliding.identification.solve._least_squares import solve_least_squares


def test_a_quadratic_profile_costs_two_inner_optimisations_per_end():
    """The walk solves at half the Wald half width and then at the secant's root: for a model
    linear in its parameters that is the end (no bracketing search, no point solved twice)."""
    x = np.linspace(0.0, 1.0, 40)
    y = 1.5 - 0.7 * x + 0.4 * x**2 + np.random.default_rng(3).normal(0.0, 0.05, x.shape)
    design = np.column_stack([np.ones_like(x), x, x**2])
    sol = solve_least_squares(
        lambda p: design @ p - y, {"a": 0.0, "b": 0.0, "c": 0.0}, jacobian=lambda p: design,
        tolerance=1e-12,
    )  # fmt: skip
    prof = sol.profiler
    v = np.array([sol.values[n] for n in prof.free])
    c0 = float(sol.residual @ sol.residual)
    normal = design.T @ design
    hinv = np.linalg.inv(normal)
    for j, name in enumerate(prof.free):
        half = prof.quantile * sol.standard_error[name]
        walk = Walker(prof, v, c0, normal, j, half * half / hinv[j, j])
        for side in (-1, 1):
            solves = walk.solves
            end = interval_end(walk, side, half)
            assert abs(end - (v[j] + side * half)) <= 1e-6 * half
            assert walk.solves - solves <= 2
