"""The noise floor of a pooled fit, estimated from the data alone.

A fit cannot leave a residual smaller than the noise of the measured signals.
Each signal's noise variance is the larger of

* the quantisation variance q²/12, with q the signal's quantum (`quantum`: the
  smallest nonzero step, when every step is a whole multiple of it: an
  encoder; else the resolution of data rounded to decimals, `decimal_quantum`:
  positions printed with 4 decimals have a quantum of 1e-4 even where a record
  hardly moves), and
* the high-frequency noise: the mean square of the second differences over 6
  (white noise of variance σ² has second differences of variance 6σ²; a
  smooth signal sampled finely has small ones), the largest 10 % left out
  (events: stops, force steps).

The floor of record i is the RMS of its weighted residual rows that noise
alone would leave; `floor_ratios` compares it with the fitted residual. A
record whose own samples show no quantum (it hardly moves) takes the quantum
of the other records' signal (one instrument), so that a record at rest is not
given a floor of round-off.

`white_variance` is the unbiased estimate the adequacy tests (`_adequacy`) read:
the second differences' mean square with outliers clipped at 4 standard
deviations (and the clipped Gaussian's shortfall restored) instead of the
largest 10 % cut, which took 40 % of a Gaussian's variance with them.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: share of the largest second differences left out of the high-frequency estimate
TRIM = 0.1
#: steps below this many units of rounding of the signal's magnitude are round-off
ROUNDING = 64 * np.finfo(float).eps
#: a floor never below this share of the signal's RMS (noise-free data, round-off)
RELATIVE_FLOOR = 1e-9
#: second differences beyond this many standard deviations are events, not noise
CLIP = 4.0
#: E[x² | |x| < 4] of a standard Gaussian: the clipped mean square's shortfall
CLIPPED = 0.998884
#: finest decimal resolution looked for (digits after the point)
DIGITS = 12


def quantum(x: FloatArray) -> float:
    """The quantum of a quantised signal (0 when it is not quantised).

    Steps at the rounding level of the signal's magnitude are no quanta: the difference
    quotient of a quantised position (a drive's velocity) has steps of q/(2·Δt) and,
    where the position stands still between two moving neighbours, steps of a few
    ulps; taken as the quantum, those made the floor of a record mostly at rest (a
    stiff stage ringing down) a thousandth of its noise. Where the steps show no
    common quantum (too few of them), the resolution of decimals is the quantum
    (`decimal_quantum`).
    """
    x = np.asarray(x, dtype=float)
    steps = np.abs(np.diff(x))
    rounding = ROUNDING * float(np.max(np.abs(x), initial=0.0))
    steps = steps[steps > rounding]
    if steps.size < 3:
        return decimal_quantum(x)
    q = float(np.min(steps))
    ratio = steps / q
    if bool(np.all(np.abs(ratio - np.round(ratio)) < 1e-3 * np.maximum(ratio, 1.0))):
        return q
    return decimal_quantum(x)


def decimal_quantum(x: FloatArray) -> float:
    """10⁻ᵈ for the fewest decimals d that every sample has (0 when there is none down to
    `DIGITS` decimals, or where 10⁻ᵈ nears the rounding level of the samples' magnitude):
    the resolution of data printed with d decimals."""
    x = np.asarray(x, dtype=float)
    if x.size == 0 or not np.all(np.isfinite(x)) or not np.any(x != 0):
        return 0.0
    top = float(np.max(np.abs(x)))
    for d in range(-int(np.floor(np.log10(top))), DIGITS + 1):
        q = 10.0**-d
        if q <= 1e5 * np.finfo(float).eps * top:  # x/q would carry its own rounding
            return 0.0
        scaled = x / q
        if float(np.max(np.abs(scaled - np.round(scaled)))) <= 1e-3:
            return q
    return 0.0


def noise_variance(x: FloatArray, q: float | None = None) -> float:
    """The noise variance of a sampled signal (module notes); `q`: its quantum when known
    (default: `quantum` of `x`)."""
    x = np.asarray(x, dtype=float)
    if x.shape[0] < 4:
        return 0.0
    d2 = np.sort(np.diff(x, 2) ** 2)
    kept = d2[: max(1, int(np.ceil((1.0 - TRIM) * d2.shape[0])))]
    high = float(np.mean(kept)) / 6.0
    q = quantum(x) if q is None else q
    rms = float(np.sqrt(np.mean(x**2)))
    return max(high, q * q / 12.0, (RELATIVE_FLOOR * rms) ** 2)


def white_variance(x: FloatArray, q: float | None = None, divisor: float = 6.0) -> float:
    """Unbiased estimate of the variance of a signal's white noise (module notes): the mean
    square of its second differences, clipped at `CLIP` standard deviations, over
    `divisor` (6 for white noise; 5 for the central difference quotient of a white
    signal, whose second differences have variance 5σ²), and at least q²/12."""
    x = np.asarray(x, dtype=float)
    q = quantum(x) if q is None else q
    if x.shape[0] < 4:
        return q * q / 12.0
    d2 = np.diff(x, 2) ** 2
    s2 = float(np.mean(d2))
    for _ in range(20):
        kept = d2[d2 <= CLIP**2 * s2]
        new = float(np.mean(kept)) / CLIPPED if kept.size else 0.0
        if not new < s2 * (1.0 - 1e-9):
            break
        s2 = new
    rms = float(np.sqrt(np.mean(x**2)))
    return max(s2 / divisor, q * q / 12.0, (RELATIVE_FLOOR * rms) ** 2)


def shows_noise(x: FloatArray, variance: float) -> bool:
    """Whether `variance` (of `x`'s noise) is measurable: above 10 times the round-off floor
    (`RELATIVE_FLOOR` of the RMS). Noise-free data (a simulation, exact velocities) give no
    noise model: a fit's residual there is its solver's tolerance, which no test can judge."""
    rms2 = float(np.mean(np.asarray(x, dtype=float) ** 2)) if np.size(x) else 0.0
    return variance > (10.0 * RELATIVE_FLOOR) ** 2 * rms2


def shared_quanta(signals: list[FloatArray]) -> list[float]:
    """The quantum of each signal, a signal without one taking the largest of the others'
    (records of one instrument: a record that hardly moves shows no steps of its own)."""
    own = [quantum(x) for x in signals]
    other = max(own, default=0.0)
    return [q if q > 0 else other for q in own]


def record_floors(problem) -> FloatArray:
    """Mean square of each record's weighted residual that the noise alone leaves (R,)."""
    out = np.empty(problem.n_rec)
    signals = [(problem.w_v, [r.velocity for r in problem.records]),
               (problem.w_y, [r.position for r in problem.records])]  # fmt: skip
    quanta = [shared_quanta(sig) if w else [] for w, sig in signals]
    for i in range(problem.n_rec):
        total, rows = 0.0, 0
        for (w, sig), qs in zip(signals, quanta, strict=True):
            if w:
                total += w * w * noise_variance(sig[i], qs[i]) * sig[i].shape[0]
                rows += sig[i].shape[0]
        out[i] = total / max(rows, 1)
    return out


def floor_ratios(problem, residual: FloatArray) -> tuple[FloatArray, float]:
    """RMS over floor of every record, and of the pooled residual."""
    floors = record_floors(problem)
    ms = np.array([np.mean(residual[problem.record_rows(i)] ** 2) for i in range(problem.n_rec)])
    sizes = np.array([problem.record_rows(i).shape[0] for i in range(problem.n_rec)])
    with np.errstate(divide="ignore", invalid="ignore"):
        ratios = np.sqrt(ms / floors)
        pooled = float(np.sqrt(np.sum(ms * sizes) / np.sum(floors * sizes)))
    return ratios, pooled
