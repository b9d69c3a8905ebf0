"""Compiled closed-form pieces of an undamped network, and their event functions.

The compiled counterpart of `presliding.network._piece` for C = 0 and σ_v = 0 (the
pieces are then sums of harmonic modes): with Δq = N·z (N an orthonormal basis of the
null space of W_Sᵀ, S the stuck contacts; N = I when none sticks), the modes of
K_r·φ = ω²·M_r·φ (M_r = NᵀMN, K_r = Nᵀ(K + W_L K_el W_Lᵀ)N, through the Cholesky factor
of M_r) give the modal coordinates

    η_i(τ) = v_i·sin(ω_i τ)/ω_i + 2·a_i·sin²(ω_i τ/2)/ω_i²   (τ and a_i τ²/2 when ω_i = 0)

and Δq = B·η with B = N·Φ. Every event function is affine in ξ = [η, η̇]: a sliding
contact's velocity, its distance to the nearest element threshold, and a stuck
contact's Coulomb force (its margin c1 − |τ_c| is the event function).

A piece is the tuple returned by `build_piece` (`P_*` name its fields).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from presliding.network._kernel_contacts import per_contact, take_columns

EPS = np.finfo(np.float64).eps

(P_DIM, P_OMEGA, P_INV, P_RIGID, P_VM, P_A0, P_A2, P_B, P_WB, P_OMAX, P_SLIDING, P_ELASTIC,
 P_KEL, P_CSAT, P_FEL0, P_LAM0, P_DMIN, P_STUCK, P_SMAP, P_H, P_H0, P_NLIN, P_C1S, P_SL,
 P_THR) = range(25)  # fmt: skip


@njit(cache=True, error_model="numpy")
def null_space(ws):  # pragma: no cover - compiled
    """(N, rank): an orthonormal basis of {x: W_Sᵀx = 0} and the rank of W_S."""
    u, sv, _ = np.linalg.svd(ws, full_matrices=True)
    rank = 0
    lim = sv[0] * max(ws.shape[0], ws.shape[1]) * EPS * 16
    for x in sv:
        if x > lim:
            rank += 1
    return np.ascontiguousarray(u[:, rank:]), rank


@njit(cache=True, error_model="numpy")
def modes(mr, kr):  # pragma: no cover - compiled
    """(ω², Φ) of K_r·φ = ω²·M_r·φ, Φᵀ·M_r·Φ = I (Cholesky reduction to eigh)."""
    low = np.linalg.cholesky(mr)
    li = np.linalg.inv(low)
    a = li @ kr @ li.T
    a = 0.5 * (a + a.T)
    w2, y = np.linalg.eigh(a)
    return w2, np.ascontiguousarray(li.T @ y)


@njit(cache=True, error_model="numpy")
def build_piece(q0, v0, s, e, f, m, k, w, minv_w, c1, ek, er, owner):  # pragma: no cover
    """The piece from the state (modes s, deformations e, force f), and whether W_S is
    rank deficient (a redundant stick set: the caller does not use the piece)."""
    n, n_c = w.shape
    sliding = s != 0.0
    s_el = s[owner]
    elastic = (s_el * e < er) & sliding[owner]
    kel = per_contact(np.where(elastic, ek, 0.0), owner, n_c)
    csat = per_contact(np.where(~elastic & sliding[owner], ek * er, 0.0), owner, n_c)
    fel0 = per_contact(ek * e, owner, n_c)
    lam0 = s * c1 + fel0
    dmin = np.full(n_c, np.inf)
    for j in range(ek.shape[0]):
        if elastic[j]:
            dmin[owner[j]] = min(dmin[owner[j]], er[j] - s_el[j] * e[j])
    stuck = np.flatnonzero(~sliding)
    sl = np.flatnonzero(sliding)
    keff = k.copy()
    b0 = f - k @ q0
    for c in sl:
        for i in range(n):
            b0[i] -= w[i, c] * lam0[c]
            if kel[c] != 0.0:
                for j in range(n):
                    keff[i, j] += w[i, c] * kel[c] * w[j, c]
    rank = 0
    smap = np.zeros((stuck.shape[0], n))
    if stuck.shape[0]:
        ws = take_columns(w, stuck)
        ns, rank = null_space(ws)
        mw = take_columns(minv_w, stuck)
        smap = np.linalg.pinv(ws.T @ mw) @ mw.T
        mr = ns.T @ m @ ns
        kr = ns.T @ keff @ ns
        br = ns.T @ b0
        zd0 = ns.T @ v0
    else:
        ns = np.eye(n)
        mr, kr, br, zd0 = m.copy(), keff, b0, v0.copy()
    d = n - rank
    if d == 1:
        w2 = np.array([kr[0, 0] / mr[0, 0]])
        phi = np.ones((1, 1))
        a0 = br / mr[0, 0]
        vm = zd0.copy()
    elif d > 1:
        w2, phi = modes(mr, kr)
        a0 = phi.T @ br
        vm = phi.T @ (mr @ zd0)
    else:
        w2, phi, a0, vm = np.zeros(0), np.zeros((0, 0)), np.zeros(0), np.zeros(0)
    top = 0.0
    for x in w2:
        top = max(top, abs(x))
    omega = np.zeros(d)
    inv = np.zeros(d)
    rigid = np.zeros(d, np.bool_)
    for i in range(d):
        if w2[i] > 1e-13 * top:
            omega[i] = np.sqrt(w2[i])
            inv[i] = 1.0 / omega[i]
        else:
            rigid[i] = True
    omax = np.max(omega) if d else 0.0
    b = np.ascontiguousarray(ns @ phi) if d else np.zeros((n, 0))
    wb = np.ascontiguousarray(w.T @ b)
    hmat, h0, n_lin, c1s, thr = _events(q0, s, f, k, w, c1, kel, lam0, fel0, dmin, sl, stuck,
                                        smap, b, wb, d)  # fmt: skip
    pc = (d, omega, inv, rigid, vm, a0, a0 * 2.0, b, wb, omax, sliding, elastic, kel, csat,
          fel0, lam0, dmin, stuck, smap, hmat, h0, n_lin, c1s, sl, thr)  # fmt: skip
    return pc, stuck.shape[0] > rank


@njit(cache=True, error_model="numpy")
def _events(q0, s, f, k, w, c1, kel, lam0, fel0, dmin, sl, stuck, smap, b, wb, d
            ):  # pragma: no cover - compiled  # fmt: skip
    """The event functions h = H·ξ + h0 (rows: velocities, thresholds, stick margins)."""
    thr = sl[np.isfinite(dmin[sl])]
    n_lin = sl.shape[0] + thr.shape[0]
    nf = n_lin + stuck.shape[0]
    hmat = np.zeros((nf, 2 * d))
    h0 = np.zeros(nf)
    for a in range(sl.shape[0]):
        c = sl[a]
        for i in range(d):
            hmat[a, d + i] = s[c] * wb[c, i]
    for a in range(thr.shape[0]):
        c = thr[a]
        row = sl.shape[0] + a
        h0[row] = dmin[c]
        for i in range(d):
            hmat[row, i] = -s[c] * wb[c, i]
    if stuck.shape[0]:
        # λ_S − F_el,S = P·(f − K·q − W_L·λ_L) − F_el,S, λ_L = λ0_L + K_el·Δg_L
        dr = -(k @ b)
        r0 = f - k @ q0
        for c in sl:
            r0 -= w[:, c] * lam0[c]
            for i in range(d):
                dr[:, i] -= w[:, c] * (kel[c] * wb[c, i])
        hs = smap @ dr
        c0 = smap @ r0
        for a in range(stuck.shape[0]):
            h0[n_lin + a] = c0[a] - fel0[stuck[a]]
            hmat[n_lin + a, :d] = hs[a]
    return hmat, h0, n_lin, c1[stuck], thr


@njit(cache=True, error_model="numpy")
def modal(pc, tau, eta, etad, etadd):  # pragma: no cover - compiled
    """η, η̇, η̈ of the piece at τ (into the arrays)."""
    d = pc[P_DIM]
    om, inv, rigid, vm, a0, a2 = pc[P_OMEGA], pc[P_INV], pc[P_RIGID], pc[P_VM], pc[P_A0], pc[P_A2]
    for i in range(d):
        wt = om[i] * tau
        if rigid[i]:
            s1, sh = tau, 0.5 * tau
        else:
            s1 = np.sin(wt) * inv[i]
            sh = np.sin(0.5 * wt) * inv[i]
        cs = np.cos(wt)
        eta[i] = vm[i] * s1 + a2[i] * sh * sh
        etad[i] = vm[i] * cs + a0[i] * s1
        etadd[i] = a0[i] * cs - vm[i] * om[i] * om[i] * s1


@njit(cache=True, error_model="numpy")
def event_values(pc, tau, out, xi):  # pragma: no cover - compiled
    """All event functions at τ (into out; xi a work array of 3·dim)."""
    d = pc[P_DIM]
    modal(pc, tau, xi[:d], xi[d : 2 * d], xi[2 * d :])
    hmat, h0, n_lin, c1s = pc[P_H], pc[P_H0], pc[P_NLIN], pc[P_C1S]
    for j in range(h0.shape[0]):
        acc = h0[j]
        for i in range(2 * d):
            acc += hmat[j, i] * xi[i]
        out[j] = acc if j < n_lin else c1s[j - n_lin] - abs(acc)
