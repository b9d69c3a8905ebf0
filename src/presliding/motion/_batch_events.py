"""Compiled batches of exact motions: many parameter sets or initial velocities at once.

Each member runs the exact event kernel (`presliding.motion._event.run_events`);
`batch_events` runs a range of members with the GIL released, and the caller
spreads ranges over threads (a serial loop compiles in a fraction of the time of
a ``prange`` loop, which matters on a cold cache); `free_kernel` is the single-run form used inside
least-squares losses: it samples position and velocity on a uniform time grid
with no Python work per call beyond argument checks.
"""

from __future__ import annotations

import numpy as np

from presliding.hysteresis._jit import njit
from presliding.motion._event import run_events, run_events_sided


@njit(cache=True)
def free_kernel(
    m, c1, sigma, k, r, f0, y0, v0, last_dir, u, dt, n_samples, max_events, damped
):  # pragma: no cover
    """Position and velocity at t = i·dt, i < n_samples, under a constant force u.

    Returns (position, velocity, status, stop_time (nan if moving), n_reversals,
    n_filled, t_last): only the first ``n_filled`` samples are computed (all of
    them when status is 0; fewer when the event limit stopped the run at t_last).
    ``damped``: None when σ = 0, else True (`presliding.motion._event`).
    """
    t_eval = np.arange(n_samples) * dt
    t_end = max(t_eval[-1], dt)
    o_y = np.empty(n_samples)
    o_v = np.empty(n_samples)
    scratch = np.empty((6, n_samples))
    rev = np.empty((2, 64))
    none = np.empty(0)  # no viscous record, no piece record
    f = f0.copy()
    u_t = np.zeros(1)
    u_val = np.full(1, u)
    res = run_events(
        m, c1, k, r, f, y0, v0, last_dir, u_t, u_val, t_eval, t_end, max_events,
        o_y, o_v, scratch[0], scratch[1], scratch[2], scratch[3], scratch[4], scratch[5],
        rev[0], rev[1], sigma, none, none, damped,
    )  # fmt: skip
    return o_y, o_v, res[0], res[3], res[2], res[1], res[10]


@njit(cache=True, nogil=True)
def batch_events(  # pragma: no cover - compiled
    b0, b1, m, c1, sigma, k, r, f0, y0, v0, last_dir, u_t, u_val, t_eval, t_end, max_events,
    o_y, o_v, stop, n_rev, status, y_end, v_end, damped,
):  # fmt: skip
    """Run members b0 <= b < b1, member b with m[b], c1[b], sigma[b], k[b], r[b], f0[b],
    y0[b], v0[b], last_dir[b]; releases the GIL (threads run disjoint ranges). ``damped``:
    None when every sigma[b] is 0, else True (`presliding.motion._event`)."""
    n_t = t_eval.shape[0]
    scratch = np.empty((6, n_t))  # samples nobody reads
    none = np.empty(0)  # no viscous record, no piece record
    rev = np.empty((2, 64))
    for b in range(b0, b1):
        f = f0[b].copy()
        # the sided kernel itself (equal sides), which `simulate` compiles already: through
        # the `run_events` wrapper a cold cache would optimise the whole event kernel again
        res = run_events_sided(
            m[b], c1[b], c1[b], k[b], r[b], r[b], f, y0[b], v0[b], last_dir[b], u_t, u_val,
            t_eval, t_end, max_events, o_y[b], o_v[b], scratch[0], scratch[1], scratch[2],
            scratch[3], scratch[4], scratch[5], rev[0], rev[1], sigma[b], sigma[b], none, none,
            damped,
        )  # fmt: skip
        status[b] = res[0]
        n_rev[b] = res[2]
        stop[b] = res[3]
        y_end[b] = res[4]
        v_end[b] = res[5]
