"""Compiled closed-form pieces of a network, and their event functions.

The compiled counterpart of `presliding.network.events._piece`. Undamped (C = 0, σ_v = 0: the
pieces are sums of harmonic modes): with Δq = N·z (N an orthonormal basis of the
null space of W_Sᵀ, S the stuck contacts; N = I when none sticks), the modes of
K_r·φ = ω²·M_r·φ (M_r = NᵀMN, K_r = Nᵀ(K + W_L K_el W_Lᵀ)N, through the Cholesky factor
of M_r) give the modal coordinates

    η_i(τ) = v_i·sin(ω_i τ)/ω_i + 2·a_i·sin²(ω_i τ/2)/ω_i²   (τ and a_i τ²/2 when ω_i = 0)

and Δq = B·η with B = N·Φ. Every event function is affine in ξ = [η, η̇]: a sliding
contact's velocity, its distance to the nearest element threshold, and a stuck
contact's Coulomb force (its margin c1 − |τ_c| is the event function). Stuck contacts
with parallel columns (w_c = α_c·w_r, the same relative displacement up to a factor)
stick and slip together as one combined contact: one margin Σ|α_c|·c1_c − |T| for the
group's Coulomb force T, shared in proportion to each c1_c (one of the distributions
that hold the structure: these forces are not unique).

Damped (C ≠ 0 or a sliding contact's σ_v): the first-order system of [z, ż] by its
complex modes (`presliding.network.events._kernel_damped`), B = N, and the event functions
affine in [z, ż] (the stick forces with −C·q̇ − W_L·σ_L·ġ_L). A piece is the tuple
returned by `build_piece` (`P_*` name its fields).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from presliding.network.events._kernel_contacts import per_contact, take_columns
from presliding.network.events._kernel_damped import damped_extras, damped_modes, damped_native

EPS = np.finfo(np.float64).eps

#: The rounding of a closed form's value, relative to the magnitudes of its terms.
ROUNDING = 64.0 * EPS

(P_DIM, P_OMEGA, P_INV, P_RIGID, P_VM, P_A0, P_A2, P_B, P_WB, P_OMAX, P_SLIDING, P_ELASTIC,
 P_KEL, P_CSAT, P_FEL0, P_LAM0, P_DMIN, P_STUCK, P_SMAP, P_H, P_H0, P_NLIN, P_C1S, P_SL,
 P_THR, P_GROUP, P_ALPHA, P_GSIZE, P_GFEL, P_CURVP, P_CURVT, P_ERR, P_ERRD, P_DAMPED, P_LAM,
 P_VEC, P_C0, P_DD, P_COEF, P_DP, P_DQ, P_RV) = range(42)  # fmt: skip


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
def parallel_groups(w, stuck):  # pragma: no cover - compiled
    """Stuck contacts with parallel columns w_c = α_c·w_r act as one combined contact.

    Returns (the representatives r, the group of each stuck contact, α_c, group sizes).
    """
    n_s = stuck.shape[0]
    wt = np.ascontiguousarray(w.T)  # rows: the contacts' columns
    reps = np.empty(n_s, np.int64)
    group = np.empty(n_s, np.int64)
    alpha = np.ones(n_s)
    size = np.zeros(n_s, np.int64)
    n_r = 0
    for a in range(n_s):
        wc = wt[stuck[a]]
        norm = np.sqrt(wc @ wc)
        group[a] = -1
        for r in range(n_r):
            wr = wt[reps[r]]
            al = (wr @ wc) / (wr @ wr)
            res = wc - al * wr
            if np.sqrt(res @ res) <= 1e-12 * norm:
                group[a], alpha[a] = r, al
                break
        if group[a] < 0:
            reps[n_r] = stuck[a]
            group[a] = n_r
            n_r += 1
        size[group[a]] += 1
    return reps[:n_r].copy(), group, alpha, size[:n_r].copy()


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
def build_piece(q0, v0, s, e, f, m, k, w, minv_w, c1, ek, er, owner, cmat, sigma, damped
                ):  # pragma: no cover - compiled  # fmt: skip
    """The piece from the state (modes s, deformations e, force f); whether the general
    loop must run it instead (stuck contacts redundant beyond parallel groups, or damped
    modes not well conditioned), and whether a parallel group sticks (its forces are not
    unique). `damped`: C (`cmat`) or a viscous term (`sigma`) is not zero."""
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
    ceff = cmat.copy()  # C + W_L·Σ_v·W_Lᵀ: the damping of the piece (the state holds q̇)
    if damped:
        for c in sl:
            if sigma[c] != 0.0:
                for i in range(n):
                    for j in range(n):
                        ceff[i, j] += w[i, c] * sigma[c] * w[j, c]
    for c in sl:
        for i in range(n):
            b0[i] -= w[i, c] * lam0[c]
            if kel[c] != 0.0:
                for j in range(n):
                    keff[i, j] += w[i, c] * kel[c] * w[j, c]
    rank = 0
    reps, group, alpha, gsize = parallel_groups(w, stuck)
    smap = np.zeros((reps.shape[0], n))
    if stuck.shape[0]:
        ws = take_columns(w, reps)
        ns, rank = null_space(ws)
        mw = take_columns(minv_w, reps)
        smap = np.linalg.pinv(ws.T @ mw) @ mw.T
        mr = ns.T @ m @ ns
        kr = ns.T @ keff @ ns
        br = ns.T @ b0
        zd0 = ns.T @ v0
        cr = ns.T @ ceff @ ns
    else:
        ns = np.eye(n)
        mr, kr, br, zd0, cr = m.copy(), keff, b0, v0.copy(), ceff
    d = n - rank
    if damped and np.any(cr != 0.0):  # as the general loop: damped when C_r is not zero
        return _damped_piece(q0, v0, s, f, k, w, kel, csat, fel0, lam0, dmin, stuck, sl, smap,
                             sliding, elastic, reps, group, alpha, gsize, rank, ns, mr, kr, br,
                             zd0, cr, c1, ek, er, owner, cmat, sigma)  # fmt: skip
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
    gfel, gc1 = _groups(fel0, c1, stuck, group, alpha, gsize, reps.shape[0])
    hmat, h0, n_lin, thr = _events(q0, s, f, k, w, kel, lam0, gfel, dmin, sl, smap, b, wb, d,
                                   cmat, sigma, damped)  # fmt: skip
    cp, ct = _curvature(hmat, omega, rigid, vm, a0, d)
    fs = _force_scale(f, k, q0, w, sl, lam0)
    # magnitudes of the terms of ξ(0), ξ'(0) and h0 (their rounding is ε times these)
    x0 = np.zeros(2 * d)
    x1 = np.zeros(2 * d)
    if d:
        pa = np.abs(phi.T)
        x0[d:] = pa @ (np.abs(mr) @ np.abs(zd0))
        x1[:d] = x0[d:]
        x1[d:] = pa @ (np.abs(ns.T) @ fs)
    e0, e1 = _rounding(hmat, h0, x0, x1, fs, smap, gfel, sl, thr, n_lin, er, owner)
    nc = np.zeros(0, np.complex128)
    ncc = np.zeros((0, 0), np.complex128)
    pc = (d, omega, inv, rigid, vm, a0, a0 * 2.0, b, wb, omax, sliding, elastic, kel, csat,
          fel0, lam0, dmin, stuck, smap, hmat, h0, n_lin, gc1, sl, thr, group, alpha, gsize,
          gfel, cp, ct, e0, e1, False, nc, ncc, nc, nc, np.zeros((0, 0)), ncc, ncc,
          np.zeros((w.shape[1], 0), np.complex128))  # fmt: skip
    return pc, reps.shape[0] > rank, reps.shape[0] < stuck.shape[0]


@njit(cache=True, error_model="numpy")
def _damped_piece(q0, v0, s, f, k, w, kel, csat, fel0, lam0, dmin, stuck, sl, smap, sliding,
                  elastic, reps, group, alpha, gsize, rank, ns, mr, kr, br, zd0, cr, c1, ek,
                  er, owner, cmat, sigma):  # pragma: no cover - compiled  # fmt: skip
    """The piece of a damped structure (`presliding.network.events._kernel_damped`)."""
    n = w.shape[0]
    d = n - rank
    ok = True
    if d:
        lam, vec, vinv, c0, dd, ok, minv = damped_modes(mr, cr, kr, br, zd0)
    else:
        lam, vec, vinv = np.zeros(0, np.complex128), np.zeros((0, 0), np.complex128), np.zeros(
            (0, 0), np.complex128)  # fmt: skip
        c0, dd, minv = np.zeros(0, np.complex128), np.zeros(0, np.complex128), np.zeros((0, 0))
    b = np.ascontiguousarray(ns) if d else np.zeros((n, 0))
    wb = np.ascontiguousarray(w.T @ b)
    gfel, gc1 = _groups(fel0, c1, stuck, group, alpha, gsize, reps.shape[0])
    hmat, h0, n_lin, thr = _events(q0, s, f, k, w, kel, lam0, gfel, dmin, sl, smap, b, wb, d,
                                   cmat, sigma, True)  # fmt: skip
    fs = _force_scale(f, k, q0, w, sl, lam0)
    fr = np.abs(ns.T) @ fs if d else np.zeros(0)
    if d and ok:
        coef, x0, x1, dp, dq, rv = damped_extras(hmat, lam, vec, vinv, c0, dd, b, cmat, w, sigma,
                                                 sliding, minv, cr, fr, zd0)  # fmt: skip
    else:
        coef, x0, x1 = np.zeros((h0.shape[0], 2 * d)), np.zeros(2 * d), np.zeros(2 * d)
        dp, dq = np.zeros((0, 0), np.complex128), np.zeros((0, 0), np.complex128)
        rv = np.zeros((w.shape[1], 0), np.complex128)
    e0, e1 = _rounding(hmat, h0, x0, x1, fs, smap, gfel, sl, thr, n_lin, er, owner)
    omax = 0.0
    for x in lam:
        omax = max(omax, abs(x))
    z = np.zeros(d)
    pc = (d, z, z, np.zeros(d, np.bool_), z, z, z, b, wb, omax, sliding, elastic, kel, csat,
          fel0, lam0, dmin, stuck, smap, hmat, h0, n_lin, gc1, sl, thr, group, alpha, gsize,
          gfel, np.zeros(h0.shape[0]), np.zeros(h0.shape[0]), e0, e1, True, lam, vec, c0, dd,
          coef, dp, dq, rv)  # fmt: skip
    return pc, reps.shape[0] > rank or not ok, reps.shape[0] < stuck.shape[0]


@njit(cache=True, error_model="numpy")
def _groups(fel0, c1, stuck, group, alpha, gsize, n_r):  # pragma: no cover - compiled
    """A group's elastic force Σ α_c·F_el,c (its Coulomb force is λ_r − it) and its bound
    Σ |α_c|·c1_c."""
    gfel = np.zeros(n_r)
    gc1 = np.zeros(n_r)
    for a in range(stuck.shape[0]):
        if gsize[group[a]] == 1:
            gfel[group[a]] = fel0[stuck[a]]
            gc1[group[a]] = c1[stuck[a]]
        else:
            gfel[group[a]] += alpha[a] * fel0[stuck[a]]
            gc1[group[a]] += abs(alpha[a]) * c1[stuck[a]]
    return gfel, gc1


@njit(cache=True, error_model="numpy")
def _force_scale(f, k, q0, w, sl, lam0):  # pragma: no cover - compiled
    """The magnitudes of the terms of f − K·q0 − W_L·λ0_L (C·q̇0 enters the damped
    pieces' rounding through |C_r|·|ż0|)."""
    fs = np.abs(f) + np.abs(k) @ np.abs(q0)
    for c in sl:
        fs += np.abs(w[:, c]) * abs(lam0[c])
    return fs


@njit(cache=True, error_model="numpy")
def _rounding(hmat, h0, x0, x1, fs, smap, gfel, sl, thr, n_lin, er, owner
              ):  # pragma: no cover - compiled  # fmt: skip
    """The rounding of each event function's value and slope at τ = 0 (ε times the
    magnitudes of their terms)."""
    e0 = np.zeros(h0.shape[0])
    for j in range(er.shape[0]):  # a distance to a threshold rounds with the thresholds
        for a in range(thr.shape[0]):
            if owner[j] == thr[a]:
                e0[sl.shape[0] + a] = max(e0[sl.shape[0] + a], er[j])
    if smap.shape[0]:
        e0[n_lin:] = np.abs(smap) @ fs + np.abs(gfel)
    ah = np.abs(hmat)
    return ROUNDING * (e0 + ah @ x0), ROUNDING * (ah @ x1)


@njit(cache=True, error_model="numpy")
def _events(q0, s, f, k, w, kel, lam0, gfel, dmin, sl, smap, b, wb, d, cmat, sigma, damped
            ):  # pragma: no cover - compiled  # fmt: skip
    """The event functions h = H·ξ + h0 (rows: velocities, thresholds, stick margins)."""
    thr = sl[np.isfinite(dmin[sl])]
    n_lin = sl.shape[0] + thr.shape[0]
    nf = n_lin + smap.shape[0]
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
    if smap.shape[0]:
        # T_r = λ_r − F_el,r, λ_r = P·(f − K·q − W_L·λ_L), λ_L = λ0_L + K_el·Δg_L
        dr = -(k @ b)
        r0 = f - k @ q0
        for c in sl:
            r0 -= w[:, c] * lam0[c]
            for i in range(d):
                dr[:, i] -= w[:, c] * (kel[c] * wb[c, i])
        hs = smap @ dr
        c0 = smap @ r0
        for a in range(smap.shape[0]):
            h0[n_lin + a] = c0[a] - gfel[a]
            hmat[n_lin + a, :d] = hs[a]
        if damped:  # − C·q̇ − W_L·σ_L·ġ_L, q̇ = B·(the velocity part)
            dv = -(cmat @ b)
            for c in sl:
                if sigma[c] != 0.0:
                    for i in range(d):
                        dv[:, i] -= w[:, c] * (sigma[c] * wb[c, i])
            hv = smap @ dv
            for a in range(smap.shape[0]):
                hmat[n_lin + a, d:] = hv[a]
    return hmat, h0, n_lin, thr


@njit(cache=True, error_model="numpy")
def _curvature(hmat, omega, rigid, vm, a0, d):  # pragma: no cover - compiled
    """(P, T): each function's second derivative lies in [P − T, P + T] for all τ.

    A mode of frequency ω > 0 adds a sinusoid A·cos ωτ + B·sin ωτ to function j
    (A = −H_η·a/ω² + H_η̇·v, B = (H_η·v + H_η̇·a)/ω), whose second derivative is at most
    ω²·√(A² + B²); a rigid mode adds the constant H_η·a."""
    nf = hmat.shape[0]
    cp = np.zeros(nf)
    ct = np.zeros(nf)
    for j in range(nf):
        for i in range(d):
            hh, gg = hmat[j, i], hmat[j, d + i]
            if rigid[i]:
                cp[j] += hh * a0[i]
            else:
                om = omega[i]
                amp_c = -hh * a0[i] / (om * om) + gg * vm[i]
                amp_s = (hh * vm[i] + gg * a0[i]) / om
                ct[j] += om * om * np.sqrt(amp_c * amp_c + amp_s * amp_s)
        ct[j] *= 1.0 + 1e-12
    return cp, ct


@njit(cache=True, error_model="numpy")
def modal(pc, tau, eta, etad, etadd):  # pragma: no cover - compiled
    """η, η̇, η̈ of the piece at τ (into the arrays); z, ż, z̈ for a damped piece."""
    if pc[P_DAMPED]:
        damped_native(pc[P_LAM], pc[P_VEC], pc[P_C0], pc[P_DD], tau, eta, etad, etadd)
        return
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
