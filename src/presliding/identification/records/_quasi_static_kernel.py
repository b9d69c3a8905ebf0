"""Compiled quasi-static responses of many records for many parameter sets.

The quasi-static balance u = c1·sign(ẏ) + F_el (inertia negligible, eq. 8)
moves the contact only while |u − F_el| > c1; the elastic force then becomes
F_el = u ∓ c1 and the position y follows from the elements' memory: moving in
direction s from deformations f_j (|f_j| <= r_j), the elastic force is
F(Δ) = s·Σ_j k_j·min(s·f_j + Δ, r_j) after a travel Δ >= 0, piecewise linear
and increasing, solved exactly by walking its knots (the exact inverse of
`presliding.hysteresis.PIInverse`, c1 included, without Python work per sample).

Task (p, i) of `quasi_static_positions` runs parameter set p on record i, in
parallel over all tasks. A force |u − offset| >= F_c has no quasi-static
response: the task then stops with status −2 and holds its last position.

Record memories (``mode``): 0 relaxed; 1 a preload on the branch from
saturation in −direction with elastic force fraction·F_m
(`presliding.friction.preload`); 3 saturated in −direction ("continuing").

Asymmetric friction: c1n and rn are the Coulomb element and the thresholds of
sliding in −y. The contact moves in +y while u − F_el > c1, in −y while
u − F_el < −c1n, each direction walking its own thresholds, and a quasi-static
response needs −(c1n + Σ k_j rn_j) < u − offset < c1 + Σ k_j r_j. A symmetric
fit passes its own arrays again: one compiled signature, the same positions.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from presliding.friction.preload import preload_deformation_sided
from presliding.hysteresis._jit import njit
from presliding.hysteresis._sorting import stable_argsort
from presliding.identification.records._pooled_kernel import check_sets

RELAXED, PRELOAD, CONTINUING = 0, 1, 3
NO_RESPONSE = -2


def _travel(k, r, f, s, target, rooms):  # pragma: no cover - compiled
    """Travel Δ >= 0 in direction s after which s·Σ k_j min(s f_j + Δ, r_j) = target (−1: none)."""
    n = k.shape[0]
    g = 0.0
    slope = 0.0
    for j in range(n):
        sf = s * f[j]
        rooms[j] = r[j] - sf
        g += k[j] * sf
        if rooms[j] > 0.0:
            slope += k[j]
    order = stable_argsort(rooms)
    prev = 0.0
    for m in range(n):
        j = order[m]
        room = rooms[j]
        if room <= 0.0:
            continue
        g_next = g + slope * (room - prev)
        if target <= g_next:
            return prev + (target - g) / slope if slope > 0.0 else prev
        g = g_next
        prev = room
        slope -= k[j]
    return -1.0


travel = njit(cache=True)(_travel)


def _quasi_static_positions(  # pragma: no cover - compiled
    c1, c1n, k, r, rn, offset, y0, fraction, mode, direction, u_all, t_off, o_y, status
):
    """Positions o_y (P, S) of every record for every parameter set; status (P, R)."""
    n_par = c1.shape[0]
    n_rec = t_off.shape[0] - 1
    n_el = k.shape[1]
    for task in nb.prange(n_par * n_rec):
        p = task // n_rec
        i = task % n_rec
        a, b = t_off[i], t_off[i + 1]
        kp, rp, rq = k[p], r[p], rn[p]
        cp, cn = c1[p], c1n[p]
        f = np.zeros(n_el)
        rooms = np.empty(n_el)
        d = direction[i]
        if mode[i] == PRELOAD:
            preload_deformation_sided(kp, rp, rq, fraction[p, i], d, True, f)
        elif mode[i] == CONTINUING:  # saturated in −d
            for j in range(n_el):
                f[j] = -d * rp[j] if d < 0.0 else -rq[j]
        fel = 0.0
        fm = 0.0
        fmn = 0.0
        for j in range(n_el):
            fel += kp[j] * f[j]
            fm += kp[j] * rp[j]
            fmn += kp[j] * rq[j]
        limit = cp + fm
        below = cn + fmn
        y = y0[p, i]
        status[p, i] = 0
        for m in range(a, b):
            u = u_all[m] - offset[p]
            if not (u < limit and -u < below):
                status[p, i] = NO_RESPONSE
                for q in range(m, b):
                    o_y[p, q] = y
                break
            if u - fel > cp:
                s = 1.0
                side = rp
                target = u - cp
            elif u - fel < -cn:
                s = -1.0
                side = rq
                target = u + cn
            else:
                o_y[p, m] = y
                continue
            delta = travel(kp, side, f, s, s * target, rooms)
            if delta < 0.0:
                status[p, i] = NO_RESPONSE
                for q in range(m, b):
                    o_y[p, q] = y
                break
            for j in range(n_el):
                f[j] = s * min(s * f[j] + delta, side[j])
            y += s * delta
            fel = target
            o_y[p, m] = y


quasi_static_positions_parallel = njit(cache=True, parallel=True)(_quasi_static_positions)
quasi_static_positions_serial = njit(cache=True)(_quasi_static_positions)


def quasi_static_positions(c1, *args):
    """`_quasi_static_positions`, in parallel for several parameter sets; the shapes of the
    parameter arrays checked first (a mismatch would read past an array in compiled code)."""
    c1n, k, r, rn, offset = args[:5]
    check_sets("quasi-static", {"c1": c1, "c1n": c1n, "offset": offset}, {"k": k, "r": r, "rn": rn})
    kernel = quasi_static_positions_parallel if c1.shape[0] > 1 else quasi_static_positions_serial
    kernel(c1, *args)
