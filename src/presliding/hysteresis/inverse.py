"""Inverse of a Prandtl–Ishlinskii operator, for hysteresis and friction compensation.

A stop-type PI operator with a linear term (eq. 4 with eq. 5),

    F(t) = a·y(t) + Σ_j w_j s_j(t),     s_j = y − x_j(y, r_j)   (stop of threshold r_j),

has the initial loading ("virgin") curve, for y >= 0 from the relaxed state,

    φ(y) = a·y + Σ_j w_j min(y, r_j).

With the thresholds sorted, r_1 < … < r_M (equal thresholds merged by adding
their weights), φ is piecewise linear with slope

    K_k = a + Σ_{j >= k} w_j   on r_{k−1} < y < r_k   (r_0 = 0),   K_{M+1} = a   for y > r_M.

The operator is invertible on all inputs iff every K_k > 0. Its inverse is again
a stop-type PI operator (Krasnosel'skii & Pokrovskii 1989; Krejčí 1996),

    y(t) = b·F(t) + Σ_k v_k σ_k(t),     σ_k = F − ξ_k(F, ρ_k)   (stop of threshold ρ_k),

whose loading curve is φ⁻¹ (piecewise linear with slopes 1/K_k, convex for
positive weights):

    b = 1/a,    ρ_k = φ(r_k),    v_k = 1/K_k − 1/K_{k+1}.

For positive w_j the K_k decrease, so the inverse weights v_k are negative: the
inverse hardens where the operator softens. Equivalently, in play form,
φ⁻¹(F) = F/K_1 + Σ_k (1/K_{k+1} − 1/K_k) max(F − ρ_k, 0).

Why the composition is the identity on every path, not only the virgin curve:
the stop of threshold ρ_k on F saturates exactly when the stop of threshold r_k
on y does (on a reversal branch F travels 2φ(travel/2), so F-travel 2ρ_k
corresponds to y-travel 2r_k, Masing's rule), and the set of saturated stops is
always those with the smallest thresholds, so between those events dF/dy = K_k
and dy/dF = b + Σ_{i >= k} v_i = 1/K_k agree.

The memories correspond through

    σ_k = a·s_k + Σ_{j <= k} w_j s_j + s_k Σ_{j > k} w_j        (`inverse_state`),

valid for memories reachable from a relaxed or saturated state, which satisfy
|s_k − s_{k+1}| <= r_{k+1} − r_k.

What is invertible: a friction bank alone (a = 0, w_j > 0) is not — its force
saturates at ±F_m = ±Σ w_j r_j, and forces beyond cannot be produced by any
displacement (φ⁻¹ has a vertical asymptote at F_m). A PI operator with a
positive linear term a > 0 and positive weights is invertible for all F; with
mixed-sign weights it is invertible iff all K_k > 0 (then its inverse is one
too, so ``op.inverse().inverse()`` recovers ``op``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from presliding.hysteresis._inversion import merged, slopes
from presliding.hysteresis.operators import _SLACK, PIOperator, PIState

__all__ = ["inverse_state", "loading_slopes", "pi_inverse"]

FloatArray = NDArray[np.float64]


def _check_operator(op: object) -> PIOperator:
    if not isinstance(op, PIOperator):
        raise TypeError(f"`operator` must be a PIOperator; got {type(op).__name__}.")
    return op


def loading_slopes(operator: PIOperator) -> tuple[FloatArray, FloatArray]:
    """Distinct sorted thresholds r_k and the slopes K_k of the initial loading curve.

    Returns
    -------
    threshold : ndarray, shape (M,)
        Distinct thresholds r_1 < … < r_M (elements with equal thresholds merged).
    slope : ndarray, shape (M + 1,)
        K_k = a + Σ_{j >= k} w_j on (r_{k−1}, r_k), and K_{M+1} = a beyond r_M.
    """
    op = _check_operator(operator)
    return slopes(op.threshold, op.weight, op.linear)


def pi_inverse(operator: PIOperator) -> PIOperator:
    """The inverse PI operator: thresholds ρ_k = φ(r_k), weights 1/K_k − 1/K_{k+1}, linear 1/a.

    Parameters
    ----------
    operator : PIOperator
        F = a·y + Σ w_j stop_j(y); every slope K_k of its loading curve must be
        positive (for positive weights: ``linear > 0``).

    Returns
    -------
    PIOperator
        y = (1/a)·F + Σ v_k stop_k(F), with one element per distinct threshold.
        Start it from `inverse_state` of the forward memory (a relaxed forward
        state at y0 corresponds to a relaxed inverse state at F0 = a·y0).

    Raises
    ------
    ValueError
        If a slope is not positive: the operator has no inverse on all of R.

    Examples
    --------
    >>> import numpy as np
    >>> op = PIOperator([0.1, 0.25], [10.0, 4.0], linear=2.0)
    >>> inv = pi_inverse(op)
    >>> y = np.array([0.0, 0.3, -0.2, 0.05])
    >>> F, _ = op.apply(y)
    >>> np.allclose(inv.apply(F)[0], y, rtol=0, atol=1e-14)
    True
    """
    return _check_operator(operator).inverse()


def inverse_state(operator: PIOperator, state: PIState) -> PIState:
    """Memory of ``operator.inverse()`` that corresponds to a memory of `operator`.

    With forward stop outputs s_k (merged, sorted by threshold) the inverse stops
    hold σ_k = a·s_k + Σ_{j <= k} w_j s_j + s_k Σ_{j > k} w_j, and the inverse's
    last input is the forward output F = a·y + Σ w_j s_j. Feeding the forward
    output path to the inverse started there returns the input path.

    Parameters
    ----------
    operator : PIOperator
        The forward operator (invertible, see `pi_inverse`).
    state : PIState
        A memory of `operator`, reachable from a relaxed or saturated state.

    Returns
    -------
    PIState
        The memory of ``pi_inverse(operator)`` (one play state per element of
        the inverse), with last input the forward output F.

    Raises
    ------
    ValueError
        If the memory is not one the operator can reach from a relaxed or
        saturated state (|s_k − s_{k+1}| <= r_{k+1} − r_k fails), since the
        inverse is exact only for those; or if `operator` is not invertible.
    """
    inverse = pi_inverse(operator)  # validates invertibility
    if not isinstance(state, PIState):
        raise TypeError(f"`state` must be a PIState; got {type(state).__name__}.")
    state.check_against(operator.threshold)
    _, w, first = merged(operator.threshold, operator.weight)
    s_all = state.deformation
    s = s_all[first]
    # Reachable memories are 1-Lipschitz in the threshold (equal thresholds: equal s).
    order = np.argsort(operator.threshold, kind="stable")
    s_sorted, r_sorted = s_all[order], operator.threshold[order]
    gap = np.abs(np.diff(s_sorted)) - np.diff(r_sorted)
    tol = _SLACK * 4 * (abs(state.last_input) + r_sorted[1:])
    if np.any(gap > tol):
        j = int(np.argmax(gap > tol))
        raise ValueError(
            "`state` must be reachable from a relaxed or saturated state "
            "(|s_i − s_j| <= |r_i − r_j| for the stop outputs s = last_input − play); "
            f"got |{s_sorted[j]!r} − {s_sorted[j + 1]!r}| > {r_sorted[j + 1] - r_sorted[j]!r} "
            f"between thresholds {r_sorted[j]!r} and {r_sorted[j + 1]!r}."
        )
    a = operator.linear
    head = np.cumsum(w * s)  # Σ_{j <= k} w_j s_j
    tail = np.append(np.cumsum(w[::-1])[::-1][1:], 0.0)  # Σ_{j > k} w_j
    sigma = a * s + head + s * tail
    force = a * state.last_input + float(np.dot(operator.weight, s_all))
    sigma = np.clip(sigma, -inverse.threshold, inverse.threshold)  # rounding only (≲ 1 ulp)
    return PIState(force, force - sigma, state.direction)
