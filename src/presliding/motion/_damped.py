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
for short times (t·(2γ + ω0) <= 1/2), and otherwise the damped oscillation
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


def _gauss(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights on [0, 1]."""
    x, w = np.polynomial.legendre.leggauss(n)
    return np.ascontiguousarray(0.5 * (x + 1.0)), np.ascontiguousarray(0.5 * w)


# rules by κ·h (κ the fastest rate of v², h the panel): the error bound
# (κh)^(2n+1)·(n!)^4/((2n+1)·((2n)!)^3) stays below 1e-15 of the panel
GL2_X, GL2_W = _gauss(2)  # κh <= 0.005
GL4_X, GL4_W = _gauss(4)  # κh <= 0.2
GL10_X, GL10_W = _gauss(10)  # κh <= π
GL12_X, GL12_W = _gauss(12)  # κh <= 2π (graded panels, where the fast mode has decayed)


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
    # the series where the closed forms would cancel: short times, unless the damping is
    # light enough (4γ < ω0²·t) for the under-damped form to lose nothing
    if t * (2.0 * gam + w0) <= 0.5 and 4.0 * gam >= w0sq * t:
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
    em1 = math.expm1(-gam * t)
    e = 1.0 + em1
    if eps >= 0.0:  # under-damped (critical for eps = 0)
        wd = math.sqrt(eps)
        if wd == 0.0:
            sn = t
            cs = 1.0
            half = 0.0
        else:
            th = wd * t
            s1 = math.sin(th)
            cs = math.cos(th)
            sn = s1 / wd
            half = s1 * s1 / (1.0 + cs) if cs > 0.0 else 1.0 - cs  # 1 − cos θ
        g = e * sn
        c = e * (cs + gam * sn)
        one_minus_c = half - em1 * cs - gam * e * sn
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
        big = -em1
        one_minus_c = big - e * (2.0 * h * h + gam * sh)
    else:  # well separated modes
        e1 = math.exp(lam1 * t)
        e21 = math.exp(-2.0 * wh * t)
        g = e1 * (1.0 - e21) / (2.0 * wh)
        c = e1 * (-lam2 + lam1 * e21) / (2.0 * wh)
        big = 1.0
        one_minus_c = 1.0 - c
    # Q = (1 − c)/ω0², or the divided difference of the modes (ψ1 − ψ2)/(λ1 − λ2):
    # the one whose subtraction loses fewer digits (K -> 0 needs the second)
    p1 = _psi(lam1, t)
    p2 = _psi(lam2, t)
    if w0sq > 0.0 and one_minus_c > 0.0 and big * (p1 - p2) <= p1 * one_minus_c:
        return g, c, one_minus_c / w0sq
    return g, c, (p1 - p2) / (2.0 * wh)


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

    v² varies at most at the rate κ = 2·max(ω0, γ + ω_h). Panels are at most
    π/κ long at the start of the piece and grow as half the time since its
    start (the fast mode has decayed there), capped by a quarter period of the
    oscillation or by the slow time scale 1/|λ1|; an over-damped piece that has
    crept towards rest for 40 slow time constants adds nothing more.
    """
    if not tb > ta:
        return 0.0
    eps = w0sq - gam * gam
    wh = math.sqrt(-eps) if eps < 0.0 else 0.0
    kappa = 2.0 * max(math.sqrt(w0sq), gam + wh)
    h0 = math.pi / kappa
    cap = np.inf
    tail = np.inf
    if eps > 0.0:
        cap = 0.5 * math.pi / math.sqrt(eps)  # half a period of v²
    elif w0sq > 0.0:
        lam1 = w0sq / (gam + wh)  # |λ1|
        cap = 0.5 * math.pi / lam1
        tail = max(40.0 / lam1, 40.0 * h0)
    total = 0.0
    s = ta
    while s < tb:
        if s >= tail:
            break
        h = min(max(h0, 0.5 * s), cap, tb - s)
        kh = kappa * h
        if kh <= 0.005:
            total += _panel(v0, a0, gam, w0sq, s, h, GL2_X, GL2_W)
        elif kh <= 0.2:
            total += _panel(v0, a0, gam, w0sq, s, h, GL4_X, GL4_W)
        elif kh <= math.pi:
            total += _panel(v0, a0, gam, w0sq, s, h, GL10_X, GL10_W)
        else:
            total += _panel(v0, a0, gam, w0sq, s, h, GL12_X, GL12_W)
        s = s + h if s + h < tb else tb
    return total
