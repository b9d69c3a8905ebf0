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

What is invertible: a PI operator with a positive linear term a > 0 and
positive weights is invertible for all F; with mixed-sign weights it is
invertible iff all K_k > 0 (then its inverse is one too, so
``op.inverse().inverse()`` recovers ``op``).

A friction bank alone (a = 0, w_j > 0) saturates at ±F_m = ±Σ w_j r_j: forces
beyond cannot be produced by any displacement (φ⁻¹ has a vertical asymptote at
F_m), and at ±F_m the displacement is not unique. On the range |F| < F_m it is
invertible (`PIInverse`): the element of the largest threshold r_M sticks there
(a reachable memory with s_M = ±r_M has every element saturated), so its play
output x_M is an anchor, and letting a → 0 in the formulas above,

    y = x_M + F/K_M + Σ_{k < M} v_k σ_k        (σ_k: stops of threshold ρ_k on F).

With a Coulomb element c1 (eq. 8) the quasi-static balance u = c1·sign(ẏ) + F_el
(inertia negligible) moves the contact only while |u − F_el| > c1, and then
F_el = u ∓ c1: on the force side c1 acts as a play operator of threshold c1,
F_el = play_{c1}[u], and y = Φ⁻¹[F_el]. A stop of zero threshold is the
Coulomb element itself; `PIInverse(operator, coulomb=c1)` is this inverse of
the whole friction model, defined while |u| < F_c = c1 + F_m (eq. 9).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import as_nonnegative_scalar, as_signal, fmt
from presliding.hysteresis import _kernels
from presliding.hysteresis._inversion import (
    inverse_deformations,
    range_inverse_parameters,
    slopes,
)
from presliding.hysteresis.operators import (
    _SLACK,
    RANGE_INVERSE,
    PIOperator,
    PIState,
    check_inverse_parameters,
)

__all__ = ["PIInverse", "inverse_state", "loading_slopes", "pi_inverse"]

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


def pi_inverse(operator: PIOperator) -> PIOperator | PIInverse:
    """The inverse PI operator: thresholds ρ_k = φ(r_k), weights 1/K_k − 1/K_{k+1}, linear 1/a.

    Parameters
    ----------
    operator : PIOperator
        F = a·y + Σ w_j stop_j(y); every slope K_k of its loading curve must be
        positive (for positive weights: ``linear > 0``), or ``linear`` 0 with
        positive weights (a friction bank, inverted on its range).

    Returns
    -------
    PIOperator or PIInverse
        With a linear term: y = (1/a)·F + Σ v_k stop_k(F), with one element per
        distinct threshold, defined for every F. Start it from `inverse_state`
        of the forward memory (a relaxed forward state at y0 corresponds to a
        relaxed inverse state at F0 = a·y0). Without one: a `PIInverse`,
        defined while |F| < F_m = Σ w_j r_j, started from the forward memory.

    Raises
    ------
    ValueError
        If a slope is not positive: the operator has no inverse.

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
        the inverse), with last input the forward output F. For an operator
        without a linear term, whose `PIInverse` runs from the forward memory
        itself, `state` (checked).

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
    if isinstance(inverse, PIInverse):
        return state  # the inverse on the range runs from the forward memory itself
    s_all = state.deformation
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
    sigma = inverse_deformations(operator.threshold, operator.weight, a, s_all)
    force = a * state.last_input + float(np.dot(operator.weight, s_all))
    sigma = np.clip(sigma, -inverse.threshold, inverse.threshold)  # rounding only (≲ 1 ulp)
    return PIState(force, force - sigma, state.direction)


@dataclass(frozen=True, eq=False)
class PIInverse:
    """Inverse of a friction bank with a Coulomb element, on its range: force → displacement.

    The quasi-static balance of eq. 8 (inertia and viscous friction negligible),
    u = c1·sign(ẏ) + Σ w_j (y − x_j(y, r_j)), solved for the displacement y:
    the elastic force follows the applied force through a play of threshold c1,
    F_el = play_{c1}[u] (the contact moves only while |u − F_el| > c1), and
    y = x_M + F_el/K_M + Σ_{k < M} v_k σ_k inverts the bank (module notes).

    Parameters
    ----------
    operator : PIOperator
        The elastic bank F_el = Σ w_j stop_j(y): no linear term, positive
        weights (the stiffnesses k_j, thresholds r_j of eq. 6).
    coulomb : float, keyword only
        The Coulomb element c1 >= 0 [N] (default 0: the bank alone).

    Notes
    -----
    Defined while |u| < F_c = c1 + F_m (eq. 9), F_m = Σ w_j r_j: at F_c the
    contact slides (gross sliding has no quasi-static position). The state is
    the forward memory (`PIState` of `operator`): `apply` returns the memory at
    the end, carrying also the memory of the inverse itself (the elastic force
    F_el, the stops on it, the anchor), so that a call continued from it gives
    the result of one call bit for bit. From any other memory of the bank the
    inverse starts at F_el = Σ w_j (y − x_j) of that memory.

    Examples
    --------
    >>> import numpy as np
    >>> bank = PIOperator(threshold=[1e-3, 4e-3], weight=[500.0, 100.0])
    >>> inv = PIInverse(bank, coulomb=0.2)
    >>> y, state = inv.apply(np.array([0.0, 0.6, 0.1, -0.5]))
    >>> bool(np.isclose(0.2 + bank.apply(y[:2])[0][-1], 0.6))
    True
    """

    operator: PIOperator
    coulomb: float = field(default=0.0, kw_only=True)

    def __post_init__(self) -> None:
        op = _check_operator(self.operator)
        if op.linear != 0.0:
            raise ValueError(
                "`operator` of a PIInverse must have no linear term (pi_inverse inverts one "
                f"with a linear term on all forces); got linear {fmt(op.linear)}."
            )
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):  # checked below
            rho, v, lin, anchor = range_inverse_parameters(op.threshold, op.weight)
        check_inverse_parameters(rho, v, lin, float(np.sum(op.weight)))
        object.__setattr__(self, "coulomb", as_nonnegative_scalar("coulomb", self.coulomb))
        object.__setattr__(self, "_parts", (rho, v, lin, anchor))

    @property
    def max_elastic_force(self) -> float:
        """F_m = Σ w_j r_j: the bank's saturation force."""
        return float(self.operator.weight @ self.operator.threshold)

    @property
    def force_limit(self) -> float:
        """F_c = c1 + F_m (eq. 9): the inverse is defined while |u| <= F_c."""
        return self.coulomb + self.max_elastic_force

    def relaxed_state(self, position: float = 0.0) -> PIState:
        """The forward bank relaxed at `position` (no elastic force, no motion yet)."""
        return self.operator.relaxed_state(position)

    def elastic_force(self, force: ArrayLike, state: PIState | None = None) -> Any:
        """F_el = play_{c1}[u]: the elastic force balancing the applied force u.

        Parameters
        ----------
        force : array_like, shape (T,)
            Applied force u [N], monotone between samples.
        state : PIState, optional
            Forward memory before the first sample (default relaxed at 0).

        Returns
        -------
        ndarray, shape (T,)
        """
        u = as_signal("force", force)
        state = self._state(state)
        memory = self._memory(state)
        fel0 = float(self.operator.weight @ state.deformation) if memory is None else memory[0]
        return self._elastic(u, fel0)

    def apply(self, force: ArrayLike, state: PIState | None = None) -> tuple[Any, PIState]:
        """Displacement y(t) under the applied force u(t), quasi-statically.

        Parameters
        ----------
        force : array_like, shape (T,)
            Applied force u [N], monotone between samples, |u| <= `force_limit` (at F_c
            every element is saturated: the end of presliding, a finite position).
        state : PIState, optional
            Memory of the forward bank before the first sample (its elastic
            force is where the play of c1 starts); default relaxed at y = 0.

        Returns
        -------
        position : ndarray, shape (T,)
            y [m] with c1·sign(ẏ) + F_el(y) = u while it moves, |u − F_el| <= c1 at rest.
        final_state : PIState
            The forward memory after the last sample; it also carries the memory
            of the inverse itself, so that passing it to the next call on the
            continuation of `force` gives one call's result bit for bit.

        Raises
        ------
        ValueError
            If some |u| > F_c (gross sliding: no quasi-static position); the first
            value refused is one float step above F_c.
        """
        u = as_signal("force", force)
        state = self._state(state)
        limit = self.force_limit
        bad = ~(np.abs(u) <= limit)
        if bad.any():
            i = int(np.argmax(bad))
            raise ValueError(
                "`force` must not exceed the Coulomb level F_c = c1 + Σ w_j r_j = "
                f"{fmt(limit)} in magnitude (beyond F_c the contact slides: gross sliding has no "
                f"quasi-static position); got {fmt(u[i])} at index {i}."
            )
        op = self.operator
        rho, v, lin, anchor = self._parts  # type: ignore[attr-defined]
        memory = self._memory(state)
        if memory is None:  # from the forward memory alone
            s = state.deformation
            fel0 = float(op.weight @ s)
            sigma = inverse_deformations(op.threshold, op.weight, 0.0, s)[:-1]
            sigma = np.clip(sigma, -rho, rho)  # rounding only (≲ 1 ulp)
            start = PIState(fel0, fel0 - sigma, state.direction)
            x_anchor = float(state.play[anchor])
        else:  # where the previous call ended, to the last bit
            fel0, start, x_anchor = memory
        fel = self._elastic(u, fel0)
        if rho.shape[0]:
            relative, inverse_final = PIOperator(rho, v, linear=lin).apply(fel, start)
        else:
            relative, inverse_final = lin * fel, start
        y = x_anchor + relative
        _, final = op.apply(y, state)
        forward = (final.last_input, final.play)
        carried = (self._key(), forward, (float(fel[-1]), inverse_final, x_anchor))
        return y, _InverseMemory(final.last_input, final.play, final.direction, carried)

    def inverse(self) -> PIOperator:
        """The forward bank (only without a Coulomb element, whose force is set-valued at rest)."""
        if self.coulomb != 0.0:
            raise ValueError(
                "the force of a Coulomb element is set-valued at rest, so the displacement does "
                f"not determine it; got coulomb {fmt(self.coulomb)} (inverse needs 0)."
            )
        return self.operator

    def _key(self) -> tuple[float, FloatArray, FloatArray, float]:
        rho, v, lin, _ = self._parts  # type: ignore[attr-defined]
        return (self.coulomb, rho, v, lin)

    def _memory(self, state: PIState) -> tuple[float, PIState, float] | None:
        """(F_el, the stops' memory on it, x_M) where a previous `apply` of this inverse
        left `state`; None for any other state (continued from the forward memory)."""
        memory = getattr(state, "memory", None)
        if memory is None:
            return None
        key, forward, carried = memory
        mine = self._key()
        same = key[0] == mine[0] and key[3] == mine[3] and forward[0] == state.last_input
        arrays = ((key[1], mine[1]), (key[2], mine[2]), (forward[1], state.play))
        if not (same and all(np.array_equal(a, b) for a, b in arrays)):
            return None
        return carried

    def _state(self, state: PIState | None) -> PIState:
        if state is None:
            return self.operator.relaxed_state(0.0)
        if not isinstance(state, PIState):
            raise TypeError(f"`state` must be a PIState or None; got {type(state).__name__}.")
        state.check_against(self.operator.threshold)
        return state

    def _elastic(self, u: Any, fel0: float) -> Any:
        if self.coulomb == 0.0:
            return u.copy()
        out = _kernels.empty_outputs(u.shape[0], 1)
        _kernels.play_outputs(u, np.array([self.coulomb]), np.array([fel0]), out)
        return out[:, 0].copy()


@dataclass(frozen=True, eq=False)
class _InverseMemory(PIState):
    """The forward memory (a `PIState`) after `PIInverse.apply`, carrying the inverse's own
    memory where that call ended: the elastic force F_el (the output of the play of c1),
    the memory of the stops on F_el, the anchor x_M, with the parameters and the forward
    memory they belong to (a state changed since is continued from its forward memory).
    The next call of the same inverse continues from them, so chunks give one call's
    result bit for bit (recomputed from the forward memory they would agree to rounding)."""

    memory: tuple[Any, ...] | None = field(default=None, repr=False)

    def __repr__(self) -> str:  # shown as what it is to the user: the bank's memory
        return repr(PIState(self.last_input, self.play, self.direction))


RANGE_INVERSE["PIInverse"] = PIInverse
