"""The structured Levenberg–Marquardt's normal equations (`identification._structured_lm`):
the block layout of a pooled Jacobian is analysed once and reused while the structure stays
the same, so a change of structure must be noticed; BLAS on one thread inside the fit."""

from __future__ import annotations

import numpy as np
from scipy import sparse
from threadpoolctl import threadpool_info

from presliding.identification.solve._structured_lm import one_blas_thread, structured_normal


def _pooled(rng, n_rec=4, rows=30, shared=3, own=2, tie=False):
    """A CSC Jacobian with `shared` full columns and `own` columns per record's rows."""
    n = n_rec * rows
    dense = np.zeros((n, shared + n_rec * own))
    dense[:, :shared] = rng.standard_normal((n, shared))
    for i in range(n_rec):
        dense[i * rows:(i + 1) * rows, shared + i * own:shared + (i + 1) * own] = \
            rng.standard_normal((rows, own))  # fmt: skip
    if tie:  # one column over two records' rows (a tie across records): blocks overlap
        dense[: 2 * rows, shared] = 0.0
        dense[: 2 * rows, shared + 1] = rng.standard_normal(2 * rows)
        dense[2 * rows :, shared + 1] = 0.0
    return sparse.csc_matrix(dense), dense


def _check(jac, dense, r):
    a, g, norms = structured_normal(jac, r)
    np.testing.assert_allclose(a, dense.T @ dense, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(g, dense.T @ r, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(norms, np.linalg.norm(dense, axis=0), rtol=1e-12)


def test_normal_equations_follow_a_change_of_structure():
    rng = np.random.default_rng(0)
    first, d_first = _pooled(rng)
    other, d_other = _pooled(rng, n_rec=3, rows=40, shared=2, own=3)
    tied, d_tied = _pooled(rng, tie=True)
    same_shape, d_same = _pooled(rng, n_rec=2, rows=60, shared=3, own=4)  # 120 × 11, as first
    assert same_shape.shape == first.shape
    r = rng.standard_normal(first.shape[0])
    for jac, dense in ((first, d_first), (other, d_other), (first, d_first), (tied, d_tied),
                       (same_shape, d_same), (first, d_first)):  # fmt: skip
        _check(jac, dense, r[: dense.shape[0]] if dense.shape[0] <= r.shape[0]
               else rng.standard_normal(dense.shape[0]))  # fmt: skip
    new_values = first.copy()
    new_values.data = rng.standard_normal(new_values.data.shape[0])  # same structure
    _check(new_values, new_values.toarray(), r)


def test_blas_runs_on_one_thread_inside_and_as_before_after():
    before = [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]
    with one_blas_thread():
        inside = [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]
    after = [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]
    assert all(n == 1 for n in inside)
    assert after == before
