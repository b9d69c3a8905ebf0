"""The Prandtl–Ishlinskii friction model with a Coulomb element (eqs. 5–9).

Friction force along a displacement y (eq. 8)::

    F(y, ẏ) = c1·sign(ẏ) + Σ_j k_j (y − x_j(y, r_j)),     r_j = c_j / k_j  (eq. 6)

where c1 >= 0 is the Coulomb element (an element of infinite stiffness), and
each elasto-plastic element j has stiffness k_j, break-away force c_j and play
operator x_j with threshold r_j (eq. 3). At unidirectional motion the force
saturates at the Coulomb level F_c = c1 + Σ c_j (eq. 9); right after every
reversal the elastic part has stiffness Σ k_j (eq. 7).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _kernels
from ._validation import as_nonnegative_scalar, as_parameter_vector, as_signal, fmt
from .operators import PIOperator, PIState, start_memory

__all__ = ["PIFriction"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class PIFriction:
    """Coulomb friction with presliding hysteresis, finite-element PI model (eq. 8).

    Parameters
    ----------
    coulomb : float
        Coulomb element c1 >= 0 [N], the force of the element with infinite
        stiffness; it contributes c1·sign(ẏ).
    stiffness : array_like, shape (N,)
        Presliding stiffnesses k_j > 0 [N/m] of the elasto-plastic elements.
    breakaway : array_like, shape (N,), optional
        Break-away forces c_j > 0 [N]. Give either `breakaway` or `threshold`.
    threshold : array_like, shape (N,), optional, keyword only
        Thresholds r_j = c_j / k_j > 0 [m] (eq. 6), the presliding displacement
        at which element j starts to slide.

    Notes
    -----
    With no elements (``stiffness=[]``) the model is classical Coulomb friction
    with F_c = c1. With c1 = 0 it is the PI operator of eq. 4. Very stiff
    elements approach F_c·sign(ẏ).

    Examples
    --------
    The model of the paper's Figure 3 (three elements, c = [1, 1, 1]):

    >>> model = PIFriction(coulomb=0.0, stiffness=[500.0, 10.0, 4.0], breakaway=[1.0, 1.0, 1.0])
    >>> model.coulomb_level, model.initial_stiffness
    (3.0, 514.0)
    """

    coulomb: float
    stiffness: FloatArray = field(default_factory=lambda: np.empty(0))
    breakaway: FloatArray | None = None
    threshold: FloatArray | None = field(default=None, kw_only=True)

    def __post_init__(self) -> None:
        c1 = as_nonnegative_scalar("coulomb", self.coulomb)
        k = as_parameter_vector("stiffness", self.stiffness, allow_empty=True)
        if (self.breakaway is None) == (self.threshold is None):
            if self.breakaway is None and k.shape[0] == 0:
                c = r = k
            else:
                raise TypeError(
                    "give exactly one of `breakaway` and `threshold`; got "
                    + ("both." if self.breakaway is not None else "neither.")
                )
        elif self.breakaway is not None:
            c = as_parameter_vector("breakaway", self.breakaway, allow_empty=True)
            _same_length(k, c, "breakaway")
            r = c / k
        else:
            r = as_parameter_vector("threshold", self.threshold, allow_empty=True)
            _same_length(k, r, "threshold")
            c = k * r
        for name, arr in (("breakaway", c), ("threshold", r)):
            if not np.all(np.isfinite(arr)) or not np.all(arr > 0):
                j = int(np.argmax(~(np.isfinite(arr) & (arr > 0))))
                raise ValueError(
                    f"`{name}` must come out finite and positive; got {fmt(arr[j])} at index {j} "
                    f"(from stiffness {fmt(k[j])})."
                )
        if c1 == 0 and k.shape[0] == 0:
            raise ValueError(
                "the model has no friction: `coulomb` must be positive when there are no "
                "elements; got coulomb 0.0 and an empty `stiffness`."
            )
        for arr in (c, r):
            arr = np.asarray(arr)
            arr.setflags(write=False)
        object.__setattr__(self, "coulomb", c1)
        object.__setattr__(self, "stiffness", k)
        object.__setattr__(self, "breakaway", c)
        object.__setattr__(self, "threshold", r)

    # ------------------------------------------------------------------ properties
    @property
    def n_elements(self) -> int:
        """Number of elasto-plastic elements (the Coulomb element not counted)."""
        return int(self.stiffness.shape[0])

    @property
    def max_elastic_force(self) -> float:
        """F_m = Σ c_j, the largest force the elastic elements can carry."""
        return float(np.sum(self.breakaway))

    @property
    def coulomb_level(self) -> float:
        """F_c = c1 + Σ c_j (eq. 9), the friction force at unidirectional sliding."""
        return self.coulomb + self.max_elastic_force

    @property
    def initial_stiffness(self) -> float:
        """Σ k_j (eq. 7): the elastic stiffness right after every reversal."""
        return float(np.sum(self.stiffness))

    @property
    def operator(self) -> PIOperator:
        """The elastic part as a PI operator (eq. 4) with weights k_j."""
        return PIOperator(self.threshold, self.stiffness)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, PIFriction):
            return NotImplemented
        return (
            self.coulomb == other.coulomb
            and np.array_equal(self.stiffness, other.stiffness)
            and np.array_equal(self.threshold, other.threshold)
            and np.array_equal(self.breakaway, other.breakaway)
        )

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return (
            f"PIFriction(coulomb={self.coulomb!r}, stiffness={self.stiffness.tolist()!r}, "
            f"breakaway={self.breakaway.tolist()!r})"
        )

    # ------------------------------------------------------------------ states
    def relaxed_state(self, position: float = 0.0) -> PIState:
        """Virgin state at `position`: no elastic deformation, no motion yet."""
        return PIState.relaxed(position, self.n_elements)

    def saturated_state(self, position: float = 0.0, direction: float = 1.0) -> PIState:
        """Every element sliding after motion in `direction`: elastic force direction·F_m."""
        if self.n_elements == 0:
            return PIState(position, np.empty(0), direction)
        return PIState.saturated(position, self.threshold, direction)

    # ------------------------------------------------------------------ curves
    def virgin_curve(self, displacement: ArrayLike, *, elastic_only: bool = False) -> FloatArray:
        """Initial loading curve from the relaxed state (odd in the displacement).

        F_v(y) = c1·sign(y) + Σ_j k_j·sign(y)·min(|y|, r_j). By the Madelung/Masing
        rules it determines every loop: after a reversal at (y_r, F_r) the force
        follows F_r − 2·F_v((y_r − y)/2) until it meets an older branch.

        Parameters
        ----------
        displacement : array_like, shape (T,) or scalar
            Displacements y from the relaxed position.
        elastic_only : bool
            Leave out the Coulomb element c1·sign(y).
        """
        scalar = np.ndim(displacement) == 0
        y = as_signal("displacement", np.atleast_1d(displacement))
        ay = np.abs(y)
        elastic = np.minimum(ay[:, None], self.threshold[None, :]) @ self.stiffness
        out = np.sign(y) * (elastic if elastic_only else elastic + self.coulomb)
        return out[0] if scalar else out

    def elastic_force(
        self, displacement: ArrayLike, state: PIState | None = None
    ) -> tuple[FloatArray, PIState]:
        """Elastic part Σ k_j (y − x_j) along a sampled displacement (eq. 4, eq. 5).

        Parameters
        ----------
        displacement : array_like, shape (T,)
            Displacement samples, monotone between consecutive samples.
        state : PIState, optional
            Memory before the first sample; default relaxed at ``displacement[0]``.

        Returns
        -------
        force : ndarray, shape (T,)
        final_state : PIState
        """
        y = as_signal("displacement", displacement)
        return self._run(y, state)[1:]

    def force(
        self, displacement: ArrayLike, state: PIState | None = None
    ) -> tuple[FloatArray, PIState]:
        """Total friction force c1·sign(ẏ) + Σ k_j (y − x_j) along a displacement (eq. 8).

        The Coulomb element contributes c1 times the sign of the last nonzero
        increment of the displacement (0 before any motion), i.e. the friction
        force acting on the contact while it moves in that direction.

        Parameters
        ----------
        displacement : array_like, shape (T,)
            Displacement samples, monotone between consecutive samples.
        state : PIState, optional
            Memory before the first sample; default relaxed at ``displacement[0]``
            with no motion yet.

        Returns
        -------
        force : ndarray, shape (T,)
        final_state : PIState
            Passing it to the next call on the continuation of the path gives
            bit-identical results to a single call.
        """
        y = as_signal("displacement", displacement)
        direction, elastic, final = self._run(y, state)
        return elastic + self.coulomb * direction, final

    def _run(self, y: FloatArray, state: PIState | None) -> tuple[FloatArray, FloatArray, PIState]:
        x, prev, d0 = start_memory(y, self.threshold, state)
        elastic = np.empty(y.shape[0])
        _kernels.stop_sum(y, self.threshold, self.stiffness, x, elastic)
        direction = np.empty(y.shape[0])
        d = _kernels.motion_direction(y, prev, d0, direction)
        return direction, elastic, PIState(float(y[-1]), x, d)


def _same_length(k: FloatArray, other: FloatArray, name: str) -> None:
    if other.shape != k.shape:
        raise ValueError(
            f"`stiffness` and `{name}` must have the same length; "
            f"`stiffness` has {k.shape[0]}, `{name}` has {other.shape[0]}."
        )
