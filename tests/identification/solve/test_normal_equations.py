"""JᵀJ and its scaled pseudo-inverse (`identification._normal_equations`)."""

from __future__ import annotations

import numpy as np
from scipy import sparse

from presliding.identification.solve._normal_equations import (
    inverse_normal,
    normal_matrix,
    scaled_pinv,
)


def _badly_scaled_jacobian(rng: np.random.Generator) -> np.ndarray:
    # columns of a mass (kg), a stiffness (N/m) and an initial position (m): scales 1e-9..1e6
    return rng.standard_normal((200, 3)) * np.array([1.0, 1e-6, 1e6])


def test_the_normal_matrix_of_a_sparse_jacobian_is_that_of_the_dense_one():
    jac = _badly_scaled_jacobian(np.random.default_rng(1))
    jac[::3, 1] = 0.0
    np.testing.assert_allclose(
        normal_matrix(sparse.csc_matrix(jac)), normal_matrix(jac), rtol=1e-13
    )
    assert isinstance(normal_matrix(sparse.csc_matrix(jac)), np.ndarray)


def test_a_badly_scaled_full_rank_matrix_is_inverted_to_machine_precision():
    jac = _badly_scaled_jacobian(np.random.default_rng(2))
    a = normal_matrix(jac)
    # the unscaled pseudo-inverse's cut (relative to the largest singular value, 1e12 × the
    # smallest here) would treat the stiffness column as undetermined; the scaled one does not
    h = inverse_normal(jac)
    d = np.sqrt(np.diag(a))  # compared in the unit-diagonal scaling (entries 1e-12..1e12)
    np.testing.assert_allclose((h * np.outer(d, d)) @ (a / np.outer(d, d)), np.eye(3), atol=1e-12)
    np.testing.assert_allclose(np.diag(h), np.diag(np.linalg.inv(a)), rtol=1e-9)


def test_an_undetermined_direction_is_cut_not_inverted():
    rng = np.random.default_rng(3)
    jac = _badly_scaled_jacobian(rng)
    jac[:, 2] = 2e12 * jac[:, 1]  # the third column a multiple of the second (scaled: ρ = 1)
    a = normal_matrix(jac)
    h = scaled_pinv(a)
    assert np.all(np.isfinite(h))
    # the pseudo-inverse: A h A = A and h A h = h, and h is symmetric
    np.testing.assert_allclose(a @ h @ a, a, rtol=1e-8, atol=1e-8 * np.abs(a).max())
    np.testing.assert_allclose(h @ a @ h, h, rtol=1e-8, atol=1e-8 * np.abs(h).max())
    np.testing.assert_allclose(h, h.T, rtol=1e-12, atol=1e-12 * np.abs(h).max())
    # the determined first column keeps its ordinary variance
    np.testing.assert_allclose(h[0, 0], np.linalg.inv(a[:2, :2])[0, 0], rtol=1e-8)


def test_a_zero_column_gives_zero_not_nan():
    jac = _badly_scaled_jacobian(np.random.default_rng(4))
    jac[:, 1] = 0.0
    h = inverse_normal(jac)
    assert np.all(np.isfinite(h))
    np.testing.assert_array_equal(h[1], 0.0)
