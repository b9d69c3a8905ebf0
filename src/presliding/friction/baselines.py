"""Classical friction models to compare the PI model with: Coulomb, Dahl, LuGre.

Each model has the interface of `PIFriction`: validated frozen parameters and
``force(displacement, state=None) -> (force, final_state)`` along a sampled
displacement path, with explicit state so that chunked and whole runs agree bit
for bit. LuGre is rate dependent and needs the sample times as well:
``force(displacement, time, state=None)``.

References
----------
- Coulomb, C. A. (1785), eq. 2 of the paper: F = F_c·sign(ẏ).
- Dahl, P. R. (1968), *A solid friction model*, TOR-158(3107-18), The Aerospace
  Corporation (ref. [5] of the paper).
- Canudas de Wit, C., Olsson, H., Åström, K. J., Lischinsky, P. (1995), *A new
  model for control of systems with friction*, IEEE Trans. Automatic Control
  40(3), 419–425 (ref. [8]).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_nonnegative_scalar,
    as_positive_scalar,
    as_real_array,
    as_real_scalar,
    as_signal,
    check_increasing,
    check_same_length,
    fmt,
    renamed,
)
from presliding.friction import _baseline_kernels as _bk
from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis.operators import PIState

if TYPE_CHECKING:  # pragma: no cover
    pass

__all__ = [
    "CoulombFriction",
    "DahlFriction",
    "DahlState",
    "LuGreFriction",
    "LuGreState",
]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class CoulombFriction:
    """Classical Coulomb friction F = F_c·sign(ẏ) (eq. 2), set-valued at rest.

    At zero velocity the force is any value in [−F_c, F_c]; along a displacement
    path it is F_c times the sign of the last nonzero increment (0 before any
    motion). It is `PIFriction` with no elastic elements (`as_pi_friction`), the
    limit of eq. 8 with infinitely stiff elements, so its state is a `PIState`
    with an empty play vector and any code that takes a PIFriction takes it.

    Parameters
    ----------
    coulomb : float
        Coulomb friction level F_c > 0 [N].
    """

    coulomb: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "coulomb", as_positive_scalar("coulomb", self.coulomb))

    @property
    def as_pi_friction(self) -> PIFriction:
        """The same model as a PIFriction (c1 = F_c, no elements)."""
        return PIFriction(coulomb=self.coulomb)

    def force(
        self, displacement: ArrayLike, state: PIState | None = None
    ) -> tuple[FloatArray, PIState]:
        """F_c·sign(last increment) along a displacement; state as for `PIFriction.force`."""
        force, final = self.as_pi_friction.force(displacement, state)
        assert isinstance(final, PIState)  # a model without a density
        return force, final


@dataclass(frozen=True)
class DahlState:
    """Memory of the Dahl model: the last displacement and the friction force there."""

    last_input: float
    force: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "last_input", as_real_scalar("last_input", self.last_input))
        object.__setattr__(self, "force", as_real_scalar("force", self.force))


@dataclass(frozen=True)
class DahlFriction:
    """Dahl's rate-independent friction model (Dahl 1968).

    dF/dy = σ0·(1 − F/F_c·sign(ẏ))^α,    |F| <= F_c,

    a first-order hysteresis whose force follows, from rest at F = 0 with α = 1,
    the virgin curve F = F_c·(1 − exp(−σ0·y/F_c)). The stiffness is σ0 at F = 0
    and σ0·2^α right after a reversal from full sliding (F = ±F_c). Unlike the PI
    model there is no memory of older reversals (no wiping-out), and F approaches
    F_c only asymptotically for α >= 1.

    The force is integrated in closed form between samples (the displacement
    is taken monotone between consecutive samples), so it is exact for any step.

    Parameters
    ----------
    coulomb : float
        F_c > 0 [N], the friction level at steady sliding.
    stiffness : float
        σ0 > 0 [N/m], the rest stiffness dF/dy at F = 0.
    exponent : float, default 1.0
        α > 0, the shape of the curve (Dahl used α = 1 for ductile, α >= 1 in general).
    viscous : float, keyword only
        σ >= 0 [N·s/m], a viscous term σ·ẏ (default 0, Dahl's model). As for `PIFriction`,
        `force` along a displacement path leaves it out; `presliding.simulate` includes it.
    """

    coulomb: float
    stiffness: float
    exponent: float = 1.0
    viscous: float = field(default=0.0, kw_only=True)

    def __post_init__(self) -> None:
        object.__setattr__(self, "coulomb", as_positive_scalar("coulomb", self.coulomb))
        object.__setattr__(self, "stiffness", as_positive_scalar("stiffness", self.stiffness))
        object.__setattr__(self, "exponent", as_positive_scalar("exponent", self.exponent))
        object.__setattr__(self, "viscous", as_nonnegative_scalar("viscous", self.viscous))

    def relaxed_state(self, position: float = 0.0) -> DahlState:
        """Rest at `position` with zero force."""
        with renamed(last_input="position"):
            return DahlState(position, 0.0)

    def force(
        self, displacement: ArrayLike, state: DahlState | None = None
    ) -> tuple[FloatArray, DahlState]:
        """Dahl friction force along a sampled displacement.

        Parameters
        ----------
        displacement : array_like, shape (T,)
            Samples, monotone between consecutive samples.
        state : DahlState, optional
            Memory before the first sample (|force| <= F_c); default zero force
            at ``displacement[0]``.

        Returns
        -------
        force : ndarray, shape (T,)
        final_state : DahlState
        """
        y = as_signal("displacement", displacement)
        if state is None:
            state = DahlState(float(y[0]), 0.0)
        elif not isinstance(state, DahlState):
            raise TypeError(f"`state` must be a DahlState or None; got {type(state).__name__}.")
        if abs(state.force) > self.coulomb:
            raise ValueError(
                f"`state.force` must satisfy |force| <= coulomb {fmt(self.coulomb)}; "
                f"got {fmt(state.force)}."
            )
        out = np.empty(y.shape[0])
        f = _bk.dahl_force(
            y, self.coulomb, self.stiffness, self.exponent, state.last_input, state.force, out
        )
        return out, DahlState(float(y[-1]), float(f))


@dataclass(frozen=True)
class LuGreState:
    """Memory of the LuGre model after a sample.

    Parameters
    ----------
    last_input, last_time : float
        The last displacement y and its time t.
    bristle : float
        Mean bristle deflection z [m], |z| <= F_s/σ0.
    velocity : float
        Velocity of the interval that ended at the last sample [m/s].
    """

    last_input: float
    last_time: float
    bristle: float = 0.0
    velocity: float = 0.0

    def __post_init__(self) -> None:
        for name in ("last_input", "last_time", "bristle", "velocity"):
            object.__setattr__(self, name, as_real_scalar(name, getattr(self, name)))


@dataclass(frozen=True)
class LuGreFriction:
    """The LuGre dynamic friction model (Canudas de Wit et al. 1995).

    dz/dt = v − σ0·|v|·z/g(v),   g(v) = F_c + (F_s − F_c)·exp(−(v/v_s)²),
    F = σ0·z + σ1·dz/dt + σ2·v,

    with the mean bristle deflection z, velocity v = ẏ. At constant velocity the
    force tends to F_ss(v) = g(v)·sign(v) + σ2·v (the Stribeck curve with viscous
    friction). From rest at z = 0 the presliding stiffness dF/dy is σ0 (slow
    motion); right after a reversal from steady sliding at v1 it is
    σ0·(1 + g(v1)/g(v)), about 2σ0, since the bristles unload from z = g(v1)/σ0.

    The path interface is ``force(displacement, time, state=None)``: the
    displacement is taken linear in time between samples, so the velocity is
    constant on each interval and the bristle equation is integrated exactly.
    The force at a sample uses the velocity of the interval ending there.

    Parameters
    ----------
    coulomb : float
        F_c > 0 [N].
    static : float
        F_s >= F_c [N], the static (breakaway) level of the Stribeck curve.
    stiffness : float
        σ0 > 0 [N/m], bristle stiffness.
    damping : float
        σ1 >= 0 [N·s/m], bristle (micro-)damping.
    viscous : float
        σ2 >= 0 [N·s/m], viscous friction.
    stribeck_velocity : float
        v_s > 0 [m/s].
    """

    coulomb: float
    static: float
    stiffness: float
    damping: float
    viscous: float
    stribeck_velocity: float

    def __post_init__(self) -> None:
        fc = as_positive_scalar("coulomb", self.coulomb)
        fs = as_positive_scalar("static", self.static)
        if fs < fc:
            raise ValueError(f"`static` must be >= `coulomb` {fmt(fc)}; got {fmt(fs)}.")
        object.__setattr__(self, "coulomb", fc)
        object.__setattr__(self, "static", fs)
        object.__setattr__(self, "stiffness", as_positive_scalar("stiffness", self.stiffness))
        object.__setattr__(self, "damping", as_nonnegative_scalar("damping", self.damping))
        object.__setattr__(self, "viscous", as_nonnegative_scalar("viscous", self.viscous))
        vs = as_positive_scalar("stribeck_velocity", self.stribeck_velocity)
        object.__setattr__(self, "stribeck_velocity", vs)

    def stribeck(self, velocity: ArrayLike) -> FloatArray:
        """g(v) = F_c + (F_s − F_c)·exp(−(v/v_s)²).

        Parameters
        ----------
        velocity : float or array_like
            v [m/s], finite.

        Returns
        -------
        ndarray
            g(v) [N], same shape as `velocity`, between F_c and F_s.
        """
        v = as_real_array("velocity", velocity)
        with np.errstate(over="ignore"):  # |v| ≫ v_s: exp(−inf) = 0, the exact limit
            decay = np.exp(-((v / self.stribeck_velocity) ** 2))
        return self.coulomb + (self.static - self.coulomb) * decay

    def steady_state_force(self, velocity: ArrayLike) -> FloatArray:
        """F_ss(v) = g(v)·sign(v) + σ2·v, the force at constant velocity v.

        Parameters
        ----------
        velocity : float or array_like
            v [m/s], finite.

        Returns
        -------
        ndarray
            F_ss(v) [N], same shape as `velocity` (0 at v = 0).
        """
        v = as_real_array("velocity", velocity)
        return self.stribeck(v) * np.sign(v) + self.viscous * v

    def relaxed_state(self, position: float = 0.0, time: float = 0.0) -> LuGreState:
        """Rest at `position` and `time` with undeflected bristles."""
        with renamed(last_input="position", last_time="time"):
            return LuGreState(position, time, 0.0, 0.0)

    def force(
        self, displacement: ArrayLike, time: ArrayLike, state: LuGreState | None = None
    ) -> tuple[FloatArray, LuGreState]:
        """LuGre friction force along a displacement sampled at the given times.

        Parameters
        ----------
        displacement : array_like, shape (T,)
            Samples, linear in time between consecutive samples.
        time : array_like, shape (T,)
            Strictly increasing sample times [s]; after ``state.last_time``.
        state : LuGreState, optional
            Memory before the first sample. Default: at rest at the first
            sample (z = 0, v = 0), which then has force 0.

        Returns
        -------
        force : ndarray, shape (T,)
        final_state : LuGreState
        """
        y = as_signal("displacement", displacement)
        t = as_signal("time", time)
        check_same_length(displacement=y, time=t)
        if state is None:
            start, state = 1, LuGreState(float(y[0]), float(t[0]))
            check_increasing("time", t)
        elif not isinstance(state, LuGreState):
            raise TypeError(f"`state` must be a LuGreState or None; got {type(state).__name__}.")
        else:
            start = 0
            check_increasing("time", t, after=state.last_time)
        zmax = self.static / self.stiffness
        if abs(state.bristle) > zmax * (1 + 1e-12):
            raise ValueError(
                f"`state.bristle` must satisfy |z| <= static/stiffness {fmt(zmax)}; "
                f"got {fmt(state.bristle)}."
            )
        out = np.empty(y.shape[0])
        z, v = _bk.lugre_force(
            y, t, start, self.stiffness, self.damping, self.viscous, self.coulomb,
            self.static, self.stribeck_velocity, state.last_input, state.last_time,
            state.bristle, state.velocity, out,
        )  # fmt: skip
        return out, LuGreState(float(y[-1]), float(t[-1]), float(z), float(v))
