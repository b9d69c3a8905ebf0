"""The implicit step of a mass with a state-variable friction model (GMS, LuGre, Dahl).

All three models are ż = f(z, ẏ), F = g(z, ẏ): the generalized Maxwell-slip model
(`presliding.friction.GMSFriction`; z the elements' forces and slip directions),
LuGre (z the bristle deflection) and Dahl (z the force). Each step of size h is
backward Euler on the velocity, as the PI model's implicit step
(`presliding.motion._implicit`): with the velocity v' constant over the step
(the path of `force(displacement, time)` of each model, y linear in time) the
friction state is advanced exactly over the step (the models' closed forms:
exponentials of the lag and the bristles, Dahl's power law), and v' solves

    m·(v' − v)/h + F(v') = u,     F(v') the friction force at the end of the step,

with, for GMS, the Coulomb element c1·ŝ(|v'|)·Sign(v') set-valued at v' = 0: the
mass sticks — its position and every state bit for bit unchanged — iff
|m·v/h + u − Σ F_i| <= c1·F_S/F_C. Otherwise v' has the sign s of that
difference, and the travel d = |v'|·h > 0 is the root of the scalar residual
R(d) = (m/h²)·d + s·F(s·d/h) − s·(m·v/h + u) (R < 0 just above 0, R → ∞),
bracketed by doubling and found by Brent's method to rounding: with no Stribeck
drop and no lag, R is the PI step's piecewise-linear residual and the root is the
same to rounding (the GMS step then *is* the PI step). LuGre and Dahl have no
set-valued part: they stick only where m·v/h + u equals the force at rest exactly.

The parameters of a family are packed in one float vector (`GMS`, `LUGRE`,
`DAHL` say how); the element arrays k, c are the GMS elements (empty for the
others), the state arrays z, e hold the elements' forces and slip directions
(GMS) or the single state in z[0]. One compiled signature serves every family.
"""

from __future__ import annotations

import math

import numpy as np

from presliding.friction._baseline_kernels import dahl_step, lugre_output, lugre_step
from presliding.friction._gms_kernels import element_step, lag_rate, stribeck_factor
from presliding.hysteresis._jit import JitFlags, njit

_JIT: JitFlags = {"cache": True, "error_model": "numpy"}

#: family codes; the parameter vector of each: GMS [c1, F_S/F_C, v_s, δ, τ, σ],
#: LuGre [F_c, F_s, σ0, σ1, σ2, v_s], Dahl [F_c, σ0, α, σ]
GMS, LUGRE, DAHL = 0, 1, 2
N_PARAMETERS = 6
#: doublings of the bracket at most (a travel beyond 2^1100 times the first guess is inf)
MAX_DOUBLINGS = 1100
#: iterations of Brent's method at most (it converges to rounding in far fewer)
MAX_ITERATIONS = 200
EPS = np.finfo(np.float64).eps


@njit(**_JIT)
def rest_force(family, par, z):  # pragma: no cover - compiled
    """The friction force at v' = 0 besides the Coulomb element's set-valued part."""
    if family == GMS:
        total = 0.0
        for j in range(z.shape[0]):
            total += z[j]
        return total
    if family == LUGRE:
        return par[2] * z[0]
    return z[0]


@njit(**_JIT)
def stick_band(family, par):  # pragma: no cover - compiled
    """The largest force the contact carries at rest besides `rest_force`: c1·F_S/F_C."""
    return par[0] * par[1] if family == GMS else 0.0


@njit(**_JIT)
def stored_energy(family, par, k, z):  # pragma: no cover - compiled
    """Σ F_i²/(2 k_i) (GMS), ½·σ0·z² (LuGre), F²/(2 σ0) (Dahl: at its rest stiffness)."""
    if family == GMS:
        total = 0.0
        for j in range(z.shape[0]):
            total += z[j] * z[j] / (2.0 * k[j])
        return total
    if family == LUGRE:
        return 0.5 * par[2] * z[0] * z[0]
    return z[0] * z[0] / (2.0 * par[1])


@njit(**_JIT)
def trial_force(family, par, k, c, z, e, s, d, h):  # pragma: no cover - compiled
    """s·F at the end of a step of travel d >= 0 in direction s (the state left as it is)."""
    if family == GMS:
        shat = stribeck_factor(d / h, par[1], par[2], par[3])
        lam = lag_rate(par[4], shat)
        total = 0.0
        for j in range(z.shape[0]):
            total += element_step(z[j], e[j], k[j], c[j], s, d, h, shat, lam)[0]
        return par[0] * shat + s * total + par[5] * d / h
    if family == LUGRE:
        if d == 0.0:
            return s * par[2] * z[0]
        v = s * d / h
        x = v / par[5]
        g = par[0] + (par[1] - par[0]) * math.exp(-(x * x))  # as `lugre_step`, once
        rate = par[2] * d / (h * g)
        zss = v / rate
        zn = zss + (z[0] - zss) * math.exp(-rate * h)
        return s * (par[2] * zn + par[3] * (v - rate * zn) + par[4] * v)
    return s * dahl_step(z[0], s * d, par[0], par[1], par[2]) + par[3] * d / h


@njit(**_JIT)
def commit(family, par, k, c, z, e, s, d, h):  # pragma: no cover - compiled
    """Advance the state over the step (travel d in direction s) in place.

    Returns (the state's force after it: Σ F_i, σ0·z or F; the energy the friction
    dissipated on the step besides the viscous term; the viscous term's σ·v'²·h).
    """
    if d == 0.0:
        return rest_force(family, par, z), 0.0, 0.0
    before = stored_energy(family, par, k, z)
    if family == GMS:
        shat = stribeck_factor(d / h, par[1], par[2], par[3])
        lam = lag_rate(par[4], shat)
        lost = par[0] * shat * d
        total = 0.0
        for j in range(z.shape[0]):
            z[j], e[j], q = element_step(z[j], e[j], k[j], c[j], s, d, h, shat, lam)
            lost += q
            total += z[j]
        return total, lost, par[5] * d * d / h
    v = s * d / h
    if family == LUGRE:
        zn = lugre_step(z[0], v, h, par[2], par[0], par[1], par[5])
        force = lugre_output(zn, v, par[2], par[3], 0.0, par[0], par[1], par[5])
        z[0] = zn
        return par[2] * zn, force * s * d - (stored_energy(family, par, k, z) - before), \
            par[4] * d * d / h  # fmt: skip
    z[0] = dahl_step(z[0], s * d, par[0], par[1], par[2])
    return z[0], z[0] * s * d - (stored_energy(family, par, k, z) - before), par[3] * d * d / h


@njit(**_JIT)
def _residual(family, par, k, c, z, e, s, d, h, mh2, base):  # pragma: no cover - compiled
    return mh2 * d + trial_force(family, par, k, c, z, e, s, d, h) - base


@njit(**_JIT)
def solve_step(family, par, k, c, z, e, m, v, u, h):  # pragma: no cover - compiled
    """The signed travel δ = h·v' of one step (0: the mass sticks); NaN if no root is found.

    The state is not changed (`commit` applies the step).
    """
    rest = rest_force(family, par, z)
    g = m * v / h + u - rest
    if abs(g) <= stick_band(family, par):
        return 0.0
    s = 1.0 if g > 0.0 else -1.0
    mh2 = m / (h * h)
    base = s * rest + abs(g)
    lo, flo = 0.0, stick_band(family, par) - abs(g)  # R(0+): the static level, no motion yet
    hi = abs(g) / mh2
    if s * v > 0.0:  # moving on: the last step's travel is the first guess
        guess = s * v * h
        fguess = _residual(family, par, k, c, z, e, s, guess, h, mh2, base)
        if fguess < 0.0:
            lo, flo = guess, fguess
            hi = guess - fguess / mh2
        else:
            hi = guess
    fhi = _residual(family, par, k, c, z, e, s, hi, h, mh2, base)
    count = 0
    while fhi < 0.0:
        lo, flo = hi, fhi
        hi *= 2.0
        count += 1
        if count > MAX_DOUBLINGS or not hi < math.inf:
            return math.nan
        fhi = _residual(family, par, k, c, z, e, s, hi, h, mh2, base)
    if not (flo < 0.0):  # pragma: no cover - R(0+) < 0 by the stick test
        return s * lo
    return s * _brent(family, par, k, c, z, e, s, h, mh2, base, lo, flo, hi, fhi)


@njit(**_JIT)
def _brent(family, par, k, c, z, e, s, h, mh2, base, a, fa, b, fb):  # pragma: no cover
    """The root of `_residual` in [a, b] (fa < 0 <= fb), to rounding (Brent 1973, ch. 4):
    the bracket within 2 ulps, or the residual within the rounding of its terms."""
    ftol = 8.0 * EPS * (abs(base) + mh2 * abs(b))  # a residual at the rounding of its terms
    if abs(fb) <= ftol:
        return b
    cc, fc = a, fa
    step = last = b - a
    for _ in range(MAX_ITERATIONS):
        if (fb > 0.0) == (fc > 0.0):
            cc, fc = a, fa
            step = last = b - a
        if abs(fc) < abs(fb):
            a, b, cc = b, cc, b
            fa, fb, fc = fb, fc, fb
        tol = 2.0 * EPS * abs(b) + 1e-300
        half = 0.5 * (cc - b)
        if abs(half) <= tol or abs(fb) <= ftol:
            return b
        if abs(last) >= tol and abs(fa) > abs(fb):
            ratio = fb / fa
            if a == cc:  # secant
                p = 2.0 * half * ratio
                q = 1.0 - ratio
            else:  # inverse quadratic interpolation
                qa = fa / fc
                rb = fb / fc
                p = ratio * (2.0 * half * qa * (qa - rb) - (b - a) * (rb - 1.0))
                q = (qa - 1.0) * (rb - 1.0) * (ratio - 1.0)
            if p > 0.0:
                q = -q
            else:
                p = -p
            if 2.0 * p < min(3.0 * half * q - abs(tol * q), abs(last * q)):
                last = step
                step = p / q
            else:
                step = last = half
        else:
            step = last = half
        a, fa = b, fb
        b += step if abs(step) > tol else (tol if half > 0.0 else -tol)
        fb = _residual(family, par, k, c, z, e, s, b, h, mh2, base)
    return b
