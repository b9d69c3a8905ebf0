"""`PeriodicOrbit` and `FrequencyResponse`: periodic responses of a jointed structure."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from presliding._display import fill_attrs
from presliding._validation import as_choice
from presliding.hysteresis._results import ResultMixin

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["FrequencyResponse", "PeriodicOrbit"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False, repr=False)
class PeriodicOrbit(ResultMixin):
    """One periodic orbit under harmonic forcing, by shooting on the exact event solver.

    Attributes
    ----------
    time : ndarray, shape (T,)
        Samples of one period [0, 2π/Ω] [s].
    position, velocity : ndarray, shape (T, n)
        q [m], q̇ [m/s] along the orbit.
    frequency : float
        Ω [rad/s]; the force is Re(F̂·e^{iΩt}).
    initial_state : ndarray, shape (2n + n_e,)
        (q, q̇, x) at t = 0: positions, velocities and the stops' plastic parts [m, m/s, m].
    amplitude : ndarray, shape (n,)
        (max q_i − min q_i)/2 [m], the extremes found to rounding.
    harmonics : ndarray, shape (H + 1, n), complex
        Exact Fourier coefficients Q_h: q(t) = Re(Σ_h Q_h·e^{ihΩt}) [m] (Q_0 the mean).
    multipliers : ndarray, complex
        Floquet multipliers (eigenvalues of the exact monodromy matrix; the plastic parts
        of stops that do not slide along the orbit are held and left out).
    stable : bool
        Every multiplier inside the unit circle (to 1e-9).
    residual : float
        max |Z(T) − Z(0)| over the state [m, m/s].
    iterations : int
        Newton iterations.
    status : str
        'success', or 'not_converged' (Newton did not reach the tolerance).
    message : str
    """

    time: FloatArray
    position: FloatArray
    velocity: FloatArray
    frequency: float
    initial_state: FloatArray
    amplitude: FloatArray
    harmonics: NDArray[np.complex128]
    multipliers: NDArray[np.complex128]
    stable: bool
    residual: float
    iterations: int
    status: str = "success"
    message: str = ""

    @property
    def success(self) -> bool:
        """True when the orbit is periodic to the tolerance."""
        return self.status == "success"

    @property
    def period(self) -> float:
        """2π/Ω [s]."""
        return float(2.0 * np.pi / self.frequency)

    def __repr__(self) -> str:
        return (
            f"PeriodicOrbit(Ω={self.frequency:.6g} rad/s, amplitude={np.round(self.amplitude, 6)}"
            f" m, stable={self.stable}, residual={self.residual:.2g}, status={self.status!r})"
        )

    def report(self) -> str:
        """The orbit's amplitudes, first harmonics, multipliers and residual."""
        mult = np.abs(self.multipliers)
        lines = [repr(self), self.message,
                 f"largest |Floquet multiplier| {mult.max(initial=0.0):.6g}",
                 "coordinate  amplitude [m]   |Q1| [m]    mean [m]"]  # fmt: skip
        for i in range(self.amplitude.shape[0]):
            lines.append(
                f"{i:10d} {self.amplitude[i]:14.8g} {abs(self.harmonics[1, i]):10.6g} "
                f"{self.harmonics[0, i].real:11.4g}"
            )
        return "\n".join(lines)

    def plot(self, ax: Axes | None = None) -> Axes:
        """q(t) over one period, one line per coordinate."""
        from presliding.structural.motion import plot_positions

        return plot_positions(ax, self.time, self.position)


@dataclass(frozen=True, eq=False, repr=False)
class FrequencyResponse(ResultMixin):
    """A curve of periodic orbits: their amplitudes against the forcing frequency (or scale).

    Attributes
    ----------
    frequency : ndarray, shape (m,)
        Ω of every orbit [rad/s].
    scale : ndarray, shape (m,)
        The force's scale s of every orbit (the force is s·Re(F̂·e^{iΩt})).
    amplitude : ndarray, shape (m, n)
        (max q_i − min q_i)/2 of every coordinate [m].
    first_harmonic : ndarray, shape (m, n)
        |Q_1|, the exact amplitude of the fundamental harmonic [m].
    stable : ndarray of bool, shape (m,)
        Every Floquet multiplier inside the unit circle.
    max_multiplier : ndarray, shape (m,)
        The largest |Floquet multiplier|.
    residual : ndarray, shape (m,)
        max |Z(T) − Z(0)| of every orbit.
    n_events : ndarray of int, shape (m,)
        Events per period (stops starting or stopping to slide).
    initial_state : ndarray, shape (m, 2n + n_e)
        (q, q̇, x) at t = 0 of every orbit.
    parameter : str
        'frequency' or 'scale': the continuation parameter.
    status : str
        'success' (the range covered), 'point_limit' (max_points reached), 'step_too_small'
        (the continuation's step fell below its minimum), or 'no_start' (no first orbit).
    message : str
    """

    frequency: FloatArray
    scale: FloatArray
    amplitude: FloatArray
    first_harmonic: FloatArray
    stable: NDArray[np.bool_]
    max_multiplier: FloatArray
    residual: FloatArray
    n_events: NDArray[np.int64]
    initial_state: FloatArray
    parameter: str = "frequency"
    status: str = "success"
    message: str = ""
    _rows: ClassVar[str] = "frequency"
    _rows_are_index: ClassVar[bool] = False

    @property
    def success(self) -> bool:
        """True when the curve covers the requested range."""
        return self.status == "success"

    def __repr__(self) -> str:
        return (
            f"FrequencyResponse(parameter={self.parameter!r}, points={self.frequency.shape[0]}, "
            f"status={self.status!r})"
        )

    def report(self) -> str:
        """The peak of every coordinate's amplitude and (up to 15) points of the curve."""
        lines = [repr(self), self.message]
        for i in range(self.amplitude.shape[1]):
            k = int(np.argmax(self.amplitude[:, i]))
            lines.append(f"q{i}: peak amplitude {self.amplitude[k, i]:.8g} m at Ω = "
                         f"{self.frequency[k]:.8g} rad/s, s = {self.scale[k]:.6g}")  # fmt: skip
        lines.append(f"{'Omega [rad/s]':>14} {'scale':>9} {'max amplitude [m]':>18} "
                     f"{'stable':>7} {'residual':>10}")  # fmt: skip
        m = self.frequency.shape[0]
        for k in np.unique(np.linspace(0, m - 1, min(m, 15)).astype(int)):
            lines.append(
                f"{self.frequency[k]:14.7g} {self.scale[k]:9.4g} "
                f"{self.amplitude[k].max():18.8g} {bool(self.stable[k])!s:>7} "
                f"{self.residual[k]:10.2g}"
            )
        return "\n".join(lines)

    def to_pandas(self) -> Any:
        """One row per orbit: frequency, scale, amplitude_i, first_harmonic_i, stable, ..."""
        import pandas as pd

        cols: dict[str, Any] = {"frequency": self.frequency, "scale": self.scale}
        for i in range(self.amplitude.shape[1]):
            cols[f"amplitude_{i}"] = self.amplitude[:, i]
            cols[f"first_harmonic_{i}"] = self.first_harmonic[:, i]
        cols.update(stable=self.stable, max_multiplier=self.max_multiplier,
                    residual=self.residual, n_events=self.n_events)  # fmt: skip
        units = {"frequency": "rad/s"} | {f"{k}_{i}": "m" for k in ("amplitude", "first_harmonic")
                                          for i in range(self.amplitude.shape[1])}  # fmt: skip
        return fill_attrs(pd.DataFrame(cols), self, units=units)

    def plot(self, ax: Axes | None = None, *, coordinate: int | None = None,
             against: str | None = None) -> Axes:  # fmt: skip
        """Amplitude against Ω (or the scale): stable orbits solid, unstable dashed.

        Parameters
        ----------
        ax : matplotlib Axes, optional
        coordinate : int, optional
            One coordinate (default: every coordinate).
        against : {'frequency', 'scale'}, optional
            The horizontal axis; default the continuation parameter.
        """
        from presliding.plotting import new_axes, place_legend

        against = self.parameter if against is None else against
        as_choice("against", against, ("frequency", "scale"))
        ax = new_axes(ax)
        x = self.frequency if against == "frequency" else self.scale
        coords = range(self.amplitude.shape[1]) if coordinate is None else [int(coordinate)]
        for i in coords:
            y = self.amplitude[:, i]
            line = ax.plot(x, np.where(self.stable, y, np.nan), label=f"q{i}")[0]
            if not self.stable.all():
                ax.plot(x, np.where(self.stable, np.nan, y), "--", color=line.get_color())
        ax.set_xlabel("forcing frequency Ω [rad/s]" if against == "frequency"
                      else "force scale s [-]")  # fmt: skip
        ax.set_ylabel("amplitude (max − min)/2 [m]")
        place_legend(ax)
        return ax
