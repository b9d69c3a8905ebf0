"""Amplitude-dependent quantities of a joint: dissipation, secant stiffness, damping.

For a symmetric cycle between −a and +a of any PI model (finite elements,
a density, an Iwan model, a compiled network), the Masing loop gives in
closed form from the primitives of μ (eq. 10)::

    backbone       F(a) = c1 + M1(a) + a·T(a)              (the virgin curve, eq. 10)
    dissipation    D(a) = 4·c1·a + 4·(a·M1(a) − M2(a))      (each stop r < a: 4·k·r·(a − r))
    secant         k_eff(a) = F(a)/a
    damping ratio  ζ(a) = D/(4π·E),  E = ½·k_eff·a² = ½·F·a
    loss factor    η(a) = D/(π·k_eff·a²) = 2ζ

and their log-log slopes from dD/da = 4·(c1 + M1(a)) and dF/da = T(a). The
viscous term σ·ẏ of a model is rate dependent and not part of these
quantities (they are those of the rate-independent friction force).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import as_parameter_vector, check_type, fmt
from presliding.friction import PIFriction
from presliding.hysteresis import Density
from presliding.hysteresis._results import ResultMixin

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["AmplitudeResponse", "amplitude_response"]

FloatArray = NDArray[np.float64]

_QUANTITIES = {
    "dissipation": ("dissipation", "dissipation per cycle D [J]"),
    "force": ("force", "backbone force F [N]"),
    "stiffness": ("secant_stiffness", "secant stiffness k_eff [N/m]"),
    "damping": ("damping_ratio", "equivalent damping ratio ζ [-]"),
    "loss": ("loss_factor", "loss factor η [-]"),
}


@dataclass(frozen=True, eq=False)
class AmplitudeResponse(ResultMixin):
    """Amplitude-dependent dissipation, stiffness and damping of a PI model.

    Attributes
    ----------
    amplitude : ndarray, shape (n,)
        Displacement amplitudes a > 0 [m] (cycles between −a and +a).
    force : ndarray, shape (n,)
        The backbone F(a) = c1 + M1(a) + a·T(a) [N]: the force amplitude.
    dissipation : ndarray, shape (n,)
        D(a), the energy dissipated per cycle [J].
    secant_stiffness : ndarray, shape (n,)
        k_eff(a) = F(a)/a [N/m].
    damping_ratio : ndarray, shape (n,)
        ζ(a) = D/(2π·F·a) [-], the equivalent viscous damping ratio.
    loss_factor : ndarray, shape (n,)
        η(a) = D/(π·F·a) = 2ζ [-].
    dissipation_slope, force_slope, stiffness_slope, damping_slope : ndarray, shape (n,)
        The log-log slopes d ln D/d ln a, d ln F/d ln a, d ln k_eff/d ln a
        (= force_slope − 1) and d ln ζ/d ln a (= d ln η/d ln a). Where D(a) = 0
        (below the smallest threshold without a Coulomb element) the slopes of
        D and ζ are undefined and NaN; the message says so.
    model : PIFriction
        The model (a density is given the Coulomb element c1 = 0).
    status : str
        'success' (every quantity defined) or 'no_dissipation' (D = 0 at some
        amplitudes: no stop slides there, and the slopes of D and ζ are NaN).
    message : str
    """

    amplitude: FloatArray
    force: FloatArray
    dissipation: FloatArray
    secant_stiffness: FloatArray
    damping_ratio: FloatArray
    loss_factor: FloatArray
    dissipation_slope: FloatArray
    force_slope: FloatArray
    stiffness_slope: FloatArray
    damping_slope: FloatArray
    model: PIFriction = field(repr=False)
    status: str = "success"
    message: str = ""
    _rows: ClassVar[str] = "amplitude"

    @property
    def success(self) -> bool:
        """True: the quantities are exact (a 'no_dissipation' result is exact too)."""
        return self.status in ("success", "no_dissipation")

    def __repr__(self) -> str:
        a = self.amplitude
        return (
            f"AmplitudeResponse(n={a.shape[0]}, amplitude=[{a[0]:.4g}, {a[-1]:.4g}] m, "
            f"status={self.status!r})"
        )

    def report(self) -> str:
        """A readable table of the quantities at (up to 12 of) the amplitudes."""
        lines = [f"amplitude response of {self.model!r}: {self.status}", self.message]
        lines.append(
            f"{'a [m]':>12} {'F [N]':>12} {'D [J]':>12} {'k_eff [N/m]':>12} "
            f"{'zeta [-]':>10} {'slope D':>8}"
        )
        n = self.amplitude.shape[0]
        for i in np.unique(np.linspace(0, n - 1, min(n, 12)).astype(int)):
            lines.append(
                f"{self.amplitude[i]:12.5g} {self.force[i]:12.5g} {self.dissipation[i]:12.5g} "
                f"{self.secant_stiffness[i]:12.5g} {self.damping_ratio[i]:10.4g} "
                f"{self.dissipation_slope[i]:8.4g}"
            )
        return "\n".join(lines)

    def plot(self, ax: Axes | None = None, *, quantity: str = "dissipation") -> Axes:
        """Log-log plot of one quantity against the amplitude, with its units.

        Parameters
        ----------
        ax : matplotlib Axes, optional
        quantity : {'dissipation', 'force', 'stiffness', 'damping', 'loss'}
        """
        from presliding.plotting import new_axes

        if quantity not in _QUANTITIES:
            raise ValueError(
                f"`quantity` must be one of {sorted(_QUANTITIES)}; got {fmt(quantity)}."
            )
        name, label = _QUANTITIES[quantity]
        ax = new_axes(ax)
        y = getattr(self, name)
        keep = y > 0
        ax.loglog(self.amplitude[keep], y[keep], label=label.split(" [")[0])
        ax.set_xlabel("displacement amplitude a [m]")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
        return ax


def amplitude_response(model: PIFriction | Density, amplitudes: ArrayLike) -> AmplitudeResponse:
    """Dissipation per cycle, secant stiffness, damping and the backbone at amplitudes a.

    Exact for every model: finite elements (eq. 8), any density μ (eq. 10),
    the Iwan family (`SegalmanIwan`, `MindlinContact`, `MicroslipBar`) and a
    compiled network, from the closed forms in the module notes (Masing loops
    of a PI operator). Vectorised over the amplitudes.

    Parameters
    ----------
    model : PIFriction or Density
        The model; a density stands for ``PIFriction(0.0, density=...)``.
    amplitudes : float or array_like, shape (n,)
        Displacement amplitudes a > 0 [m].

    Returns
    -------
    AmplitudeResponse

    Examples
    --------
    Segalman's Iwan model dissipates D ∝ a^(χ+3) at small amplitudes:

    >>> from presliding import SegalmanIwan
    >>> res = amplitude_response(SegalmanIwan(2.0, 3.0, -0.1, 0.1), [1e-3, 1e-2])
    >>> [round(float(s), 12) for s in res.dissipation_slope]
    [2.9, 2.9]
    """
    check_type("model", model, (PIFriction, Density))
    if isinstance(model, Density):
        model = PIFriction(0.0, density=model)
    a = np.array(as_parameter_vector("amplitudes", amplitudes), dtype=np.float64)
    density = model.density
    assert density is not None
    c1 = model.coulomb
    big_r = density.max_threshold
    m1 = np.asarray(density.M1(a), dtype=np.float64)
    m2 = np.asarray(density.M2(a), dtype=np.float64)
    tail = np.where(a < big_r, np.asarray(density.tail(a), dtype=np.float64), 0.0)
    force = c1 + m1 + a * tail
    dissipation = 4.0 * c1 * a + 4.0 * np.maximum(a * m1 - m2, 0.0)
    if not np.all(np.isfinite(force) & np.isfinite(dissipation)):
        raise ValueError(
            f"`amplitudes` give forces or energies beyond the floating-point range; got {fmt(a)}."
        )
    secant = force / a
    with np.errstate(divide="ignore", invalid="ignore"):
        zeta = np.where(force > 0, dissipation / (2.0 * math.pi * force * a), 0.0)
        force_slope = np.where(force > 0, a * tail / force, 1.0)
        positive = np.where(dissipation > 0, dissipation, 1.0)
        dissipation_slope = np.where(dissipation > 0, 4.0 * a * (c1 + m1) / positive, np.nan)
    damping_slope = dissipation_slope - force_slope - 1.0
    none = dissipation == 0
    status, message = "success", "every stop is cycled exactly (Masing loops)."
    if none.any():
        status = "no_dissipation"
        message = (
            f"D(a) = 0 at {int(none.sum())} amplitude(s) up to {fmt(float(a[none].max()))} m: no "
            f"stop slides there, so the slopes of D and ζ are undefined (NaN)."
        )
    return AmplitudeResponse(
        amplitude=a,
        force=force,
        dissipation=dissipation,
        secant_stiffness=secant,
        damping_ratio=zeta,
        loss_factor=2.0 * zeta,
        dissipation_slope=dissipation_slope,
        force_slope=force_slope,
        stiffness_slope=force_slope - 1.0,
        damping_slope=damping_slope,
        model=model,
        status=status,
        message=message,
    )
