"""Fast compiled forms of the PI sum (eq. 4): time-blocked and batched kernels.

They compute exactly the play update of `presliding.hysteresis._kernels`,

    x_j[t] = min(max(x_j[t-1], y[t] - r_j), y[t] + r_j),

so play states are bit-identical to the straightforward kernels; only the
order in which the weighted sum Σ w_j (y − x_j) is accumulated differs
(fastmath on the sums, within 1e-12 of F_m = Σ |w_j| r_j).

Time blocking. Four time steps are taken per pass over the elements: each
element's state, threshold and weight are loaded once and stay in registers
for the four updates, and each step has its own vector accumulators, so the
loop is bounded by the arithmetic (six vector operations per element update)
rather than by loads, stores or the latency of one accumulator. A run whose
length is not a multiple of four ends with a block padded by repeating the
last sample (the update is idempotent for a repeated input: a clamp of a
clamp with the same bounds), so every output is produced by the same
compiled block whatever its position: chunked and whole runs agree bit for
bit.

One-sided steps. Between two samples the input moves one way, and then only
one side of the clamp can bind. If x_j lies in its band for the previous
sample, fl(y' − r) ≤ x ≤ fl(y' + r), and the input rises, y' ≤ y, then
x ≤ fl(y' + r) ≤ fl(y + r) (rounding is monotone) and fl(y − r) ≤ fl(y + r),
so the outer min of the update is the identity and

    min(max(x, y − r), y + r) = max(x, y − r)      (bit for bit),

and symmetrically min(x, y + r) for a falling input; an unchanged input is a
rising one whose update leaves x as it is. Each result lies in its own band,
so the argument carries from step to step; the first sample of every call
takes the full two-sided clamp, so the state handed in need not satisfy it.
The direction is one scalar test per time step, shared by all elements, which
cuts an element update from six vector operations to four.
`stop_sum_one_sided` uses this for long banks and `batch_loss` for batches;
small banks are faster with `stop_sum_blocked`, whose short element loop
cannot pay for the branch between sixteen direction patterns per block.

Batches. A batch of B operators on one input is laid out element-major,
``threshold[j, b]``, so the batch index is contiguous and is the SIMD axis;
the identification loss Σ_t (F_b(t) + a_b·z(t) + o_b − target(t))² (z a given
design signal, e.g. y or the direction of motion) is accumulated
inside the time loop, so no (T × B) output is ever stored. The parallel form
splits the batch into contiguous blocks, one per thread (``prange``).
"""

from __future__ import annotations

import numba as nb
import numpy as np

from presliding.hysteresis._jit import JitFlags, njit

# Sums may be reassociated/contracted; 'nnan'/'ninf' (inputs are validated on
# entry) let min/max compile to single vector instructions. The play update
# is min/max only, which no flag changes.
_FASTMATH = {"reassoc", "contract", "nnan", "ninf", "nsz"}
_JIT: JitFlags = {
    "cache": True,
    "fastmath": _FASTMATH,
    "error_model": "numpy",
    "boundscheck": False,
}

#: time steps per pass over the elements
BLOCK = 4
#: batch members per work item of the parallel batch kernels (a multiple of 8)
BATCH_CHUNK = 32


@njit(**_JIT)
def _step_direction(yt, before, d):  # pragma: no cover - compiled
    """Sign of the increment yt − before, or the previous direction d when it is zero."""
    if yt > before:
        return 1.0
    if yt < before:
        return -1.0
    return d


@njit(**_JIT)
def stop_sum_blocked(
    y, threshold, weight, x, out, linear, coulomb, prev, direction
):  # pragma: no cover - compiled
    """out[t] = a·y[t] + c·d[t] + Σ_j w_j (y[t] − x_j[t]), four steps per pass.

    a = `linear`, c = `coulomb`, d[t] the sign of the last nonzero increment of
    y (starting from the input `prev` and the direction `direction` before the
    first sample). ``x`` holds the play state before the first sample and is
    updated in place; returns the direction after the last sample.
    """
    n_time = y.shape[0]
    n_el = threshold.shape[0]
    last = n_time - 1
    d = direction
    for t in range(0, n_time, BLOCK):
        # the last block repeats the last sample (an idempotent update, no new direction)
        y0 = y[t]
        y1 = y[min(t + 1, last)]
        y2 = y[min(t + 2, last)]
        y3 = y[min(t + 3, last)]
        d0 = _step_direction(y0, prev, d)
        d1 = _step_direction(y1, y0, d0)
        d2 = _step_direction(y2, y1, d1)
        d = _step_direction(y3, y2, d2)
        prev = y3
        a0 = linear * y0 + coulomb * d0
        a1 = linear * y1 + coulomb * d1
        a2 = linear * y2 + coulomb * d2
        a3 = linear * y3 + coulomb * d
        for j in range(n_el):
            rj = threshold[j]
            wj = weight[j]
            xj = min(max(x[j], y0 - rj), y0 + rj)
            a0 += wj * (y0 - xj)
            xj = min(max(xj, y1 - rj), y1 + rj)
            a1 += wj * (y1 - xj)
            xj = min(max(xj, y2 - rj), y2 + rj)
            a2 += wj * (y2 - xj)
            xj = min(max(xj, y3 - rj), y3 + rj)
            a3 += wj * (y3 - xj)
            x[j] = xj
        out[t] = a0
        if t + 1 <= last:
            out[t + 1] = a1
        if t + 2 <= last:
            out[t + 2] = a2
        if t + 3 <= last:
            out[t + 3] = a3
    return d


@njit(**_JIT)
def stop_sum_one_sided(
    y, threshold, weight, x, out, linear, coulomb, prev, direction
):  # pragma: no cover - compiled
    """`stop_sum_blocked` with one-sided updates after the first sample (see module docstring).

    Same play states bit for bit; four vector operations per element update.
    """
    n_time = y.shape[0]
    n_el = threshold.shape[0]
    last = n_time - 1
    d = direction
    # the full clamp at the first sample puts every state in its band; the
    # first block then repeats that sample (an update that changes nothing), so
    # every output sum comes from the same block code, wherever a chunk starts
    y_first = y[0]
    for j in range(n_el):
        x[j] = min(max(x[j], y_first - threshold[j]), y_first + threshold[j])
    up_prev = y_first
    for t in range(0, n_time, BLOCK):
        # the last block repeats the last sample (a rising step that changes nothing)
        y0 = y[t]
        y1 = y[min(t + 1, last)]
        y2 = y[min(t + 2, last)]
        y3 = y[min(t + 3, last)]
        up0 = y0 >= up_prev
        up1 = y1 >= y0
        up2 = y2 >= y1
        up3 = y3 >= y2
        up_prev = y3
        d0 = _step_direction(y0, prev, d)
        d1 = _step_direction(y1, y0, d0)
        d2 = _step_direction(y2, y1, d1)
        d = _step_direction(y3, y2, d2)
        prev = y3
        a0 = linear * y0 + coulomb * d0
        a1 = linear * y1 + coulomb * d1
        a2 = linear * y2 + coulomb * d2
        a3 = linear * y3 + coulomb * d
        for j in range(n_el):
            rj = threshold[j]
            wj = weight[j]
            xj = max(x[j], y0 - rj) if up0 else min(x[j], y0 + rj)
            a0 += wj * (y0 - xj)
            xj = max(xj, y1 - rj) if up1 else min(xj, y1 + rj)
            a1 += wj * (y1 - xj)
            xj = max(xj, y2 - rj) if up2 else min(xj, y2 + rj)
            a2 += wj * (y2 - xj)
            xj = max(xj, y3 - rj) if up3 else min(xj, y3 + rj)
            a3 += wj * (y3 - xj)
            x[j] = xj
        out[t] = a0
        if t + 1 <= last:
            out[t + 1] = a1
        if t + 2 <= last:
            out[t + 2] = a2
        if t + 3 <= last:
            out[t + 3] = a3
    return d


@njit(**_JIT)
def _loss_chunk(
    y, design, target, threshold, weight, linear, offset, x, loss, b0
):  # pragma: no cover
    """Add Σ_t residual² of members b0 <= b < b0 + BATCH_CHUNK to ``loss`` (see `batch_loss`).

    The chunk is copied into one scratch array with rows of exactly BATCH_CHUNK
    members (missing members padded with weight 0), so every inner loop has a
    constant trip count over disjoint rows of one array.
    """
    n_time = y.shape[0]
    n_el = threshold.shape[0]
    nb_ = min(BATCH_CHUNK, threshold.shape[1] - b0)
    # rows: thresholds [0, n), weights [n, 2n), play states [2n, 3n), linear 3n,
    # accumulators 3n + 1 ... 3n + 4, loss 3n + 5, offset 3n + 6
    buf = np.zeros((3 * n_el + 7, BATCH_CHUNK))
    for j in range(n_el):
        for i in range(BATCH_CHUNK):
            buf[j, i] = threshold[j, b0 + i] if i < nb_ else 1.0
            buf[n_el + j, i] = weight[j, b0 + i] if i < nb_ else 0.0
            buf[2 * n_el + j, i] = x[j, b0 + i] if i < nb_ else y[0]
    for i in range(nb_):
        buf[3 * n_el, i] = linear[b0 + i]
        buf[3 * n_el + 6, i] = offset[b0 + i]
    c = 3 * n_el
    n_block = (n_time + BLOCK - 1) // BLOCK
    last = n_time - 1
    # the first sample takes the full clamp; every later update is one-sided
    prev = y[0]
    for j in range(n_el):
        for i in range(BATCH_CHUNK):
            rj = buf[j, i]
            buf[2 * n_el + j, i] = min(max(buf[2 * n_el + j, i], prev - rj), prev + rj)
    for blk in range(n_block):
        t = blk * BLOCK
        y0 = y[t]
        y1 = y[min(t + 1, last)]
        y2 = y[min(t + 2, last)]
        y3 = y[min(t + 3, last)]
        up0 = y0 >= prev
        up1 = y1 >= y0
        up2 = y2 >= y1
        up3 = y3 >= y2
        prev = y3
        g0 = target[t]
        g1 = target[min(t + 1, last)]
        g2 = target[min(t + 2, last)]
        g3 = target[min(t + 3, last)]
        z0 = design[t]
        z1 = design[min(t + 1, last)]
        z2 = design[min(t + 2, last)]
        z3 = design[min(t + 3, last)]
        for i in range(BATCH_CHUNK):
            a = buf[c, i]
            o = buf[c + 6, i]
            buf[c + 1, i] = a * z0 + o - g0
            buf[c + 2, i] = a * z1 + o - g1
            buf[c + 3, i] = a * z2 + o - g2
            buf[c + 4, i] = a * z3 + o - g3
        for j in range(n_el):
            for i in range(BATCH_CHUNK):
                rj = buf[j, i]
                wj = buf[n_el + j, i]
                xj = buf[2 * n_el + j, i]
                xj = max(xj, y0 - rj) if up0 else min(xj, y0 + rj)
                buf[c + 1, i] += wj * (y0 - xj)
                xj = max(xj, y1 - rj) if up1 else min(xj, y1 + rj)
                buf[c + 2, i] += wj * (y1 - xj)
                xj = max(xj, y2 - rj) if up2 else min(xj, y2 + rj)
                buf[c + 3, i] += wj * (y2 - xj)
                xj = max(xj, y3 - rj) if up3 else min(xj, y3 + rj)
                buf[c + 4, i] += wj * (y3 - xj)
                buf[2 * n_el + j, i] = xj
        # padded steps of the last block repeat the last sample: not counted
        m1 = 1.0 if t + 1 <= last else 0.0
        m2 = 1.0 if t + 2 <= last else 0.0
        m3 = 1.0 if t + 3 <= last else 0.0
        for i in range(BATCH_CHUNK):
            e0 = buf[c + 1, i]
            e1 = buf[c + 2, i]
            e2 = buf[c + 3, i]
            e3 = buf[c + 4, i]
            buf[c + 5, i] += e0 * e0 + m1 * e1 * e1 + m2 * e2 * e2 + m3 * e3 * e3
    for i in range(nb_):
        loss[b0 + i] += buf[c + 5, i]
        for j in range(n_el):
            x[j, b0 + i] = buf[2 * n_el + j, i]


@njit(**_JIT)
def batch_loss(y, design, target, threshold, weight, linear, offset, x, loss):  # pragma: no cover
    """Identification loss of B PI operators on one input, fused into the time loop.

    loss[b] += Σ_t (linear[b]·design[t] + offset[b]
                    + Σ_j weight[j, b]·(y[t] − x[j, b](t)) − target[t])²,
    with ``threshold``, ``weight`` and the play states ``x`` of shape (N, B)
    (element-major: the batch is contiguous); ``x`` is updated in place.
    """
    for b0 in range(0, threshold.shape[1], BATCH_CHUNK):
        _loss_chunk(y, design, target, threshold, weight, linear, offset, x, loss, b0)


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy", boundscheck=False, parallel=True)
def batch_loss_parallel(
    y, design, target, threshold, weight, linear, offset, x, loss
):  # pragma: no cover
    """`batch_loss` with the batch split into blocks of BATCH_CHUNK members, one per thread."""
    n_chunk = (threshold.shape[1] + BATCH_CHUNK - 1) // BATCH_CHUNK
    for c in nb.prange(n_chunk):
        _loss_chunk(y, design, target, threshold, weight, linear, offset, x, loss, c * BATCH_CHUNK)
