"""Compiled time loop of a batch of PI operators on one input, with the full output F[T, B].

The batch is laid out element-major, ``threshold[j, b]``, so the batch index is
contiguous and is the SIMD axis (as in `presliding.hysteresis._fused`). The
batch is taken in chunks of `BATCH_CHUNK` members; each chunk is copied into
one scratch array whose rows hold exactly `BATCH_CHUNK` members (missing
members padded with weight 0, which adds exact zeros), so every inner loop
has a constant trip count. Four time steps are taken per pass over the
elements, with one-sided play updates after the first sample (the argument
is in `presliding.hysteresis._fused`): play states are bit-identical to the
straightforward kernels, and every output row is computed by the same block
code wherever a chunk of time starts, so chunked and whole runs agree bit for
bit.

Each output is a·y(t) + c·d(t) + Σ_j w_j (y(t) − x_j(t)), with a per-member
linear coefficient a, a per-member Coulomb element c (eq. 8) and d(t) the
sign of the last nonzero increment of y, shared by every member.
"""

from __future__ import annotations

import numpy as np

from presliding.hysteresis._fused import _FASTMATH, BATCH_CHUNK, BLOCK, _step_direction
from presliding.hysteresis._jit import JitFlags, njit

_JIT: JitFlags = {
    "cache": True,
    "fastmath": _FASTMATH,
    "error_model": "numpy",
    "boundscheck": False,
}


#: time steps per tile: every chunk of the batch runs one tile before the next
#: tile starts, so the output rows of a tile are completed while they are in cache
#: and written back in order (a multiple of BLOCK)
TILE = 64


@njit(**_JIT)
def _load_chunk(y_first, threshold, weight, linear, coulomb, x, b0, buf):  # pragma: no cover
    """Copy members b0 <= b < b0 + BATCH_CHUNK into ``buf`` and clamp their states at y_first.

    Rows of ``buf``: thresholds [0, n), weights [n, 2n), play states [2n, 3n),
    linear 3n, Coulomb 3n + 1, accumulators 3n + 2 ... 3n + 5; missing members
    are padded with weight 0.
    """
    n_el = threshold.shape[0]
    nb_ = min(BATCH_CHUNK, threshold.shape[1] - b0)
    for j in range(n_el):
        for i in range(BATCH_CHUNK):
            buf[j, i] = threshold[j, b0 + i] if i < nb_ else 1.0
            buf[n_el + j, i] = weight[j, b0 + i] if i < nb_ else 0.0
            buf[2 * n_el + j, i] = x[j, b0 + i] if i < nb_ else y_first
    for i in range(BATCH_CHUNK):
        buf[3 * n_el, i] = linear[b0 + i] if i < nb_ else 0.0
        buf[3 * n_el + 1, i] = coulomb[b0 + i] if i < nb_ else 0.0
    # the first sample takes the full clamp; every later update is one-sided
    for j in range(n_el):
        for i in range(BATCH_CHUNK):
            rj = buf[j, i]
            buf[2 * n_el + j, i] = min(max(buf[2 * n_el + j, i], y_first - rj), y_first + rj)


@njit(**_JIT)
def _run_tile(y, t_start, t_stop, up_prev, prev, d, buf, n_el, out, b0):  # pragma: no cover
    """Steps t_start <= t < t_stop of one chunk; returns the direction after them.

    ``up_prev`` is the sample before t_start for the one-sided updates (the
    first sample itself at the start) and ``prev``, ``d`` the input and
    direction before t_start for the Coulomb term.
    """
    nb_ = min(BATCH_CHUNK, out.shape[1] - b0)
    c = 3 * n_el
    last = y.shape[0] - 1
    for t in range(t_start, t_stop, BLOCK):
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
        for i in range(BATCH_CHUNK):
            a = buf[c, i]
            k = buf[c + 1, i]
            buf[c + 2, i] = a * y0 + k * d0
            buf[c + 3, i] = a * y1 + k * d1
            buf[c + 4, i] = a * y2 + k * d2
            buf[c + 5, i] = a * y3 + k * d
        for j in range(n_el):
            for i in range(BATCH_CHUNK):
                rj = buf[j, i]
                wj = buf[n_el + j, i]
                xj = buf[2 * n_el + j, i]
                xj = max(xj, y0 - rj) if up0 else min(xj, y0 + rj)
                buf[c + 2, i] += wj * (y0 - xj)
                xj = max(xj, y1 - rj) if up1 else min(xj, y1 + rj)
                buf[c + 3, i] += wj * (y1 - xj)
                xj = max(xj, y2 - rj) if up2 else min(xj, y2 + rj)
                buf[c + 4, i] += wj * (y2 - xj)
                xj = max(xj, y3 - rj) if up3 else min(xj, y3 + rj)
                buf[c + 5, i] += wj * (y3 - xj)
                buf[2 * n_el + j, i] = xj
        if nb_ == BATCH_CHUNK and t + 3 <= last:
            for k in range(BLOCK):
                for i in range(BATCH_CHUNK):
                    out[t + k, b0 + i] = buf[c + 2 + k, i]
        else:
            for k in range(min(BLOCK, last + 1 - t)):
                for i in range(nb_):
                    out[t + k, b0 + i] = buf[c + 2 + k, i]
    return d


@njit(**_JIT)
def batch_apply(
    y, threshold, weight, linear, coulomb, x, prev, direction, out
):  # pragma: no cover - compiled
    """out[t, b] = a_b·y[t] + c_b·d[t] + Σ_j w[j, b]·(y[t] − x[j, b](t)) for B operators.

    ``threshold``, ``weight`` and the play states ``x`` have shape (N, B)
    (element-major: the batch is contiguous); ``linear`` and ``coulomb`` shape
    (B,); ``out`` shape (T, B). ``x`` is updated in place. `prev` and
    `direction` are the input and the direction of motion before the first
    sample; returns the direction after the last sample.
    """
    n_time = y.shape[0]
    n_el = threshold.shape[0]
    n_batch = threshold.shape[1]
    n_chunk = (n_batch + BATCH_CHUNK - 1) // BATCH_CHUNK
    bufs = np.zeros((n_chunk, 3 * n_el + 6, BATCH_CHUNK))
    for k in range(n_chunk):
        _load_chunk(y[0], threshold, weight, linear, coulomb, x, k * BATCH_CHUNK, bufs[k])
    d = direction
    up_prev = y[0]
    for t0 in range(0, n_time, TILE):
        t1 = min(t0 + TILE, n_time)
        d_tile = d
        for k in range(n_chunk):
            d = _run_tile(y, t0, t1, up_prev, prev, d_tile, bufs[k], n_el, out, k * BATCH_CHUNK)
        up_prev = y[t1 - 1]
        prev = y[t1 - 1]
    for k in range(n_chunk):
        b0 = k * BATCH_CHUNK
        for i in range(min(BATCH_CHUNK, n_batch - b0)):
            for j in range(n_el):
                x[j, b0 + i] = bufs[k, 2 * n_el + j, i]
    return d
