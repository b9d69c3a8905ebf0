"""Compiled damped pieces: the first-order system by its complex modes, in closed form.

With damping (C_r ≠ 0: dashpots, or a sliding contact's viscous term) the reduced
motion x = [z, ż] obeys ẋ = A·x + h, A = [[0, I], [−M_r⁻¹K_r, −M_r⁻¹C_r]],
h = [0, M_r⁻¹b_r]. With A = V·Λ·V⁻¹ (complex eigenvectors, well conditioned: the
caller falls back to the general loop otherwise), c0 = V⁻¹x(0), dd = V⁻¹h:

    x(τ) = Re V·(e^{Λτ}·c0 + τ·φ1(Λτ)·dd),   ẋ(τ) = Re V·e^{Λτ}·g,   g = Λ·c0 + dd,

φ1(z) = (e^z − 1)/z, without cancellation (the complex expm1 from the real one). The
event functions H·x + h0 have second derivatives bounded on a cell [a, b] by
Σ_i |(H·V)_ji|·|g_i|·|λ_i|·e^{max(Re λ_i·a, Re λ_i·b)} (the certified search, per cell).
The dissipation ∫ żᵀC_z ż and σ_c·∫ ġ_c² is in closed form: with ż = ẋ[:d] = Re Σ_i u_i·e^{λ_i t},
Re(a)·Re(b) = ½·Re(a·b + a·b̄) and ∫_0^τ e^{μt} dt = τ·φ1(μτ).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from presliding.network.events._piece import MAX_CONDITION  # beyond it: the general loop


@njit(cache=True, error_model="numpy")
def phi1(z):  # pragma: no cover - compiled
    """(e^z − 1)/z for complex z, without cancellation (1 at z = 0)."""
    x, y = z.real, z.imag
    if x == 0.0 and y == 0.0:
        return 1.0 + 0.0j
    if abs(z) < 1e-4:
        return 1.0 + z * (0.5 + z * (1.0 / 6.0 + z / 24.0))
    em = math.expm1(x)
    sh = math.sin(0.5 * y)
    re = em * math.cos(y) - 2.0 * sh * sh
    im = math.exp(x) * math.sin(y)
    return complex(re, im) / z


@njit(cache=True, error_model="numpy")
def damped_modes(mr, cr, kr, br, zd0):  # pragma: no cover - compiled
    """(λ, V, V⁻¹, c0, dd, well conditioned, M_r⁻¹) of the first-order reduced system."""
    d = mr.shape[0]
    minv = np.linalg.inv(mr)
    a = np.zeros((2 * d, 2 * d), np.complex128)
    mk = minv @ kr
    mc = minv @ cr
    for i in range(d):
        a[i, d + i] = 1.0
        for j in range(d):
            a[d + i, j] = -mk[i, j]
            a[d + i, d + j] = -mc[i, j]
    hb = minv @ br
    x0 = np.zeros(2 * d, np.complex128)
    h = np.zeros(2 * d, np.complex128)
    for i in range(d):
        x0[d + i] = zd0[i]
        h[d + i] = hb[i]
    lam, vec_any = np.linalg.eig(a)
    vec = np.ascontiguousarray(vec_any)
    ok = np.linalg.cond(vec) < MAX_CONDITION
    vinv = np.ascontiguousarray(
        np.linalg.inv(vec) if ok else np.zeros((2 * d, 2 * d), np.complex128)
    )
    return lam, vec, vinv, vinv @ x0, vinv @ h, ok, minv


@njit(cache=True, error_model="numpy")
def damped_native(lam, vec, c0, dd, tau, pos, vel, acc):  # pragma: no cover - compiled
    """z, ż, z̈ of a damped piece at τ (into pos, vel, acc)."""
    n2 = lam.shape[0]
    d = n2 // 2
    m = np.empty(n2, np.complex128)
    mp = np.empty(n2, np.complex128)
    for i in range(n2):
        z = lam[i] * tau
        ex = np.exp(z)
        m[i] = ex * c0[i] + tau * phi1(z) * dd[i]
        mp[i] = ex * (lam[i] * c0[i] + dd[i])
    for r in range(d):
        xz, xv, xa = 0.0, 0.0, 0.0
        for i in range(n2):
            xz += (vec[r, i] * m[i]).real
            xv += (vec[d + r, i] * m[i]).real
            xa += (vec[d + r, i] * mp[i]).real
        pos[r], vel[r], acc[r] = xz, xv, xa


@njit(cache=True, error_model="numpy")
def damped_bound(coef, lam, a, b, out):  # pragma: no cover - compiled
    """T_j of every function on [a, b] (into out): Σ_i coef_ji·e^{max(Re λ_i a, Re λ_i b)}."""
    grow = np.empty(lam.shape[0])
    for i in range(lam.shape[0]):
        grow[i] = math.exp(max(lam[i].real * a, lam[i].real * b))
    for j in range(coef.shape[0]):
        acc = 0.0
        for i in range(lam.shape[0]):
            acc += coef[j, i] * grow[i]
        out[j] = acc * (1.0 + 1e-12)


@njit(cache=True, error_model="numpy")
def damped_extras(hmat, lam, vec, vinv, c0, dd, ns, cmat, w, sigma, sliding, minv, cr, fr, zd0
                  ):  # pragma: no cover - compiled  # fmt: skip
    """(curvature coefficients |(H·V)_ji|·|g_i|·|λ_i|, the rounding scales |x(0)|, |ẋ(0)|,
    and the dissipation's matrices P = UᵀC_zU, Q = UᵀC_zŪ and rows r_c = w_cᵀN·U of the
    viscous contacts), U = V[d:]·diag(g)."""
    n2 = lam.shape[0]
    d = n2 // 2
    g = lam * c0 + dd
    beta = np.ascontiguousarray(hmat.astype(np.complex128)) @ vec
    coef = np.abs(beta) * (np.abs(g) * np.abs(lam))
    # the magnitudes of the terms of x(0) and ẋ(0)
    vabs, iabs = np.abs(vec), np.abs(vinv)
    acc = np.abs(minv) @ (fr + np.abs(cr) @ np.abs(zd0))
    x0 = np.zeros(n2)
    x1 = np.zeros(n2)
    x0[d:] = np.abs(zd0)
    x1[:d] = np.abs(zd0)
    x1[d:] = acc
    c0abs = iabs @ x0
    xa = np.zeros(n2)
    xa[d:] = acc
    s0 = x0 + vabs @ c0abs
    s1 = x1 + vabs @ (np.abs(lam) * c0abs + iabs @ xa)
    u = np.empty((d, n2), np.complex128)  # ż = ẋ[:d] = Re Σ_i u_i·e^{λ_i t}
    for r in range(d):
        for i in range(n2):
            u[r, i] = vec[r, i] * g[i]
    ut = np.ascontiguousarray(u.T)
    cz = np.ascontiguousarray((ns.T @ cmat @ ns).astype(np.complex128))
    p = ut @ (cz @ u)
    q = ut @ (cz @ np.conj(u))
    wn = np.ascontiguousarray((w.T @ ns).astype(np.complex128)) @ u  # ġ = Re(wn·e^{λt})
    rv = np.zeros((w.shape[1], n2), np.complex128)
    for c in range(w.shape[1]):
        if sliding[c] and sigma[c] > 0.0:
            rv[c] = wn[c]
    return coef, s0, s1, p, q, rv


@njit(cache=True, error_model="numpy")
def dissipation(lam, p, q, rv, sigma, tau, visc):  # pragma: no cover - compiled
    """∫_0^τ żᵀC_z ż dt, and σ_c·∫_0^τ ġ_c² dt of every contact (into visc)."""
    n2 = lam.shape[0]
    i1 = np.empty((n2, n2), np.complex128)
    i2 = np.empty((n2, n2), np.complex128)
    for i in range(n2):
        for j in range(n2):
            mu = lam[i] + lam[j]
            i1[i, j] = tau * phi1(mu * tau)
            nu = lam[i] + np.conj(lam[j])
            i2[i, j] = tau * phi1(nu * tau)
    total = 0.0
    for i in range(n2):
        for j in range(n2):
            total += 0.5 * (p[i, j] * i1[i, j] + q[i, j] * i2[i, j]).real
    for c in range(rv.shape[0]):
        acc = 0.0
        if sigma[c] > 0.0 and np.any(rv[c] != 0.0):
            for i in range(n2):
                for j in range(n2):
                    a = rv[c, i]
                    acc += 0.5 * (a * rv[c, j] * i1[i, j] + a * np.conj(rv[c, j]) * i2[i, j]).real
        visc[c] = sigma[c] * acc
    return total
