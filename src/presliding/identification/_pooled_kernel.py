"""Compiled batched responses for the pooled output-error fit (eq. 17, many records).

`pooled_responses` simulates every record of a pooled fit for several parameter
sets in one compiled call: task (p, i) runs the exact event kernel
(`presliding.motion._event.run_events`) for parameter set p on record i, in
parallel over all tasks (``prange``), and writes position and velocity into
row p of flat output arrays, each record at its own offset. One call evaluates
the residual of every record; one more evaluates all the finite-difference
columns of a Jacobian.

Record memories: ``mode`` 0 relaxed, 1 on the branch from saturation in
−direction with elastic force fraction·F_m, 2 along the virgin curve
(`presliding.friction.preload`).
"""

from __future__ import annotations

import numba as nb
import numpy as np

from presliding.friction.preload import preload_deformation
from presliding.hysteresis._jit import njit
from presliding.motion._event import run_events

RELAXED, BRANCH, VIRGIN = 0, 1, 2


def _pooled_responses(  # pragma: no cover - compiled
    mass, c1, sigma, k, r, offset, y0, v0, fraction, mode, direction,
    t_all, t_off, ut_all, uv_all, u_off, max_events, o_y, o_v, status, n_rev,
):  # fmt: skip
    """Positions and velocities of every record for every parameter set.

    Parameters (P parameter sets, R records, N elements, S samples in all):
    mass, c1, sigma (viscous), offset (P,); k, r (P, N); y0, v0, fraction (P, R); mode,
    direction (R,); t_all (S,) sample times, record i at t_off[i]:t_off[i+1];
    ut_all, uv_all the zero-order-hold pieces of u, record i at
    u_off[i]:u_off[i+1]. Outputs o_y, o_v (P, S); status, n_rev (P, R).
    """
    n_par = mass.shape[0]
    n_rec = t_off.shape[0] - 1
    n_el = k.shape[1]
    for task in nb.prange(n_par * n_rec):
        p = task // n_rec
        i = task % n_rec
        a, b = t_off[i], t_off[i + 1]
        ua, ub = u_off[i], u_off[i + 1]
        t_eval = t_all[a:b]
        u_t = ut_all[ua:ub]
        u_val = uv_all[ua:ub] - offset[p]
        f = np.zeros(n_el)
        if mode[i] != RELAXED:
            preload_deformation(k[p], r[p], fraction[p, i], direction[i], mode[i] == BRANCH, f)
        s = 1.0 if v0[p, i] > 0.0 else (-1.0 if v0[p, i] < 0.0 else 0.0)
        last_dir = s
        if s == 0.0 and mode[i] == BRANCH:
            last_dir = direction[i]
        n_t = b - a
        scratch = np.empty((6, n_t))
        none = np.empty(0)  # no viscous record, no piece record
        rev = np.empty((2, 8))
        res = run_events(
            mass[p], c1[p], k[p], r[p], f, y0[p, i], v0[p, i], last_dir, u_t, u_val, t_eval,
            t_eval[n_t - 1], max_events, o_y[p, a:b], o_v[p, a:b], scratch[0], scratch[1],
            scratch[2], scratch[3], scratch[4], scratch[5], rev[0], rev[1], sigma[p],
            none, none,
        )  # fmt: skip
        filled = res[1]
        for j in range(filled, n_t):  # only after an event limit: hold the last values
            o_y[p, a + j] = o_y[p, a + filled - 1] if filled > 0 else y0[p, i]
            o_v[p, a + j] = o_v[p, a + filled - 1] if filled > 0 else v0[p, i]
        status[p, i] = res[0]
        n_rev[p, i] = res[2]


def _assemble(o_y, o_v, index, w_v, w_y, data, out):  # pragma: no cover - compiled
    """out[p, i] = w_v[i]·o_v[p, index[i]] + w_y[i]·o_y[p, index[i]] − data[i]."""
    n_par, n_res = out.shape
    for p in range(n_par):
        for i in range(n_res):
            j = index[i]
            out[p, i] = w_v[i] * o_v[p, j] + w_y[i] * o_y[p, j] - data[i]


# Parallel forms for batches of parameter sets (a Jacobian); serial forms for one
# set, where a parallel region costs more than it saves on a busy machine.
pooled_responses_parallel = njit(cache=True, parallel=True)(_pooled_responses)
pooled_responses_serial = njit(cache=True)(_pooled_responses)
assemble = njit(cache=True)(_assemble)  # memory bound: serial is as fast


def pooled_responses(mass, *args):
    """`_pooled_responses`, in parallel for several parameter sets."""
    kernel = pooled_responses_parallel if mass.shape[0] > 1 else pooled_responses_serial
    kernel(mass, *args)
