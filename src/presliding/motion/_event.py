"""Exact event-driven motion of a mass with finite-element PI friction (eqs. 8, 17).

Between two events the equation of motion (17),

    m·ÿ + c1·s + Σ_sliding c_j·s + Σ_elastic k_j (y − x_j) = u,     s = sign(ẏ),

is linear with constant coefficients: m·d̈ + K·d = F0, where d is the displacement
since the start of the piece, K = Σ_elastic k_j the stiffness of the elements
that stick (eq. 7 right after a reversal) and F0 the net force at the start. Its
solution is harmonic (ω = sqrt(K/m)) or, when every element slides, parabolic:

    d(t) = v0·sin(ωt)/ω + a0·2·(sin(ωt/2)/ω)²,    a0 = F0/m,

written so that ω → 0 gives v0·t + a0·t²/2 without cancellation. Events:

* an elastic element reaches its threshold, s·f_j = r_j: the smallest distance
  D = s·r_j − f_j is reached at t = 2·atan(D·ω / (v + sqrt(v² + 2aD − ω²D²)))/ω
  (the root of the closed form in tan(ωt/2); v, a, D mirrored to the direction s);
* the velocity reaches zero, at t = atan2(v·ω, −a)/ω, after the displacement
  d_max = v²/(sqrt(a² + ω²v²) − a);
* the applied force changes (piecewise-constant u).

At zero velocity the mass sticks iff |u − F_el| <= c1 (set-valued sign; equality
sticks; the viscous force σ·0 vanishes) and stays exactly put until u changes;
otherwise it moves in the direction of u − F_el. Element deformations
f_j = y − x_j are set exactly to s·r_j when an element starts to slide, so the
element classification never depends on rounding.

With a viscous term σ > 0 the pieces are damped: m·d̈ + σ·ḋ + K·d = F0, solved in
closed form by `presliding.motion._damped` (under-, critically or over-damped;
the exponential Coulomb–viscous decay when K = 0), with the time of zero
velocity in closed form and the time an element reaches its threshold by a
bracketed, safeguarded Newton iteration on the closed form. σ = 0 runs the
undamped formulas above, unchanged.

The damped pieces are compiled only where they can run: the kernels take a
last argument ``damped``, None when σ = 0 on both sides (numba then removes
every ``damped is None`` branch by its type before it compiles, and the damped
closed forms are never compiled) or True otherwise. A first undamped motion
compiles about half the code it did with both kinds of piece.

No event is found on a grid, so none can hide between samples: a piece has one
degree of freedom, so its velocity v(t) = v0·c(t) + a0·g(t) solves a homogeneous
second-order equation, whose zeros are π/ω_d apart (under-damped; the closed form
atan2 gives the first) or single (critical, over-damped, parabolic); the
displacement increases until that rest (v > 0 there), so the time to an element's
threshold is the unique root of an increasing function on [0, t_rest] (closed form,
or bracketed Newton with bisection); and at rest under a constant u nothing changes
until u does. `presliding.control` runs this kernel one period at a time, and the
batches of `presliding.motion._batch_events` call it too
(tests/motion/test_event_roots.py checks the first roots against dense samples).
"""

from __future__ import annotations

import math

import numpy as np

from presliding.hysteresis._jit import JitFlags, njit
from presliding.motion import _damped

STATUS_OK = 0
STATUS_EVENT_LIMIT = -1


def kernel_array(a: np.ndarray) -> np.ndarray:
    """`a` as the kernels take it (C-contiguous, writable float64), copied only if needed.

    One type for every call keeps `run_events` to a single compiled version
    (a read-only array is a type of its own in numba).
    """
    if a.dtype == np.float64 and a.flags.c_contiguous and a.flags.writeable:
        return a
    return np.array(a, dtype=np.float64, order="C")


def damped_flag(*sigma: float | np.ndarray) -> bool | None:
    """The kernels' `damped` argument: None when every σ (scalars or arrays) is 0 (the damped
    pieces are then not compiled), else True."""
    return True if any(np.any(np.asarray(s) != 0.0) for s in sigma) else None


_JIT: JitFlags = {"cache": True, "error_model": "numpy"}


@njit(**_JIT)
def closed_form(v0, a0, w, t):  # pragma: no cover - compiled
    """Displacement, velocity and acceleration after time t of one piece."""
    if w == 0.0:
        return v0 * t + 0.5 * a0 * t * t, v0 + a0 * t, a0
    wt = w * t
    sn = math.sin(wt)
    cs = math.cos(wt)
    sh = math.sin(0.5 * wt) / w
    s1 = sn / w
    return v0 * s1 + a0 * 2.0 * sh * sh, v0 * cs + a0 * s1, a0 * cs - v0 * w * sn


@njit(**_JIT)
def reach(vp, ap, w):  # pragma: no cover - compiled
    """Displacement until the velocity vanishes (mirrored: vp >= 0), inf if never."""
    if w == 0.0:
        return vp * vp / (-2.0 * ap) if ap < 0.0 else np.inf
    q = math.sqrt(ap * ap + w * w * vp * vp)
    if ap < 0.0:
        return vp * vp / (q - ap)
    return (ap + q) / (w * w)


@njit(**_JIT)
def time_to_rest(vp, ap, w):  # pragma: no cover - compiled
    """Time until the velocity vanishes (mirrored: vp >= 0), inf if never."""
    if w == 0.0:
        return vp / (-ap) if ap < 0.0 else np.inf
    return math.atan2(vp * w, -ap) / w


@njit(**_JIT)
def time_to_reach(vp, ap, w, dist):  # pragma: no cover - compiled
    """Time to travel `dist` (0 < dist <= reach) from velocity vp, acceleration ap."""
    disc = vp * vp + 2.0 * ap * dist - w * w * dist * dist
    den = vp + math.sqrt(max(disc, 0.0))
    if w == 0.0:
        return 2.0 * dist / den
    return 2.0 * math.atan(dist * w / den) / w


@njit(refcount=False, **_JIT)
def run_events(  # pragma: no cover - compiled
    m, c1, k, r, f, y, v, last_dir, u_t, u_val, t_eval, t_end, max_events,
    o_y, o_v, o_a, o_fel, o_u, o_eel, o_dis, o_work, rev_t, rev_y, sigma, o_vis, piece, damped,
):  # fmt: skip
    """`run_events_sided` with equal sides: symmetric friction (c1, r_j and σ)."""
    return run_events_sided(
        m, c1, c1, k, r, r, f, y, v, last_dir, u_t, u_val, t_eval, t_end, max_events,
        o_y, o_v, o_a, o_fel, o_u, o_eel, o_dis, o_work, rev_t, rev_y, sigma, sigma, o_vis,
        piece, damped,
    )  # fmt: skip


@njit(refcount=False, **_JIT)
def run_events_sided(  # pragma: no cover - compiled
    m, c1p, c1n, k, rp, rn, f, y, v, last_dir, u_t, u_val, t_eval, t_end, max_events,
    o_y, o_v, o_a, o_fel, o_u, o_eel, o_dis, o_work, rev_t, rev_y, sigmap, sigman, o_vis, piece,
    damped,
):  # fmt: skip
    """Event-driven exact motion from time u_t[0]; samples written at t_eval.

    Asymmetric friction: c1p/c1n, rp/rn and sigmap/sigman are the Coulomb
    element, thresholds and viscous coefficient for sliding in +y and −y. The
    mass sticks iff −c1n <= u − F_el <= c1p, and element j slides in +y at
    f_j = rp_j, in −y at f_j = −rn_j. Equal sides give the symmetric motion bit
    for bit (every operation picks a side, then computes as before).

    ``sigma`` is the viscous coefficient σ >= 0. ``f`` (deformations, shape
    (N,)) is updated in place to the final state. u is u_val[i] on
    [u_t[i], u_t[i+1]), the last value held forever. ``last_dir`` is the
    direction of the trajectory's last motion (0: none; a reversal is a change
    of the sign of the velocity, so a start from rest is never one). Reversals
    beyond the capacity of rev_t/rev_y are counted but not recorded. ``o_vis``
    receives the viscous dissipation σ·∫v² at the samples (an empty array
    skips it: then the returned viscous dissipation is 0). ``piece`` (shape
    (5 + N,), or empty to skip it) receives the start of the last closed-form
    piece: [t, y, v, last_dir, u, f_1..f_N] (a continuation that resumes it
    reproduces this run bit for bit). ``damped``: None when sigmap = sigman = 0 (the
    damped pieces are then not compiled: see the module notes), else True.

    Every caller passes the same argument types (C-contiguous, writable
    float64 arrays; empty arrays rather than None), so that this kernel is
    compiled once.

    Returns (status, n_samples, n_rev, stop_time (nan if moving at the end),
    y, v, last_dir, n_events, dissipated, work, t, viscous dissipation).
    """
    n = k.shape[0]
    n_u = u_t.shape[0]
    n_eval = t_eval.shape[0]
    t = u_t[0]
    iu = 0
    ie = 0
    n_rev = 0
    n_ev = 0
    dis = 0.0
    vis = 0.0
    work = 0.0
    rest_start = np.nan
    frozen = False  # at rest in floating point: the state repeats until u changes
    record_vis = o_vis.shape[0] > 0
    record_piece = piece.shape[0] > 0
    status = STATUS_OK
    while True:
        while iu + 1 < n_u and u_t[iu + 1] <= t:  # an event exactly at a change of u
            iu += 1
            frozen = False
        u = u_val[iu]
        t_u = u_t[iu + 1] if iu + 1 < n_u else np.inf
        fel = 0.0
        eel = 0.0
        for j in range(n):
            fel += k[j] * f[j]
            eel += k[j] * f[j] * f[j]
        s = 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)
        if s == 0.0:
            g = u - fel
            if (-c1n <= g and g <= c1p) or frozen:  # sticks: exactly at rest until u changes
                if np.isnan(rest_start):
                    rest_start = t
                # a change of u exactly at t_end is taken, like any other, before the
                # sample at t_end: that sample has the new u, as in a longer run
                t1 = min(t_u, t_end)
                while ie < n_eval and (t_eval[ie] < t1 or (t_u > t_end and t_eval[ie] <= t1)):
                    o_y[ie] = y
                    o_v[ie] = 0.0
                    o_a[ie] = 0.0
                    o_fel[ie] = fel
                    o_u[ie] = u
                    o_eel[ie] = 0.5 * eel
                    o_dis[ie] = dis
                    if record_vis:
                        o_vis[ie] = vis
                    o_work[ie] = work
                    ie += 1
                if t_u > t_end:
                    t = t_end
                    break
                t = t_u
                iu += 1
                frozen = False
                continue
            s = 1.0 if g > 0.0 else -1.0
            if last_dir != 0.0 and s != last_dir:
                if n_rev < rev_t.shape[0]:
                    rev_t[n_rev] = t
                    rev_y[n_rev] = y
                n_rev += 1
            last_dir = s
        # the side of this piece: its Coulomb element, thresholds and viscous coefficient
        c1 = c1p if s > 0.0 else c1n
        r = rp if s > 0.0 else rn
        sigma = sigmap if s > 0.0 else sigman
        rest_before = rest_start
        rest_start = np.nan
        if record_piece:
            piece[0] = t
            piece[1] = y
            piece[2] = v
            piece[3] = last_dir
            piece[4] = u
            for j in range(n):
                piece[5 + j] = f[j]
        n_ev += 1
        if n_ev > max_events:
            status = STATUS_EVENT_LIMIT
            break
        # the piece: stiffness of the sticking elements, nearest threshold
        kk = 0.0
        csl = 0.0
        pel = 0.0
        dmin = np.inf
        for j in range(n):
            if s * f[j] >= r[j]:
                csl += k[j] * r[j]
            else:
                kk += k[j]
                pel += k[j] * f[j]
                dj = r[j] - s * f[j]
                dmin = min(dmin, dj)
        vp = abs(v)  # s·v >= 0; abs also clears a signed zero (atan2 tells -0.0 apart)
        gam = 0.0
        if damped is None or sigma == 0.0:
            a0 = (u - c1 * s - fel) / m
            w = math.sqrt(kk / m)
            ap = s * a0
            if vp == 0.0 and not ap > 0.0:
                # a start from rest: |u − F_el| > c1 was decided above, but u − c1·s − F_el
                # rounds to <= 0 (an order of operations the stick test does not use), which
                # would give a piece of zero length and no progress; take the net force as
                # the stick test computed it, > 0 in floating point
                ap = (s * (u - fel) - c1) / m
                a0 = s * ap
            dmax = reach(vp, ap, w)
            kind = 0  # 0: element, 1: rest, 2: change of u, 3: end
            if dmin < dmax:
                dt = time_to_reach(vp, ap, w, dmin)
            else:
                kind = 1
                dt = time_to_rest(vp, ap, w)
        else:
            gam = 0.5 * sigma / m
            w = kk / m  # ω0² of the damped piece
            fp = (s * (u - fel) - c1) / m
            ap = fp - sigma * vp / m
            a0 = s * ap
            kind, dt, dmax = _damped_event(vp, ap, fp, gam, w, dmin, min(t_u, t_end) - t)
        # an element or a rest exactly at the change of u or at the end is an event
        # (set exactly; a rest at t_end is a stop at t_end); a change of u at t_end
        # ends the piece there, and the next one (of length 0) gives the sample at t_end
        if t + dt > t_u and t_u <= t_end:
            kind = 2
            dt = t_u - t
        if t + dt > t_end and kind != 2:
            kind = 3
            dt = t_end - t
        t1 = t + dt if kind < 2 else (t_u if kind == 2 else t_end)
        dfric = c1 + csl
        while ie < n_eval and (t_eval[ie] < t1 or (kind == 3 and t_eval[ie] <= t1)):
            tau = t_eval[ie] - t
            sq = 0.0
            if damped is None or sigma == 0.0:
                d, vv, aa = closed_form(v, a0, w, tau)
            elif not record_vis:
                d, vv, aa = _damped.state(v, a0, gam, w, tau)
            else:  # with σ·∫v² since the start of the piece, in closed form
                d, vv, aa, sq = _damped.state_square(v, a0, gam, w, tau)
            o_y[ie] = y + d
            o_v[ie] = vv
            o_a[ie] = aa
            o_fel[ie] = fel + kk * d
            o_u[ie] = u
            o_eel[ie] = 0.5 * (eel + 2.0 * d * pel + kk * d * d)
            o_dis[ie] = dis + dfric * s * d
            if record_vis:
                o_vis[ie] = vis + sigma * sq
            o_work[ie] = work + u * d
            ie += 1
        if damped is not None and record_vis and sigma > 0.0:
            vis += sigma * _damped.square_integral(v, a0, gam, w, t1 - t)
        if damped is None or sigma == 0.0:
            if kind == 0:
                d = s * dmin
                v = closed_form(v, a0, w, dt)[1]
            elif kind == 1:
                d = s * dmax
                v = 0.0
            else:
                d, v, _ = closed_form(v, a0, w, dt)
        elif kind == 0:
            d = s * dmin
            v = _damped.state(v, a0, gam, w, dt)[1]
        elif kind == 1:
            d = s * dmax
            v = 0.0
        else:
            d, v, _ = _damped.state(v, a0, gam, w, dt)
        if s * v <= 0.0:
            v = 0.0
        hit = kind == 0 or (kind == 1 and dmin == dmax)
        # a piece from rest back to rest that moved neither y nor any deformation in
        # floating point leaves the state as it found it: every later piece under this u
        # would repeat it, so the mass stays at rest until u changes
        same = vp == 0.0 and kind == 1 and y + d == y
        for j in range(n):
            if s * f[j] < r[j]:
                fj = f[j] + d
                # an element reaching its threshold is set exactly (rounding only)
                if s * fj >= r[j] or (hit and r[j] - s * f[j] == dmin):
                    fj = s * r[j]
                same = same and fj == f[j]
                f[j] = fj
        if same:
            frozen = True
            rest_start = rest_before if not np.isnan(rest_before) else t
        elif kind == 3 and vp == 0.0 and t1 == t:
            rest_start = rest_before  # the piece from rest starts at t_end: still at rest
        y += d
        dis += dfric * s * d
        work += u * d
        t = t1
        if kind == 2:
            iu += 1
        elif kind == 3:
            break
    stop = rest_start if v == 0.0 else np.nan
    return status, ie, n_rev, stop, y, v, last_dir, n_ev, dis, work, t, vis


@njit(**_JIT)
def _damped_event(vp, ap, fp, gam, w0sq, dmin, t_cap):  # pragma: no cover - compiled
    """Next event of a damped piece (mirrored: vp >= 0, acceleration ap, fp = F0/m).

    Returns (kind, dt, dmax): kind 0 when the nearest elastic element (distance
    dmin to its threshold) is reached first, 1 when the velocity vanishes
    first (after the displacement dmax); dt = inf when neither happens within
    t_cap (the caller then ends the piece at the change of u or at the end).
    """
    tr = _damped.rest_time(vp, fp, gam, w0sq)
    if tr <= t_cap:
        dmax = _damped.state(vp, ap, gam, w0sq, tr)[0]
        if dmin < dmax:
            return 0, _damped.time_to_distance(vp, ap, gam, w0sq, dmin, tr), dmax
        return 1, tr, dmax
    if dmin < np.inf and _damped.state(vp, ap, gam, w0sq, t_cap)[0] > dmin:
        return 0, _damped.time_to_distance(vp, ap, gam, w0sq, dmin, t_cap), np.inf
    return 1, np.inf, np.inf
