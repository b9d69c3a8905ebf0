"""The Iwan family of joint models as densities μ (eq. 10), with their closed forms.

An Iwan model (a parallel bank of Jenkins elements: spring and Coulomb slider)
is a Prandtl–Ishlinskii operator with a density: the slider of the element
with stiffness dμ(r) slips once its deformation reaches the threshold r. The
structural-dynamics literature writes the density φ(r) over slip displacements
r; here it is dμ/dr. Provided, each evaluated exactly by the compiled
primitives (kinds ``POWER`` and ``MINDLIN`` of `_density_primitives`):

* `SegalmanIwan`: Segalman's four-parameter model (K_T, F_S, χ, β),
  dμ/dr = R·r^χ on (0, φ_max] plus a point mass S at φ_max;
* `MindlinContact`: the Cattaneo–Mindlin sphere under constant normal load
  (Mindlin–Deresiewicz), virgin curve T(δ) = μP[1 − (1 − δ/δ0)^(3/2)];
* `MicroslipBar`: an elastic bar on a rigid-plastic (Coulomb) foundation pulled
  at one end, virgin curve u = F²/(2·EA·τ) up to gross slip at F = τ·L.

The optional Coulomb element is the ``coulomb`` of `PIFriction`
(``PIFriction(coulomb, density=SegalmanIwan(...))``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_nonnegative_scalar,
    as_positive_scalar,
    as_real_array,
    as_real_scalar,
    fmt,
)
from presliding.hysteresis._density_base import Density
from presliding.hysteresis._density_primitives import MINDLIN, POWER

__all__ = ["MicroslipBar", "MindlinContact", "SegalmanIwan"]

FloatArray = NDArray[np.float64]

#: |ln| of the largest and smallest numbers a density's parameters may reach (1e±300).
_LOG_RANGE = 300.0 * math.log(10.0)


def _amplitudes(name: str, value: ArrayLike, upper: float | None = None) -> Any:
    a = as_real_array(name, value)
    if (a < 0).any() or (upper is not None and (a > upper).any()):
        bad = a[(a < 0) | (a > (math.inf if upper is None else upper))]
        rule = "nonnegative" if upper is None else f"in [0, {fmt(upper)}]"
        raise ValueError(f"`{name}` must be {rule}; got {fmt(bad.flat[0])}.")
    return a


def _out(x: Any) -> Any:
    return float(x) if np.ndim(x) == 0 else x


@dataclass(frozen=True)
class SegalmanIwan(Density):
    """Segalman's four-parameter Iwan model (K_T, F_S, χ, β) as a density.

    dμ/dr = R·r^χ on (0, φ_max] plus a point mass S at φ_max, with
    (Segalman, J. Appl. Mech. 72, 752, 2005)::

        φ_max = F_S (1 + β) / (K_T (β + (χ+1)/(χ+2)))
        R     = F_S (χ+1) / (φ_max^(χ+2) (β + (χ+1)/(χ+2)))
        S     = F_S β / (φ_max (β + (χ+1)/(χ+2)))

    so that μ([0, φ_max]) = K_T and F_m = M1(φ_max) = F_S.

    Parameters
    ----------
    stiffness : float
        K_T > 0 [N/m], the joint stiffness at small loads (eq. 7).
    slip_force : float
        F_S > 0 [N], the force of macroslip (F_m, section 3).
    exponent : float
        χ > −1, the power of the slider distribution; the dissipation at small
        amplitudes grows as a^(χ+3) (Segalman: −1 < χ <= 0).
    mass_ratio : float
        β >= 0, the weight of the point mass S at φ_max relative to the power law.
    """

    stiffness: float
    slip_force: float
    exponent: float
    mass_ratio: float
    _kind: ClassVar[int] = POWER

    def __post_init__(self) -> None:
        k = as_positive_scalar("stiffness", self.stiffness)
        f = as_positive_scalar("slip_force", self.slip_force)
        chi = as_real_scalar("exponent", self.exponent)
        if not chi > -1.0:
            raise ValueError(f"`exponent` must be a finite number > -1; got {fmt(self.exponent)}.")
        beta = as_nonnegative_scalar("mass_ratio", self.mass_ratio)
        for name, val in (("stiffness", k), ("slip_force", f), ("exponent", chi)):
            object.__setattr__(self, name, val)
        object.__setattr__(self, "mass_ratio", beta)
        # R·r^χ and its moments up to φ_max^(χ+3) must be floating-point numbers
        log_phi = math.log(self.max_threshold)
        log_r = math.log(f * (chi + 1.0) / self._denominator) - (chi + 2.0) * log_phi
        worst = max(abs(log_r), abs((chi + 3.0) * log_phi))
        if not worst < _LOG_RANGE:
            raise ValueError(
                f"`exponent` must keep the density R·r^χ within floating point (R and "
                f"φ_max^(χ+3) between 1e-300 and 1e300); got {fmt(self.exponent)}, for which "
                f"R = 10^{log_r / math.log(10.0):.4g} and φ_max^(χ+3) = "
                f"10^{(chi + 3.0) * log_phi / math.log(10.0):.4g} (φ_max = "
                f"{self.max_threshold:.6g} m)."
            )
        par = np.array([self.max_threshold, self.height, chi])
        self._freeze(par, np.array([[self.point_mass]]))

    @property
    def _denominator(self) -> float:
        chi = self.exponent
        return self.mass_ratio + (chi + 1.0) / (chi + 2.0)

    @property
    def max_threshold(self) -> float:
        """φ_max [m], the slip displacement of the point mass (end of the support)."""
        return self.slip_force * (1.0 + self.mass_ratio) / (self.stiffness * self._denominator)

    @property
    def height(self) -> float:
        """R [N/m^(χ+2)], the coefficient of the power law R·r^χ."""
        phi = self.max_threshold
        chi = self.exponent
        return self.slip_force * (chi + 1.0) / (phi ** (chi + 2.0) * self._denominator)

    @property
    def point_mass(self) -> float:
        """S [N/m], the stiffness of the sliders that all slip at φ_max."""
        return self.slip_force * self.mass_ratio / (self.max_threshold * self._denominator)

    def loop_energy(self, amplitude: ArrayLike) -> Any:
        """Closed-form dissipation per cycle D(a) of the elastic part at amplitude a [m].

        D(a) = 4R·a^(χ+3)/((χ+2)(χ+3)) for a <= φ_max; above it every slider
        slips and D grows linearly: 4·(M1(φ_max)·a − M2(φ_max)) from the power
        law plus 4·S·φ_max·(a − φ_max) from the point mass.

        Parameters
        ----------
        amplitude : float or array_like
            Displacement amplitudes a >= 0 [m] (cycles between −a and +a).

        Returns
        -------
        float or ndarray
            D(a) [J].
        """
        a = _amplitudes("amplitude", amplitude)
        chi, rr, s, phi = self.exponent, self.height, self.point_mass, self.max_threshold
        small = 4.0 * rr * a ** (chi + 3.0) / ((chi + 2.0) * (chi + 3.0))
        m1 = rr * phi ** (chi + 2.0) / (chi + 2.0)
        m2 = rr * phi ** (chi + 3.0) / (chi + 3.0)
        large = 4.0 * (m1 * a - m2) + 4.0 * s * phi * (a - phi)
        return _out(np.where(a <= phi, small, large))


@dataclass(frozen=True)
class MindlinContact(Density):
    """The Cattaneo–Mindlin sphere in tangential loading (Mindlin–Deresiewicz).

    Virgin curve T(δ) = μP·[1 − (1 − δ/δ0)^(3/2)] for δ <= δ0 (full slip at
    δ0), i.e. dμ/dr = 3μP/(4δ0²)·(1 − r/δ0)^(−1/2) on [0, δ0): initial
    stiffness 3μP/(2δ0) (Mindlin's 8G*a), F_m = μP.

    Parameters
    ----------
    slip_force : float
        μP > 0 [N], the friction limit of the contact (friction coefficient
        times normal load).
    slip_displacement : float
        δ0 > 0 [m], the tangential displacement of full slip,
        δ0 = 3μP/(16 G* a) for a Hertz contact of radius a.
    """

    slip_force: float
    slip_displacement: float
    _kind: ClassVar[int] = MINDLIN

    def __post_init__(self) -> None:
        f = as_positive_scalar("slip_force", self.slip_force)
        d0 = as_positive_scalar("slip_displacement", self.slip_displacement)
        object.__setattr__(self, "slip_force", f)
        object.__setattr__(self, "slip_displacement", d0)
        self._freeze(np.array([d0, 0.75 * f / (d0 * d0)]), np.zeros((1, 1)))

    @property
    def max_threshold(self) -> float:
        """δ0 [m], the end of the support."""
        return self.slip_displacement

    def loop_energy_at_force(self, force_amplitude: ArrayLike) -> Any:
        """Mindlin–Deresiewicz loop energy W at tangential force amplitude T* [J].

        W = 4.8·μP·δ0·[1 − (1−q)^(5/3) − (5q/6)(1 + (1−q)^(2/3))], q = T*/μP
        (i.e. (9μ²P²/(10 a G*))·[...] with δ0 = 3μP/(16 G* a)). The bracket is
        evaluated in its exact factored form e³(5 − 5e + e²)/6 with
        e = 1 − (1−q)^(1/3) = q/(1 + p + p²), p = (1−q)^(1/3), free of the
        cancellation of the closed form at small q (where it equals its series
        5q³/162 + 5q⁴/243 + 7q⁵/486 + ...).
        """
        f = self.slip_force
        q = _amplitudes("force_amplitude", force_amplitude, f) / f
        return _out(4.8 * f * self.slip_displacement * mindlin_bracket(q))


def mindlin_bracket(q: Any) -> Any:
    """1 − (1−q)^(5/3) − (5q/6)(1 + (1−q)^(2/3)) without cancellation (q in [0, 1])."""
    p = np.cbrt(1.0 - q)
    e = q / (1.0 + p + p * p)
    return e**3 * (5.0 - 5.0 * e + e * e) / 6.0


@dataclass(frozen=True)
class MicroslipBar(Density):
    """An elastic bar on a Coulomb foundation pulled at one end (microslip).

    A slip zone of length F/τ grows from the loaded end while the rest sticks,
    so the virgin curve is u = F²/(2·EA·τ) up to gross slip at F = τ·L,
    u = τL²/(2EA). As a density: dμ/dr = √(EAτ/8)·r^(−3/2) on (0, R] plus a
    point mass EA/L at R = τL²/(2EA). The stuck part does not move, so the
    bar is infinitely stiff at every reversal (μ([0, R]) = inf): the
    dissipation and the branches are exact, the initial slope is not finite,
    and `simulate` and `turning_points` refuse it (a motion would need a
    finite stiffness; model the bar as a `SliderNetwork` chain instead).

    Parameters
    ----------
    axial_stiffness : float
        EA > 0 [N], Young's modulus times cross-section.
    shear_strength : float
        τ > 0 [N/m], the friction force per unit length of the foundation.
    length : float
        L > 0 [m], the bar length (gross slip at F = τ·L).
    """

    axial_stiffness: float
    shear_strength: float
    length: float
    _kind: ClassVar[int] = POWER

    def __post_init__(self) -> None:
        ea = as_positive_scalar("axial_stiffness", self.axial_stiffness)
        tau = as_positive_scalar("shear_strength", self.shear_strength)
        length = as_positive_scalar("length", self.length)
        for name, val in (("axial_stiffness", ea), ("shear_strength", tau), ("length", length)):
            object.__setattr__(self, name, val)
        par = np.array([self.max_threshold, math.sqrt(ea * tau / 8.0), -1.5])
        self._freeze(par, np.array([[ea / length]]))

    @property
    def max_threshold(self) -> float:
        """R = τL²/(2EA) [m], the end displacement at gross slip."""
        return self.shear_strength * self.length**2 / (2.0 * self.axial_stiffness)

    def _check_totals(self) -> None:
        """F_m = τL and ½M2(R) finite; μ([0, R]) is infinite by construction."""
        from presliding._validation import check_finite_derived

        names = ("axial_stiffness", "shear_strength", "length")
        check_finite_derived("gross-slip force τ·L", self.M1(self.max_threshold), names)
        check_finite_derived("largest stored energy", 0.5 * self.M2(self.max_threshold), names)

    def loop_energy_at_force(self, force_amplitude: ArrayLike) -> Any:
        """Dissipation per cycle D = 2F³/(3·EA·τ) at force amplitude F <= τL [J].

        The cycle is F between −F and +F (amplitude, not peak-to-peak).
        """
        tl = self.shear_strength * self.length
        f = _amplitudes("force_amplitude", force_amplitude, tl)
        return _out(2.0 * f**3 / (3.0 * self.axial_stiffness * self.shear_strength))
