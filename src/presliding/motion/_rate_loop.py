"""The implicit time loop of a mass with GMS, LuGre or Dahl friction (`_rate_step`).

As the PI model's loop (`presliding.motion._implicit_loop`): n equal steps
h = (t_end − t_start)/n fixed by the span and the largest step alone, u at each
step's midpoint, samples between two grid points read off the step that holds
them (θ = (t − t_i)/h): the position y_i + θ·δ, the velocity interpolated
linearly, the acceleration and friction force of the step, and the friction
state advanced exactly over the partial step (travel θ·d in time θ·h, at the
step's velocity); dissipation, viscous loss and work follow the partial step.
A sample on a grid point is that grid point's state, bit for bit.
"""

from __future__ import annotations

import math

import numpy as np

from presliding.hysteresis._jit import njit
from presliding.motion._implicit_loop import BLOCK, fill_applied
from presliding.motion._rate_step import _JIT, commit, rest_force, solve_step, stored_energy


@njit(**_JIT)
def run_rate(  # pragma: no cover - compiled
    family, par, k, c, z, e, m, y, v, last_dir, t0, t_end, n_steps,
    u_kind, u_t, u_val, u_mid, t_eval,
    o_y, o_v, o_a, o_fric, o_fel, o_eel, o_dis, o_vis, o_work, rev_t, rev_y,
):  # fmt: skip
    """n_steps equal implicit steps from t0 to t_end; samples at t_eval (sorted, in range).

    ``z`` and ``e`` (the friction state) are updated in place; ``last_dir`` is the
    direction of the trajectory's last motion (0: none), for counting reversals.
    Samples at t0 get the initial state; their o_a/o_fric are left to the caller.
    Returns (n_rev, rest_start (nan if moving at the end), y, v, last_dir, status):
    status 0, or −3 when a step found no velocity (the motion left the floating-point
    range).
    """
    n_eval = t_eval.shape[0]
    h = (t_end - t0) / n_steps
    inv_h = 1.0 / h
    zp = np.empty_like(z)
    ep = np.empty_like(e)
    fel = rest_force(family, par, z)
    dis = vis = work = 0.0
    n_rev = 0
    cap = rev_t.shape[0]
    rest_start = np.nan
    ptr = 0
    u_blk = np.empty(BLOCK)
    ie = 0
    while ie < n_eval and t_eval[ie] <= t0:
        ie = _grid_sample(family, par, k, z, fel, y, v, dis, vis, work, ie, t0, t_eval, o_y,
                          o_v, o_fel, o_eel, o_dis, o_vis, o_work)  # fmt: skip
    t_i = t0
    for i_blk in range(0, n_steps, BLOCK):
        n_blk = min(BLOCK, n_steps - i_blk)
        ptr = fill_applied(u_blk, i_blk, n_blk, u_kind, u_t, u_val, u_mid, t0, h, ptr)
        for j_blk in range(n_blk):
            i = i_blk + j_blk
            t_next = t0 + (i + 1) * h if i + 1 < n_steps else t_end
            u = u_blk[j_blk]
            delta = solve_step(family, par, k, c, z, e, m, v, u, h)
            if not math.isfinite(delta):
                return n_rev, rest_start, y, v, last_dir, -3
            d = abs(delta)
            s = 1.0 if delta > 0.0 else (-1.0 if delta < 0.0 else 0.0)
            v_new = delta * inv_h
            acc = (v_new - v) * inv_h
            if d == 0.0 and rest_start != rest_start:
                rest_start = t_i
            while ie < n_eval and t_eval[ie] < t_next:  # samples strictly inside the step
                th = (t_eval[ie] - t_i) * inv_h
                zp[:] = z
                ep[:] = e
                fel_p, lost, vloss = commit(family, par, k, c, zp, ep, s, th * d, th * h)
                o_y[ie] = y + th * delta
                o_v[ie] = v + th * (v_new - v)
                o_a[ie] = acc
                o_fric[ie] = u - m * acc
                o_fel[ie] = fel_p
                o_eel[ie] = stored_energy(family, par, k, zp)
                o_dis[ie] = dis + lost
                o_vis[ie] = vis + vloss
                o_work[ie] = work + th * u * delta
                ie += 1
            if d != 0.0:
                fel, lost, vloss = commit(family, par, k, c, z, e, s, d, h)
                y += delta
                dis += lost
                vis += vloss
                work += u * delta
                if s != last_dir:
                    if last_dir != 0.0:
                        if n_rev < cap:
                            rev_t[n_rev] = t_i
                            rev_y[n_rev] = y - delta
                        n_rev += 1
                    last_dir = s
                rest_start = np.nan
            v = v_new
            while ie < n_eval and t_eval[ie] <= t_next:  # samples on the grid point
                o_a[ie] = acc
                o_fric[ie] = u - m * acc
                ie = _grid_sample(family, par, k, z, fel, y, v, dis, vis, work, ie, t_next,
                                  t_eval, o_y, o_v, o_fel, o_eel, o_dis, o_vis, o_work)  # fmt: skip
            t_i = t_next
    return n_rev, rest_start, y, v, last_dir, 0


@njit(**_JIT)
def _grid_sample(family, par, k, z, fel, y, v, dis, vis, work, ie, t, t_eval, o_y, o_v, o_fel,
                 o_eel, o_dis, o_vis, o_work):  # fmt: skip  # pragma: no cover - compiled
    """Write the samples at grid time t (the state after it); returns the next index."""
    eel = stored_energy(family, par, k, z)
    while ie < t_eval.shape[0] and t_eval[ie] <= t:
        o_y[ie] = y
        o_v[ie] = v
        o_fel[ie] = fel
        o_eel[ie] = eel
        o_dis[ie] = dis
        o_vis[ie] = vis
        o_work[ie] = work
        ie += 1
    return ie
