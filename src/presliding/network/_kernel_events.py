"""Compiled event location of a piece: a grid of the closed form, then Brent's method.

The same rules as `presliding.network._events`: grid steps of min(horizon/32,
1/(2·ω_max)); the first grid interval where an event function triggers (h <= 0, a
stick margin h < 0) is refined, the candidate whose linear interpolation crosses first
first, by Brent's method (xtol 1e-15 s, rtol 4ε) when its ends have strict opposite
signs, else by bisection on the trigger; a function that triggers at the earliest time
found so far is refined too, until none triggers earlier.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from presliding.network._kernel_piece import P_DIM, P_H0, P_NLIN, P_OMAX, event_values

BLOCK = 32
XTOL = 1e-15
RTOL = 4.0 * np.finfo(np.float64).eps


@njit(cache=True, error_model="numpy")
def _value(pc, j, t, out, xi):  # pragma: no cover - compiled
    event_values(pc, t, out, xi)
    return out[j]


@njit(cache=True, error_model="numpy")
def _trig(val, strict):  # pragma: no cover - compiled
    return val < 0.0 if strict else val <= 0.0


@njit(cache=True, error_model="numpy")
def brent(pc, j, xa, xb, out, xi):  # pragma: no cover - compiled
    """A root of event function j in [xa, xb] (its values of strict opposite signs)."""
    xpre, xcur = xa, xb
    xblk, fblk, spre, scur = 0.0, 0.0, 0.0, 0.0
    fpre = _value(pc, j, xpre, out, xi)
    fcur = _value(pc, j, xcur, out, xi)
    if fpre == 0.0:
        return xpre
    if fcur == 0.0:
        return xcur
    for _ in range(200):
        if fpre != 0.0 and fcur != 0.0 and (fpre < 0.0) != (fcur < 0.0):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = 0.5 * (XTOL + RTOL * abs(xcur))
        sbis = 0.5 * (xblk - xcur)
        if fcur == 0.0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:  # secant
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:  # inverse quadratic
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2.0 * abs(stry) < min(abs(spre), 3.0 * abs(sbis) - delta):
                spre, scur = scur, stry
            else:
                spre, scur = sbis, sbis
        else:
            spre, scur = sbis, sbis
        xpre, fpre = xcur, fcur
        if abs(scur) > delta:
            xcur += scur
        else:
            xcur += delta if sbis > 0.0 else -delta
        fcur = _value(pc, j, xcur, out, xi)
    return xcur


@njit(cache=True, error_model="numpy")
def _root(pc, j, a, b, out, xi):  # pragma: no cover - compiled
    """The first time in (a, b] where function j triggers (b if only there)."""
    strict = j >= pc[P_NLIN]
    lo, hi = a, b
    fa = _value(pc, j, lo, out, xi)
    fb = _value(pc, j, hi, out, xi)
    if not fb <= 0.0:
        return hi
    if fa > 0.0 and fb < 0.0:
        t = brent(pc, j, lo, hi, out, xi)
        if t > a:
            return t
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if _trig(_value(pc, j, mid, out, xi), strict):
            hi = mid
        else:
            lo = mid
    return hi


@njit(cache=True, error_model="numpy")
def _refine(pc, a, b, first, out, xi):  # pragma: no cover - compiled
    """(the earliest trigger time in (a, b], the functions that trigger there)."""
    nf = pc[P_H0].shape[0]
    n_lin = pc[P_NLIN]
    best, best_j = b, -1
    done = np.zeros(nf, np.bool_)
    todo = np.zeros(nf, np.bool_)
    todo[first] = True
    mask = np.zeros(nf, np.bool_)
    while True:
        for j in range(nf):
            if todo[j]:
                done[j] = True
                t = _root(pc, j, a, best, out, xi)
                if t < best or best_j < 0:
                    best, best_j = t, j
        event_values(pc, best, out, xi)
        more = False
        for j in range(nf):
            mask[j] = _trig(out[j], j >= n_lin)
            todo[j] = mask[j] and not done[j]
            more = more or todo[j]
        if not more:
            break
    if best_j >= 0:
        mask[best_j] = True
    return best, mask


@njit(cache=True, error_model="numpy")
def find_event(pc, horizon):  # pragma: no cover - compiled
    """(τ, mask) of the first event in (0, horizon]; τ = −1 when there is none."""
    nf = pc[P_H0].shape[0]
    n_lin = pc[P_NLIN]
    none = np.zeros(nf, np.bool_)
    if horizon <= 0.0 or nf == 0:
        return -1.0, none
    h = horizon / BLOCK
    if pc[P_OMAX] > 0.0:
        h = min(h, 0.5 / pc[P_OMAX])
    xi = np.empty(3 * pc[P_DIM])
    prev = np.empty(nf)
    cur = np.empty(nf)
    event_values(pc, 0.0, prev, xi)
    lo = 0.0
    t_prev = 0.0
    while lo < horizon:
        last = lo
        for kk in range(1, BLOCK + 1):
            t = lo + h * kk
            if t >= horizon:
                t = horizon
            if t == last:
                continue
            event_values(pc, t, cur, xi)
            first, frac_min = -1, np.inf
            for j in range(nf):
                if _trig(cur[j], j >= n_lin):
                    frac = prev[j] / (prev[j] - cur[j])
                    if np.isnan(frac):
                        frac = 0.0
                    if first < 0 or frac < frac_min:
                        first, frac_min = j, frac
            if first >= 0:
                return _refine(pc, t_prev, t, first, cur, xi)
            prev[:] = cur
            t_prev = t
            last = t
        lo = last
    return -1.0, none
