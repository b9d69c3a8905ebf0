"""Implicit time stepping of eq. 17 with exact stiction (first order, stable for any step).

Each step of size h solves the monotone inclusion for the new velocity v'

    m·(v' − v)/h + σ·v' + F_el(y + h·v') + c1·Sign(v') ∋ u,

with Sign the set-valued sign (Sign(0) = [−1, 1]) and F_el(y + δ) the elastic
force of the PI bank after the trial increment δ = h·v' from its current memory
(the play update is exact for a monotone increment). The left side is monotone
in v', so the inclusion has exactly one solution:

* v' = 0 (the mass sticks, its position does not change by a single bit) iff
  |m·v/h + u − F_el(y)| <= c1;
* otherwise v' has the sign s of m·v/h + u − F_el(y) and solves
  (m/h² + σ/h)·δ + F_el(y + δ) − F_el(y) = m·v/h + u − F_el(y) − c1·s.

The viscous term σ·v' (σ >= 0) enters linearly: it adds σ/h to the coefficient
of δ and nothing to the stick test (σ·0 = 0).

For finite elements F_el(y + δ) − F_el(y) = Σ k_j (clamp(f_j + δ, ±r_j) − f_j) is
piecewise linear and concave in s·δ, so Newton's method from δ = 0 reaches the
root from below and ends, exactly, once no element changes state between two
iterates (at most N + 1 passes). The elastic evaluation is the one function
`_trial_increment`; a model with another memory (a continuous density) needs
only that function and `_commit` replaced.

The scheme is backward Euler on the velocity (first order in h); its energy
balance misses the numerical dissipation ½·m·(v' − v)² + O(h²) per step. The
viscous dissipation of a step is σ·v'²·h.
"""

from __future__ import annotations

import numpy as np

from presliding.hysteresis._jit import JitFlags, njit

_JIT: JitFlags = {"cache": True, "error_model": "numpy", "fastmath": {"nsz", "arcp", "contract"}}


@njit(**_JIT)
def _trial_increment(k, r, f, s, d):  # pragma: no cover - compiled
    """Mirrored elastic increment s·(F_el(y + s·d) − F_el(y)) and its slope, d >= 0."""
    val = 0.0
    stiff = 0.0
    for j in range(k.shape[0]):
        fj = s * f[j]
        if fj + d < r[j]:
            val += k[j] * d
            stiff += k[j]
        else:
            val += k[j] * (r[j] - fj)
    return val, stiff


@njit(**_JIT)
def _newton_walk(mh2, k, r, f, s, b, slope, d):  # pragma: no cover - compiled
    """Continue Newton's method for mh2·d + s·(F_el(y + s·d) − F_el(y)) = b from d.

    The left side is increasing, piecewise linear and concave in d >= 0, so the
    iterates approach the root from below; the last one is exact once no
    element changes state between two iterates (at most N + 1 passes).
    """
    for _ in range(k.shape[0] + 1):
        inc, stiff = _trial_increment(k, r, f, s, d)
        if mh2 + stiff == slope:
            break
        slope = mh2 + stiff
        d += (b - mh2 * d - inc) / slope
    return d


@njit(**_JIT)
def _commit(k, r, f, delta):  # pragma: no cover - compiled
    """Apply the increment to the deformations.

    Returns F_el, Σk of the elements saturated at +r and at −r, the dissipation
    Σ c_j·|plastic increment|, and the distances of the nearest elastic element
    to +r and to −r.
    """
    fel = 0.0
    kpos = 0.0
    kneg = 0.0
    dis = 0.0
    dpos = np.inf
    dneg = np.inf
    for j in range(k.shape[0]):
        fj = f[j] + delta
        rj = r[j]
        if fj >= rj:
            dis += k[j] * rj * (fj - rj)
            fj = rj
            kpos += k[j]
        elif fj <= -rj:
            dis += k[j] * rj * (-rj - fj)
            fj = -rj
            kneg += k[j]
        f[j] = fj
        fel += k[j] * fj
        dpos = min(dpos, rj - fj if fj < rj else np.inf)
        dneg = min(dneg, rj + fj if fj > -rj else np.inf)
    return fel, kpos, kneg, dis, dpos, dneg


@njit(**_JIT)
def run_implicit(  # pragma: no cover - compiled
    m, c1, k, r, f, y, v, last_dir, t_grid, u_mid, out_idx,
    o_y, o_v, o_a, o_fric, o_fel, o_eel, o_dis, o_work, rev_t, rev_y, sigma=0.0, o_vis=None,
):  # fmt: skip
    """Step from t_grid[0] to t_grid[-1] with u = u_mid[i] on step i.

    Sample q is the state after grid point out_idx[q] (0: the initial state;
    its o_a/o_fric entries are left to the caller). ``f`` is updated in place.
    ``sigma`` is the viscous coefficient σ >= 0; ``o_vis``, when given, receives
    the viscous dissipation. Returns (n_rev, rest_start (nan if moving at the end), y, v, last_dir,
    dissipated, work, viscous dissipation).
    """
    n_steps = t_grid.shape[0] - 1
    n_out = out_idx.shape[0]
    n_el = k.shape[0]
    ktot = 0.0
    for j in range(n_el):
        ktot += k[j]
    fel, kpos, kneg, _, dpos, dneg = _commit(k, r, f, 0.0)
    npos = nneg = 0  # elements saturated at +r and at −r
    for j in range(n_el):
        npos += f[j] >= r[j]
        nneg += f[j] <= -r[j]
    dis = 0.0
    vis = 0.0
    work = 0.0
    n_rev = 0
    cap = rev_t.shape[0]
    rest_start = np.nan
    if o_vis is not None:
        for p in range(n_out):
            if out_idx[p] != 0:
                break
            o_vis[p] = 0.0
    q = _record(0, k, f, y, v, out_idx, 0, dis, work, o_y, o_v, o_fel, o_eel, o_dis, o_work)
    h_prev = -1.0
    inv_h = m_h = mh2 = 0.0
    for i in range(n_steps):
        h = t_grid[i + 1] - t_grid[i]
        if h != h_prev:
            h_prev = h
            inv_h = 1.0 / h
            m_h = m * inv_h
            mh2 = m_h * inv_h + sigma * inv_h  # m/h² + σ/h (m/h² when σ = 0)
        u = u_mid[i]
        g = m_h * v + u - fel
        if abs(g) <= c1:  # sticks: y and the memory stay exactly as they are
            v_new = 0.0
            if rest_start != rest_start:
                rest_start = t_grid[i]
        else:
            if g > 0.0:
                s = 1.0
                b = g - c1
                slope = mh2 + ktot - kpos
                dist = dpos
            else:
                s = -1.0
                b = -g - c1
                slope = mh2 + ktot - kneg
                dist = dneg
            d = b / slope  # exact unless an element reaches its threshold on the way
            if d >= dist:
                d = _newton_walk(mh2, k, r, f, s, b, slope, d)
            delta = s * d
            if (npos if s > 0.0 else nneg) == n_el:
                # every element slides on and stays at s·r_j: the memory, F_el and the
                # stiffness sums are unchanged (the same numbers, bit for bit); only the
                # plastic dissipation is summed
                dplastic = 0.0
                for j in range(n_el):
                    fj = f[j] + delta
                    rj = r[j]
                    dplastic += k[j] * rj * ((fj - rj) if s > 0.0 else (-rj - fj))
            else:  # `_commit` written out (the hot path), counting saturated elements
                fel = kpos = kneg = dplastic = 0.0
                dpos = dneg = np.inf
                npos = nneg = 0
                for j in range(n_el):
                    fj = f[j] + delta
                    rj = r[j]
                    if fj >= rj:
                        dplastic += k[j] * rj * (fj - rj)
                        fj = rj
                        kpos += k[j]
                        npos += 1
                    elif fj <= -rj:
                        dplastic += k[j] * rj * (-rj - fj)
                        fj = -rj
                        kneg += k[j]
                        nneg += 1
                    f[j] = fj
                    fel += k[j] * fj
                    dpos = min(dpos, rj - fj if fj < rj else np.inf)
                    dneg = min(dneg, rj + fj if fj > -rj else np.inf)
            y += delta
            v_new = delta * inv_h
            dis += c1 * d + dplastic
            vis += sigma * d * d * inv_h
            work += u * delta
            if s != last_dir:
                if last_dir != 0.0:
                    if n_rev < cap:
                        rev_t[n_rev] = t_grid[i]
                        rev_y[n_rev] = y - delta
                    n_rev += 1
                last_dir = s
            rest_start = np.nan
        if q < n_out and out_idx[q] == i + 1:
            acc = (v_new - v) * inv_h
            if o_vis is not None:
                for p in range(q, n_out):
                    if out_idx[p] != i + 1:
                        break
                    o_vis[p] = vis
            q0 = q
            q = _record(
                i + 1, k, f, y, v_new, out_idx, q, dis, work, o_y, o_v, o_fel, o_eel, o_dis, o_work
            )
            for p in range(q0, q):
                o_a[p] = acc
                o_fric[p] = u - m * acc
        v = v_new
    return n_rev, rest_start, y, v, last_dir, dis, work, vis


@njit(**_JIT)
def _record(i, k, f, y, v, out_idx, q, dis, work, o_y, o_v, o_fel, o_eel, o_dis, o_work):
    """Write the samples that fall on grid point i; returns the next sample index."""
    eel = 0.0
    fel = 0.0
    for j in range(k.shape[0]):
        fel += k[j] * f[j]
        eel += k[j] * f[j] * f[j]
    while q < out_idx.shape[0] and out_idx[q] == i:
        o_y[q] = y
        o_v[q] = v
        o_fel[q] = fel
        o_eel[q] = 0.5 * eel
        o_dis[q] = dis
        o_work[q] = work
        q += 1
    return q
