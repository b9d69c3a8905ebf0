"""Play and stop hysteresis operators and the weighted Prandtl–Ishlinskii sum.

The play operator with threshold r (eq. 3, Figure 1) maps an input y(t) to the
play output x(t) with |y − x| <= r; x stays put while the input moves inside the
play zone and is dragged along at its edge. The stop operator returns the
elastic deformation f = y − x (eq. 5, eq. 11). A Prandtl–Ishlinskii (PI)
operator is a weighted parallel connection of stops, F = Σ w_j (y − x_j) (eq. 4).

For a sampled input the update

    x_j[t] = min(max(x_j[t−1], y[t] − r_j), y[t] + r_j)

is exact whenever the input is monotone between consecutive samples, because
the operators are rate independent: only the turning points of the input
matter, not how fast it moves between them.

Accuracy: the play outputs are stored as absolute positions, so each carries the
rounding of the input, ulp(|y|). Forces are accurate to about Σ k_j·ulp(|y|),
i.e. to ~1e-16·|y|/r relative; choose the origin of y near the motion
when |y| exceeds the thresholds by many orders of magnitude.

State is explicit: every function takes the memory it starts from and returns
the memory it ends in (`PIState`), so a long signal can be processed in chunks
with bit-identical results.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._out import as_output
from presliding._validation import (
    as_count,
    as_parameter_vector,
    as_real_scalar,
    as_real_vector,
    as_signal,
    as_state_vector,
    check_finite_derived,
    check_size,
    fmt,
)
from presliding.hysteresis import _kernels
from presliding.hysteresis._inversion import inverse_parameters

__all__ = ["PIOperator", "PIState", "play", "stop"]

FloatArray = NDArray[np.float64]

# Play states produced by the kernel may exceed the threshold by rounding of
# y ± r; states are accepted within this relative slack.
_SLACK = 16 * np.finfo(np.float64).eps
# The inverse is refused when rounding could reach this relative size (fewer than
# 4 significant digits left).
_INVERSE_ROUNDING = 1e-4

#: The inverse on its range of a bank without a linear term, registered by
#: `presliding.hysteresis.inverse` (``PIInverse``) when the package is imported,
#: so that `PIOperator.inverse` can return it without importing that module.
RANGE_INVERSE: dict[str, type] = {}


@dataclass(frozen=True, eq=False)
class PIState:
    """Memory of a bank of play operators after a sample.

    Parameters
    ----------
    last_input : float
        The last input value y seen (the displacement of the friction contact).
    play : ndarray, shape (N,)
        Play outputs x_j at that input (eq. 3); the elastic deformations are
        f_j = last_input − play_j (eq. 5).
    direction : {-1.0, 0.0, 1.0}
        Sign of the last nonzero input increment, 0 before any motion. Used by
        the Coulomb element c1·sign(ẏ) of eq. 8.
    """

    last_input: float
    play: FloatArray
    direction: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "last_input", as_real_scalar("last_input", self.last_input))
        play = as_real_vector("play", self.play, allow_empty=True)  # types (and ragged) first
        if np.ndim(self.play) == 0:
            raise ValueError(
                f"`play` must be one-dimensional (shape (N,)); got shape {np.shape(self.play)}."
            )
        object.__setattr__(self, "play", play)
        d = as_real_scalar("direction", self.direction)
        if d not in (-1, 0, 1):
            raise ValueError(f"`direction` must be -1, 0 or 1; got {fmt(d)}.")
        object.__setattr__(self, "direction", d)

    @property
    def deformation(self) -> FloatArray:
        """Elastic deformations f_j = y − x_j (eq. 5, eq. 11)."""
        return self.last_input - self.play

    @classmethod
    def relaxed(cls, position: float, n_elements: int) -> PIState:
        """The relaxed (virgin) state: every play output equals the input, f_j = 0.

        Parameters
        ----------
        position : float
            The input y [m] at which the bank rests.
        n_elements : int
            Number of play operators N (>= 0).

        Returns
        -------
        PIState
            x_j = y for every j, direction 0.
        """
        position = as_real_scalar("position", position)
        n = as_count("n_elements", n_elements)
        check_size("n_elements", n, n, what="elements")
        return cls(position, np.full(n, position), 0.0)

    @classmethod
    def saturated(cls, position: float, threshold: ArrayLike, direction: float) -> PIState:
        """Every element at its threshold after motion in `direction` (+1 or −1).

        The elastic deformations are f_j = direction·r_j, so a bank with
        stiffnesses k_j carries its maximal elastic force direction·Σ k_j r_j.

        Parameters
        ----------
        position : float
            The input y [m] reached by that motion.
        threshold : array_like, shape (N,)
            Thresholds r_j >= 0 [m] of the play operators (eq. 3).
        direction : {-1, 1}
            Sign of the motion that saturated every element.

        Returns
        -------
        PIState
            x_j = y − direction·r_j, with that direction.
        """
        position = as_real_scalar("position", position)
        r = as_parameter_vector("threshold", threshold, positive=False, allow_empty=True)
        d = as_real_scalar("direction", direction)
        if d not in (-1, 1):
            raise ValueError(f"`direction` must be -1 or 1; got {fmt(d)}.")
        return cls(position, position - d * r, d)

    def check_against(self, threshold: FloatArray, name: str = "state") -> None:
        """Check that this state fits a bank with the given thresholds.

        Parameters
        ----------
        threshold : ndarray, shape (N,)
            Thresholds r_j of the bank (already validated).
        name : str
            Parameter name used in the error message.

        Raises
        ------
        ValueError
            If the state does not hold N play outputs, or some |y − x_j| exceeds
            r_j (beyond rounding).
        """
        if type(threshold) is not np.ndarray or threshold.dtype != np.float64:
            threshold = as_parameter_vector("threshold", threshold, positive=False)
        n = threshold.shape[0]
        if self.play.shape != (n,):
            raise ValueError(
                f"`{name}` must hold {n} play states for this operator; got {self.play.shape[0]}."
            )
        excess = np.abs(self.last_input - self.play) - threshold
        bad = excess > _SLACK * (abs(self.last_input) + threshold)
        if bad.any():
            j = int(np.argmax(bad))
            raise ValueError(
                f"`{name}` must satisfy |last_input − play_j| <= threshold_j; "
                f"got |{fmt(self.last_input)} − {fmt(self.play[j])}| > {fmt(threshold[j])} "
                f"at index {j}."
            )


def _initial_play(y0: float, threshold: FloatArray, initial: ArrayLike | None) -> FloatArray:
    """The play state at the first sample, validated against |y0 − x| <= r."""
    n = threshold.shape[0]
    if initial is None:
        return np.full(n, y0)
    x0 = as_state_vector("initial", initial, n)
    PIState(y0, x0).check_against(threshold, "initial")
    return x0


def _thresholds(threshold: ArrayLike) -> tuple[FloatArray, bool]:
    """Thresholds r_j >= 0 (r = 0 is the identity play, x = y) and whether one was a scalar."""
    r = as_parameter_vector("threshold", threshold, positive=False)  # types (and ragged) first
    return r, np.ndim(threshold) == 0


def check_input_range(
    y: FloatArray, threshold: FloatArray, weight: FloatArray, linear: float
) -> None:
    """The operator's arithmetic along `y` stays in the floating-point range.

    The kernels form y ± r_j, and every output obeys
    |F(t)| <= |a|·|y(t)| + Σ_j |w_j|·r_j (|y − x_j| <= r_j), so it suffices that
    max|y| + max r_j and |a|·max|y| + Σ |w_j|·r_j are finite. O(1) extra memory.
    """
    if y.shape[0] == 0:
        return
    peak = float(_kernels.peak(y))  # one compiled pass (max and min would take two)
    with np.errstate(over="ignore"):
        reach = peak + (float(np.max(threshold)) if threshold.shape[0] else 0.0)
        bound = abs(linear) * peak + float(np.abs(weight) @ threshold)
    check_finite_derived("reach max|y| + max r_j of the play operators", reach, ("y", "threshold"))
    check_finite_derived("output bound |a|·max|y| + Σ |w_j|·r_j", bound, ("y", "linear"))


def play(y: ArrayLike, threshold: ArrayLike, initial: ArrayLike | None = None) -> FloatArray:
    """Play operator outputs x(t) for a sampled input (eq. 3).

    Parameters
    ----------
    y : array_like, shape (T,)
        Sampled input, assumed monotone between consecutive samples.
    threshold : float or array_like, shape (N,)
        Half-widths r_j >= 0 of the play zones (r = 0 is the identity, x = y).
    initial : float or array_like, shape (N,), optional
        Play state x at the first sample; must satisfy |y[0] − x| <= r.
        Default: the relaxed state x = y[0].

    Returns
    -------
    ndarray, shape (T,) for a scalar threshold, else (T, N)
        The play outputs x_j(t), with |y − x_j| <= r_j at every sample.
    """
    yv = as_signal("y", y)
    r, scalar = _thresholds(threshold)
    check_input_range(yv, r, np.zeros_like(r), 0.0)
    check_size("y", yv.shape[0], float(yv.shape[0]) * r.shape[0], what="play outputs")
    x = _initial_play(float(yv[0]), r, initial)
    out = _kernels.empty_outputs(yv.shape[0], r.shape[0])
    _kernels.play_outputs(yv, r, x, out)
    return out[:, 0] if scalar else out


def stop(y: ArrayLike, threshold: ArrayLike, initial: ArrayLike | None = None) -> FloatArray:
    """Stop operator outputs f(t) = y(t) − x(t) (eq. 5 and eq. 11).

    The stop is the elastic-perfectly-plastic element of unit stiffness: its
    output follows the input increments and saturates at ±r.

    Parameters and returns as for `play`; ``initial`` is the *play* state at the
    first sample, so that ``stop(y, r, x0) == y[:, None] − play(y, r, x0)``.
    """
    yv = as_signal("y", y)
    x = play(yv, threshold, initial)
    return yv - x if x.ndim == 1 else yv[:, None] - x


@dataclass(frozen=True, eq=False)
class PIOperator:
    """Prandtl–Ishlinskii operator: a weighted sum of stops, F = Σ w_j (y − x_j) (eq. 4).

    Parameters
    ----------
    threshold : array_like, shape (N,)
        Thresholds r_j >= 0 of the play operators (an element with r_j = 0 is
        the identity play: its stop output is always 0).
    weight : array_like, shape (N,)
        Weights w_j (the stiffnesses k_j for a friction bank). Any finite real
        number; a physical (dissipative) bank has w_j > 0.
    linear : float, keyword only, default 0.0
        Coefficient a of an added linear term, F = a·y + Σ w_j (y − x_j). A
        friction bank has a = 0; a > 0 makes a positive-weight operator
        invertible on all inputs (see `inverse`).

    Examples
    --------
    >>> import numpy as np
    >>> op = PIOperator(threshold=[0.1, 0.25], weight=[10.0, 4.0])
    >>> force, state = op.apply(np.array([0.0, 0.05, 0.3, 0.2]))
    >>> force.round(6).tolist()
    [0.0, 0.7, 2.0, 0.6]
    """

    threshold: FloatArray
    weight: FloatArray
    linear: float = field(default=0.0, kw_only=True)

    def __post_init__(self) -> None:
        r = as_parameter_vector("threshold", self.threshold, positive=False)
        w = as_real_vector("weight", self.weight)
        object.__setattr__(self, "linear", as_real_scalar("linear", self.linear))
        if w.shape != r.shape:
            raise ValueError(
                f"`weight` must have the same length as `threshold` ({r.shape[0]}); "
                f"got {w.shape[0]}."
            )
        with np.errstate(over="ignore", invalid="ignore"):
            stiffness, saturation = float(np.sum(np.abs(w))), float(np.abs(w) @ r)
        check_finite_derived("total stiffness Σ |w_j|", stiffness, "weight")
        check_finite_derived("saturation bound Σ |w_j|·r_j", saturation, ("weight", "threshold"))
        object.__setattr__(self, "threshold", r)
        object.__setattr__(self, "weight", w)

    @property
    def n_elements(self) -> int:
        """Number N of stop elements."""
        return int(self.threshold.shape[0])

    def relaxed_state(self, position: float = 0.0) -> PIState:
        """All elements relaxed at `position`."""
        return PIState.relaxed(position, self.n_elements)

    def apply(
        self, y: ArrayLike, state: PIState | None = None, *, out: np.ndarray | None = None
    ) -> tuple[FloatArray, PIState]:
        """Evaluate the operator along a sampled input.

        Parameters
        ----------
        y : array_like, shape (T,)
            Input samples, monotone between consecutive samples. A C-contiguous
            float64 array is read in place (not copied).
        state : PIState, optional
            Memory before the first sample (as returned by a previous call).
            Default: relaxed at ``y[0]``.
        out : ndarray, shape (T,), optional, keyword only
            C-contiguous float64 array to write the output into (as numpy's
            ``out=``); a new array by default.

        Returns
        -------
        output : ndarray, shape (T,)
            a·y + Σ_j w_j (y − x_j) at each sample (a = `linear`).
        final_state : PIState
            Memory after the last sample; passing it to the next call on the
            continuation of the signal gives bit-identical output to one call.
        """
        yv = as_signal("y", y, copy=False, kind="position")  # read in place; a Quantity in SI
        x, prev, direction = start_memory(yv, self.threshold, state)
        check_input_range(yv, self.threshold, self.weight, self.linear)
        out = as_output("out", out, yv.shape)
        d = _kernels.stop_sum(
            yv, self.threshold, self.weight, x, out, self.linear, 0.0, prev, direction
        )
        return out, PIState(float(yv[-1]), x, d)

    def inverse(self) -> Any:
        """The inverse PI operator, y = inverse(F) (see `presliding.hysteresis.inverse.pi_inverse`).

        With ``linear > 0`` (or mixed weights and every slope of the initial
        loading curve positive) a `PIOperator` on all forces; start it from
        ``presliding.hysteresis.inverse.inverse_state(self, state)``. Without a
        linear term and with positive weights (a friction bank) a
        ``presliding.hysteresis.inverse.PIInverse``, defined on the range
        |F| < F_m = Σ w_j r_j, which raises outside it. ValueError otherwise.
        """
        if self.linear == 0.0 and np.all(self.weight > 0):
            return RANGE_INVERSE["PIInverse"](self)
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):  # checked below
            rho, weight, linear = inverse_parameters(self.threshold, self.weight, self.linear)
        check_inverse_parameters(rho, weight, linear, self.linear + float(np.sum(self.weight)))
        return PIOperator(rho, weight, linear=linear)


def check_inverse_parameters(
    rho: FloatArray, weight: FloatArray, linear: float, initial_slope: float
) -> None:
    """The inverse's 1/a, weights 1/K_k − 1/K_(k+1) and thresholds φ(r_k) are finite and usable.

    A tiny `linear` a (e.g. subnormal) makes 1/a overflow; slopes K_k near the
    end of the range make the reciprocals overflow or lose all digits.
    `initial_slope` is the forward operator's K_1 = a + Σ w_j.
    """
    check_finite_derived("inverse linear term 1/a", linear, "linear")
    check_finite_derived(
        "inverse weights 1/K_k − 1/K_(k+1) (K_k = a + Σ_(r_j >= r_k) w_j)",
        weight,
        ("weight", "linear"),
    )
    check_finite_derived(
        "inverse thresholds φ(r_k) = a·r_k + Σ_j w_j·min(r_k, r_j)",
        rho,
        ("threshold", "weight", "linear"),
    )
    # y = b·F + Σ v_k σ_k cancels terms of size (|b| + Σ|v_k|)·|F| down to |y| >= |F|/K_1:
    # rounding is amplified by κ = (|b| + Σ|v_k|)·K_1.
    with np.errstate(over="ignore", invalid="ignore"):
        kappa = (abs(linear) + float(np.sum(np.abs(weight)))) * abs(initial_slope)
    if not kappa * np.finfo(np.float64).eps <= _INVERSE_ROUNDING:
        raise ValueError(
            "`linear` must be large enough against the weights for the inverse to keep 4 "
            f"significant digits (condition number (|1/a| + Σ|v_k|)·K_1 at most "
            f"{_INVERSE_ROUNDING / np.finfo(np.float64).eps:.3g}); got {fmt(1.0 / linear)} "
            f"for 1/a, which gives {kappa:.3g}."
        )


def start_memory(
    y: FloatArray,
    threshold: FloatArray,
    state: object,  # a PIState or None; else TypeError
) -> tuple[FloatArray, float, float]:
    """Play vector (a fresh copy), previous input and direction to start a kernel from."""
    if state is None:
        return np.full(threshold.shape[0], y[0]), float(y[0]), 0.0
    if not isinstance(state, PIState):
        raise TypeError(f"`state` must be a PIState or None; got {type(state).__name__}.")
    state.check_against(threshold)
    return state.play.copy(), state.last_input, state.direction
