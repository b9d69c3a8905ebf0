"""The compiled Moreau–Jean loop: one velocity-level contact problem per step, by PGS.

Per step of length h (θ-method for the smooth forces):

    Ŵ·Δv = h·(f − C·v − K·q − hθ·K·v) − W·P,        Ŵ = M + hθ·C + h²θ²·K
    u = Wᵀ(v + Δv) = u_free − G·P,                  G = Wᵀ Ŵ⁻¹ W (the Delassus matrix)
    P_c = h·λ_c(u_c),  λ_c ∈ c1_c·Sign(u_c) + Σ_j k_j·clip(e_j + h·u_c, ±r_j) + σ_v,c·u_c

solved by projected Gauss–Seidel over the contacts: each contact's 1-D inclusion is
solved exactly (stick when |ũ − ψ(0)| <= G_cc·h·c1, else Newton on the concave,
increasing, piecewise-linear ψ from u = 0, finite). Then v ← v + Δv,
q ← q + h·(θ·v_new + (1 − θ)·v), g ← g + h·u, e ← clip(e + h·u, ±r) (the stop
elements, exact for the step's constant u). A contact that sticks has u = 0.0
exactly, so its g and elements do not move (no creep); with every contact stuck and
W of full row rank, v = 0 and q stays exactly. Matrices are CSR (indptr, indices,
data); entries below 1e-18 of the diagonal scale are dropped when they are built.
"""

from __future__ import annotations

import math

import numpy as np

from presliding.hysteresis._jit import JitFlags, njit

_JIT: JitFlags = {"cache": True, "error_model": "numpy"}


@njit(**_JIT)
def matvec(ptr, idx, val, x, out):  # pragma: no cover - compiled
    for i in range(ptr.shape[0] - 1):
        acc = 0.0
        for p in range(ptr[i], ptr[i + 1]):
            acc += val[p] * x[idx[p]]
        out[i] = acc


@njit(**_JIT)
def elastic_forces(k, e, estart, out):  # pragma: no cover - compiled
    """F_el,c = Σ_j k_j·e_j of every contact (into out)."""
    for c in range(out.shape[0]):
        acc = 0.0
        for j in range(estart[c], estart[c + 1]):
            acc += k[j] * e[j]
        out[c] = acc


@njit(**_JIT)
def local_step(ut, gcc, h, c1, sig, k, r, e, lo, hi, fel0):  # pragma: no cover - compiled
    """(u, P) of one contact: u = ũ − G_cc·P, P = h·λ(u); fel0 its elastic force."""
    psi0 = gcc * h * fel0
    if abs(ut - psi0) <= gcc * h * c1:
        return 0.0, ut / gcc
    s = 1.0 if ut > psi0 else -1.0
    target = ut - s * gcc * h * c1
    u = 0.0
    for _ in range(hi - lo + 3):
        fel = 0.0
        slope = 1.0 + gcc * h * sig
        for j in range(lo, hi):
            x = e[j] + h * u
            if s * x < r[j]:
                fel += k[j] * x
                slope += gcc * h * k[j] * h
            else:
                fel += k[j] * s * r[j]
        psi = u + gcc * h * (fel + sig * u)
        if psi == target:
            break
        un = u + (target - psi) / slope
        if un == u:
            break
        u = un
    fel = 0.0
    for j in range(lo, hi):
        fel += k[j] * min(max(e[j] + h * u, -r[j]), r[j])
    return u, h * (c1 * s + fel + sig * u)


@njit(**_JIT)
def contacts_step(u, h, g, e, coul, hyst, visc, c1, sig, ek, er, estart
                  ):  # pragma: no cover - compiled  # fmt: skip
    """Move the contacts by their step velocities u: g, the elements (clipped at ±r) and
    the dissipated energies."""
    for c in range(g.shape[0]):
        if u[c] != 0.0:
            g[c] += h * u[c]
            coul[c] += c1[c] * h * abs(u[c])
            visc[c] += sig[c] * h * u[c] * u[c]
            for j in range(estart[c], estart[c + 1]):
                x = e[j] + h * u[c]
                e[j] = min(max(x, -er[j]), er[j])
                hyst[c] += ek[j] * er[j] * abs(x - e[j])


@njit(**_JIT)
def sample(row, q, v, acc, g, p, u, e, coul, hyst, visc, damp, work, h, ek, estart, o_q, o_v,
           o_a, o_g, o_lam, o_fel, o_ee, o_mode, o_en, o_sd):  # pragma: no cover  # fmt: skip
    """Write the state into sample row `row`."""
    o_q[row] = q
    o_v[row] = v
    o_a[row] = acc
    ee = 0.0
    for c in range(g.shape[0]):
        fel = 0.0
        for j in range(estart[c], estart[c + 1]):
            fel += ek[j] * e[j]
            ee += 0.5 * ek[j] * e[j] * e[j]
        o_fel[row, c] = fel
        o_g[row, c] = g[c]
        o_lam[row, c] = p[c] / h
        o_mode[row, c] = 0.0 if u[c] == 0.0 else math.copysign(1.0, u[c])
        o_en[row, 0, c] = coul[c]
        o_en[row, 1, c] = hyst[c]
        o_en[row, 2, c] = visc[c]
    o_ee[row] = ee
    o_sd[row, 0] = damp
    o_sd[row, 1] = work


@njit(**_JIT)
def moreau_loop(  # pragma: no cover - compiled
    n_steps, h, theta, t0, q, v, g, e, p,
    wi_p, wi_i, wi_v, b_p, b_i, b_v, wt_p, wt_i, wt_v, g_p, g_i, g_v, gdiag,
    c_p, c_i, c_v, k_p, k_i, k_v, f_t, f_v,
    c1, sig, ek, er, estart, tol, max_sweeps, rigid, every,
    o_q, o_v, o_a, o_g, o_lam, o_fel, o_ee, o_mode, o_en, o_sd,
):  # fmt: skip
    """Run n_steps steps from the state (q, v, g, e, p updated in place); samples every
    `every` steps into o_* (row 0 is the start). Returns (sweeps used at most, steps whose
    PGS stopped at max_sweeps)."""
    n = q.shape[0]
    n_c = g.shape[0]
    rhs = np.empty(n)
    tmp = np.empty(n)
    tmp2 = np.empty(n)
    dfree = np.empty(n)
    vfree = np.empty(n)
    u = np.empty(n_c)
    bp = np.empty(n)
    gp = np.empty(n_c)
    vt = np.empty(n)
    fel0 = np.empty(n_c)
    coul = np.zeros(n_c)
    hyst = np.zeros(n_c)
    visc = np.zeros(n_c)
    damp = 0.0
    work = 0.0
    most = 0
    capped = 0
    iu = 0
    for step in range(n_steps):
        t = t0 + (step + theta) * h
        while iu + 1 < f_t.shape[0] and f_t[iu + 1] <= t:
            iu += 1
        # the free motion
        matvec(c_p, c_i, c_v, v, tmp)
        for i in range(n):
            tmp2[i] = q[i] + h * theta * v[i]
        matvec(k_p, k_i, k_v, tmp2, rhs)
        for i in range(n):
            rhs[i] = h * (f_v[iu, i] - tmp[i] - rhs[i])
        matvec(wi_p, wi_i, wi_v, rhs, dfree)
        for i in range(n):
            vfree[i] = v[i] + dfree[i]
        matvec(wt_p, wt_i, wt_v, vfree, u)
        # warm start: u = u_free − G·P
        matvec(g_p, g_i, g_v, p, gp)
        for c in range(n_c):
            u[c] -= gp[c]
        elastic_forces(ek, e, estart, fel0)
        sweeps = 0
        scale = 1e-300
        for c in range(n_c):
            scale = max(scale, abs(p[c]))
        while True:
            sweeps += 1
            change = 0.0
            for c in range(n_c):
                ut = u[c] + gdiag[c] * p[c]
                uc, pc = local_step(ut, gdiag[c], h, c1[c], sig[c], ek, er, e, estart[c],
                                    estart[c + 1], fel0[c])  # fmt: skip
                d = pc - p[c]
                if d != 0.0:
                    for q_ in range(g_p[c], g_p[c + 1]):
                        u[g_i[q_]] -= g_v[q_] * d
                    p[c] = pc
                    change = max(change, abs(d))
                    scale = max(scale, abs(pc))
                u[c] = uc
            if change <= tol * scale:
                break
            if sweeps >= max_sweeps:
                capped += 1
                break
        most = max(most, sweeps)
        # the new velocity, positions, contacts and elements
        matvec(b_p, b_i, b_v, p, bp)
        stuck_all = True
        for c in range(n_c):
            if u[c] != 0.0:
                stuck_all = False
        for i in range(n):
            vn = vfree[i] - bp[i]
            if rigid and stuck_all:
                vn = 0.0
            vt[i] = theta * vn + (1.0 - theta) * v[i]
            tmp2[i] = (vn - v[i]) / h
            q[i] += h * vt[i]
            work += h * vt[i] * f_v[iu, i]
            v[i] = vn
        matvec(c_p, c_i, c_v, vt, tmp)
        for i in range(n):
            damp += h * vt[i] * tmp[i]
        contacts_step(u, h, g, e, coul, hyst, visc, c1, sig, ek, er, estart)
        row = -1
        if (step + 1) % every == 0:
            row = (step + 1) // every
        elif step == n_steps - 1:
            row = o_q.shape[0] - 1
        if row >= 0:
            sample(row, q, v, tmp2, g, p, u, e, coul, hyst, visc, damp, work, h, ek, estart,
                   o_q, o_v, o_a, o_g, o_lam, o_fel, o_ee, o_mode, o_en, o_sd)  # fmt: skip
    return most, capped
