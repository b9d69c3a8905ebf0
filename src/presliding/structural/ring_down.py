"""`analyze_ring_down`, `RingDown`: amplitude-dependent frequency and damping of a free decay.

The signal (a measured or simulated ring-down: displacement, velocity or acceleration on
a uniform time base) is tapered to zero over its first and last three periods, padded
with zeros and band-passed around the mode (zero-phase second-order Butterworth, default
0.5–1.5 times the spectrum's peak); either its analytic signal (scipy.signal.hilbert) or
its extremes (peak tracking) give ln A(t) and the phase θ(t). Over windows of a few
periods (half overlapping) a parabola through ln A and a line through θ give
σ = −d ln A/dt and ω_d = dθ/dt at the window's centre: ω = √(σ² + ω_d²), ζ = σ/ω, A a
displacement amplitude (divided by the filter's gain at ω_d; a velocity's divided by ω,
an acceleration's by ω²). The ends are trimmed (`trim`, default eight periods: the
taper's, the filter's and the transform's edge effects) and so is the tail below `floor`
times the largest amplitude (the decay's end, or a rest); the message says how much.

The stated error of each estimate combines the standard error of its fit, the window's
resolution (half the change of the estimate between the neighbouring windows: the window
averages over the amplitudes it spans), an allowance for the slow-decay (averaging)
view of a nonlinear decay, second order in the decay per cycle: ζ·(πζ)² for ζ and
ω·ζ² for ω, and the estimators' own bias on linear decays after the default trim (the
taper, the band-pass and the transform), measured over phases, 24 to 200 samples per
period and ζ from 1e-3 to 0.05 (tests/structural): peaks 1e-3 of ζ and 3e-5 of ω; the
analytic signal, whose leakage grows with the decay, max(3.5e-3, 50ζ²) of ζ and
max(1.2e-5, 1.5ζ²) of ω; and 1e-6 where ζ is about 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from presliding._validation import (
    as_choice,
    as_count,
    as_positive_scalar,
    as_real_array,
    as_signal,
    check_type,
    fmt,
)
from presliding.hysteresis._results import ResultMixin
from presliding.measurement import Measurement
from presliding.structural import _ring_down_estimators as est
from presliding.structural.motion import StructureMotion

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from presliding.structural.backbone import ModalBackbone

__all__ = ["RingDown", "analyze_ring_down"]

FloatArray = NDArray[np.float64]
SIGNALS = ("position", "velocity", "acceleration")

#: The estimators' relative bias on linear decays after the default trim (module notes).
BIAS = {"peaks": (1e-3, 0.0, 3e-5, 0.0), "hilbert": (3.5e-3, 50.0, 1.2e-5, 1.5)}


def _bias(method: str, zeta: FloatArray, w: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The stated bias of ζ and ω (absolute) of a method at these estimates."""
    z0, z2, w0, w2 = BIAS[method]
    z = np.abs(zeta)
    return np.maximum(np.maximum(z0, z2 * z * z) * z, 1e-6), np.maximum(w0, w2 * z * z) * w


def _resolution(values: FloatArray) -> FloatArray:
    """Half the change between neighbouring windows (one-sided at the ends)."""
    if values.shape[0] < 2:
        return np.zeros_like(values)
    grad = np.gradient(values)
    return np.abs(grad)


@dataclass(frozen=True, eq=False, repr=False)
class RingDown(ResultMixin):
    """Frequency and damping of a free decay against its amplitude.

    Attributes
    ----------
    time : ndarray, shape (m,)
        Centres of the windows [s].
    amplitude : ndarray, shape (m,)
        Displacement amplitude A there [m] (of the band-passed signal: its fundamental).
    frequency : ndarray, shape (m,)
        ω = √(σ² + ω_d²) [rad/s].
    damped_frequency : ndarray, shape (m,)
        ω_d = dθ/dt [rad/s].
    damping_ratio : ndarray, shape (m,)
        ζ = σ/ω [-], σ = −d ln A/dt.
    frequency_error, damping_ratio_error : ndarray, shape (m,)
        The stated errors: the fits' standard errors combined with the windows'
        resolution and the allowances (see the module notes).
    frequency_se, damping_ratio_se : ndarray, shape (m,)
        The fits' standard errors alone (the noise's share).
    method : str
        'hilbert' or 'peaks'.
    signal : str
        The signal analysed: 'position', 'velocity' or 'acceleration'.
    band : ndarray, shape (2,)
        The band-pass [rad/s].
    analysed : ndarray, shape (2,)
        The span kept after trimming [s].
    status : str
        'success'.
    message : str
    """

    time: FloatArray
    amplitude: FloatArray
    frequency: FloatArray
    damped_frequency: FloatArray
    damping_ratio: FloatArray
    frequency_error: FloatArray
    damping_ratio_error: FloatArray
    frequency_se: FloatArray
    damping_ratio_se: FloatArray
    method: str
    signal: str
    band: FloatArray
    analysed: FloatArray
    status: str = "success"
    message: str = ""
    _rows: ClassVar[str] = "time"

    @property
    def success(self) -> bool:
        """True: the estimates and their stated errors are there."""
        return self.status == "success"

    def __repr__(self) -> str:
        return (f"RingDown(method={self.method!r}, windows={self.time.shape[0]}, amplitude="
                f"[{self.amplitude.min():.4g}, {self.amplitude.max():.4g}] m, "
                f"status={self.status!r})")  # fmt: skip

    def report(self) -> str:
        """A table of ω, ζ and their stated errors against the amplitude."""
        lines = [repr(self), self.message,
                 f"{'t [s]':>9} {'A [m]':>11} {'omega [rad/s]':>14} {'+-':>9} "
                 f"{'zeta [-]':>10} {'+-':>9}"]  # fmt: skip
        m = self.time.shape[0]
        for i in np.unique(np.linspace(0, m - 1, min(m, 15)).astype(int)):
            lines.append(
                f"{self.time[i]:9.4g} {self.amplitude[i]:11.5g} {self.frequency[i]:14.7g} "
                f"{self.frequency_error[i]:9.2g} {self.damping_ratio[i]:10.5g} "
                f"{self.damping_ratio_error[i]:9.2g}"
            )
        return "\n".join(lines)

    def compare(self, backbone: ModalBackbone, coordinate: int = 0) -> dict[str, FloatArray]:
        """The differences from a mode's backbone at the same amplitude of `coordinate`.

        The backbone's deflection at `coordinate` maps each ring-down amplitude to a modal
        amplitude (log-log interpolation on the backbone's grid: give it a dense grid that
        spans the ring-down). Returns arrays by name: ``modal_amplitude``; ``frequency``
        and ``damping`` differences ring-down − backbone against what a slow decay shows
        (``harmonic_frequency`` relative, ``decay_damping_ratio`` absolute), and against the
        quasi-static secant quantities (``quasi_static_frequency`` relative,
        ``quasi_static_damping`` absolute); ``damping_within`` and ``frequency_within``
        where the differences from the slow-decay quantities are within twice the stated
        errors.
        """
        from presliding.structural.backbone import ModalBackbone

        check_type("backbone", backbone, ModalBackbone)
        i = as_count("coordinate", coordinate, maximum=backbone.deflection.shape[1] - 1)
        phys = np.abs(backbone.deflection[:, i])
        order = np.argsort(phys)
        phys, modal = phys[order], backbone.amplitude[order]
        lo, hi = float(phys[0]), float(phys[-1])
        if self.amplitude.min() < lo or self.amplitude.max() > hi:
            raise ValueError(
                f"`backbone` must span the ring-down's amplitudes at coordinate {i} "
                f"([{self.amplitude.min():.4g}, {self.amplitude.max():.4g}] m); its deflection "
                f"spans [{lo:.4g}, {hi:.4g}] m."
            )
        la = np.log(self.amplitude)
        a = np.exp(np.interp(la, np.log(phys), np.log(modal)))

        def at(values: FloatArray) -> FloatArray:
            return np.asarray(np.interp(np.log(a), np.log(modal), values[order]))

        w1, zd = at(backbone.harmonic_frequency), at(backbone.decay_damping_ratio)
        dw = self.frequency / w1 - 1.0
        dz = self.damping_ratio - zd
        return {
            "modal_amplitude": a,
            "frequency": dw,
            "damping": dz,
            "quasi_static_frequency": self.frequency / at(backbone.frequency) - 1.0,
            "quasi_static_damping": self.damping_ratio - at(backbone.damping_ratio),
            "damping_within": np.abs(dz) <= 2.0 * self.damping_ratio_error,
            "frequency_within": np.abs(dw) * w1 <= 2.0 * self.frequency_error,
        }

    def plot(self, ax: Axes | None = None, *, quantity: str = "damping",
             backbone: ModalBackbone | None = None, coordinate: int = 0) -> Axes:  # fmt: skip
        """ζ(A) (log-log) or ω(A) (log amplitude) with the stated errors; optionally a
        backbone's slow-decay and quasi-static curves at the same coordinate."""
        from presliding.plotting import new_axes, place_legend

        as_choice("quantity", quantity, ("damping", "frequency"))
        ax = new_axes(ax)
        y, err = ((self.damping_ratio, self.damping_ratio_error) if quantity == "damping"
                  else (self.frequency, self.frequency_error))  # fmt: skip
        ax.errorbar(self.amplitude, y, yerr=err, fmt=".", ms=3, lw=0.8,
                    label=f"ring-down ({self.method})")  # fmt: skip
        if backbone is not None:
            phys = np.abs(backbone.deflection[:, int(coordinate)])
            slow, qs = ((backbone.decay_damping_ratio, backbone.damping_ratio)
                        if quantity == "damping" else
                        (backbone.harmonic_frequency, backbone.frequency))  # fmt: skip
            ax.plot(phys, slow, "-", label="backbone: slow decay")
            ax.plot(phys, qs, "--", label="backbone: quasi-static (secant)")
        ax.set_xscale("log")
        if quantity == "damping":
            ax.set_yscale("log")
        ax.set_xlabel("displacement amplitude A [m]")
        ax.set_ylabel("damping ratio ζ [-]" if quantity == "damping" else "frequency ω [rad/s]")
        ax.grid(True, which="both", alpha=0.3)
        place_legend(ax)
        return ax


def _series(data: Any, coordinate: int, signal: str | None) -> tuple[FloatArray, FloatArray, str]:
    """(time, values, kind) from a Measurement, a StructureMotion or (time, values)."""
    if isinstance(data, StructureMotion):
        data = data.to_measurement(coordinate)
    if isinstance(data, Measurement):
        present = [s for s in SIGNALS if getattr(data, s) is not None]
        if not present:
            raise ValueError("`data` must hold a position, velocity or acceleration; got none.")
        kind = present[0] if signal is None else as_choice("signal", signal, SIGNALS)
        (values,) = data.require(kind, purpose="a ring-down")
        return np.asarray(data.time), np.asarray(values), kind
    if isinstance(data, tuple) and len(data) == 2:
        t = as_signal("data[0] (time)", data[0], min_length=16)
        x = as_signal("data[1] (values)", data[1], min_length=16)
        if x.shape != t.shape:
            raise ValueError(f"`data` must pair time and values of one length; got {t.shape[0]} "
                             f"and {x.shape[0]}.")  # fmt: skip
        kind = "position" if signal is None else as_choice("signal", signal, SIGNALS)
        return t, x, kind
    raise TypeError(
        f"`data` must be a Measurement, a StructureMotion or (time, values); got "
        f"{type(data).__name__}."
    )


def analyze_ring_down(
    data: Measurement | StructureMotion | tuple[Any, Any],
    *,
    coordinate: int = 0,
    signal: str | None = None,
    method: str = "hilbert",
    frequency: float | None = None,
    band: tuple[float, float] | None = None,
    trim: float | None = None,
    cycles: float = 2.0,
    floor: float = 1e-3,
) -> RingDown:
    """ω(A), ζ(A) of a free decay: band-pass, then the analytic signal or the extremes.

    Parameters
    ----------
    data : Measurement, StructureMotion or (time, values)
        The ring-down on a uniform time base.
    coordinate : int
        The coordinate of a `StructureMotion`.
    signal : {'position', 'velocity', 'acceleration'}, optional
        The signal to analyse (default: the first present, in that order; 'position' for
        a pair).
    method : {'hilbert', 'peaks'}
    frequency : float, optional
        ω₀ of the mode [rad/s]; default the spectrum's peak.
    band : (float, float), optional
        The band-pass [rad/s]; default (0.5·ω₀, 1.5·ω₀).
    trim : float, optional
        Seconds trimmed at each end (default eight periods of ω₀; the first three of them
        tapered).
    cycles : float
        Window width in periods of ω₀ (>= 1).
    floor : float
        The tail where the amplitude is below floor × its largest value is trimmed.

    Returns
    -------
    RingDown
    """
    t, x, kind = _series(data, coordinate, signal)
    as_choice("method", method, ("hilbert", "peaks"))
    dt = float(t[1] - t[0])
    if np.max(np.abs(np.diff(t) - dt)) > 1e-6 * dt:
        raise ValueError("`data` must be sampled uniformly (resample it: Measurement.resample).")
    w0 = est.peak_frequency(x, dt) if frequency is None else as_positive_scalar(
        "frequency", frequency)  # fmt: skip
    nyquist = math.pi / dt
    lo, hi = (0.5 * w0, 1.5 * w0) if band is None else tuple(
        as_real_array("band", band).reshape(-1).tolist())  # fmt: skip
    if not 0.0 < lo < hi < nyquist:
        raise ValueError(f"`band` must satisfy 0 < low < high < the Nyquist frequency "
                         f"{nyquist:.6g} rad/s; got {fmt((lo, hi))}.")  # fmt: skip
    period = 2.0 * math.pi / w0
    trim = 8.0 * period if trim is None else as_positive_scalar("trim", trim)
    cycles = as_positive_scalar("cycles", cycles)
    if cycles < 1.0:
        raise ValueError(
            f"`cycles` must be at least 1 (a window of whole periods); got {cycles!r}."
        )
    floor = as_positive_scalar("floor", floor)
    taper = min(3.0 * period, trim)
    xf = est.band_pass(x, dt, (lo, hi), taper=taper)
    keep = (t >= t[0] + trim) & (t <= t[-1] - trim)
    if method == "hilbert":
        log_a, theta = est.analytic_points(xf)
        pt, pa, pth = t[keep], log_a[keep], theta[keep]
        min_points = 8
    else:
        pt, pa, pth = est.extreme_points(t, xf)
        inside = (pt >= t[0] + trim) & (pt <= t[-1] - trim)
        pt, pa, pth = pt[inside], pa[inside], pth[inside]
        min_points = 3
    span = 0.0
    if pt.shape[0]:
        alive = pa >= np.log(floor) + float(np.max(pa))
        last = int(np.flatnonzero(alive)[-1]) + 1
        span = float(pt[last - 1] - pt[0]) if last > 1 else 0.0
        pt, pa, pth = pt[:last], pa[:last], pth[:last]
    if span < 2.0 * cycles * period:
        raise ValueError(
            f"`data` must keep at least {2 * cycles:g} periods of the mode after trimming "
            f"{trim:.4g} s at each end and the tail below floor={floor:g}; it keeps {span:.4g} s "
            f"(period {period:.4g} s)."
        )
    res = est.windows(pt, pa, pth, cycles * period, min_points)
    sigma, wd = res["decay"], res["damped"]
    w = np.sqrt(sigma**2 + wd**2)
    zeta = sigma / w
    power = SIGNALS.index(kind)
    amp = np.exp(res["log_amplitude"]) / w**power / est.gain(dt, (lo, hi), wd)
    bias_z, bias_w = _bias(method, zeta, w)
    z_err = np.sqrt((res["decay_se"] / w) ** 2 + _resolution(zeta) ** 2
                    + (zeta * (math.pi * zeta) ** 2) ** 2 + bias_z**2)  # fmt: skip
    w_err = np.sqrt(res["damped_se"] ** 2 + _resolution(w) ** 2 + (w * zeta**2) ** 2
                    + bias_w**2)  # fmt: skip
    message = (
        f"{res['time'].shape[0]} windows of {cycles:g} periods (ω₀ = {w0:.6g} rad/s) over "
        f"[{pt[0]:.6g}, {pt[-1]:.6g}] s: {trim:.4g} s trimmed at each end (edge effects of "
        f"the band-pass {lo:.4g}–{hi:.4g} rad/s"
        + (" and of the analytic signal" if method == "hilbert" else "")
        + f"), and the tail below {floor:g} of the largest amplitude."
    )
    return RingDown(time=res["time"], amplitude=amp, frequency=w, damped_frequency=wd,
                    damping_ratio=zeta, frequency_error=w_err, damping_ratio_error=z_err,
                    frequency_se=res["damped_se"], damping_ratio_se=res["decay_se"] / w,
                    method=method, signal=kind, band=np.array([lo, hi]),
                    analysed=np.array([pt[0], pt[-1]]), message=message)  # fmt: skip
