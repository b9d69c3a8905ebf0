"""The normal equations of a least-squares problem: JᵀJ and its scaled pseudo-inverse.

The profile walk (`_profile_walk`), the choice of the parameters to profile
(`_profile`), the far step along the least determined split (`_flat_probe`), the
comparison of second optima (`_alternatives`) and the quasi-static errors
(`_quasi_static_errors`) all read the curvature of the cost ‖r‖² from the
Jacobian J of the residual: A = JᵀJ (half the Gauss–Newton Hessian) and its
inverse h = A⁻¹, whose diagonal gives the Wald variances up to s².

The inverse is a pseudo-inverse of A scaled to a unit diagonal
(D⁻¹AD⁻¹, D = diag(√A_jj)): the parameters' scales differ by many orders
(a mass in kg, stiffnesses in N/m, initial positions in m), and an undetermined
direction shows as a small eigenvalue of the scaled matrix, cut at a relative
1e-12, not as a column scale.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import sparse

__all__ = ["inverse_normal", "normal_matrix", "scaled_pinv"]

FloatArray = NDArray[np.float64]


def normal_matrix(jac: Any) -> FloatArray:
    """JᵀJ, dense p × p (from a dense or a sparse Jacobian)."""
    a = (jac.T @ jac).toarray() if sparse.issparse(jac) else jac.T @ jac
    return np.asarray(a, dtype=float)


def scaled_pinv(a: FloatArray) -> FloatArray:
    """The inverse of a symmetric matrix by a pseudo-inverse of its unit-diagonal scaling."""
    d = np.sqrt(np.maximum(np.diag(a), 0.0))
    d[d == 0] = 1.0
    return np.linalg.pinv(a / np.outer(d, d), rcond=1e-12) / np.outer(d, d)


def inverse_normal(jac: Any) -> FloatArray:
    """(JᵀJ)⁻¹ by the scaled pseudo-inverse (dense p × p)."""
    return scaled_pinv(normal_matrix(jac))
