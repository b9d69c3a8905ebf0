"""Arithmetic of the inverse PI operator, on the parameter arrays alone.

`PIOperator.inverse` and `presliding.hysteresis.inverse` both build on these;
the derivation is in the docstring of `presliding.hysteresis.inverse`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from presliding._validation import fmt

FloatArray = NDArray[np.float64]


def merged(
    threshold: FloatArray, weight: FloatArray
) -> tuple[FloatArray, FloatArray, NDArray[np.intp]]:
    """Sorted distinct thresholds, summed weights, and the first element of each group."""
    order = np.argsort(threshold, kind="stable")
    r_sorted = threshold[order]
    r, start = np.unique(r_sorted, return_index=True)
    w = np.add.reduceat(weight[order], start)
    return r, w, order[start]


def slopes(
    threshold: FloatArray, weight: FloatArray, linear: float
) -> tuple[FloatArray, FloatArray]:
    """Distinct sorted thresholds r_k and the loading-curve slopes K_k (see `loading_slopes`)."""
    r, w, _ = merged(threshold, weight)
    tail = np.cumsum(w[::-1])[::-1]  # Σ_{j >= k} w_j
    return r, np.append(linear + tail, linear)


def inverse_parameters(
    threshold: FloatArray, weight: FloatArray, linear: float
) -> tuple[FloatArray, FloatArray, float]:
    """Thresholds ρ_k = φ(r_k), weights 1/K_k − 1/K_{k+1} and linear term 1/a of the inverse.

    Raises ValueError when a slope K_k is not positive.
    """
    r, slope = slopes(threshold, weight, linear)
    a = linear
    if not np.all(slope > 0):
        fm = float(np.sum(weight * threshold))
        if a == 0.0 and np.all(weight > 0):
            raise ValueError(
                "`operator` has no inverse on all forces: with `linear` 0.0 and positive "
                f"weights its output saturates at ±Σ w_j r_j = ±{fm!r}, which no input "
                "exceeds; give it a positive `linear` term."
            )
        k = int(np.argmax(~(slope > 0)))
        where = f"below threshold {fmt(r[k])}" if k < r.shape[0] else f"beyond {fmt(r[-1])}"
        raise ValueError(
            "`operator` must have an increasing initial loading curve to be invertible "
            f"(every slope a + Σ_(r_j >= r) w_j > 0); got slope {fmt(slope[k])} {where}."
        )
    # ρ_k = φ(r_k) = a r_k + Σ_j w_j min(r_k, r_j), exact sums of the merged bank.
    _, w, _ = merged(threshold, weight)
    rho = a * r + np.minimum(r[:, None], r[None, :]) @ w
    inv_slope = 1.0 / slope
    return rho, inv_slope[:-1] - inv_slope[1:], float(inv_slope[-1])
