"""Compiled time loops of the play/stop operators (eqs. 3, 5, 11) and the PI sum (eq. 4).

All kernels take contiguous float64 arrays, mutate only the output arrays and
the play-state vector they are handed (a copy made by the caller), and never
allocate per time step.

The play update is the exact solution of eq. 3 for an input that is monotone
between two samples::

    x_j[t] = min(max(x_j[t-1], y[t] - r_j), y[t] + r_j)

Every kernel computes this update, or the one-sided form that `presliding.hysteresis._fused`
shows equal to it bit for bit, so every caller shares bit-identical play states.
The weighted sum over elements may be reassociated by the compiler (fastmath
``reassoc``); it is deterministic for a given bank, so chunked and whole runs
agree bit for bit.

`stop_sum` runs a time-blocked kernel of `presliding.hysteresis._fused` (one-sided
updates for banks of `ONE_SIDED_MIN` elements or more) on the bank padded to
a multiple of `LANES` elements (padding elements have weight 0 and
add exact zeros), with the linear term a·y and the Coulomb term c·sign(ẏ) of
eq. 8 added inside the time loop (no O(T) temporaries); `_stop_sum_short`
and `_stop_sum_long` are the straightforward loops it is tested against (same
play states, sums within 1e-12 of F_m).
"""

from __future__ import annotations

import numpy as np

from presliding.hysteresis._fused import stop_sum_blocked, stop_sum_one_sided
from presliding.hysteresis._jit import njit

# Only the sum may be reordered/contracted; no NaN or inf reaches a kernel
# (inputs are validated on entry), so 'nnan'/'ninf' let min/max compile to
# single vector instructions.
_FASTMATH = {"reassoc", "contract", "nnan", "ninf", "nsz"}


@njit(cache=True, fastmath=_FASTMATH)
def play_outputs(y, threshold, x, out):  # pragma: no cover - compiled
    """Write the play states x_j(t) into ``out`` (T, N); ``x`` holds the prior state."""
    n_time = y.shape[0]
    n_el = threshold.shape[0]
    for t in range(n_time):
        yt = y[t]
        for j in range(n_el):
            xj = min(max(x[j], yt - threshold[j]), yt + threshold[j])
            x[j] = xj
            out[t, j] = xj


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy", boundscheck=False)
def peak(y):  # pragma: no cover - compiled
    """max_t |y[t]| in one pass (y finite: checked by the caller); 0 for an empty y.

    Eight independent partial maxima, so the loop is bound by loads rather than
    by the latency of one max.
    """
    n = y.shape[0]
    h0 = h1 = h2 = h3 = h4 = h5 = h6 = h7 = 0.0
    stop = n - n % 8
    for t in range(0, stop, 8):
        h0 = max(h0, abs(y[t]))
        h1 = max(h1, abs(y[t + 1]))
        h2 = max(h2, abs(y[t + 2]))
        h3 = max(h3, abs(y[t + 3]))
        h4 = max(h4, abs(y[t + 4]))
        h5 = max(h5, abs(y[t + 5]))
        h6 = max(h6, abs(y[t + 6]))
        h7 = max(h7, abs(y[t + 7]))
    hi = max(max(max(h0, h1), max(h2, h3)), max(max(h4, h5), max(h6, h7)))
    for t in range(stop, n):
        hi = max(hi, abs(y[t]))
    return hi


def _stop_sum(y, threshold, weight, x, out):  # pragma: no cover - compiled
    """Weighted stop sum out[t] = sum_j w_j (y[t] - x_j[t]) (eq. 4 with eq. 5).

    ``x`` holds the play state before the first sample and is updated in place
    to the state after the last one.
    """
    n_time = y.shape[0]
    n_el = threshold.shape[0]
    for t in range(n_time):
        yt = y[t]
        acc = 0.0
        for j in range(n_el):
            xj = min(max(x[j], yt - threshold[j]), yt + threshold[j])
            x[j] = xj
            acc += weight[j] * (yt - xj)
        out[t] = acc


# The straightforward loop, compiled with two flag sets: the reference that the
# blocked kernel behind `stop_sum` is tested and benchmarked against (same play
# states bit for bit, sums within 1e-12).
_stop_sum_short = njit(cache=True, fastmath=_FASTMATH)(_stop_sum)
_stop_sum_long = njit(cache=True, fastmath=True)(_stop_sum)


#: banks are padded to a multiple of this many elements (two AVX2 vectors of
#: float64), so the element loop never ends in a scalar remainder
LANES = 8
#: banks of at least this many (padded) elements take the one-sided kernel
ONE_SIDED_MIN = 64


def stop_sum(
    y: np.ndarray,
    threshold: np.ndarray,
    weight: np.ndarray,
    x: np.ndarray,
    out: np.ndarray,
    linear: float = 0.0,
    coulomb: float = 0.0,
    prev: float | None = None,
    direction: float = 0.0,
) -> float:
    """out[t] = a·y[t] + c·d[t] + Σ_j w_j (y[t] − x_j[t]) (eq. 4, eq. 8); ``x`` updated in place.

    a = `linear`, c = `coulomb` and d[t] the sign of the last nonzero increment
    of y, from the input `prev` (default y[0]) and `direction` before the first
    sample. Returns the direction after the last sample. Same play states as
    `_stop_sum` bit for bit; the sum is accumulated in a different (fixed)
    order. Every output depends only on the bank and the state before it, not
    on where a chunk starts, so chunked = whole. The kernel always receives
    fresh writable copies of the (padded) bank, so it is compiled for one
    set of argument types only.
    """
    n = threshold.shape[0]
    pad = -n % LANES
    kernel = stop_sum_one_sided if n + pad >= ONE_SIDED_MIN else stop_sum_blocked
    r = np.ones(n + pad)
    w = np.zeros(n + pad)
    xp = np.full(n + pad, y[0])
    r[:n] = threshold
    w[:n] = weight
    xp[:n] = x
    p = float(y[0]) if prev is None else float(prev)
    d = kernel(y, r, w, xp, out, float(linear), float(coulomb), p, float(direction))
    x[:] = xp[:n]
    return d


@njit(cache=True)
def motion_direction(y, previous_input, previous_direction, out):  # pragma: no cover
    """Sign of the last nonzero increment of ``y`` (0 before any motion).

    Returns the direction after the last sample.
    """
    prev = previous_input
    d = previous_direction
    for t in range(y.shape[0]):
        yt = y[t]
        if yt > prev:
            d = 1.0
        elif yt < prev:
            d = -1.0
        prev = yt
        out[t] = d
    return d


@njit(cache=True)
def last_direction(y, previous_input, previous_direction):  # pragma: no cover
    """Only the direction after the last sample: scans back to the last nonzero increment."""
    for t in range(y.shape[0] - 1, -1, -1):
        before = y[t - 1] if t > 0 else previous_input
        if y[t] > before:
            return 1.0
        if y[t] < before:
            return -1.0
    return previous_direction


def empty_outputs(n_time: int, n_el: int) -> np.ndarray:
    """C-ordered (T, N) float64 buffer for per-element outputs."""
    return np.empty((n_time, n_el), dtype=np.float64)
