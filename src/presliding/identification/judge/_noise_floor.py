"""The noise floor of a pooled fit, estimated from the data alone.

A fit cannot leave a residual smaller than the noise of the measured signals.
Each signal's noise variance is the larger of

* the quantisation variance q²/12, with q the signal's quantum (the smallest
  nonzero step, when every step is a whole multiple of it: an encoder), and
* the high-frequency noise: the mean square of the second differences over 6
  (white noise of variance σ² has second differences of variance 6σ²; a
  smooth signal sampled finely has small ones), the largest 10 % left out
  (events: stops, force steps).

The floor of record i is the RMS of its weighted residual rows that noise
alone would leave; `floor_ratios` compares it with the fitted residual.
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


def quantum(x: FloatArray) -> float:
    """The quantum of a quantised signal (0 when it is not quantised).

    Steps at the rounding level of the signal's magnitude are no quanta: the difference
    quotient of a quantised position (a drive's velocity) has steps of q/(2·Δt) and,
    where the position stands still between two moving neighbours, steps of a few
    ulps; taken as the quantum, those made the floor of a record mostly at rest (a
    stiff stage ringing down) a thousandth of its noise.
    """
    x = np.asarray(x, dtype=float)
    steps = np.abs(np.diff(x))
    rounding = ROUNDING * float(np.max(np.abs(x), initial=0.0))
    steps = steps[steps > rounding]
    if steps.size < 3:
        return 0.0
    q = float(np.min(steps))
    ratio = steps / q
    return (
        q if bool(np.all(np.abs(ratio - np.round(ratio)) < 1e-3 * np.maximum(ratio, 1.0))) else 0.0
    )


def noise_variance(x: FloatArray) -> float:
    """The noise variance of a sampled signal (module notes)."""
    x = np.asarray(x, dtype=float)
    if x.shape[0] < 4:
        return 0.0
    d2 = np.sort(np.diff(x, 2) ** 2)
    kept = d2[: max(1, int(np.ceil((1.0 - TRIM) * d2.shape[0])))]
    high = float(np.mean(kept)) / 6.0
    q = quantum(x)
    rms = float(np.sqrt(np.mean(x**2)))
    return max(high, q * q / 12.0, (RELATIVE_FLOOR * rms) ** 2)


def record_floors(problem) -> FloatArray:
    """Mean square of each record's weighted residual that the noise alone leaves (R,)."""
    out = np.empty(problem.n_rec)
    for i, rec in enumerate(problem.records):
        total, rows = 0.0, 0
        for w, sig in ((problem.w_v, rec.velocity), (problem.w_y, rec.position)):
            if w:
                total += w * w * noise_variance(sig) * sig.shape[0]
                rows += sig.shape[0]
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
