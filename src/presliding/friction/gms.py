"""The generalized Maxwell-slip model (GMS): the PI elements with a Stribeck curve and a lag.

Al-Bender, Lampaert and Swevers (2005) keep the Maxwell-slip structure of eq. 8 —
elements in parallel, each a spring that sticks until its force reaches a slip
force — and make the slip force follow the Stribeck curve of the sliding speed,
with a frictional lag while the element slips::

    F = c1·ŝ(|ẏ|)·Sign(ẏ) + σ·ẏ + Σ_i F_i,
    sticking:  dF_i/dt = k_i·ẏ                      until |F_i| = c_i·ŝ(|ẏ|),
    slipping:  dF_i/dt = sign(ẏ)·C·(α_i − F_i/s(ẏ))   until ẏ reverses,

with the Stribeck curve s(v) = F_C + (F_S − F_C)·exp(−|v/v_s|^δ) = F_C·ŝ(v),
F_C = c1 + Σ c_i the Coulomb level (eq. 9), F_S the static level, α_i = c_i/F_C
and the attraction C = F_C/τ of the lag time τ. A slipping element is never
stretched faster than the motion stretches its spring (|dF_i/dt| <= k_i·|ẏ| while
it rises): the lag may hold a force back, never create energy
(`presliding.friction._gms_kernels`). The Coulomb element c1 (infinitely stiff)
follows the Stribeck curve without lag; at rest it carries any force up to
c1·F_S/F_C (the break-away of the contact is F_S).

With F_S = F_C (no Stribeck drop) and τ = 0 (instantaneous slip) the model *is*
`PIFriction(c1, k, breakaway=c, viscous=σ)`: every element is the play element
of eq. 8, to rounding (`GMSFriction.pi_friction`). At rest nothing moves: the
rates carry sign(ẏ) = 0, so a mass held below break-away never drifts
(`presliding.simulate`).

Reference
---------
Al-Bender, F., Lampaert, V., Swevers, J. (2005), *The generalized Maxwell-slip
model: a novel model for friction simulation and compensation*, IEEE Trans.
Automatic Control 50(11), 1883–1887.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_nonnegative_scalar,
    as_parameter_vector,
    as_positive_scalar,
    as_real_array,
    as_real_scalar,
    as_signal,
    as_state_vector,
    check_increasing,
    check_same_length,
    fmt,
)
from presliding.friction import _gms_kernels as _gk
from presliding.friction._model_checks import check_has_friction
from presliding.friction.pi_friction import PIFriction

__all__ = ["GMSFriction", "GMSState"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class GMSState:
    """Memory of the GMS model after a sample.

    Parameters
    ----------
    last_input, last_time : float
        The last displacement y [m] and its time t [s].
    forces : array_like, shape (N,)
        The elements' forces F_i [N].
    slipping : array_like, shape (N,)
        Each element's slip direction: +1 or −1 while it slips that way, 0 while it sticks.
    velocity : float
        Velocity of the interval that ended at the last sample [m/s].
    direction : float
        Sign of the last nonzero increment (0 before any motion): the direction the
        Coulomb element's force acts in.
    """

    last_input: float
    last_time: float
    forces: FloatArray
    slipping: FloatArray
    velocity: float = 0.0
    direction: float = 0.0

    def __post_init__(self) -> None:
        for name in ("last_input", "last_time", "velocity"):
            object.__setattr__(self, name, as_real_scalar(name, getattr(self, name)))
        f = np.array(as_real_array("forces", self.forces), dtype=float).reshape(-1)
        e = np.array(as_real_array("slipping", self.slipping), dtype=float).reshape(-1)
        if e.shape != f.shape:
            raise ValueError(
                f"`slipping` must have the length of `forces` ({f.shape[0]}); got {e.shape[0]}."
            )
        if not np.all(np.isin(e, (-1.0, 0.0, 1.0))):
            raise ValueError(f"`slipping` must hold only −1, 0 or +1; got {e.tolist()}.")
        if self.direction not in (-1.0, 0.0, 1.0):
            raise ValueError(f"`direction` must be −1, 0 or +1; got {fmt(self.direction)}.")
        for arr in (f, e):
            arr.setflags(write=False)
        object.__setattr__(self, "forces", f)
        object.__setattr__(self, "slipping", e)
        object.__setattr__(self, "direction", float(self.direction))


@dataclass(frozen=True, eq=False)
class GMSFriction:
    """The generalized Maxwell-slip friction model (module notes).

    Parameters
    ----------
    coulomb : float
        c1 >= 0 [N], the Coulomb element (infinitely stiff), as in `PIFriction`.
    stiffness : array_like, shape (N,)
        k_i > 0 [N/m], the elements' stiffnesses.
    breakaway : array_like, shape (N,)
        c_i > 0 [N], the elements' slip forces at the Coulomb level (fast sliding);
        α_i = c_i/F_C in the paper's notation.
    static_level : float, optional, keyword only
        F_S >= F_C [N], the static level of the Stribeck curve (the break-away force
        of the contact). Default: F_C (no Stribeck drop).
    stribeck_velocity : float, optional, keyword only
        v_s > 0 [m/s], where the Stribeck curve falls. Needed when F_S > F_C.
    stribeck_exponent : float, keyword only
        δ > 0, the shape of the fall (default 2, Gaussian).
    lag_time : float, keyword only
        τ >= 0 [s], the time constant of the frictional lag at the Coulomb level
        (C = F_C/τ in the paper); 0 (default): instantaneous slip.
    viscous : float, keyword only
        σ >= 0 [N·s/m], viscous friction σ·ẏ.

    Examples
    --------
    With no Stribeck drop and no lag, the model is the PI model of eq. 8:

    >>> gms = GMSFriction(0.2, [1e4, 2e3], [0.3, 0.3])
    >>> gms.is_rate_independent, gms.pi_friction.coulomb_level
    (True, 0.8)

    Static friction 1.2 N falling to F_C = 0.8 N around 1 mm/s:

    >>> fast = GMSFriction(0.2, [1e4, 2e3], [0.3, 0.3], static_level=1.2,
    ...                    stribeck_velocity=1e-3, lag_time=5e-3)
    >>> [round(float(x), 6) for x in fast.steady_force([0.0005, 0.01])]
    [1.11152, 0.8]
    """

    coulomb: float
    stiffness: FloatArray
    breakaway: FloatArray
    static_level: float | None = field(default=None, kw_only=True)
    stribeck_velocity: float | None = field(default=None, kw_only=True)
    stribeck_exponent: float = field(default=2.0, kw_only=True)
    lag_time: float = field(default=0.0, kw_only=True)
    viscous: float = field(default=0.0, kw_only=True)

    if TYPE_CHECKING:  # the constructor takes array_like; the fields hold float64 arrays

        def __init__(self, coulomb: float, stiffness: ArrayLike, breakaway: ArrayLike, *,
                     static_level: float | None = None, stribeck_velocity: float | None = None,
                     stribeck_exponent: float = 2.0, lag_time: float = 0.0,
                     viscous: float = 0.0) -> None: ...  # fmt: skip

    def __post_init__(self) -> None:
        c1 = as_nonnegative_scalar("coulomb", self.coulomb)
        k = as_parameter_vector("stiffness", self.stiffness, allow_empty=True)
        c = as_parameter_vector("breakaway", self.breakaway, allow_empty=True)
        if c.shape != k.shape:
            raise ValueError(
                f"`breakaway` must have the same length as `stiffness` ({k.shape[0]}); "
                f"got {c.shape[0]}."
            )
        check_has_friction(np.array([c1]), k.shape[0])
        with np.errstate(over="ignore"):  # refused below
            fc = c1 + float(np.sum(c))
        if not np.isfinite(fc):
            raise ValueError(f"`breakaway` must give a finite Coulomb level; got {fmt(fc)}.")
        fs = fc if self.static_level is None else as_positive_scalar(
            "static_level", self.static_level)  # fmt: skip
        if fs < fc:
            raise ValueError(
                f"`static_level` must be >= the Coulomb level c1 + Σ c_i = {fmt(fc)}; got "
                f"{fmt(fs)}."
            )
        vs = self.stribeck_velocity
        if vs is not None:
            vs = as_positive_scalar("stribeck_velocity", vs)
        elif fs > fc:
            raise ValueError(
                "`stribeck_velocity` must be given with a `static_level` above the Coulomb level "
                f"{fmt(fc)}; got None."
            )
        for name, value in (("coulomb", c1), ("stiffness", k), ("breakaway", c),
                            ("static_level", fs), ("stribeck_velocity", vs)):  # fmt: skip
            object.__setattr__(self, name, value)
        object.__setattr__(
            self,
            "stribeck_exponent",
            as_positive_scalar("stribeck_exponent", self.stribeck_exponent),
        )
        object.__setattr__(self, "lag_time", as_nonnegative_scalar("lag_time", self.lag_time))
        object.__setattr__(self, "viscous", as_nonnegative_scalar("viscous", self.viscous))

    # ------------------------------------------------------------------ properties
    @property
    def n_elements(self) -> int:
        """Number N of elements (the Coulomb element not counted)."""
        return int(self.stiffness.shape[0])

    @property
    def coulomb_level(self) -> float:
        """F_C = c1 + Σ c_i (eq. 9): the friction at fast steady sliding."""
        return self.coulomb + float(np.sum(self.breakaway))

    @property
    def static_ratio(self) -> float:
        """F_S/F_C >= 1: the Stribeck curve's rise at rest (1: no Stribeck drop)."""
        return float(self.static_level) / self.coulomb_level  # type: ignore[arg-type]

    @property
    def is_rate_independent(self) -> bool:
        """True when F_S = F_C and τ = 0: the model is `pi_friction` (eq. 8) exactly."""
        return self.static_level == self.coulomb_level and self.lag_time == 0.0

    @property
    def pi_friction(self) -> PIFriction:
        """The PI model with the same c1, k_i, c_i and σ (eq. 8): the model itself when
        `is_rate_independent`, its fast-sliding limit otherwise."""
        if self.n_elements == 0:
            return PIFriction(self.coulomb, viscous=self.viscous)
        return PIFriction(self.coulomb, self.stiffness, breakaway=self.breakaway,
                          viscous=self.viscous)  # fmt: skip

    @classmethod
    def from_pi(cls, model: PIFriction, **rate: float) -> GMSFriction:
        """The GMS model of a finite-element `PIFriction` (symmetric) with the rate terms
        `rate` (``static_level``, ``stribeck_velocity``, ``stribeck_exponent``, ``lag_time``)."""
        if not isinstance(model, PIFriction):
            raise TypeError(f"`model` must be a PIFriction; got {type(model).__name__}.")
        if not model.is_discrete or not model.is_symmetric:
            raise ValueError(
                f"`model` must have finite elements and equal sides for a GMS model; got {model!r}."
            )
        k = np.empty(0) if model.stiffness is None else model.stiffness
        c = np.empty(0) if model.breakaway is None else model.breakaway
        return cls(model.coulomb, k, c, viscous=model.viscous, **rate)

    def _kernel_args(self) -> tuple[float, FloatArray, FloatArray, float, float, float, float,
                                    float]:  # fmt: skip
        vs = 1.0 if self.stribeck_velocity is None else float(self.stribeck_velocity)
        return (self.coulomb, self.stiffness, self.breakaway, self.static_ratio, vs,
                self.stribeck_exponent, self.lag_time, self.viscous)  # fmt: skip

    def __repr__(self) -> str:
        rate = ""
        if self.static_level != self.coulomb_level:
            rate += f", static_level={self.static_level!r}, stribeck_velocity="
            rate += f"{self.stribeck_velocity!r}"
            if self.stribeck_exponent != 2.0:
                rate += f", stribeck_exponent={self.stribeck_exponent!r}"
        rate += f", lag_time={self.lag_time!r}" if self.lag_time else ""
        rate += f", viscous={self.viscous!r}" if self.viscous else ""
        return (f"GMSFriction(coulomb={self.coulomb!r}, stiffness={self.stiffness.tolist()!r}, "
                f"breakaway={self.breakaway.tolist()!r}{rate})")  # fmt: skip

    # ------------------------------------------------------------------ curves
    def stribeck(self, velocity: ArrayLike) -> FloatArray:
        """s(v) = F_C + (F_S − F_C)·exp(−|v/v_s|^δ) [N], between F_C and F_S.

        Parameters
        ----------
        velocity : float or array_like
            v [m/s], finite.
        """
        v = np.abs(as_real_array("velocity", velocity))
        if self.stribeck_velocity is None:
            return np.full(v.shape, self.coulomb_level)
        with np.errstate(over="ignore"):  # |v| ≫ v_s: exp(−inf) = 0, the exact limit
            decay = np.exp(-((v / self.stribeck_velocity) ** self.stribeck_exponent))
        return self.coulomb_level + (self.static_ratio - 1.0) * self.coulomb_level * decay

    def steady_force(self, velocity: ArrayLike) -> FloatArray:
        """s(v)·sign(v) + σ·v: the force at steady sliding with velocity v (0 at v = 0) [N]."""
        v = as_real_array("velocity", velocity)
        return self.stribeck(v) * np.sign(v) + self.viscous * v

    # ------------------------------------------------------------------ states
    def relaxed_state(self, position: float = 0.0, time: float = 0.0) -> GMSState:
        """Rest at `position` [m] and `time` [s] with every element unloaded and sticking."""
        n = self.n_elements
        y0, t0 = as_real_scalar("position", position), as_real_scalar("time", time)
        return GMSState(y0, t0, np.zeros(n), np.zeros(n))

    def saturated_state(self, position: float = 0.0, time: float = 0.0,
                        direction: float = 1.0, velocity: float = 0.0) -> GMSState:  # fmt: skip
        """Steady sliding in `direction` at `velocity`: every element slipping at its slip
        force c_i·ŝ(|velocity|)."""
        y0, t0 = as_real_scalar("position", position), as_real_scalar("time", time)
        if direction not in (-1.0, 1.0):
            raise ValueError(f"`direction` must be −1 or +1; got {fmt(direction)}.")
        v = as_real_scalar("velocity", velocity)
        shat = float(self.stribeck(v)) / self.coulomb_level
        f = direction * self.breakaway * shat
        return GMSState(y0, t0, f, np.full(self.n_elements, float(direction)), v,
                        direction)  # fmt: skip

    def elastic_energy(self, state: GMSState) -> float:
        """Σ F_i²/(2 k_i): the energy the elements' springs store in `state` [J]."""
        f = self._check_state(state)
        return float(np.sum(f * f / (2.0 * self.stiffness)))

    def _check_state(self, state: GMSState) -> FloatArray:
        if not isinstance(state, GMSState):
            raise TypeError(f"`state` must be a GMSState or None; got {type(state).__name__}.")
        if state.forces.shape != self.stiffness.shape:
            raise ValueError(
                f"`state.forces` must have one entry per element ({self.n_elements}); got "
                f"{state.forces.shape[0]}."
            )
        limit = self.breakaway * self.static_ratio * (1.0 + 1e-12)
        bad = np.abs(state.forces) > limit
        if bad.any():
            i = int(np.argmax(bad))
            raise ValueError(
                f"`state.forces` must satisfy |F_i| <= c_i·F_S/F_C; got {fmt(state.forces[i])} "
                f"for element {i + 1} (limit {fmt(limit[i])})."
            )
        return state.forces

    # ------------------------------------------------------------------ the path
    def force(
        self, displacement: ArrayLike, time: ArrayLike, state: GMSState | None = None
    ) -> tuple[FloatArray, GMSState]:
        """GMS friction force along a displacement sampled at the given times.

        Parameters
        ----------
        displacement : array_like, shape (T,)
            Samples, linear in time between consecutive samples.
        time : array_like, shape (T,)
            Strictly increasing sample times [s]; after ``state.last_time``.
        state : GMSState, optional
            Memory before the first sample. Default: relaxed at rest at the first
            sample, which then has force 0.

        Returns
        -------
        force : ndarray, shape (T,)
            c1·ŝ(|v|)·sign + Σ F_i + σ·v with the velocity v of the interval ending at
            each sample (sign: of the last nonzero increment).
        final_state : GMSState
            Passing it on to the continuation of the path gives the same results as
            one call.
        """
        force, final, _ = self._run(displacement, time, state)
        return force, final

    def _run(self, displacement: ArrayLike, time: ArrayLike,
             state: GMSState | None) -> tuple[FloatArray, GMSState, FloatArray]:  # fmt: skip
        """Force, final state and the energy dissipated since the first sample."""
        y = as_signal("displacement", displacement)
        t = as_signal("time", time)
        check_same_length(displacement=y, time=t)
        if state is None:
            start, state = 1, self.relaxed_state(float(y[0]), float(t[0]))
            check_increasing("time", t)
        else:
            self._check_state(state)
            start = 0
            check_increasing("time", t, after=state.last_time)
        f = as_state_vector("state.forces", state.forces, self.n_elements).copy()
        e = np.array(state.slipping, dtype=float)
        out, dissipated = np.empty(y.shape[0]), np.empty(y.shape[0])
        v, d = _gk.gms_force(y, t, start, *self._kernel_args(), f, e, state.last_input,
                             state.last_time, state.velocity, state.direction, out,
                             dissipated)  # fmt: skip
        final = GMSState(float(y[-1]), float(t[-1]), f, e, float(v), float(d))
        return out, final, dissipated
