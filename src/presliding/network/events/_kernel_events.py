"""Compiled certified event location of a piece: cells of the closed form, then Brent.

The same rules as `presliding.network.events._events.scan`: each side of each event function
(the velocities and threshold distances; c1 ∓ τ of every stick margin) has its second
derivative in [P − T, P + T] over the whole piece (`_kernel_piece._curvature`: a mode
of frequency ω adds at most ω²·(its amplitude) to it, a rigid mode a constant), so
its quadratic lower bounds from both ends of a cell prove the cell free of events, or
its slope bounds prove that it holds exactly one root; undecided cells are halved,
and the next cell doubles. A cell at the time resolution (XTOL + RTOL·τ) that stays
undecided holds a trigger to that resolution (a start, a touch of zero) or a graze of
zero within rounding. A side at zero to rounding at the start that stays or moves
away is lifted by its rounding for the piece (the start is not an event). Isolated
roots are refined by Brent's method (xtol 1e-15 s, rtol 4ε), the others by bisection
on the trigger; a function that triggers at the earliest time found so far is
refined too, until none triggers earlier.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from presliding.network.events._kernel_damped import damped_bound
from presliding.network.events._kernel_piece import (
    P_C1S,
    P_COEF,
    P_CURVP,
    P_CURVT,
    P_DAMPED,
    P_DIM,
    P_ERR,
    P_ERRD,
    P_H,
    P_H0,
    P_LAM,
    P_NLIN,
    P_OMAX,
    ROUNDING,
    event_values,
    modal,
)

XTOL = 1e-15
RTOL = 4.0 * np.finfo(np.float64).eps


@njit(cache=True, error_model="numpy")
def _value(pc, j, t, out, xi, lift):  # pragma: no cover - compiled
    event_values(pc, t, out, xi)
    return out[j] + lift


@njit(cache=True, error_model="numpy")
def _trig(val, strict):  # pragma: no cover - compiled
    return val < 0.0 if strict else val <= 0.0


@njit(cache=True, error_model="numpy")
def brent(pc, j, xa, xb, out, xi, lift):  # pragma: no cover - compiled
    """A root of event function j in [xa, xb] (its values of strict opposite signs)."""
    xpre, xcur = xa, xb
    xblk, fblk, spre, scur = 0.0, 0.0, 0.0, 0.0
    fpre = _value(pc, j, xpre, out, xi, lift)
    fcur = _value(pc, j, xcur, out, xi, lift)
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
        fcur = _value(pc, j, xcur, out, xi, lift)
    return xcur


@njit(cache=True, error_model="numpy")
def _root(pc, j, a, b, out, xi, lift):  # pragma: no cover - compiled
    """The first time in (a, b] where function j (raised by `lift`) triggers (b if only
    there)."""
    strict = j >= pc[P_NLIN]
    lo, hi = a, b
    fa = _value(pc, j, lo, out, xi, lift)
    fb = _value(pc, j, hi, out, xi, lift)
    if not fb <= 0.0:
        return hi
    if fa > 0.0 and fb < 0.0:
        t = brent(pc, j, lo, hi, out, xi, lift)
        if t > a:
            return t
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if _trig(_value(pc, j, mid, out, xi, lift), strict):
            hi = mid
        else:
            lo = mid
    return hi


@njit(cache=True, error_model="numpy")
def _refine(pc, a, b, todo, out, xi, lift):  # pragma: no cover - compiled
    """(the earliest trigger time in (a, b] of the candidates `todo`, the functions that
    trigger there); `lift`: each function's lift at the start of the piece."""
    nf = pc[P_H0].shape[0]
    n_lin = pc[P_NLIN]
    best, best_j = b, -1
    done = np.zeros(nf, np.bool_)
    mask = np.zeros(nf, np.bool_)
    while True:
        for j in range(nf):
            if todo[j]:
                done[j] = True
                t = _root(pc, j, a, best, out, xi, lift[j])
                if t < best or best_j < 0:
                    best, best_j = t, j
        event_values(pc, best, out, xi)
        more = False
        for j in range(nf):
            mask[j] = _trig(out[j] + lift[j], j >= n_lin)
            todo[j] = mask[j] and not done[j]
            more = more or todo[j]
        if not more:
            break
    if best_j >= 0:
        mask[best_j] = True
    return best, mask


@njit(cache=True, error_model="numpy")
def _sides(pc, t, h, dh, xi):  # pragma: no cover - compiled
    """Every side's value and slope at t (into h, dh): the functions H·ξ + h0, then
    c1 − τ and c1 + τ of every stick margin."""
    d = pc[P_DIM]
    modal(pc, t, xi[:d], xi[d : 2 * d], xi[2 * d :])
    hmat, h0, n_lin, c1s = pc[P_H], pc[P_H0], pc[P_NLIN], pc[P_C1S]
    for j in range(h0.shape[0]):
        acc, rate = h0[j], 0.0
        for i in range(d):
            acc += hmat[j, i] * xi[i]
            rate += hmat[j, i] * xi[d + i]
        for i in range(d):
            acc += hmat[j, d + i] * xi[d + i]
            rate += hmat[j, d + i] * xi[2 * d + i]
        if j < n_lin:
            h[j], dh[j] = acc, rate
        else:
            k = n_lin + 2 * (j - n_lin)
            h[k], dh[k] = c1s[j - n_lin] - acc, -rate
            h[k + 1], dh[k + 1] = c1s[j - n_lin] + acc, rate


@njit(cache=True, error_model="numpy")
def _lowest(h, d, k, ell):  # pragma: no cover - compiled
    """min over δ ∈ [0, ℓ] of h + d·δ + k·δ²/2."""
    low = min(h, h + d * ell + 0.5 * k * ell * ell)
    if k > 0.0 and d < 0.0 and -d < k * ell:
        low = min(low, h - d * d / (2.0 * k))
    return low


@njit(cache=True, error_model="numpy")
def find_event(pc, horizon, counts):  # pragma: no cover - compiled
    """(τ, mask) of the first event in (0, horizon]; τ = −1 when there is none.

    Certified on cells (as `presliding.network.events._events.scan`): every side's second
    derivative lies in [P − T, P + T] (the piece's modal bounds), so its quadratic lower
    bounds from both ends prove a cell free of events, or its slope bounds prove one
    root. ``counts`` (cells, isolated, resolved, grazes, ends) are added to in place.
    """
    nf = pc[P_H0].shape[0]
    n_lin = pc[P_NLIN]
    none = np.zeros(nf, np.bool_)
    if horizon <= 0.0:
        return -1.0, none
    if nf == 0:
        counts[4] += 1
        return -1.0, none
    ns = n_lin + 2 * (nf - n_lin)
    cp, ct, e0, e1 = pc[P_CURVP], pc[P_CURVT], pc[P_ERR], pc[P_ERRD]
    lo, hi, lift = np.empty(ns), np.empty(ns), np.zeros(ns)
    strict = np.empty(ns, np.bool_)
    c1s = pc[P_C1S]
    for k in range(ns):
        j = k if k < n_lin else n_lin + (k - n_lin) // 2
        sg = 1.0 if (k < n_lin or (k - n_lin) % 2 == 1) else -1.0
        lo[k] = sg * cp[j] - ct[j]
        hi[k] = sg * cp[j] + ct[j]
        strict[k] = k >= n_lin
    d = pc[P_DIM]
    xi = np.empty(3 * d)
    ha, da, hb, db = np.empty(ns), np.empty(ns), np.empty(ns), np.empty(ns)
    trig_a = np.zeros(ns, np.bool_)
    trig_b = np.zeros(ns, np.bool_)
    _sides(pc, 0.0, ha, da, xi)
    lf = np.zeros(nf)  # the functions' lifts (as the refinement sees them)
    for k in range(ns):
        j = k if k < n_lin else n_lin + (k - n_lin) // 2
        err = e0[j] + (ROUNDING * c1s[j - n_lin] if k >= n_lin else 0.0)
        if abs(ha[k]) <= err and da[k] >= -e1[j]:
            lift[k] = err  # at zero to rounding, staying or moving away: the start
            lf[j] = max(lf[j], err)
        ha[k] += lift[k]
        trig_a[k] = _trig(ha[k], strict[k])
    width = horizon if pc[P_OMAX] <= 0.0 else min(horizon, 0.5 / pc[P_OMAX])
    a = 0.0
    out = np.empty(nf)
    todo = np.zeros(nf, np.bool_)
    damped = pc[P_DAMPED]
    bound = np.zeros(nf)
    while True:
        b = min(a + width, horizon)
        ell = 0.5 * (b - a)
        if damped:  # the bounds of the cell (decaying modes)
            damped_bound(pc[P_COEF], pc[P_LAM], a, b, bound)
            for k in range(ns):
                j = k if k < n_lin else n_lin + (k - n_lin) // 2
                lo[k], hi[k] = -bound[j], bound[j]
        _sides(pc, b, hb, db, xi)
        all_safe, all_known, any_trig = True, True, False
        for k in range(ns):
            hb[k] += lift[k]
            trig_b[k] = _trig(hb[k], strict[k])
            any_trig = any_trig or trig_b[k]
            low = min(_lowest(ha[k], da[k], lo[k], ell), _lowest(hb[k], -db[k], lo[k], ell))
            if not trig_b[k] and low >= 0.0:
                continue
            all_safe = False
            slope = max(max(da[k], da[k] + hi[k] * ell), max(db[k], db[k] - lo[k] * ell))
            if not (trig_b[k] and not trig_a[k] and slope < 0.0):
                all_known = False
        if all_safe:
            counts[0] += 1
            if b >= horizon:
                counts[4] += 1
                return -1.0, none
            a = b
            ha[:] = hb
            da[:] = db
            trig_a[:] = False
            width *= 2.0
            continue
        if all_known or (b - a <= XTOL + RTOL * b and any_trig):
            todo[:] = False
            for k in range(ns):
                if trig_b[k]:
                    todo[k if k < n_lin else n_lin + (k - n_lin) // 2] = True
            counts[1 if all_known else 2] += 1
            return _refine(pc, a, b, todo, out, xi, lf)
        if b - a <= XTOL + RTOL * b:  # a graze of zero within rounding
            counts[3] += 1
            a = b
            ha[:] = hb
            da[:] = db
            trig_a[:] = False
            continue
        width = 0.5 * (b - a)
