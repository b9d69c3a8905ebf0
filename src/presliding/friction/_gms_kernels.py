"""Compiled pieces of the generalized Maxwell-slip model (GMS; Al-Bender et al. 2005).

One element i (stiffness k_i, slip force c_i·ŝ(w) at the sliding speed w) along a
monotone piece of travel d >= 0 in direction s over a time h (constant speed
w = d/h): with the element's force f̃ = s·F_i in the direction of motion and
a = c_i·ŝ(w) its slip force,

* an element that sticks (or has just reversed) loads elastically, f̃ + k_i·d, until
  it reaches a; it then slips at a (its lag starts from the target itself);
* an element that already slips in direction s follows the frictional lag
  df̃/dt = λ·(a − f̃), λ = 1/(τ·ŝ(w)) (the brief's C·(α_i − F_i/s(v)) with
  C = F_C/τ, s(v) = F_C·ŝ(v), α_i = c_i/F_C), but never faster than the spring
  can be stretched by the motion, df̃/dt <= k_i·w: it sticks while the lag would
  pull harder (below F* = a − k_i·w/λ), so that no energy is ever created;
* an element whose force is above its slip force (the Stribeck curve fell as the
  speed rose) slips at once and relaxes towards a by the same lag.

Every case is integrated in closed form (exponentials), so the lag is exact for
any step and τ = 0 is the instantaneous limit: then, with ŝ ≡ 1 (no Stribeck
drop), the element is exactly the play element of eq. 8 (F = k_j·(y − x_j),
|F| <= c_j). At rest (d = 0) nothing changes: the GMS rates carry sign(v) = 0.

`element_step` returns the new force, the new slip direction and the energy the
element dissipated on the piece (the work done on it minus the change of its
stored energy F²/(2k), computed from the closed form: >= 0 in every case).
`gms_force` is the model along a sampled path (`GMSFriction.force`).
"""

from __future__ import annotations

import math

from presliding.hysteresis._jit import JitFlags, njit

_JIT: JitFlags = {"cache": True, "error_model": "numpy"}


@njit(**_JIT)
def stribeck_factor(w, ratio, velocity, exponent):  # pragma: no cover - compiled
    """ŝ(w) = 1 + (ρ − 1)·exp(−(w/v_s)^δ) for a speed w >= 0 (1 when ρ = 1)."""
    if ratio == 1.0:
        return 1.0
    x = w / velocity
    return 1.0 + (ratio - 1.0) * math.exp(-(x * x if exponent == 2.0 else x**exponent))


@njit(**_JIT)
def lag_rate(lag, shat):  # pragma: no cover - compiled
    """λ = 1/(τ·ŝ): the rate of the frictional lag (inf for τ = 0, instantaneous slip)."""
    if lag == 0.0:
        return math.inf
    return 1.0 / (lag * shat)


@njit(**_JIT)
def element_step(f, e, k, c, s, d, h, shat, lam):  # pragma: no cover - compiled
    """One element over travel d >= 0 in direction s during h (module notes).

    Returns (force, slip direction, dissipated energy).
    """
    if d == 0.0:
        return f, e, 0.0
    ft = s * f
    a = c * shat
    w = d / h
    if ft >= a:  # above its slip force: slips at once, relaxing towards a
        if lam == math.inf:
            return s * a, s, a * d + (ft * ft - a * a) / (2.0 * k)
        x = math.exp(-lam * h)
        fn = a + (ft - a) * x
        work = w * (a * h + (ft - a) * (1.0 - x) / lam)
        return s * fn, s, work - (fn * fn - ft * ft) / (2.0 * k)
    if e != s or lam == math.inf:  # sticks until it reaches a, then slips at a
        fn = ft + k * d
        if fn < a:
            return s * fn, (e if e == s else 0.0), 0.0
        return s * a, s, a * (d - (a - ft) / k)
    star = a - k * w / lam  # the lag pulls harder than the spring below this force
    if ft < star:
        t1 = (star - ft) / (k * w)
        if t1 >= h:
            return s * (ft + k * d), s, 0.0
        rest = h - t1
        x = math.exp(-lam * rest)
        fn = a - (a - star) * x
        work = w * (a * rest - (a - star) * (1.0 - x) / lam)
        return s * fn, s, work - (fn * fn - star * star) / (2.0 * k)
    x = math.exp(-lam * h)
    fn = a - (a - ft) * x
    work = w * (a * h - (a - ft) * (1.0 - x) / lam)
    return s * fn, s, work - (fn * fn - ft * ft) / (2.0 * k)


@njit(**_JIT)
def gms_force(  # pragma: no cover - compiled
    y, time, start, coulomb, k, c, ratio, velocity, exponent, lag, viscous,
    f, e, prev_y, prev_t, v0, dir0, out, dissipated,
):  # fmt: skip
    """GMS force along (time, y) from the element forces f and slip directions e (updated
    in place); returns (velocity, direction) after the last sample.

    The displacement is linear in time between samples; the force at a sample is
    c1·ŝ(|v|)·sign + Σ F_i + σ·v with the velocity v of the interval ending there
    (sign: of the last nonzero increment). Samples before `start` get the force of
    the initial state. ``dissipated`` receives the energy dissipated since the start
    (elements, the Coulomb element and σ), cumulative.
    """
    v = v0
    d_last = dir0
    py = prev_y
    pt = prev_t
    total = 0.0
    for m in range(y.shape[0]):
        if m >= start:
            h = time[m] - pt
            dy = y[m] - py
            v = dy / h
            if dy != 0.0:
                s = 1.0 if dy > 0.0 else -1.0
                d = abs(dy)
                shat = stribeck_factor(d / h, ratio, velocity, exponent)
                lam = lag_rate(lag, shat)
                for j in range(k.shape[0]):
                    f[j], e[j], q = element_step(f[j], e[j], k[j], c[j], s, d, h, shat, lam)
                    total += q
                total += coulomb * shat * d + viscous * d * d / h
                d_last = s
            py = y[m]
            pt = time[m]
        fel = 0.0
        for j in range(k.shape[0]):
            fel += f[j]
        shat = stribeck_factor(abs(v), ratio, velocity, exponent)
        out[m] = coulomb * shat * d_last + fel + viscous * v
        dissipated[m] = total
    return v, d_last
