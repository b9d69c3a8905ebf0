"""The matrices of a structure, checked: square, symmetric, (semi)definite; dense or sparse.

A dense matrix is checked by a Cholesky factorisation (of M; of K + δ·I and C + δ·I,
δ = 1e-12 of the largest entry, for the semidefinite ones), its smallest eigenvalue
named when it fails. A `scipy.sparse` matrix is kept sparse (CSR): its definiteness
is read off the pivots of an LDLᵀ-like factorisation (SuperLU with symmetric
ordering and diagonal pivots: for a symmetric matrix its pivots are those of LDLᵀ of
the reordered matrix, all positive iff it is positive definite). Sizes are checked
before anything is copied: `dense_entries` counts what the dense checks allocate.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.linalg
import scipy.sparse
from numpy.typing import NDArray
from scipy.sparse.linalg import splu

from presliding._validation import as_real_array, check_size, fmt

FloatArray = NDArray[np.float64]

#: Matrices a dense structure allocates per n² entries while it is checked and held:
#: M, K, C (each copied, symmetrised and factorised in turn: 3 + 3) and W.
DENSE_COPIES = 7


def issparse(value: Any) -> bool:
    """True for a scipy.sparse matrix or array."""
    return bool(scipy.sparse.issparse(value))


def dense_entries(n: int, n_contacts: int) -> float:
    """The float64 entries a dense structure of n coordinates allocates (checks included)."""
    return float(DENSE_COPIES) * n * n + 2.0 * n * n_contacts


def check_dense_size(name: str, value: Any, n: int, n_contacts: int, hint: str = "") -> None:
    """Refuse a dense structure whose matrices do not fit in memory (before allocating)."""
    try:
        check_size(name, value, dense_entries(n, n_contacts), what="matrix entries")
    except ValueError as exc:
        raise ValueError(f"{exc} {hint}".rstrip()) from None


def _shape(value: Any) -> tuple[int, ...]:
    if issparse(value) or isinstance(value, np.ndarray):
        return tuple(value.shape)
    return tuple(np.shape(value))


def square(name: str, value: Any, n: int | None, *, definite: bool) -> Any:
    """A symmetric, positive (semi)definite n × n matrix (a scalar is 1 × 1, a vector its
    diagonal): a read-only ndarray, or a CSR matrix when `value` is sparse."""
    shape = _shape(value)
    if issparse(value):
        return _sparse_square(name, value, n, definite=definite)
    if len(shape) == 2:
        check_size(name, fmt(shape), 4.0 * shape[0] * shape[1], what="matrix entries")
    arr = as_real_array(name, value)
    if arr.ndim == 0:
        arr = arr.reshape(1, 1)
    if arr.ndim == 1:
        check_size(name, fmt(arr.shape), 4.0 * arr.shape[0] ** 2, what="matrix entries")
        arr = np.diag(arr)
    _check_shape(name, arr.shape, n)
    scale = float(np.max(np.abs(arr), initial=0.0))
    if not np.allclose(arr, arr.T, rtol=0.0, atol=1e-12 * scale):
        raise ValueError(f"`{name}` must be symmetric; got {fmt(arr)}.")
    arr = 0.5 * (arr + arr.T)
    if arr.size and (definite or scale > 0.0):  # zeros are semidefinite
        _check_definite(name, arr, scale, definite)
    arr.setflags(write=False)
    return arr


def _check_shape(name: str, shape: tuple[int, ...], n: int | None) -> None:
    if len(shape) != 2 or shape[0] != shape[1] or (n is not None and shape[0] != n):
        want = "(n, n)" if n is None else f"({n}, {n})"
        raise ValueError(f"`{name}` must be a square matrix of shape {want}; got {shape}.")


def _check_definite(name: str, arr: FloatArray, scale: float, definite: bool) -> None:
    shift = 0.0 if definite else 1e-12 * scale
    try:
        if definite and not scale > 0.0:
            raise np.linalg.LinAlgError
        scipy.linalg.cholesky(arr + shift * np.eye(arr.shape[0]), check_finite=False)
        return
    except np.linalg.LinAlgError:
        low = float(np.min(np.linalg.eigvalsh(arr)))
    if definite and not (low > 1e-13 * scale and scale > 0.0):
        raise ValueError(f"`{name}` must be positive definite; its smallest eigenvalue is {low!r}.")
    if not definite and low < -1e-12 * scale:
        raise ValueError(
            f"`{name}` must be positive semidefinite; its smallest eigenvalue is {low!r}."
        )


def _sparse_square(name: str, value: Any, n: int | None, *, definite: bool) -> Any:
    mat = scipy.sparse.csr_array(value, dtype=np.float64, copy=True)
    _check_shape(name, mat.shape, n)
    if not np.all(np.isfinite(mat.data)):
        raise ValueError(f"`{name}` must be finite; got a non-finite entry.")
    scale = float(np.max(np.abs(mat.data), initial=0.0))
    asym = abs(mat - mat.T)
    if asym.nnz and float(asym.max()) > 1e-12 * scale:
        raise ValueError(f"`{name}` must be symmetric; it differs from its transpose by "
                         f"{float(asym.max())!r}.")  # fmt: skip
    mat = scipy.sparse.csr_array(0.5 * (mat + mat.T))
    mat.sum_duplicates()
    mat.eliminate_zeros()
    if mat.shape[0] and (definite or scale > 0.0):  # zeros are semidefinite
        pivot = _lowest_pivot(mat, 0.0 if definite else 1e-12 * scale)
        ok = pivot > 1e-13 * scale and scale > 0.0 if definite else pivot > 0.0
        if not ok:
            rule = "positive definite" if definite else "positive semidefinite"
            raise ValueError(f"`{name}` must be {rule}; its LDLᵀ factorisation has the pivot "
                             f"{pivot!r}.")  # fmt: skip
    for arr in (mat.data, mat.indices, mat.indptr):
        arr.setflags(write=False)
    return mat


def _lowest_pivot(mat: Any, shift: float) -> float:
    """The smallest pivot of LDLᵀ of a symmetric sparse matrix plus shift·I (−inf if a
    pivot is zero)."""
    a = scipy.sparse.csc_matrix(mat + shift * scipy.sparse.identity(mat.shape[0]))
    try:
        lu = splu(a, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                  options={"SymmetricMode": True})  # fmt: skip
    except RuntimeError:  # an exactly zero pivot
        return -np.inf
    return float(np.min(lu.U.diagonal())) - shift


def as_contacts(value: Any, n: int) -> Any:
    """The contact matrix W (n × n_c, no zero column): a read-only ndarray, or CSR."""
    if issparse(value):
        w = scipy.sparse.csr_array(value, dtype=np.float64, copy=True)
        if w.ndim != 2 or w.shape[0] != n or w.shape[1] == 0:
            raise ValueError(f"`contacts` must have shape ({n}, n_c) with n_c >= 1 (one column "
                             f"per contact); got {w.shape}.")  # fmt: skip
        if not np.all(np.isfinite(w.data)):
            raise ValueError("`contacts` must be finite; got a non-finite entry.")
        w.eliminate_zeros()
        norms = np.asarray(abs(w).sum(axis=0)).ravel()
        for arr in (w.data, w.indices, w.indptr):
            arr.setflags(write=False)
    else:
        w = as_real_array("contacts", value)
        if w.ndim == 1 and n == 1:
            w = w.reshape(1, -1)
        if w.ndim != 2 or w.shape[0] != n or w.shape[1] == 0:
            raise ValueError(
                f"`contacts` must have shape ({n}, n_c) with n_c >= 1 (one column per contact); "
                f"got {w.shape}."
            )
        norms = np.abs(w).sum(axis=0)
        w = np.ascontiguousarray(w)
        w.setflags(write=False)
    zero = ~(norms > 0.0)
    if zero.any():
        raise ValueError(f"`contacts` must not have a zero column; column {int(np.argmax(zero))} "
                         "is zero.")  # fmt: skip
    return w


def dense(name: str, value: Any, n: int, n_c: int) -> Any:
    """A matrix of the structure as a dense array (sizes checked first)."""
    if not issparse(value):
        return np.asarray(value)
    check_size(name, n, float(n) * max(n, n_c), what="matrix entries")
    return np.asarray(value.toarray())
