"""Compiled time loops of the baseline friction models (Dahl 1968; LuGre 1995).

Both integrate their model exactly between samples for the input the caller
documents: the Dahl model along a displacement that is monotone between
samples, the LuGre model along a displacement that is linear in time between
samples (constant velocity on each interval). Inputs are validated before they
reach a kernel; kernels write only their output array and return the final state.
"""

from __future__ import annotations

import math

from presliding.hysteresis._jit import njit


@njit(cache=True)
def dahl_step(f, dy, coulomb, stiffness, exponent):  # pragma: no cover
    """The Dahl force after a monotone move dy from the force f (closed form).

    With s = sign(ẏ) and u = 1 − s·F/F_c ∈ [0, 2], the Dahl law dF/dy = σ0·u^α
    becomes, along a monotone move of length z (dy = s·dz), du/dz = −(σ0/F_c)·u^α,
    solved in closed form:

    α = 1:  u = u0·exp(−σ0 z/F_c)
    α > 1:  u = (u0^(1−α) + (α−1)·σ0 z/F_c)^(−1/(α−1))
    α < 1:  u = max(u0^(1−α) − (1−α)·σ0 z/F_c, 0)^(1/(1−α))   (reaches F_c in finite travel)
    """
    if dy == 0.0:
        return f
    s = 1.0 if dy > 0.0 else -1.0
    u0 = 1.0 - s * f / coulomb
    z = abs(dy) * (stiffness / coulomb)
    if u0 <= 0.0:
        u = 0.0
    elif exponent == 1.0:
        u = u0 * math.exp(-z)
    elif exponent > 1.0:
        e = exponent - 1.0
        u = (u0 ** (-e) + e * z) ** (-1.0 / e)
    else:
        e = 1.0 - exponent
        base = u0**e - e * z
        u = base ** (1.0 / e) if base > 0.0 else 0.0
    # u decreases along the move; the power round trip may overshoot u0 by an ulp
    u = min(u, u0)
    return s * coulomb * (1.0 - u)


@njit(cache=True)
def dahl_force(y, coulomb, stiffness, exponent, prev_y, force0, out):  # pragma: no cover
    """Dahl force along ``y`` from (prev_y, force0); returns the force after the last sample
    (each move between samples in closed form, `dahl_step`)."""
    f = force0
    prev = prev_y
    for t in range(y.shape[0]):
        f = dahl_step(f, y[t] - prev, coulomb, stiffness, exponent)
        prev = y[t]
        out[t] = f
    return f


@njit(cache=True)
def lugre_step(z, v, h, stiffness, coulomb, static, stribeck):  # pragma: no cover
    """The bristle deflection after a time h at the constant velocity v (exact).

    dz/dt = v − σ0|v|z/g(v) is linear at constant v, with the solution
    z(t + h) = z_ss + (z − z_ss)·exp(−σ0|v|h/g(v)),  z_ss = g(v)·sign(v)/σ0.
    """
    if v == 0.0:
        return z
    g = coulomb + (static - coulomb) * math.exp(-((v / stribeck) ** 2))
    rate = stiffness * abs(v) / g
    zss = v / rate
    return zss + (z - zss) * math.exp(-rate * h)


@njit(cache=True)
def lugre_output(z, v, stiffness, damping, viscous, coulomb, static, stribeck):  # pragma: no cover
    """F = σ0·z + σ1·ż + σ2·v at the deflection z and velocity v."""
    if v != 0.0:
        g = coulomb + (static - coulomb) * math.exp(-((v / stribeck) ** 2))
        zdot = v - stiffness * abs(v) * z / g
    else:
        zdot = 0.0
    return stiffness * z + damping * zdot + viscous * v


@njit(cache=True)
def lugre_force(
    y,
    time,
    start,
    stiffness,
    damping,
    viscous,
    coulomb,
    static,
    stribeck,
    prev_y,
    prev_t,
    z0,
    v0,
    out,
):  # pragma: no cover
    """LuGre force along (time, y) from bristle state z0; returns (z, v) after the last sample.

    On each interval the velocity v = Δy/Δt is constant, so the bristle equation
    is integrated exactly (`lugre_step`). Samples before `start` get the force of
    the initial state (z0, v0).
    """
    z = z0
    v = v0
    py = prev_y
    pt = prev_t
    for k in range(y.shape[0]):
        if k >= start:
            h = time[k] - pt
            v = (y[k] - py) / h
            z = lugre_step(z, v, h, stiffness, coulomb, static, stribeck)
            py = y[k]
            pt = time[k]
        out[k] = lugre_output(z, v, stiffness, damping, viscous, coulomb, static, stribeck)
    return z, v
