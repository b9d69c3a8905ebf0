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

The viscous dissipation σ·∫v² is in closed form too (`square_integral`): the
integral of the square of the closed-form velocity, by modes (a series in
γ² − ω0² near critical damping and over short times), never through the energy
balance, so that the balance of a motion stays an independent check of the
closed forms.
"""

from __future__ import annotations

import math

import numpy as np

from presliding.hysteresis._jit import JitFlags, njit

_JIT: JitFlags = {"cache": True, "error_model": "numpy"}
_EPS = 2.220446049250313e-16
_MAX_TERMS = 60
_MAX_ITER = 200


_INV_FACT = np.array([1.0 / math.factorial(n) for n in range(64)])
_SERIES_TERMS = 20  # at most, of the near-critical series of ∫v²


@njit(**_JIT)
def _psi(lam, t):  # pragma: no cover - compiled
    """(e^{λt} − 1)/λ (t when λ = 0)."""
    if lam == 0.0:
        return t
    return math.expm1(lam * t) / lam


@njit(**_JIT)
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


@njit(**_JIT)
def state(v0, a0, gam, w0sq, t):  # pragma: no cover - compiled
    """Displacement, velocity and acceleration after time t of one damped piece."""
    g, c, q = basis(gam, w0sq, t)
    d = v0 * (g + 2.0 * gam * q) + a0 * q
    v = v0 * c + a0 * g
    a = a0 * (c - 2.0 * gam * g) - v0 * w0sq * g
    return d, v, a


@njit(**_JIT)
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


@njit(**_JIT)
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


@njit(**_JIT)
def _square_series(v0, b, gam, eta, h):  # pragma: no cover - compiled
    """∫_0^h v² with v = e^{−γs}·(v0·C(s) + b·S(s)), C, S entire in η = γ² − ω0² (real).

    C = cosh(√η s), S = sinh(√η s)/√η (cos and sin/ω when η < 0). With
    q = 4ηh² and the moments μ_n = ∫_0^1 u^n·e^{−x·u} du / n! (x = 2γh; all positive
    sums: μ_N = e^{−x}·Σ_j x^j/(N+1+j)!, then μ_{n−1} = x·μ_n + e^{−x}/n! downward, or
    x^{−(n+1)} once the tail e^{−x}·Σ_{j<=n} x^j/j! is below 1e-18, x >= 2N + 50):

        ∫ = v0²·h·(μ0 + ½Σ_{k>=1} q^k μ_2k) + 2·v0·b·h²·Σ_{k>=0} q^k μ_2k+1
            + b²·h³·2·Σ_{k>=1} q^{k−1} μ_2k

    (C² = (1 + C(2s))/2, C·S = S(2s)/2, S² = (C(2s) − 1)/(2η)). The terms fall
    at least as fast as |q|^k/(2k+1)! and as (|η|/γ²)^k: used where either is small.
    """
    q = 4.0 * eta * h * h
    # terms needed: the k-th is below min(|q|^k/(2k+1)!, (|η|/γ²)^k) of the first
    ratio = abs(eta) / (gam * gam)
    b1 = 1.0
    b2 = 1.0
    n_terms = _SERIES_TERMS
    for k in range(1, _SERIES_TERMS + 1):
        b1 *= abs(q) / ((2 * k) * (2 * k + 1))
        b2 *= ratio
        if min(b1, b2) < 1e-18:
            n_terms = k
            break
    n_max = 2 * n_terms + 1
    x = 2.0 * gam * h
    if x >= 2.0 * n_max + 50.0:  # μ_n = x^{−(n+1)}: sums of powers of r = q/x²
        r = q / (x * x)
        rk = 1.0
        s_all = 1.0  # Σ_{k<=K} r^k
        for _ in range(n_terms):
            rk *= r
            s_all += rk
        cc = (1.0 + 0.5 * (s_all - 1.0)) / x
        cs = s_all / (x * x)
        ss = (s_all - rk) / (x * x * x)
    else:
        # μ_N by its series, then downward μ_{n−1} = x·μ_n + e^{−x}/n!, each moment
        # taken into the Horner sums as it comes: no array
        e = math.exp(-x)
        term = _INV_FACT[n_max + 1]
        acc = term
        j = 0
        while term > 1e-18 * acc:
            term *= x / (n_max + 2 + j)
            acc += term
            j += 1
        mu = e * acc
        acc_o = 0.0  # Σ_{k>=0} q^k μ_{2k+1}
        acc_s = 0.0  # Σ_{k>=1} q^{k−1} μ_{2k}
        for n in range(n_max, 0, -1):
            if n % 2 == 1:
                acc_o = mu + q * acc_o
            else:
                acc_s = mu + q * acc_s
            mu = x * mu + e * _INV_FACT[n]
        cc = mu + 0.5 * q * acc_s  # μ0 + ½Σ_{k>=1} q^k μ_{2k}
        cs = acc_o
        ss = acc_s
    return h * (v0 * v0 * cc + h * (2.0 * v0 * b * cs + 2.0 * b * b * h * ss))


@njit(**_JIT)
def square_integral(v0, a0, gam, w0sq, h):  # pragma: no cover - compiled
    """∫_0^h v(s)² ds of one damped piece with v(0) = v0, v'(0) = a0, in closed form.

    With η = γ² − ω0² (> 0 over-damped, < 0 under-damped) and δ = 2·sqrt(|η|) the
    spacing of the modes (λ1 − λ2 = δ, or the frequency 2ω_d):

    * near critical damping or over short times (δ·h <= 1 or δ <= γ/2), the
      series of `_square_series` in η (real, no division by δ);
    * under-damped (ω_d = sqrt(−η)): v = e^{−γs}(v0·cos ω_d s + b·sin ω_d s),
      b = (γ·v0 + a0)/ω_d, and with E = ∫e^{−2γs} and ψ = ∫e^{(−2γ + 2iω_d)s},
      ∫v² = (v0² + b²)/2·E + (v0² − b²)/2·Re ψ + v0·b·Im ψ;
    * over-damped (modes λ1 = −ω0²/(γ + ω_h) slow, λ2 = −(γ + ω_h) fast):
      v = v0·e^{λ2 s} + w·g(s), w = a0 − λ2·v0, g = (e^{λ1 s} − e^{λ2 s})/δ, and
      ∫v² = v0²·Ψ(2λ2) + 2·v0·w·Ψ[2λ2, λ1+λ2] + 2·w²·Ψ[2λ2, λ1+λ2, 2λ1],
      divided differences of Ψ(μ) = ∫_0^h e^{μs} ds = expm1(μh)/μ, whose points
      are δ apart (well separated in this branch). K = 0 (λ1 = 0) is this case.

    Independent of the energy balance of the motion: it integrates the
    closed-form velocity, so the balance stays a check of the closed forms.
    """
    if not h > 0.0:
        return 0.0
    eta = gam * gam - w0sq
    delta = 2.0 * math.sqrt(abs(eta))
    if delta * h <= 1.0 or delta <= 0.5 * gam:
        return _square_series(v0, gam * v0 + a0, gam, eta, h)
    beta = 2.0 * gam
    if eta < 0.0:
        wd = 0.5 * delta
        b = (gam * v0 + a0) / wd
        e = -math.expm1(-beta * h) / beta
        ex = math.exp(-beta * h)
        th = 2.0 * wd * h
        re = ex * math.cos(th) - 1.0  # e^{zh} − 1, z = −β + 2iω_d
        im = ex * math.sin(th)
        den = beta * beta + 4.0 * wd * wd  # (e^{zh} − 1)/z = (re + i·im)·conj(z)/|z|²
        rc = (-beta * re + 2.0 * wd * im) / den
        rs = (-beta * im - 2.0 * wd * re) / den
        return 0.5 * (v0 * v0 + b * b) * e + 0.5 * (v0 - b) * (v0 + b) * rc + v0 * b * rs
    wh = 0.5 * delta
    lam1 = -w0sq / (gam + wh)
    lam2 = -(gam + wh)
    w = a0 - lam2 * v0
    p0 = _psi(2.0 * lam2, h)
    p1 = _psi(lam1 + lam2, h)
    p2 = _psi(2.0 * lam1, h)
    d01 = (p1 - p0) / delta
    d12 = (p2 - p1) / delta
    d012 = (d12 - d01) / (2.0 * delta)
    return v0 * v0 * p0 + 2.0 * v0 * w * d01 + 2.0 * w * w * d012


@njit(**_JIT)
def state_square(v0, a0, gam, w0sq, t):  # pragma: no cover - compiled
    """`state` and `square_integral` at once: (d, v, a, ∫_0^t v²).

    Where both are in closed form and under-damped, the square integral reuses
    the exponential and the sine and cosine of the state (e^{−2γt} = e², the
    double angle), so a sample with the viscous loss costs little more than
    one without; elsewhere the two functions are called.
    """
    eta = gam * gam - w0sq
    if t > 0.0 and eta < 0.0:
        wd = math.sqrt(-eta)
        if 2.0 * wd * t > 1.0 and 2.0 * wd > 0.5 * gam:
            # basis() in its under-damped closed form (the series cannot apply: w0·t > 1/2)
            em1 = math.expm1(-gam * t)
            e = 1.0 + em1
            th = wd * t
            s1 = math.sin(th)
            cs = math.cos(th)
            sn = s1 / wd
            half = s1 * s1 / (1.0 + cs) if cs > 0.0 else 1.0 - cs
            g = e * sn
            c = e * (cs + gam * sn)
            q = (half - em1 * cs - gam * e * sn) / w0sq
            d = v0 * (g + 2.0 * gam * q) + a0 * q
            v = v0 * c + a0 * g
            a = a0 * (c - 2.0 * gam * g) - v0 * w0sq * g
            # square_integral() in its under-damped closed form, from the same values
            beta = 2.0 * gam
            b = (gam * v0 + a0) / wd
            ee = -(em1 * (em1 + 2.0)) / beta  # −expm1(−2γt)/(2γ)
            ex = e * e
            re = ex * (cs * cs - s1 * s1) - 1.0
            im = ex * (2.0 * s1 * cs)
            den = beta * beta + 4.0 * wd * wd
            rc = (-beta * re + 2.0 * wd * im) / den
            rs = (-beta * im - 2.0 * wd * re) / den
            sq = 0.5 * (v0 * v0 + b * b) * ee + 0.5 * (v0 - b) * (v0 + b) * rc + v0 * b * rs
            return d, v, a, sq
    d, v, a = state(v0, a0, gam, w0sq, t)
    return d, v, a, square_integral(v0, a0, gam, w0sq, t)


@njit(**_JIT)
def velocity_square_integral(v0, a0, gam, w0sq, ta, tb):  # pragma: no cover - compiled
    """∫_ta^tb v(s)² ds of one damped piece (times since its start), in closed form.

    The piece is restarted at ta (its velocity and acceleration there) and
    `square_integral` taken over tb − ta.
    """
    if not tb > ta:
        return 0.0
    if ta > 0.0:
        _, v0, a0 = state(v0, a0, gam, w0sq, ta)
    return square_integral(v0, a0, gam, w0sq, tb - ta)
