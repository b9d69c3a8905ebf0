"""Zero-phase filters and derivative estimates for sampled signals (section 4, eq. 17).

Encoders measure the displacement y quantised; the identification of eq. 17
needs ẏ and ÿ. `lowpass` filters a uniformly sampled signal without phase lag
(forward–backward Butterworth or Savitzky–Golay); `estimate_derivatives`
differentiates the filtered position. Both are re-exported by `measurement`,
whose `Measurement.differentiate` applies them to a whole measurement.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_choice,
    as_count,
    as_positive_scalar,
    as_signal,
    check_same_length,
    fmt,
)

FloatArray = NDArray[np.float64]

#: The highest filter order (Butterworth) or polynomial degree (Savitzky–Golay);
#: Butterworth filters of higher order lose all digits in transfer-function form.
MAX_ORDER = 10


def _sampling(time: ArrayLike, values: ArrayLike, cutoff: float) -> tuple[np.ndarray, float, float]:
    t = as_signal("time", time, min_length=2)
    y = as_signal("signal", values)
    check_same_length(time=t, signal=y)
    fc = as_positive_scalar("cutoff", cutoff)
    h = float(np.median(np.diff(t)))
    nyquist = 0.5 / h
    if not fc < nyquist:
        raise ValueError(
            f"`cutoff` must be below the Nyquist frequency {fmt(nyquist)} Hz; got {fmt(fc)}."
        )
    return y, h, fc / nyquist


def lowpass(
    time: ArrayLike, values: ArrayLike, cutoff: float, *, method: str = "butter", order: int = 4
) -> FloatArray:
    """Zero-phase low-pass filter of a uniformly sampled signal.

    Parameters
    ----------
    time, values : array_like, shape (T,)
    cutoff : float
        Cut-off frequency [Hz] (the −3 dB point of the forward filter for
        ``"butter"``; the approximate −3 dB point for ``"savgol"``).
    method : {"butter", "savgol"}
        ``"butter"``: Butterworth filter of `order`, run forwards and backwards
        (scipy.signal.sosfiltfilt, in second-order sections), so the phase
        is zero and the magnitude is squared. ``"savgol"``: Savitzky–Golay
        smoothing, polynomial degree `order`, with the longest window whose
        gain at the cut-off is still at least 1/√2 (−3 dB).
    order : int
        Filter order or polynomial degree, 1 to `MAX_ORDER` (10).
    """
    y, h, wn = _sampling(time, values, cutoff)
    return _smooth(y, h, wn, method, order, deriv=0)


def estimate_derivatives(
    time: ArrayLike, position: ArrayLike, cutoff: float, *, method: str = "butter", order: int = 4
) -> tuple[FloatArray, FloatArray]:
    """Velocity and acceleration from a quantised position, without phase lag.

    ``"butter"``: the position is low-passed by a zero-phase Butterworth filter
    (see `lowpass`), then differentiated twice by central differences
    (numpy.gradient, second order at the ends). ``"savgol"``: the derivatives
    of the local Savitzky–Golay polynomials. The cut-off [Hz] trades the
    quantisation noise (amplified ∝ f² in the acceleration) against the
    bandwidth of the motion; choose it a few times above the highest
    frequency of interest.

    Returns
    -------
    velocity, acceleration : ndarray, shape (T,)
    """
    y, h, wn = _sampling(time, position, cutoff)
    if as_choice("method", method, ("butter", "savgol")) == "savgol":
        return _smooth(y, h, wn, method, order, 1), _smooth(y, h, wn, method, order, 2)
    smooth = _smooth(y, h, wn, method, order, deriv=0)
    v = np.gradient(smooth, h)
    return v, np.gradient(v, h)


def _smooth(y: FloatArray, h: float, wn: float, method: str, order: int, deriv: int) -> FloatArray:
    from scipy import signal

    method = as_choice("method", method, ("butter", "savgol"))
    order = as_count("order", order, minimum=1, maximum=MAX_ORDER)
    if method == "butter":
        # second-order sections: the (b, a) form loses the filter to rounding at low cut-offs
        # (order 6 at 2e-4 of Nyquist gave velocities of 1e48)
        sos = signal.butter(int(order), wn, output="sos")
        trivial = min(int(np.sum(sos[:, 2] == 0)), int(np.sum(sos[:, 5] == 0)))
        need = 3 * (2 * len(sos) + 1 - trivial) + 1  # sosfiltfilt's default padding + 1
        if y.shape[0] < need:
            raise ValueError(
                f"the signal must have at least {need} samples for a Butterworth filter of "
                f"order {order}; got {y.shape[0]}."
            )
        # the line through the end samples passes unchanged (unit gain, zero phase) and is
        # removed first, so that the edges start from rest and a ramp comes out exact
        line = np.linspace(y[0], y[-1], y.shape[0])
        try:
            with np.errstate(all="ignore"):  # an unstable filter is reported below
                out = signal.sosfiltfilt(sos, y - line) + line
        except ValueError:  # newer scipy refuses an unstable filter itself
            out = np.full(y.shape, np.nan)
        if not np.all(np.isfinite(out)):
            raise ValueError(
                f"`order` must give a numerically stable Butterworth filter at this `cutoff` "
                f"({fmt(wn)} of the Nyquist frequency); got {order} (lower `order` or raise "
                "`cutoff`)."
            )
        return np.ascontiguousarray(out)
    window = _savgol_window(wn, int(order))
    if y.shape[0] < window:
        raise ValueError(
            f"the signal must have at least {window} samples for this Savitzky–Golay window; "
            f"got {y.shape[0]} (raise `cutoff` or give more samples)."
        )
    return np.ascontiguousarray(
        signal.savgol_filter(y, window, int(order), deriv=deriv, delta=h, mode="interp")
    )


def _savgol_window(wn: float, order: int) -> int:
    """Longest odd window whose smoother keeps a gain >= 1/√2 at the cut-off wn (× Nyquist)."""
    from scipy import signal

    def gain(half: int) -> float:
        taps = signal.savgol_coeffs(2 * half + 1, order)
        return float(abs(signal.freqz(taps, worN=[wn * np.pi])[1][0]))

    lo = order // 2 + 1  # the shortest window that smooths at all
    hi = lo
    while gain(hi) >= np.sqrt(0.5) and hi < 1 << 20:
        lo, hi = hi, 2 * hi
    while hi - lo > 1:  # gain(lo) >= 1/√2 > gain(hi)
        mid = (lo + hi) // 2
        lo, hi = (mid, hi) if gain(mid) >= np.sqrt(0.5) else (lo, mid)
    return 2 * lo + 1
