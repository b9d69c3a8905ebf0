"""The implicit time loop behind `simulate`: uniform steps, u(t) in the loop, dense samples.

The step sequence is fixed by the time span and the largest step alone: n equal
steps h = (t_end − t_start)/n, n = ceil((t_end − t_start)/step), so the output
grid never changes the computed motion. The applied force of step i is u at its
midpoint, evaluated inside the loop for a constant or sampled u (no array of
step times is built) or read from an array of midpoint values for a callable u.

Samples between two grid points are read off the step that contains them
(θ = (t − t_i)/h in (0, 1)): the position moves linearly, y_i + θ·δ (the
backward Euler path, y' = v_{i+1} on the step), the velocity is interpolated
linearly between v_i and v_{i+1}, the acceleration and friction force are those
of the step, and the memory is the exact play update of the partial increment
θ·δ (the motion within a step is monotone); dissipation, viscous loss and work
follow the same partial increment. A sample on a grid point is that grid
point's state, bit for bit.

The step itself is `presliding.motion._implicit` (the exact solution of the
inclusion, Newton's method on the piecewise-linear elastic force).
"""

from __future__ import annotations

import numpy as np

from presliding.hysteresis._jit import njit
from presliding.motion._implicit import _JIT, _newton_walk

U_CONSTANT, U_ZOH, U_LINEAR, U_ARRAY = 0, 1, 2, 3
BLOCK = 256  # steps per block of applied-force values


@njit(**_JIT)
def fill_applied(buf, i0, count, u_kind, u_t, u_val, u_mid, t0, h, ptr):  # pragma: no cover
    """buf[j] = u at the midpoint t0 + (i0 + j + 0.5)·h of step i0 + j, j < count.

    Samples are held (zoh) or interpolated linearly (as `numpy.interp`; the last
    value held after the last sample); ``ptr`` is the index of the sample at or
    before the last midpoint (times only increase). Returns the new ``ptr``.
    The loops read u from a block filled here every BLOCK steps, which keeps the
    dispatch on the kind of u out of the step itself.
    """
    if u_kind == U_CONSTANT:
        for j in range(count):
            buf[j] = u_val[0]
        return ptr
    if u_kind == U_ARRAY:
        for j in range(count):
            buf[j] = u_mid[i0 + j]
        return ptr
    n = u_t.shape[0]
    for j in range(count):
        t = t0 + (i0 + j + 0.5) * h
        while ptr + 1 < n and u_t[ptr + 1] <= t:
            ptr += 1
        if u_kind == U_ZOH or ptr + 1 >= n:
            buf[j] = u_val[ptr]
        else:
            t_a = u_t[ptr]
            slope = (u_val[ptr + 1] - u_val[ptr]) / (u_t[ptr + 1] - t_a)
            buf[j] = slope * (t - t_a) + u_val[ptr]
    return ptr


@njit(**_JIT)
def bank_sums(k, r, rn, f):  # pragma: no cover - compiled
    """F_el, Σk saturated at +r and −rn, their counts and the nearest distances to them;
    f untouched (``rn`` is ``r`` for symmetric friction).

    Deformations at or beyond ±r_j (a given memory may exceed r_j by rounding)
    count as saturated; nothing is clipped, so a mass that never moves keeps
    its memory bit for bit.
    """
    fel = kpos = kneg = 0.0
    npos = nneg = 0
    dpos = dneg = np.inf
    for j in range(k.shape[0]):
        fj = f[j]
        rj = r[j]
        fel += k[j] * fj
        if fj >= rj:
            kpos += k[j]
            npos += 1
        else:
            dpos = min(dpos, rj - fj)
        rj = rn[j]
        if fj <= -rj:
            kneg += k[j]
            nneg += 1
        else:
            dneg = min(dneg, rj + fj)
    return fel, kpos, kneg, npos, nneg, dpos, dneg


@njit(**_JIT)
def _partial(k, r, rn, f, delta):  # pragma: no cover - compiled
    """F_el, ½Σk f², plastic dissipation after the partial increment delta (f untouched)."""
    fel = eel = dpl = 0.0
    for j in range(k.shape[0]):
        fj = f[j] + delta
        rj = r[j]
        if fj > rj:
            dpl += k[j] * rj * (fj - max(f[j], rj))
            fj = rj
        elif fj < -rn[j]:
            rj = rn[j]
            dpl += k[j] * rj * (min(f[j], -rj) - fj)
            fj = -rj
        fel += k[j] * fj
        eel += k[j] * fj * fj
    return fel, 0.5 * eel, dpl


@njit(**_JIT)
def run_uniform(  # pragma: no cover - compiled
    m, c1, sigma, k, r, f, y, v, last_dir, t0, t_end, n_steps,
    u_kind, u_t, u_val, u_mid, t_eval,
    o_y, o_v, o_a, o_fric, o_fel, o_eel, o_dis, o_vis, o_work, rev_t, rev_y,
):  # fmt: skip
    """`run_uniform_sided` with equal sides: symmetric friction."""
    return run_uniform_sided(
        m, c1, c1, sigma, sigma, k, r, r, f, y, v, last_dir, t0, t_end, n_steps,
        u_kind, u_t, u_val, u_mid, t_eval,
        o_y, o_v, o_a, o_fric, o_fel, o_eel, o_dis, o_vis, o_work, rev_t, rev_y,
    )  # fmt: skip


@njit(**_JIT)
def run_uniform_sided(  # pragma: no cover - compiled
    m, c1p, c1n, sigmap, sigman, k, r, rn, f, y, v, last_dir, t0, t_end, n_steps,
    u_kind, u_t, u_val, u_mid, t_eval,
    o_y, o_v, o_a, o_fric, o_fel, o_eel, o_dis, o_vis, o_work, rev_t, rev_y,
):  # fmt: skip
    """n_steps equal implicit steps from t0 to t_end; samples at t_eval (sorted, in range).

    Asymmetric friction: c1p, sigmap and r act in +y, c1n, sigman and rn in −y;
    the mass sticks while −c1n <= m·v/h + u − F_el <= c1p. Equal sides compute
    exactly as the symmetric scheme.

    ``f`` is updated in place. ``last_dir`` is the direction of the trajectory's
    last motion (0: none), for counting reversals (sign changes of the velocity).
    Samples at t0 get the initial state; their o_a/o_fric are left to the
    caller. Returns (n_rev, rest_start (nan if moving at the end), y, v,
    last_dir, dissipated, work, viscous dissipation).
    """
    n_el = k.shape[0]
    n_eval = t_eval.shape[0]
    h = (t_end - t0) / n_steps
    inv_h = 1.0 / h
    m_h = m * inv_h
    mh2p = m_h * inv_h + sigmap * inv_h  # m/h² + σ/h
    mh2n = m_h * inv_h + sigman * inv_h
    ktot = csum = csumn = 0.0  # Σk, Σ k·r⁺, Σ k·r⁻
    for j in range(n_el):
        ktot += k[j]
        csum += k[j] * r[j]
        csumn += k[j] * rn[j]
    fel, kpos, kneg, npos, nneg, dpos, dneg = bank_sums(k, r, rn, f)
    c1 = c1p
    sigma = sigmap
    dis = vis = work = 0.0
    n_rev = 0
    cap = rev_t.shape[0]
    rest_start = np.nan
    ptr = 0
    u_blk = np.empty(BLOCK)
    ie = 0
    while ie < n_eval and t_eval[ie] <= t0:
        ie = _grid_sample(k, f, y, v, dis, vis, work, ie, t0, t_eval, o_y, o_v, o_fel, o_eel,
                          o_dis, o_vis, o_work)  # fmt: skip
    t_i = t0
    for i_blk in range(0, n_steps, BLOCK):
        n_blk = min(BLOCK, n_steps - i_blk)
        ptr = fill_applied(u_blk, i_blk, n_blk, u_kind, u_t, u_val, u_mid, t0, h, ptr)
        for j_blk in range(n_blk):
            i = i_blk + j_blk
            t_next = t0 + (i + 1) * h if i + 1 < n_steps else t_end
            u = u_blk[j_blk]
            g = m_h * v + u - fel
            s = 0.0
            d = 0.0
            if -c1n <= g and g <= c1p:  # sticks: y and the memory stay exactly as they are
                v_new = 0.0
                if rest_start != rest_start:
                    rest_start = t_i
            else:
                if g > 0.0:
                    s = 1.0
                    c1, sigma, mh2, rs = c1p, sigmap, mh2p, r
                    b = g - c1
                    slope = mh2 + ktot - kpos
                    dist = dpos
                else:
                    s = -1.0
                    c1, sigma, mh2, rs = c1n, sigman, mh2n, rn
                    b = -g - c1
                    slope = mh2 + ktot - kneg
                    dist = dneg
                d = b / slope  # exact unless an element reaches its threshold on the way
                if d >= dist:
                    d = _newton_walk(mh2, k, rs, f, s, b, slope, d)
                v_new = s * d * inv_h
            acc = (v_new - v) * inv_h
            delta = s * d
            # samples strictly inside the step, from the memory before it
            while ie < n_eval and t_eval[ie] < t_next:
                th = (t_eval[ie] - t_i) * inv_h
                if d == 0.0:
                    fel_p, eel_p, dpl_p = fel, _energy(k, f), 0.0
                else:
                    fel_p, eel_p, dpl_p = _partial(k, r, rn, f, th * delta)
                o_y[ie] = y + th * delta
                o_v[ie] = v + th * (v_new - v)
                o_a[ie] = acc
                o_fric[ie] = u - m * acc
                o_fel[ie] = fel_p
                o_eel[ie] = eel_p
                o_dis[ie] = dis + th * c1 * d + dpl_p
                o_vis[ie] = vis + th * sigma * d * d * inv_h
                o_work[ie] = work + th * u * delta
                ie += 1
            if d != 0.0:
                if (npos if s > 0.0 else nneg) == n_el:
                    # every element slides on and stays at s·r_j: the memory, F_el and the
                    # stiffness sums are unchanged; each element dissipates c_j·d
                    dplastic = (csum if s > 0.0 else csumn) * d
                else:
                    fel = kpos = kneg = dplastic = 0.0
                    dpos = dneg = np.inf
                    npos = nneg = 0
                    for j in range(n_el):
                        fj = f[j] + delta
                        rj = r[j]
                        if fj >= rj:
                            dplastic += k[j] * rj * (fj - max(f[j], rj))
                            fj = rj
                            kpos += k[j]
                            npos += 1
                        elif fj <= -rn[j]:
                            rj = rn[j]
                            dplastic += k[j] * rj * (min(f[j], -rj) - fj)
                            fj = -rj
                            kneg += k[j]
                            nneg += 1
                        f[j] = fj
                        fel += k[j] * fj
                        dpos = min(dpos, r[j] - fj if fj < r[j] else np.inf)
                        dneg = min(dneg, rn[j] + fj if fj > -rn[j] else np.inf)
                y += delta
                dis += c1 * d + dplastic
                vis += sigma * d * d * inv_h
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
                ie = _grid_sample(k, f, y, v, dis, vis, work, ie, t_next, t_eval, o_y, o_v, o_fel,
                                  o_eel, o_dis, o_vis, o_work)  # fmt: skip
            t_i = t_next
    return n_rev, rest_start, y, v, last_dir, dis, work, vis


@njit(**_JIT)
def _energy(k, f):  # pragma: no cover - compiled
    eel = 0.0
    for j in range(k.shape[0]):
        eel += k[j] * f[j] * f[j]
    return 0.5 * eel


@njit(**_JIT)
def _grid_sample(k, f, y, v, dis, vis, work, ie, t, t_eval, o_y, o_v, o_fel, o_eel, o_dis,
                 o_vis, o_work):  # fmt: skip  # pragma: no cover - compiled
    """Write the samples at grid time t (the state after it); returns the next index."""
    fel = 0.0
    for j in range(k.shape[0]):
        fel += k[j] * f[j]
    eel = _energy(k, f)
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


@njit(cache=True)
def energy_terms(m, e0, y, v, e_el, dis, vis, work):  # pragma: no cover - compiled
    """Kinetic energy ½·m·v² and the balance residual kinetic + elastic + dissipated +
    viscous − work − e0 of the samples, in one pass; and whether the positions,
    velocities and residuals are all finite."""
    kinetic = np.empty(v.shape[0])
    residual = np.empty(v.shape[0])
    finite = True
    for i in range(v.shape[0]):
        kinetic[i] = 0.5 * m * (v[i] * v[i])
        residual[i] = kinetic[i] + e_el[i] + dis[i] + vis[i] - work[i] - e0
        finite &= np.isfinite(y[i] + residual[i])
    return kinetic, residual, finite


@njit(cache=True)
def applied_at_times(u_kind, u_t, u_val, t, out):  # pragma: no cover - compiled
    """out[i] = u(t[i]) for a constant or sampled u (t increasing), as `Forcing.__call__`."""
    ptr = 0
    n = u_t.shape[0]
    for i in range(t.shape[0]):
        if u_kind == U_CONSTANT:
            out[i] = u_val[0]
            continue
        ti = t[i]
        while ptr + 1 < n and u_t[ptr + 1] <= ti:
            ptr += 1
        if u_kind == U_ZOH or ptr + 1 >= n or ti < u_t[ptr]:
            out[i] = u_val[ptr]
        else:
            t_a = u_t[ptr]
            out[i] = (u_val[ptr + 1] - u_val[ptr]) / (u_t[ptr + 1] - t_a) * (ti - t_a) + u_val[ptr]
