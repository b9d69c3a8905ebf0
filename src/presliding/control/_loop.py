"""Compiled sampled-data loops: a discrete controller, zero-order hold, a mass with PI friction.

Between two sample instants the applied force is constant, so the motion over
one period is the exact event-driven solution of eq. 17 (`presliding.motion._event`,
called here for one period at a time). At t_k the controller reads y_k, updates
its state and holds u_k until t_k + dt. The controller forms:

* kind 0, a PID: ``p`` = [kp, ki, kd, dt, T_f, low, high, anti-windup, T_t,
  on-error] (`PID.parameters`), state ``s`` = [I, D, s_prev, started];
* kind 1, state space: x ← A x + B w, u = sat(C x + D w), w = e or (r, y).

`pid_output` and `plant_period` are the single steps that
`presliding.control.iosys` calls too, so that a python-control loop and these
kernels do the same arithmetic.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from presliding.hysteresis._jit import JitFlags, njit
from presliding.motion._event import damped_flag, run_events, run_events_sided

_JIT: JitFlags = {"cache": True, "error_model": "numpy"}
_JIT_PARALLEL: JitFlags = {"cache": True, "error_model": "numpy", "parallel": True}
REVERSALS_PER_PERIOD = 64


@njit(refcount=False, **_JIT)
def pid_output(p, s, ref, y, ff):  # pragma: no cover - compiled
    """u_k of the PID at (r_k, y_k) with feedforward ff; updates the state s in place."""
    kp, ki, kd, dt, tf, low, high = p[0], p[1], p[2], p[3], p[4], p[5], p[6]
    e = ref - y
    sig = e if p[9] != 0.0 else -y
    prev = s[2] if s[3] != 0.0 else sig
    d = (tf * s[1] + kd * (sig - prev)) / (tf + dt)
    v = kp * e + s[0] + d + ff
    u = min(max(v, low), high)
    inc = ki * dt * e
    if p[7] == 0.0:  # clamping: hold the integral while it drives further into saturation
        if u != v and e * (v - u) > 0.0:
            inc = 0.0
    elif p[7] == 1.0:  # back-calculation
        inc += dt / p[8] * (u - v)
    s[0] += inc
    s[1] = d
    s[2] = sig
    s[3] = 1.0
    return u


@njit(refcount=False, **_JIT)
def ss_output(a, b, c, d, x, low, high, ref, y, ff, w, tmp):  # pragma: no cover - compiled
    """u_k of the state-space controller; x advanced in place (w, tmp: scratch)."""
    if d.shape[1] == 1:
        w[0] = ref - y
    else:
        w[0] = ref
        w[1] = y
    n = x.shape[0]
    v = ff
    for j in range(n):
        v += c[0, j] * x[j]
    for i in range(d.shape[1]):
        v += d[0, i] * w[i]
    for i in range(n):
        acc = 0.0
        for j in range(n):
            acc += a[i, j] * x[j]
        for j in range(d.shape[1]):
            acc += b[i, j] * w[j]
        tmp[i] = acc
    for i in range(n):
        x[i] = tmp[i]
    return min(max(v, low), high)


@njit(**_JIT)
def acceleration(m, c1, sigma, fel, v, u):  # pragma: no cover - compiled
    """ÿ from eq. 17 with the set-valued sign and σ·ẏ (at rest: 0 while |u − F_el| <= c1)."""
    if v > 0.0:
        return (u - c1 - sigma * v - fel) / m
    if v < 0.0:
        return (u + c1 - sigma * v - fel) / m
    g = u - fel
    if abs(g) <= c1:
        return 0.0
    return (g - math.copysign(c1, g)) / m


@njit(**_JIT)
def acceleration_sided(m, c1p, c1n, sp, sn, fel, v, u):  # pragma: no cover - compiled
    """`acceleration` with asymmetric friction: c1⁺, σ⁺ while v > 0, c1⁻, σ⁻ while v < 0, and
    rest while −c1⁻ <= u − F_el <= c1⁺ (equal sides: the same arithmetic as `acceleration`)."""
    if v > 0.0:
        return (u - c1p - sp * v - fel) / m
    if v < 0.0:
        return (u + c1n - sn * v - fel) / m
    g = u - fel
    if -c1n <= g and g <= c1p:
        return 0.0
    return (g - c1p) / m if g > 0.0 else (g + c1n) / m


@njit(**_JIT)
def plant_period(m, c1, sigma, k, r, f, y, v, last_dir, u, t0, t1, max_events,
                 damped):  # fmt: skip  # pragma: no cover
    """The exact motion over [t0, t1] under a constant u (viscous σ); f updated in place.
    ``damped``: None when σ = 0, else True (`presliding.motion._event`).

    Returns (status, y, v, last_dir, n_events).
    """
    u_t = np.array([t0])
    u_val = np.array([u])
    none = np.empty(0)
    rev = np.empty(REVERSALS_PER_PERIOD)
    res = run_events(m, c1, k, r, f, y, v, last_dir, u_t, u_val, none, t1, max_events,
                     none, none, none, none, none, none, none, none, rev, rev, sigma, none,
                     none, damped)  # fmt: skip
    return res[0], res[4], res[5], res[6], res[7]


def run_loop(
    m, c1, sigma, k, r, f, y, v, last_dir, kind, p, s, a, b, c, d, x, ref, ff, t0, dt, sub,
    max_events, o_y, o_v, o_a, o_fel, o_u, o_eel, o_dis, o_work, o_vis, o_ctrl, rev_t, rev_y,
    c1n, sigman, rn,
):  # fmt: skip
    """K = ref.shape[0] − 1 periods of the closed loop; samples at t0 + (k + j/sub)·dt.

    ``c1``, ``sigma``, ``r`` act while the mass slides in +y, ``c1n``, ``sigman``,
    ``rn`` in −y (asymmetric friction; the same values for a symmetric model).

    ``ref`` and ``ff`` hold r_k, u_ff,k at the K + 1 instants. Outputs have
    K·sub + 1 entries; ``o_ctrl`` holds u_k at the K + 1 instants (NaN after a
    failure). Returns (status, n_rev, rest_start, y, v, last_dir, n_events,
    periods done).

    The scratch arrays are made here, in Python, and the compiled `_loop_body` is
    called directly: a compiled wrapper would cost a cold cache a second LLVM
    optimisation of the whole loop and event kernel for a few allocations.
    """
    w = np.empty(2)
    tmp = np.empty(x.shape[0])
    rt = np.empty(REVERSALS_PER_PERIOD)
    ry = np.empty(REVERSALS_PER_PERIOD)
    u_t = np.empty(1)
    u_val = np.empty(1)
    te = np.empty(sub)
    none = np.empty(0)  # no piece record
    return _loop_body(
        m, c1, sigma, k, r, f, y, v, last_dir, kind, p, s, a, b, c, d, x, ref, ff, t0, dt, sub,
        max_events, o_y, o_v, o_a, o_fel, o_u, o_eel, o_dis, o_work, o_vis, o_ctrl, rev_t,
        rev_y, w, tmp, rt, ry, u_t, u_val, te, none, c1n, sigman, rn,
        damped_flag(sigma, sigman),
    )  # fmt: skip


# Without reference counting (no array is allocated here): the per-period views of the
# outputs and the calls of the event kernel then cost no atomic operations
@njit(refcount=False, **_JIT)
def _loop_body(  # pragma: no cover - compiled
    m, c1, sigma, k, r, f, y, v, last_dir, kind, p, s, a, b, c, d, x, ref, ff, t0, dt, sub,
    max_events, o_y, o_v, o_a, o_fel, o_u, o_eel, o_dis, o_work, o_vis, o_ctrl, rev_t, rev_y,
    w, tmp, rt, ry, u_t, u_val, te, none, c1n, sigman, rn, damped,
):  # fmt: skip
    """The periods of `run_loop`, with its scratch arrays handed in (``damped``: None when
    σ = 0 on both sides, else True; `presliding.motion._event`)."""
    n_k = ref.shape[0] - 1
    low, high = (p[5], p[6]) if kind == 0 else (p[0], p[1])
    n_rev = 0
    n_ev = 0
    dis = 0.0
    work = 0.0
    vis = 0.0
    rest = np.nan
    status = 0
    done = 0
    for kk in range(n_k + 1):
        if kind == 0:
            u = pid_output(p, s, ref[kk], y, ff[kk])
        else:
            u = ss_output(a, b, c, d, x, low, high, ref[kk], y, ff[kk], w, tmp)
        o_ctrl[kk] = u
        if kk == n_k:
            break
        tk = t0 + kk * dt
        for j in range(sub):
            te[j] = tk + j * (dt / sub)
        i0 = kk * sub
        u_t[0] = tk
        u_val[0] = u
        res = run_events_sided(m, c1, c1n, k, r, rn, f, y, v, last_dir, u_t, u_val, te,
                               tk + dt, max_events - n_ev, o_y[i0:], o_v[i0:], o_a[i0:],
                               o_fel[i0:], o_u[i0:], o_eel[i0:], o_dis[i0:], o_work[i0:], rt,
                               ry, sigma, sigman, o_vis[i0:], none, damped)  # fmt: skip
        st, n_s, nr, stop, y, v, last_dir, ne, dd, ww, _, vv = res
        for j in range(n_s):
            o_dis[i0 + j] += dis
            o_work[i0 + j] += work
            o_vis[i0 + j] += vis
        dis += dd
        work += ww
        vis += vv
        n_ev += ne
        for j in range(min(nr, REVERSALS_PER_PERIOD)):
            if n_rev + j < rev_t.shape[0]:
                rev_t[n_rev + j] = rt[j]
                rev_y[n_rev + j] = ry[j]
        n_rev += nr
        if st != 0:
            status = st
            break
        if np.isnan(stop):
            rest = np.nan
        elif np.isnan(rest) or stop > tk:
            rest = stop
        done = kk + 1
    if status == 0:
        # the last instant: state at t_K, acceleration under u_K
        i = n_k * sub
        fel = 0.0
        eel = 0.0
        for j in range(k.shape[0]):
            fel += k[j] * f[j]
            eel += k[j] * f[j] * f[j]
        o_y[i] = y
        o_v[i] = v
        o_a[i] = acceleration_sided(m, c1, c1n, sigma, sigman, fel, v, o_ctrl[n_k])
        o_fel[i] = fel
        o_u[i] = o_ctrl[n_k]
        o_eel[i] = 0.5 * eel
        o_dis[i] = dis
        o_work[i] = work
        o_vis[i] = vis
    return status, n_rev, rest, y, v, last_dir, n_ev, done


@njit(**_JIT_PARALLEL)
def run_loop_batch(  # pragma: no cover - compiled
    m, c1, sigma, k, r, f0, y0, v0, d0, p_all, s0, ref, ff, t0, dt, max_events, i_from,
    o_y, o_u, status, n_rev, e_rms, e_max, half_range, y_end, v_end, damped,
):  # fmt: skip
    """Many PID loops (one row of ``p_all`` each), in parallel; positions and u at the
    K + 1 instants when ``o_y`` has B rows (else summaries only), and summaries of
    the samples from index ``i_from`` on: rms and max |e|, half the range of y (``damped``:
    None when σ = 0, else True; `presliding.motion._event`)."""
    n_b = p_all.shape[0]
    n_k = ref.shape[0] - 1
    full = o_y.shape[0] == n_b
    for ib in nb.prange(n_b):
        p = p_all[ib].copy()
        s = s0.copy()
        f = f0.copy()
        y = y0
        v = v0
        last_dir = d0
        rt = np.empty(REVERSALS_PER_PERIOD)
        none = np.empty(0)
        u_t = np.empty(1)
        u_val = np.empty(1)
        st = 0
        nr_all = 0
        ne_all = 0
        sq = 0.0
        big = 0.0
        lo = np.inf
        hi = -np.inf
        cnt = 0
        for kk in range(n_k + 1):
            u = pid_output(p, s, ref[kk], y, ff[kk])
            if kk >= i_from:
                e = ref[kk] - y
                sq += e * e
                big = max(big, abs(e))
                lo = min(lo, y)
                hi = max(hi, y)
                cnt += 1
            if full:
                o_y[ib, kk] = y
                o_u[ib, kk] = u
            if kk == n_k:
                break
            tk = t0 + kk * dt
            u_t[0] = tk
            u_val[0] = u
            res = run_events(m, c1, k, r, f, y, v, last_dir, u_t, u_val, none, tk + dt,
                             max_events - ne_all, none, none, none, none, none, none, none,
                             none, rt, rt, sigma, none, none, damped)  # fmt: skip
            st = res[0]
            nr_all += res[2]
            y, v, last_dir = res[4], res[5], res[6]
            ne_all += res[7]
            if st != 0:
                break
        status[ib] = st
        n_rev[ib] = nr_all
        e_rms[ib] = math.sqrt(sq / cnt) if cnt else np.nan
        e_max[ib] = big if cnt else np.nan
        half_range[ib] = 0.5 * (hi - lo) if cnt else np.nan
        y_end[ib] = y
        v_end[ib] = v
