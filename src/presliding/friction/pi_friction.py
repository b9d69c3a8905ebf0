"""The Prandtl–Ishlinskii friction model with a Coulomb element (eqs. 5–9).

Friction force along a displacement y (eq. 8, plus an optional viscous term)::

    F(y, ẏ) = c1·sign(ẏ) + σ·ẏ + Σ_j k_j (y − x_j(y, r_j)),     r_j = c_j / k_j  (eq. 6)

where c1 >= 0 is the Coulomb element (an element of infinite stiffness), and
each elasto-plastic element j has stiffness k_j, break-away force c_j and play
operator x_j with threshold r_j (eq. 3). At unidirectional motion the force
saturates at the Coulomb level F_c = c1 + Σ c_j (eq. 9); right after every
reversal the elastic part has stiffness Σ k_j (eq. 7).

With ``density=`` the elements form a continuum with distribution μ (section
3, eq. 10): F(y, ẏ) = c1·sign(ẏ) + σ·ẏ + ∫_0^R (y − x(y, r)) dμ(r), evaluated
exactly by `GeneralPIOperator` with a `MemoryState`.

The viscous coefficient σ >= 0 [N·s/m] (``viscous``) defaults to 0, the paper's
assumption (i) ("no viscous friction effects"), and is the only rate-dependent term:
`PIFriction.force`, `elastic_force` and `virgin_curve` return the rate-independent
part, `viscous_force` gives σ·ẏ, and `presliding.simulate` includes σ (eq. 17).

Asymmetric friction (the ``*_negative`` fields) gives sliding in −y its own levels, the play
band becoming [y − r_j⁺, y + r_j⁻] (`presliding.friction._sides`); without them every result
is the symmetric one, bit for bit.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._display import model_html
from presliding._out import as_output
from presliding._validation import as_real_array, as_signal, fmt
from presliding.friction import _pi_setup, _sides, _summary
from presliding.hysteresis import _kernels
from presliding.hysteresis.densities import Density
from presliding.hysteresis.general_pi import GeneralPIOperator, MemoryState, run_density
from presliding.hysteresis.operators import PIOperator, PIState, start_memory

__all__ = ["PIFriction"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class PIFriction:
    """Coulomb friction with presliding hysteresis, finite-element PI model (eq. 8).

    F(y, ẏ) = c1·sign(ẏ) + σ·ẏ + Σ_j k_j (y − x_j(y, r_j)): eq. 8 with an optional
    viscous term σ·ẏ (σ = 0 by default, the paper's assumption (i)).

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
    density : Density, optional, keyword only
        Instead of elements: the distribution μ of eq. 10 (`Uniform`,
        `Exponential`, ...). A `Discrete` density gives the finite-element
        model with its stiffnesses and thresholds. For any other density
        ``stiffness``, ``breakaway`` and ``threshold`` are None, states are
        `MemoryState` objects, and ``n_elements`` raises.
    viscous : float, optional, keyword only
        Viscous coefficient σ >= 0 [N·s/m]: the term σ·ẏ, proportional to the
        sliding velocity. Default 0, the paper's assumption (i). It does not
        change the rate-independent quantities (F_c, F_m, eq. 7, the virgin
        curve, `force`); `presliding.simulate` and the batches include it.
    coulomb_negative : float, optional, keyword only
        Asymmetric friction: the Coulomb element c1⁻ >= 0 [N] for sliding in −y
        (then `coulomb` is c1⁺, for sliding in +y). Default None: c1⁻ = c1⁺.
    breakaway_negative, threshold_negative : array_like, shape (N,), optional, keyword only
        Asymmetric friction: break-away forces c_j⁻ > 0 [N] (or thresholds
        r_j⁻ = c_j⁻/k_j [m]) for sliding in −y; `breakaway`/`threshold` are
        then c_j⁺/r_j⁺. The play operator keeps x_j in [y − r_j⁺, y + r_j⁻], so
        element j carries k_j·(y − x_j) in [−c_j⁻, c_j⁺]. Default None: equal
        sides.
    viscous_negative : float, optional, keyword only
        Asymmetric friction: σ⁻ >= 0 [N·s/m] for ẏ < 0 (`viscous` is then σ⁺).

    A negative side equal to the positive one is stored as None (equal sides give the
    symmetric model); a continuous density takes no negative side.

    Notes
    -----
    With no elements (``stiffness=[]``) the model is classical Coulomb friction with
    F_c = c1; with c1 = 0 it is the PI operator of eq. 4. Very stiff elements approach
    F_c·sign(ẏ). Steady sliding at velocity v costs F_c·sign(v) + σ·v (`steady_force`).

    Examples
    --------
    The model of the paper's Figure 3 (three elements, c = [1, 1, 1]):

    >>> model = PIFriction(coulomb=0.0, stiffness=[500.0, 10.0, 4.0], breakaway=[1.0, 1.0, 1.0])
    >>> model.coulomb_level, model.initial_stiffness
    (3.0, 514.0)

    With a viscous term σ = 2 N·s/m, steady sliding at 0.5 m/s costs F_c + σ·v:

    >>> PIFriction(3.0, viscous=2.0).steady_force(0.5)
    4.0

    Asymmetric friction: F_c⁺ = 2 + 1, F_c⁻ = 1 + 0.5:

    >>> PIFriction(2.0, [100.0], [1.0], coulomb_negative=1.0,
    ...            breakaway_negative=[0.5]).coulomb_levels
    (3.0, 1.5)
    """

    coulomb: float
    stiffness: FloatArray = field(default_factory=lambda: np.empty(0))
    breakaway: FloatArray | None = None
    threshold: FloatArray | None = field(default=None, kw_only=True)
    density: Density | None = field(default=None, kw_only=True)
    viscous: float = field(default=0.0, kw_only=True)
    coulomb_negative: float | None = field(default=None, kw_only=True)
    breakaway_negative: FloatArray | None = field(default=None, kw_only=True)
    threshold_negative: FloatArray | None = field(default=None, kw_only=True)
    viscous_negative: float | None = field(default=None, kw_only=True)

    if TYPE_CHECKING:  # the constructor takes array_like; the fields hold float64 arrays

        def __init__(self, coulomb: float, stiffness: ArrayLike = ..., breakaway: ArrayLike | None
                     = None, *, threshold: ArrayLike | None = None, density: Density | None =
                     None, viscous: float = 0.0, coulomb_negative: float | None = None,
                     breakaway_negative: ArrayLike | None = None, threshold_negative: ArrayLike
                     | None = None, viscous_negative: float | None = None) -> None: ...  # fmt: skip

    def __post_init__(self) -> None:
        _pi_setup.setup(self)

    # ------------------------------------------------------------------ properties
    @property
    def is_discrete(self) -> bool:
        """True for finite elements (eq. 8), False for a continuous density (eq. 10)."""
        return self.stiffness is not None

    @property
    def n_elements(self) -> int:
        """Number of elasto-plastic elements (the Coulomb element not counted)."""
        if self.stiffness is None:
            raise TypeError(
                f"a model with a continuous density has no finite number of elements; "
                f"got density {self.density!r}."
            )
        return int(self.stiffness.shape[0])

    @property
    def is_symmetric(self) -> bool:
        """True when both directions share every level (no negative side given)."""
        return (
            self.coulomb_negative is None
            and self.breakaway_negative is None
            and self.viscous_negative is None
        )

    @property
    def coulomb_levels(self) -> tuple[float, float]:
        """(F_c⁺, F_c⁻) = (c1⁺ + Σ c_j⁺, c1⁻ + Σ c_j⁻): the sliding levels in +y and −y (eq. 9).

        Both equal `coulomb_level` for a symmetric model.
        """
        return _sides.levels(self)

    @property
    def max_elastic_force(self) -> float:
        """F_m = Σ c_j = ∫ r dμ(r), the largest force the elastic elements can carry.

        An asymmetric model has two (Σ c_j⁺ and Σ c_j⁻): use `coulomb_levels`.
        """
        _sides.require_symmetric(self, "max_elastic_force (one level)")
        if self.breakaway is None:
            return cast(Density, self.density).max_elastic_force
        return float(np.sum(self.breakaway))

    @property
    def coulomb_level(self) -> float:
        """F_c = c1 + Σ c_j (eq. 9), the friction force at unidirectional sliding.

        An asymmetric model has two: use `coulomb_levels`.
        """
        _sides.require_symmetric(self, "coulomb_level (one level)")
        return self.coulomb + self.max_elastic_force

    @property
    def initial_stiffness(self) -> float:
        """Σ k_j = μ([0, R]) (eq. 7): the elastic stiffness right after every reversal.

        Finite for every density provided here (a density not integrable at
        r = 0 would give inf: an infinitely stiff start).
        """
        if self.stiffness is None:
            return cast(Density, self.density).total_stiffness
        return float(np.sum(self.stiffness))

    @property
    def operator(self) -> PIOperator | GeneralPIOperator:
        """The elastic part: a PI operator (eq. 4) with weights k_j, or the general one."""
        _sides.require_symmetric(self, "PIFriction.operator (a symmetric PI operator)")
        if self.stiffness is None:
            return GeneralPIOperator(cast(Density, self.density))
        return PIOperator(cast(FloatArray, self.threshold), self.stiffness)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, PIFriction):
            return NotImplemented
        if self.viscous != other.viscous or not _sides.same_sides(self, other):
            return False
        if not (self.is_discrete and other.is_discrete):
            return self.coulomb == other.coulomb and self.density == other.density
        return self.coulomb == other.coulomb and all(
            np.array_equal(getattr(self, a), getattr(other, a))
            for a in ("stiffness", "threshold", "breakaway")
        )

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        visc = f", viscous={self.viscous!r}" if self.viscous else ""
        visc += _sides.repr_suffix(self)
        if self.stiffness is None or self.breakaway is None:  # a continuous density
            return f"PIFriction(coulomb={self.coulomb!r}, density={self.density!r}{visc})"
        return (
            f"PIFriction(coulomb={self.coulomb!r}, stiffness={self.stiffness.tolist()!r}, "
            f"breakaway={self.breakaway.tolist()!r}{visc})"
        )

    def _repr_html_(self) -> str:  # a notebook's view: F_c, F_m, Σk, each parameter's unit
        return model_html(self, _summary.figures(self))

    # ------------------------------------------------------------------ viscous term
    def viscous_force(self, velocity: ArrayLike) -> FloatArray | float:
        """σ·ẏ, the viscous part of the friction force at the velocity ẏ [N].

        Add it to `force` (the rate-independent part) to get the whole law
        F(y, ẏ) = c1·sign(ẏ) + σ·ẏ + F_el(y) along a motion with known velocity.

        Parameters
        ----------
        velocity : float or array_like
            ẏ [m/s], finite.

        Returns
        -------
        float or ndarray
            σ·ẏ, of the shape of `velocity` (0 everywhere when σ = 0).
        """
        v = as_real_array("velocity", velocity)
        if self.viscous_negative is not None:
            out = np.where(v < 0, self.viscous_negative, self.viscous) * v
        else:
            out = self.viscous * v
        return float(out) if np.ndim(out) == 0 else out

    def steady_force(self, velocity: ArrayLike) -> FloatArray | float:
        """F_c·sign(v) + σ·v: the friction force at steady sliding with velocity v (eq. 9).

        Every element slides at constant velocity, so the elastic part is
        saturated at F_m·sign(v); at v = 0 the value is 0 (the friction force at
        rest is set by the applied force, anywhere in [−c1 − F_el, c1 − F_el]).

        Parameters
        ----------
        velocity : float or array_like
            v [m/s], finite.
        """
        v = as_real_array("velocity", velocity)
        if not self.is_symmetric:
            return _sides.steady_force(self, v)
        out = self.coulomb_level * np.sign(v) + self.viscous * v
        return float(out) if np.ndim(out) == 0 else out

    # ------------------------------------------------------------------ states
    def relaxed_state(self, position: float = 0.0) -> PIState | MemoryState:
        """Virgin state at `position`: no elastic deformation, no motion yet."""
        if not self.is_discrete:
            return MemoryState.relaxed(position)
        return PIState.relaxed(position, self.n_elements)

    def saturated_state(
        self, position: float = 0.0, direction: float = 1.0
    ) -> PIState | MemoryState:
        """Every element sliding after motion in `direction`: elastic force direction·F_m."""
        if not self.is_discrete:
            return MemoryState.saturated(
                position, direction, cast(Density, self.density).max_threshold
            )
        if self.threshold_negative is not None and direction == -1:
            return PIState.saturated(position, self.threshold_negative, direction)
        return PIState.saturated(position, cast(FloatArray, self.threshold), direction)

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
        if not isinstance(elastic_only, (bool, np.bool_)):
            raise TypeError(f"`elastic_only` must be True or False; got {fmt(elastic_only)}.")
        scalar = (y := as_real_array("displacement", displacement)).ndim == 0
        y = as_signal("displacement", np.atleast_1d(y))
        ay = np.abs(y)
        if not self.is_symmetric:
            return _sides.virgin_curve(self, y, elastic_only)[0] if scalar else (
                _sides.virgin_curve(self, y, elastic_only))  # fmt: skip
        if self.stiffness is None or self.threshold is None:  # a continuous density
            elastic = cast(Density, self.density).virgin_curve(ay)
        else:
            elastic = np.minimum(ay[:, None], self.threshold[None, :]) @ self.stiffness
        out = np.sign(y) * (elastic if elastic_only else elastic + self.coulomb)
        return out[0] if scalar else out

    def elastic_force(
        self, displacement: ArrayLike, state: PIState | MemoryState | None = None
    ) -> tuple[FloatArray, PIState | MemoryState]:
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
        y = as_signal("displacement", displacement, copy=False, kind="position")  # read only
        return self._run(y, state)[:2]

    def force(
        self,
        displacement: ArrayLike,
        state: PIState | MemoryState | None = None,
        *,
        out: np.ndarray | None = None,
    ) -> tuple[FloatArray, PIState | MemoryState]:
        """Friction force c1·sign(ẏ) + Σ k_j (y − x_j) along a displacement (eq. 8).

        The Coulomb element contributes c1 times the sign of the last nonzero
        increment of the displacement (0 before any motion), i.e. the friction
        force acting on the contact while it moves in that direction.

        This is the rate-independent part of the law: a displacement path has
        no time, so the viscous term σ·ẏ is not included (it is 0 for the
        default σ = 0). Add ``viscous_force(velocity)`` for a motion with known
        velocity; `presliding.simulate` includes σ·ẏ in the motion.

        Parameters
        ----------
        displacement : array_like, shape (T,)
            Displacement samples, monotone between consecutive samples.
        state : PIState, optional
            Memory before the first sample; default relaxed at ``displacement[0]``
            with no motion yet.
        out : ndarray, shape (T,), optional, keyword only
            C-contiguous float64 array to write the force into (as numpy's
            ``out=``); a new array by default. A C-contiguous float64
            displacement is read in place (not copied).

        Returns
        -------
        force : ndarray, shape (T,)
        final_state : PIState
            Passing it to the next call on the continuation of the path gives
            bit-identical results to a single call.
        """
        y = as_signal("displacement", displacement, copy=False, kind="position")  # read only
        out = as_output("out", out, y.shape)
        if not self.is_symmetric:
            return _sides.force(self, y, state, out)
        if self.is_discrete:
            # one fused pass: the Coulomb term c1·sign(ẏ) is added in the time loop
            return self._run(y, state, self.coulomb, out)[:2]
        elastic, final, prev, d0 = self._run(y, state)
        _kernels.motion_direction(y, prev, d0, out)
        out *= self.coulomb
        out += elastic
        return out, final

    def _run(
        self,
        y: FloatArray,
        state: PIState | MemoryState | None,
        coulomb: float = 0.0,
        out: FloatArray | None = None,
    ) -> tuple[FloatArray, PIState | MemoryState, float, float]:
        """Elastic force (plus ``coulomb``·sign(ẏ) for finite elements), final memory, and
        the input and direction before the first sample."""
        if self.stiffness is None or self.threshold is None:  # a continuous density
            elastic, _, final = run_density(cast(Density, self.density), y, state)
            prev, d0 = (float(y[0]), 0.0) if state is None else (state.last_input, state.direction)
            return elastic, final, prev, d0
        if not self.is_symmetric:
            return _sides.run_bank(self, y, state)
        x, prev, d0 = start_memory(y, self.threshold, state)
        elastic = np.empty(y.shape[0]) if out is None else out
        d = _kernels.stop_sum(y, self.threshold, self.stiffness, x, elastic, 0.0, coulomb, prev, d0)
        return elastic, PIState(float(y[-1]), x, d), prev, d0
