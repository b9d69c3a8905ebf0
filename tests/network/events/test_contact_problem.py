"""The stick/slip decision: the box QP over the Delassus matrix satisfies its KKT conditions."""

from __future__ import annotations

import numpy as np
import pytest

from presliding.network.events._contact_problem import redundant_margin, solve_box_qp


@pytest.mark.parametrize("seed", range(20))
def test_box_qp_solution_satisfies_kkt(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 7))
    a = rng.normal(size=(n, max(n - int(rng.integers(0, 2)), 1)))  # sometimes singular
    g = a @ a.T + 1e-3 * np.eye(n) * (seed % 2)
    g[np.diag_indices(n)] += 1e-12
    b = rng.normal(size=n) * 3
    c1 = rng.uniform(0.1, 2.0, n)
    tau, acc = solve_box_qp(g, b, c1)
    np.testing.assert_allclose(acc, b - g @ tau, atol=1e-9)
    assert np.all(np.abs(tau) <= c1 * (1 + 1e-12))
    tol = 1e-8 * (np.max(np.abs(b)) + np.max(np.abs(g)) * np.max(c1))
    interior = np.abs(tau) < c1 * (1 - 1e-9)
    assert np.all(np.abs(acc[interior]) <= tol)  # sticks: no acceleration
    assert np.all(acc[tau >= c1 * (1 - 1e-9)] >= -tol)  # slides the way its force says
    assert np.all(acc[tau <= -c1 * (1 - 1e-9)] <= tol)


def test_redundant_margin_spreads_the_load():
    """Two equal contacts (Z = [1, −1]/√2) carry a total of 1.0: 0.5 each leaves a margin 0.2
    to c1 = 0.7, where the minimum-norm start (1.0, 0.0) exceeds it."""
    z = np.array([[1.0], [-1.0]]) / np.sqrt(2.0)
    margin, lam = redundant_margin(np.array([1.0, 0.0]), z, np.zeros(2), np.array([0.7, 0.7]))
    assert abs(margin - 0.2) < 1e-9
    np.testing.assert_allclose(lam, [0.5, 0.5], atol=1e-9)
