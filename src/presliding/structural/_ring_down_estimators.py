"""The estimators behind `analyze_ring_down`: the analytic signal and peak tracking.

Both reduce the decay to points (t_i, ln A_i, θ_i): the analytic signal of the band-passed
signal (scipy.signal.hilbert) gives them at every sample, peak tracking at every
extreme (θ advancing by π from one extreme to the next, A the half peak-to-peak of the
half cycle). A straight line through ln A and through θ over each window of a few
periods gives the decay rate σ = −d ln A/dt and the damped frequency ω_d = dθ/dt at the
window's centre, so ω = √(σ² + ω_d²) and ζ = σ/ω (exact for a linear mode).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from scipy.signal import butter, hilbert, sosfiltfilt, sosfreqz

FloatArray = NDArray[np.float64]


def band_pass(x: FloatArray, dt: float, band: tuple[float, float], taper: float,
              order: int = 2) -> FloatArray:  # fmt: skip
    """Zero-phase Butterworth band-pass of x between band [rad/s] (sosfiltfilt), the record
    first tapered to zero over `taper` seconds at each end (raised cosine) and padded with
    zeros, so that neither the filter nor a later analytic signal meets an abrupt end."""
    nyquist = math.pi / dt
    lo, hi = band[0] / nyquist, min(band[1] / nyquist, 0.99)
    sos = butter(order, [lo, hi], btype="bandpass", output="sos")
    n = x.shape[0]
    pad = n // 4
    y = np.r_[np.zeros(pad), (x - np.mean(x)) * _taper(n, int(taper / dt)), np.zeros(pad)]
    return np.asarray(sosfiltfilt(sos, y))[pad : pad + n]


def gain(dt: float, band: tuple[float, float], w: FloatArray, order: int = 2) -> FloatArray:
    """|H(ω)|² of `band_pass` (the Butterworth filter run forth and back) at ω [rad/s]."""
    nyquist = math.pi / dt
    sos = butter(order, [band[0] / nyquist, min(band[1] / nyquist, 0.99)], btype="bandpass",
                 output="sos")  # fmt: skip
    _, h = sosfreqz(sos, worN=np.asarray(w, dtype=np.float64) * dt)
    return np.asarray(np.abs(h) ** 2)


def peak_frequency(x: FloatArray, dt: float) -> float:
    """ω [rad/s] of the largest peak of the Hann-windowed spectrum (parabolic refinement),
    above four cycles per record (a drifting mean, a joint's offset, is not the mode)."""
    y = (x - np.mean(x)) * np.hanning(x.shape[0])
    spec = np.abs(np.fft.rfft(y))
    k = int(np.argmax(spec[4:])) + 4
    if 1 <= k < spec.shape[0] - 1:
        a, b, c = np.log(spec[k - 1 : k + 2] + 1e-300)
        k = k + 0.5 * (a - c) / (a - 2 * b + c) if (a - 2 * b + c) != 0 else k
    return float(2 * math.pi * k / (x.shape[0] * dt))


def _taper(n: int, m: int) -> FloatArray:
    """1 inside, raised-cosine ramps of m samples at both ends."""
    window = np.ones(n)
    m = min(max(m, 2), n // 2)
    ramp = 0.5 - 0.5 * np.cos(np.linspace(0.0, math.pi, m))
    window[:m], window[-m:] = ramp, ramp[::-1]
    return window


def analytic_points(x: FloatArray) -> tuple[FloatArray, FloatArray]:
    """(ln A, θ) of the analytic signal at every sample (the record padded with zeros: it
    ends at zero after `band_pass`, so no wrap-around)."""
    pad = x.shape[0] // 4
    z = hilbert(np.r_[np.zeros(pad), x, np.zeros(pad)])[pad : pad + x.shape[0]]
    return np.log(np.abs(z) + 1e-300), np.unwrap(np.angle(z))


def extreme_points(t: FloatArray, x: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """(t_i, ln A_i, θ_i) of the half cycles between consecutive extremes (parabolic
    refinement of each extreme): A the half peak-to-peak, θ = π·i."""
    d = np.diff(x)
    idx = np.flatnonzero(np.sign(d[:-1]) != np.sign(d[1:])) + 1
    if idx.size < 3:
        return np.empty(0), np.empty(0), np.empty(0)
    y0, y1, y2 = x[idx - 1], x[idx], x[idx + 1]
    den = y0 - 2 * y1 + y2
    shift = np.where(den != 0, 0.5 * (y0 - y2) / np.where(den != 0, den, 1.0), 0.0)
    dt = t[1] - t[0]
    te = t[idx] + shift * dt
    xe = y1 - 0.25 * (y0 - y2) * shift
    amp = 0.5 * np.abs(np.diff(xe))
    keep = amp > 0
    tm = 0.5 * (te[1:] + te[:-1])
    theta = math.pi * np.arange(amp.shape[0], dtype=np.float64)
    return tm[keep], np.log(amp[keep]), theta[keep]


def windows(t: FloatArray, log_a: FloatArray, theta: FloatArray, width: float,
            min_points: int) -> dict[str, FloatArray]:  # fmt: skip
    """Over windows of `width` seconds (half overlapping): a parabola through ln A and a
    straight line through θ, least squares; at the window's centre ln A, σ = −d ln A/dt,
    ω_d = dθ/dt and their standard errors (from the residuals, the samples taken as
    independent)."""
    names = ("time", "log_amplitude", "decay", "damped", "decay_se", "damped_se")
    out: dict[str, list[float]] = {k: [] for k in names}
    start = t[0]
    while start + width <= t[-1] + 1e-12 * width:
        sel = (t >= start) & (t <= start + width)
        m = int(sel.sum())
        if m >= max(min_points, 4):
            tc = start + 0.5 * width
            tt = (t[sel] - tc) / width
            for y, degree, key in ((log_a[sel], 2, "log"), (theta[sel], 1, "phase")):
                basis = np.vander(tt, degree + 1, increasing=True)
                coef, *_ = np.linalg.lstsq(basis, y, rcond=None)
                res = y - basis @ coef
                cov = np.linalg.pinv(basis.T @ basis) * float(res @ res) / max(m - degree - 1, 1)
                slope, se = coef[1] / width, math.sqrt(max(cov[1, 1], 0.0)) / width
                if key == "log":
                    out["log_amplitude"].append(float(coef[0]))
                    out["decay"].append(-float(slope))
                    out["decay_se"].append(se)
                else:
                    out["damped"].append(float(slope))
                    out["damped_se"].append(se)
            out["time"].append(tc)
        start += 0.5 * width
    return {k: np.array(v) for k, v in out.items()}
