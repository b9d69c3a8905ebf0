"""Closed-form pieces of the exact event method with a viscous term σ > 0.

Between two events the motion of eq. 17 with the viscous term σ·ẏ is linear
with constant coefficients; for the displacement d since the start of the
piece (velocity v0, acceleration a0 at the start)

    m·d̈ + σ·ḋ + K·d = F0,        γ = σ/(2m),  ω0² = K/m,

with K = Σ_elastic k_j the stiffness of the sticking elements (0 when every
element slides: the Coulomb–viscous decay). The velocity obeys the homogeneous
equation, so with the two fundamental solutions g (g(0) = 0, ġ(0) = 1) and
c = ġ + 2γ·g (c(0) = 1, ċ(0) = 0) and Q = ∫g = (1 − c)/ω0²:

    v(t) = v0·c + a0·g,    d(t) = v0·(g + 2γ·Q) + a0·Q,    a(t) = a0·(c − 2γ·g) − v0·ω0²·g.

g, c and Q are evaluated without cancellation in every regime: a Taylor series
for short times (t·(2γ + ω0) <= 2), and otherwise the damped oscillation
(ω0 > γ, g = e^{−γt}·sin(ω_d t)/ω_d), the critically damped piece, or the
over-damped one (ω0 < γ) with the eigenvalues λ1 = −ω0²/(γ + ω_h) (slow) and
λ2 = −(γ + ω_h) (fast), ω_h = sqrt(γ² − ω0²), the hyperbolic form near
critical damping. K = 0 is the over-damped case with λ1 = 0:
g = t·φ1(−2γt), Q = t²·φ2(−2γt).

Events (mirrored so that v0 >= 0):

* the velocity vanishes, in closed form: t = atan2(v0·ω_d, −b)/ω_d (under-damped),
  v0/(−b) (critical), log1p(2·v0·ω_h/(−F0/m − v0·λ1))/(2ω_h) (over-damped),
  with b = (F0 − σ·v0/2)/m; for K = 0 this is the stop time
  (m/σ)·ln(1 + σ·v0/F_d) of a Coulomb–viscous decay against the force F_d = −F0;
* an element reaches its threshold, d(t) = D: d is increasing until the
  velocity vanishes, so the root is bracketed and found by Newton's method on
  the closed form (ḋ = v), safeguarded by bisection, to rounding.

The viscous dissipation σ·∫v² is integrated by Gauss–Legendre quadrature of the
closed-form velocity on panels graded to the time scales of the piece, so that
the energy balance of a motion is an independent check of the closed forms.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

_JIT = {"cache": True, "error_model": "numpy"}
_EPS = 2.220446049250313e-16
_MAX_TERMS = 60
_MAX_ITER = 200

# Gauss–Legendre nodes and weights on [0, 1]
_X12, _W12 = np.polynomial.legendre.leggauss(12)
GL12_X = np.ascontiguousarray(0.5 * (_X12 + 1.0))
GL12_W = np.ascontiguousarray(0.5 * _W12)
_X4, _W4 = np.polynomial.legendre.leggauss(4)
GL4_X = np.ascontiguousarray(0.5 * (_X4 + 1.0))
GL4_W = np.ascontiguousarray(0.5 * _W4)


@nb.njit(**_JIT)
def _psi(lam, t):  # pragma: no cover - compiled
    """(e^{λt} − 1)/λ (t when λ = 0)."""
    if lam == 0.0:
        return t
    return math.expm1(lam * t) / lam


@nb.njit(**_JIT)
def basis(gam, w0sq, t):  # pragma: no cover - compiled
    """g(t), c(t), Q(t) of m·d̈ + σ·ḋ + K·d (γ = σ/(2m) > 0, ω0² = K/m >= 0), t >= 0."""
    if t <= 0.0:
        return 0.0, 1.0, 0.0
    w0 = math.sqrt(w0sq)
    if t * (2.0 * gam + w0) <= 2.0:
        # Taylor series of Q: T_{n+2} = −(2γt(n+1)·T_{n+1} + ω0²t²·T_n)/((n+2)(n+1))
        gt = 2.0 * gam * t
        wt2 = w0sq * t * t
        t_prev = 0.0  # T_{n}
        t_cur = 0.5 * t * t  # T_{n+1}, n + 1 = 2
        q = t_cur
        dq = 2.0 * t_cur  # t·Q'(t) = Σ n·T_n
        for n in range(1, _MAX_TERMS):
            t_next = -(gt * (n + 1) * t_cur + wt2 * t_prev) / ((n + 2) * (n + 1))
            q += t_next
            dq += (n + 2) * t_next
            t_prev = t_cur
            t_cur = t_next
            if abs(t_cur) <= 1e-18 * abs(q) and abs(t_prev) <= 1e-18 * abs(q):
                break
        return dq / t, 1.0 - w0sq * q, q
    eps = w0sq - gam * gam
    e = math.exp(-gam * t)
    if eps >= 0.0:  # under-damped (critical for eps = 0)
        wd = math.sqrt(eps)
        if wd == 0.0:
            sn = t
            cs = 1.0
            half = 0.0
        else:
            th = wd * t
            sn = math.sin(th) / wd
            cs = math.cos(th)
            h = math.sin(0.5 * th)
            half = 2.0 * h * h
        g = e * sn
        c = e * (cs + gam * sn)
        one_minus_c = half - math.expm1(-gam * t) * cs - gam * e * sn
        return g, c, one_minus_c / w0sq
    wh = math.sqrt(-eps)
    lam1 = -w0sq / (gam + wh)
    lam2 = -(gam + wh)
    if wh * t < 1.0:  # near critical damping: the hyperbolic form
        sh = math.sinh(wh * t) / wh
        ch = math.cosh(wh * t)
        g = e * sh
        c = e * (ch + gam * sh)
        h = math.sinh(0.5 * wh * t)
        one_minus_c = -math.expm1(-gam * t) - e * (2.0 * h * h + gam * sh)
    else:  # well separated modes
        e1 = math.exp(lam1 * t)
        e21 = math.exp(-2.0 * wh * t)
        g = e1 * (1.0 - e21) / (2.0 * wh)
        c = e1 * (-lam2 + lam1 * e21) / (2.0 * wh)
        one_minus_c = 1.0 - c
    if c <= 0.9 and w0sq > 0.0:
        q = one_minus_c / w0sq
    else:  # the slow mode dominates: the divided difference of the modes
        q = (_psi(lam1, t) - _psi(lam2, t)) / (2.0 * wh)
    return g, c, q


@nb.njit(**_JIT)
def state(v0, a0, gam, w0sq, t):  # pragma: no cover - compiled
    """Displacement, velocity and acceleration after time t of one damped piece."""
    g, c, q = basis(gam, w0sq, t)
    d = v0 * (g + 2.0 * gam * q) + a0 * q
    v = v0 * c + a0 * g
    a = a0 * (c - 2.0 * gam * g) - v0 * w0sq * g
    return d, v, a


@nb.njit(**_JIT)
def rest_time(vp, fp, gam, w0sq):  # pragma: no cover - compiled
    """Time until the velocity vanishes (mirrored: vp >= 0), inf if never.

    ``fp`` = F0/m, the net force per unit mass at the start without the viscous
    part (the acceleration is fp − 2γ·vp).
    """
    b = fp - gam * vp  # a0 + γ·v0
    eps = w0sq - gam * gam
    if eps > 0.0:
        wd = math.sqrt(eps)
        return math.atan2(vp * wd, -b) / wd
    if eps == 0.0:
        return vp / (-b) if b < 0.0 else np.inf
    wh = math.sqrt(-eps)
    lam1 = -w0sq / (gam + wh)
    den = -fp - vp * lam1  # (−b − vp·ω_h), without cancellation
    if not den > 0.0:
        return np.inf
    return math.log1p(2.0 * vp * wh / den) / (2.0 * wh)


@nb.njit(**_JIT)
def time_to_distance(vp, ap, gam, w0sq, dist, hi):  # pragma: no cover - compiled
    """Root t in (0, hi] of d(t) = dist (mirrored; d increasing on [0, hi], d(hi) >= dist)."""
    lo = 0.0
    disc = vp * vp + 2.0 * ap * dist
    t = 2.0 * dist / (vp + math.sqrt(disc)) if disc > 0.0 else 0.5 * hi
    if not (t > lo and t < hi):
        t = 0.5 * (lo + hi)
    for _ in range(_MAX_ITER):
        d, v, _ = state(vp, ap, gam, w0sq, t)
        f = d - dist
        if f < 0.0:
            lo = t
        elif f > 0.0:
            hi = t
        else:
            return t
        tn = t - f / v if v > 0.0 else -1.0
        if not (tn > lo and tn < hi):
            tn = 0.5 * (lo + hi)
        if abs(tn - t) <= 2.0 * _EPS * t or hi - lo <= 2.0 * _EPS * hi:
            return tn
        t = tn
    return t


@nb.njit(**_JIT)
def _panel(v0, a0, gam, w0sq, a, h, xs, ws):  # pragma: no cover - compiled
    acc = 0.0
    for i in range(xs.shape[0]):
        g, c, _ = basis(gam, w0sq, a + h * xs[i])
        v = v0 * c + a0 * g
        acc += ws[i] * v * v
    return acc * h


@nb.njit(**_JIT)
def velocity_square_integral(v0, a0, gam, w0sq, ta, tb):  # pragma: no cover - compiled
    """∫_ta^tb v(s)² ds of one damped piece (times since its start), by Gauss–Legendre.

    Panels grow with the time since the start of the piece (the fast mode has
    decayed there) and are capped by the slow time scale; an over-damped piece
    that has crept to rest for 40 slow time constants adds nothing more.
    """
    if not tb > ta:
        return 0.0
    w0 = math.sqrt(w0sq)
    rate = 2.0 * gam + w0  # the fastest rate of the piece
    tau0 = 1.0 / rate
    eps = w0sq - gam * gam
    cap = np.inf
    tail = np.inf
    if eps > 0.0:
        cap = 0.5 / math.sqrt(eps)
    elif w0sq > 0.0:
        lam1 = w0sq / (gam + math.sqrt(-eps))  # |λ1|
        cap = 0.5 / lam1
        tail = max(40.0 / lam1, 40.0 * tau0)
    total = 0.0
    s = ta
    while s < tb:
        if s >= tail:
            break
        h = min(max(tau0, s), cap, tb - s)
        if h * rate <= 0.1:
            total += _panel(v0, a0, gam, w0sq, s, h, GL4_X, GL4_W)
        else:
            total += _panel(v0, a0, gam, w0sq, s, h, GL12_X, GL12_W)
        s = s + h if s + h < tb else tb
    return total
