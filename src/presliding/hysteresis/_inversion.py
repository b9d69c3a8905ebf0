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

    Raises ValueError when a slope K_k is not positive (a bank without a
    linear term is inverted on its range by `range_inverse_parameters`).
    """
    r, slope = slopes(threshold, weight, linear)
    a = linear
    if not np.all(slope > 0):
        k = int(np.argmax(~(slope > 0)))
        where = f"below threshold {fmt(r[k])}" if k < r.shape[0] else f"beyond {fmt(r[-1])}"
        raise ValueError(
            "`linear` and `weight` must give an increasing initial loading curve to be invertible "
            f"(every slope a + Σ_(r_j >= r) w_j > 0); got slope {fmt(slope[k])} {where}."
        )
    # ρ_k = φ(r_k) = a r_k + Σ_j w_j min(r_k, r_j), exact sums of the merged bank.
    _, w, _ = merged(threshold, weight)
    rho = a * r + np.minimum(r[:, None], r[None, :]) @ w
    inv_slope = 1.0 / slope
    return rho, inv_slope[:-1] - inv_slope[1:], float(inv_slope[-1])


def inverse_deformations(
    threshold: FloatArray, weight: FloatArray, linear: float, deformation: FloatArray
) -> FloatArray:
    """Stop outputs σ_k of the inverse that correspond to forward stop outputs s_j.

    σ_k = a·s_k + Σ_{j <= k} w_j s_j + s_k Σ_{j > k} w_j over the merged bank
    sorted by threshold (see `presliding.hysteresis.inverse.inverse_state`).
    """
    _, w, first = merged(threshold, weight)
    s = deformation[first]
    head = np.cumsum(w * s)  # Σ_{j <= k} w_j s_j
    tail = np.append(np.cumsum(w[::-1])[::-1][1:], 0.0)  # Σ_{j > k} w_j
    return linear * s + head + s * tail


def range_inverse_parameters(
    threshold: FloatArray, weight: FloatArray
) -> tuple[FloatArray, FloatArray, float, int]:
    """The inverse of a bank without a linear term (a = 0) on its range |F| < F_m.

    With a = 0 the last slope K_{M+1} vanishes: the element of the largest
    threshold r_M sticks while |F| < F_m (a reachable memory with s_M = ±r_M
    has every element saturated), so its play output x_M is an anchor and

        y = x_M + F/K_M + Σ_{k < M} v_k σ_k,    v_k = 1/K_k − 1/K_{k+1},

    with stops σ_k of thresholds ρ_k = φ(r_k), k < M, on the force. Returns
    (ρ_1..ρ_{M−1}, v_1..v_{M−1}, 1/K_M, index of an element of threshold r_M).

    Raises ValueError unless every weight is positive (the range is then
    (−F_m, F_m) with F_m = Σ w_j r_j).
    """
    if not np.all(weight > 0):
        j = int(np.argmax(~(weight > 0)))
        raise ValueError(
            "`operator` without a linear term must have positive weights to be invertible on "
            f"its range; got weight {fmt(weight[j])} at index {j}."
        )
    r, slope = slopes(threshold, weight, 0.0)
    _, w, first = merged(threshold, weight)
    rho = np.minimum(r[:, None], r[None, :]) @ w  # φ(r_k), a = 0
    inv_slope = 1.0 / slope[:-1]  # 1/K_1 .. 1/K_M (K_{M+1} = 0 is left out)
    v = inv_slope[:-1] - inv_slope[1:]
    return rho[:-1], v, float(inv_slope[-1]), int(first[-1])
