"""One closed-form piece of a network's motion: fixed stick/slip modes, constant force.

Between two events every contact either sticks (the constraint w_cᵀ·q̇ = 0) or slides
in a fixed direction s_c with a fixed set of elastic elements, so the motion is linear
with constant coefficients. With Δq = q − q0 = N·z (N an orthonormal basis of the null
space of W_Sᵀ, S the sticking contacts; N = I when none sticks):

    M_r·z̈ + C_r·ż + K_r·z = b_r,       M_r = NᵀMN,  C_r = Nᵀ(C + W_L Σ_v W_Lᵀ)N,
                                       K_r = Nᵀ(K + W_L K_el W_Lᵀ)N,
                                       b_r = Nᵀ(f − K·q0 − W_L·λ0_L − (C + W_L Σ_v W_Lᵀ)·0)

Undamped pieces (C_r = 0) are solved per mode of the generalised eigenproblem
K_r·φ = ω²·M_r·φ in the closed form of the single mass (harmonic, or parabolic for
ω = 0, without cancellation); damped pieces by the matrix exponential of the
augmented first-order system [[0, I, 0], [−M_r⁻¹K_r, −M_r⁻¹C_r, M_r⁻¹b_r], [0, 0, 0]]
(scipy's expm, batched over the sample times), with the dissipated energies
∫ q̇ᵀCq̇ and σ_v,c·∫ ġ_c² in closed form by Van Loan's block exponential.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.linalg
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: Damped pieces whose eigenvector matrix has a larger condition number take the matrix
#: exponential (their modal closed form would lose cond·ε: a defective matrix, e.g. a
#: critically damped mode, has computed eigenvectors with cond about 1/√ε ≈ 7e7 or more).
MAX_CONDITION = 1e6


def null_space(ws: FloatArray, n: int) -> tuple[FloatArray | None, int]:
    """(N, rank of W_S): an orthonormal basis of {x: W_Sᵀx = 0}; N is None for the identity."""
    if ws.shape[1] == 0:
        return None, 0
    u, sv, _ = np.linalg.svd(ws, full_matrices=True)
    rank = int(np.sum(sv > sv[0] * max(ws.shape) * np.finfo(float).eps * 16))
    return np.ascontiguousarray(u[:, rank:]), rank


class Piece:
    """The closed form of one piece, evaluated at times τ since its start (vectorised)."""

    def __init__(self, m: FloatArray, c: FloatArray, k: FloatArray, w: FloatArray,
                 f: FloatArray, q0: FloatArray, v0: FloatArray, sliding: NDArray[np.bool_],
                 s: FloatArray, kel: FloatArray, lam0: FloatArray, sigma: FloatArray,
                 nullsp: FloatArray | None, cache: dict | None = None,
                 key: bytes = b"") -> None:  # fmt: skip
        self.q0, self.v0, self.f, self.w, self.c = q0, v0, f, w, c
        wl = w[:, sliding]
        self.sliding = sliding
        ceff = c + (wl * sigma[sliding]) @ wl.T
        keff = k + (wl * kel[sliding]) @ wl.T
        b0 = f - k @ q0 - wl @ lam0[sliding]
        self.ceff, self.keff, self.b0 = ceff, keff, b0
        self.nullsp = nullsp
        if nullsp is None:
            mr, cr, kr, br, zd0 = m, ceff, keff, b0, v0
        else:
            mr = nullsp.T @ m @ nullsp
            cr = nullsp.T @ ceff @ nullsp
            kr = nullsp.T @ keff @ nullsp
            br = nullsp.T @ b0
            zd0 = nullsp.T @ v0
        self.dim = mr.shape[0]
        self.damped = bool(np.any(cr != 0.0))
        self.mr = mr
        if self.dim == 0:
            self.omega_max = 0.0
        elif not self.damped:
            if self.dim == 1:  # as the single mass: ω² = K/M, a0 = b/M
                w2 = np.array([kr[0, 0] / mr[0, 0]])
                self.phi = np.ones((1, 1))
                self.a0 = br / mr[0, 0]
                self.vm = zd0.copy()
            else:
                if cache is not None and key in cache:  # the same modes, met before
                    w2, self.phi = cache[key]
                else:
                    w2, self.phi = scipy.linalg.eigh(kr, mr, check_finite=False)
                    if cache is not None:
                        cache[key] = (w2, self.phi)
                self.a0 = self.phi.T @ br
                self.vm = self.phi.T @ (mr @ zd0)
            w2 = np.where(w2 > 1e-13 * max(float(np.max(np.abs(w2))), 0.0), w2, 0.0)
            self.omega = np.sqrt(w2)
            self.omega_max = float(np.max(self.omega))
            self.rigid = self.omega == 0.0
            self.any_rigid = bool(self.rigid.any())
            self.a2 = self.a0 * 2.0  # exact: the products below are unchanged
            self.inv_omega = np.where(self.rigid, 0.0, 1.0 / np.where(self.rigid, 1.0, self.omega))
        else:
            d = self.dim
            entry: Any = cache.get(key) if cache is not None else None
            minv = np.linalg.inv(mr) if entry is None else entry[0]
            a = np.zeros((2 * d, 2 * d))
            a[:d, d:] = np.eye(d)
            a[d:, :d] = -minv @ kr
            a[d:, d:] = -minv @ cr
            h = np.concatenate([np.zeros(d), minv @ br])
            x0 = np.concatenate([np.zeros(d), zd0])
            self.amat, self.h, self.x0 = a, h, x0
            if entry is None:
                lam, vec = np.linalg.eig(a)
                modal = bool(np.linalg.cond(vec) < MAX_CONDITION)
                entry = (minv, lam, vec, modal, np.linalg.inv(vec) if modal else None)
                if cache is not None:
                    cache[key] = entry
            lam, vec, vinv = entry[1], entry[2], entry[4]
            self.modal: bool = entry[3]
            self.omega_max = float(np.max(np.abs(lam)))
            if self.modal:  # x(t) = V·(e^{Λt}·c0 + t·φ1(Λt)·d), φ1(z) = (e^z − 1)/z
                self.lam, self.vec, self.c0, self.dd = lam, vec, vinv @ x0, vinv @ h
                self.vinv = vinv
        self.kr, self.cr, self.br, self.zd0 = kr, cr, br, zd0

    # ---------------------------------------------------------------- evaluation
    def native(self, tau: FloatArray) -> FloatArray:
        """ξ(τ), shape (T, 2·dim): [η, η̇] (modes) or [z, ż] (damped); z = ξ·`maps`[0],
        ż = ξ·`maps`[1]."""
        tau = np.asarray(tau, dtype=float).reshape(-1, 1)
        d = self.dim
        if d == 0:
            return np.zeros((tau.shape[0], 0))
        if not self.damped:
            wt = self.omega * tau
            s1 = np.sin(wt) * self.inv_omega
            sh = np.sin(0.5 * wt) * self.inv_omega
            if self.any_rigid:  # ω = 0: the parabola, without cancellation
                rows = np.broadcast_to(tau, s1.shape)
                s1[:, self.rigid] = rows[:, self.rigid]
                sh[:, self.rigid] = 0.5 * rows[:, self.rigid]
            out = np.empty((tau.shape[0], 2 * d))
            out[:, :d] = self.vm * s1 + self.a2 * sh * sh
            out[:, d:] = self.vm * np.cos(wt) + self.a0 * s1
            return out
        return self._first_order(tau[:, 0])[0]

    def native_one(self, t: float) -> FloatArray:
        """ξ(t) at one time, shape (2·dim,) (as a row of `native`)."""
        d = self.dim
        if d == 0 or self.damped:
            return self.native(np.array([t]))[0]
        wt = self.omega * t
        s1 = np.sin(wt) * self.inv_omega
        sh = np.sin(0.5 * wt) * self.inv_omega
        if self.any_rigid:
            s1[self.rigid] = t
            sh[self.rigid] = 0.5 * t
        out = np.empty(2 * d)
        out[:d] = self.vm * s1 + self.a2 * sh * sh
        out[d:] = self.vm * np.cos(wt) + self.a0 * s1
        return out

    def native_rate(self, t: float) -> FloatArray:
        """dξ/dτ at one time, shape (2·dim,): [η̇, η̈] (modes) or ẋ (damped)."""
        d = self.dim
        if d == 0:
            return np.zeros(0)
        if self.damped:
            return self._first_order(np.array([t]))[1][0]
        wt = self.omega * t
        s1 = np.sin(wt) * self.inv_omega
        if self.any_rigid:
            s1[self.rigid] = t
        cs = np.cos(wt)
        out = np.empty(2 * d)
        out[:d] = self.vm * cs + self.a0 * s1
        out[d:] = self.a0 * cs - self.vm * self.omega * self.omega * s1
        return out

    def rounding_scales(self, force_scale: FloatArray) -> tuple[FloatArray, FloatArray]:
        """(|ξ(0)|, |ξ'(0)|) as sums of the magnitudes of the terms they are computed from
        (their rounding is ε times these), with `force_scale` the magnitudes of the
        terms of the force f − K·q0 − W_L·λ0_L (shape (n,))."""
        d = self.dim
        if d == 0:
            return np.zeros(0), np.zeros(0)
        ns = np.abs(self.nullsp) if self.nullsp is not None else None
        fr = force_scale if ns is None else force_scale @ ns
        v = np.abs(self.zd0)
        if not self.damped:
            base = np.abs(self.phi.T)
            v = base @ (np.abs(self.mr) @ v)
            return np.concatenate([np.zeros(d), v]), np.concatenate([v, base @ fr])
        acc = np.abs(np.linalg.inv(self.mr)) @ (fr + np.abs(self.cr) @ v)
        x0, x1 = np.concatenate([np.zeros(d), v]), np.concatenate([v, acc])
        if not self.modal:  # the matrix exponential: x(0) = x0, ẋ(0) = A·x0 + h
            return x0, x1
        # x = V·(e^{Λτ}·c0 + τ·φ1(Λτ)·d): at τ = 0 the terms V·c0 and V·(Λ·c0 + d)
        vabs, iabs = np.abs(self.vec), np.abs(self.vinv)
        c0 = iabs @ x0
        return x0 + vabs @ c0, x1 + vabs @ (np.abs(self.lam) * c0 + iabs @ np.concatenate(
            [np.zeros(d), acc]))  # fmt: skip

    def curvature(self, rows: FloatArray, a: float, b: float) -> tuple[FloatArray, FloatArray]:
        """(P, T): the second derivative of every linear function ξ·rows[:, r] of the
        native coordinates lies in [P − T, P + T] on [a, b] (rows: shape (2·dim, R)).

        Undamped: a mode of frequency ω > 0 adds a sinusoid of amplitude R to the function
        (R from its initial velocity and constant force), bounded in second derivative by
        ω²·R; a rigid mode (ω = 0) adds the parabola's constant a·H. Damped (modal): the
        terms γ·e^{λτ} bounded by |γ|·|λ|²·max(e^{Re λ·a}, e^{Re λ·b}). Without modes (a
        defective matrix): |rows·A·ẋ(τ)| <= ‖Aᵀrows‖·‖ẋ(a)‖·e^{‖A‖·(b − a)}.
        """
        d = self.dim
        n_r = rows.shape[1]
        if d == 0 or n_r == 0:
            return np.zeros(n_r), np.zeros(n_r)
        if not self.damped:
            hh, gg = rows[:d], rows[d:]
            om = self.omega[:, None]
            v, acc = self.vm[:, None], self.a0[:, None]
            rig = self.rigid
            p = (hh[rig] * acc[rig]).sum(axis=0)
            fl = ~rig
            safe = np.where(fl, self.omega, 1.0)[:, None]
            amp_c = -hh * acc / (safe * safe) + gg * v
            amp_s = (hh * v + gg * acc) / safe
            t = (np.hypot(amp_c, amp_s)[fl] * (om[fl] ** 2)).sum(axis=0)
            return p, t * (1.0 + 1e-12)
        if self.modal:
            lam = self.lam
            coef = np.abs(rows.T @ self.vec) * np.abs((lam * self.c0 + self.dd) * lam)
            grow = np.exp(np.maximum(lam.real * a, lam.real * b))
            return np.zeros(n_r), (coef @ grow) * (1.0 + 1e-12)
        xd = self._first_order(np.array([a]))[1][0]
        big = float(np.linalg.norm(self.amat, 2))
        t = np.linalg.norm(self.amat.T @ rows, axis=0) * float(np.linalg.norm(xd))
        return np.zeros(n_r), t * np.exp(big * (b - a)) * (1.0 + 1e-12)

    def maps(self) -> tuple[FloatArray, FloatArray]:
        """(A_z, A_ż), shapes (2·dim, dim): z = ξ·A_z, ż = ξ·A_ż."""
        d = self.dim
        base = self.phi.T if (d and not self.damped) else np.eye(d)
        az = np.zeros((2 * d, d))
        azd = np.zeros((2 * d, d))
        az[:d] = base
        azd[d:] = base
        return az, azd

    def reduced(self, tau: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(z, ż, z̈) at the times tau, shapes (T, dim)."""
        tau = np.asarray(tau, dtype=float).reshape(-1, 1)
        d = self.dim
        if d == 0:
            z = np.zeros((tau.shape[0], 0))
            return z, z, z
        if not self.damped:
            om = self.omega
            wt = om * tau
            safe = np.where(om > 0.0, om, 1.0)
            s1 = np.where(om > 0.0, np.sin(wt) / safe, tau)
            sh = np.where(om > 0.0, np.sin(0.5 * wt) / safe, 0.5 * tau)
            cs = np.cos(wt)
            eta = self.vm * s1 + self.a0 * 2.0 * sh * sh
            etad = self.vm * cs + self.a0 * s1
            etadd = self.a0 * cs - self.vm * om * om * s1
            if self.dim == 1:
                return eta, etad, etadd
            return eta @ self.phi.T, etad @ self.phi.T, etadd @ self.phi.T
        x, xd = self._first_order(tau[:, 0])
        return x[:, :d], x[:, d:], xd[:, d:]

    def _first_order(self, tau: FloatArray) -> tuple[FloatArray, FloatArray]:
        """x = [z, ż] and ẋ at the times tau (damped pieces)."""
        if self.modal:
            zt = self.lam * tau[:, None]
            ex = np.exp(zt)
            safe = np.where(zt != 0.0, zt, 1.0)
            phi1 = np.where(zt != 0.0, np.expm1(zt) / safe, 1.0)
            x = (ex * self.c0 + tau[:, None] * phi1 * self.dd) @ self.vec.T
            xd = (ex * (self.lam * self.c0 + self.dd)) @ self.vec.T
            return x.real, xd.real
        dd = self.amat.shape[0]
        aug = np.zeros((dd + 1, dd + 1))
        aug[:dd, :dd] = self.amat
        aug[:dd, dd] = self.h
        x = np.array([(scipy.linalg.expm(aug * t) @ np.append(self.x0, 1.0))[:dd] for t in tau])
        x = x.reshape(-1, dd)
        return x, x @ self.amat.T + self.h

    def full(self, tau: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(Δq, q̇, q̈) at the times tau, shapes (T, n)."""
        z, zd, zdd = self.reduced(tau)
        n = self.q0.shape[0]
        if self.dim == 0:
            zero = np.zeros((z.shape[0], n))
            return zero, zero.copy(), zero.copy()
        if self.nullsp is None:
            return z, zd, zdd
        ns = self.nullsp
        return z @ ns.T, zd @ ns.T, zdd @ ns.T

    def damping_losses(self, tau: FloatArray, sigma: FloatArray) -> tuple[FloatArray, FloatArray]:
        """(∫ q̇ᵀCq̇ dt (T,), σ_v,c ∫ ġ_c² dt (T, n_c)) since the start of the piece."""
        tau = np.asarray(tau, dtype=float).reshape(-1)
        n_c = self.w.shape[1]
        if not self.damped:
            return np.zeros(tau.shape[0]), np.zeros((tau.shape[0], n_c))
        # Gauss–Legendre (16 nodes) on pieces no longer than 1/ω_max: exact to rounding
        edges = np.concatenate([[0.0], tau])
        lengths = np.diff(edges)
        parts = np.maximum(np.ceil(lengths * max(self.omega_max, 1e-300)), 1).astype(np.int64)
        parts[lengths == 0.0] = 1
        idx = np.repeat(np.arange(tau.shape[0]), parts)
        first = np.repeat(np.cumsum(parts) - parts, parts)
        k = np.arange(idx.shape[0]) - first
        width = lengths[idx] / parts[idx]
        left = edges[idx] + k * width
        nodes = left[:, None] + 0.5 * width[:, None] * (_GL_X + 1.0)
        weights = 0.5 * width[:, None] * _GL_W
        zd = self.reduced(nodes.reshape(-1))[1]
        ns = np.eye(self.q0.shape[0]) if self.nullsp is None else self.nullsp
        v = zd @ ns.T
        wts = weights.reshape(-1)
        structural = np.einsum("ti,ij,tj->t", v, self.c, v) * wts
        gd = v @ self.w
        visc = gd * gd * np.where(self.sliding, sigma, 0.0) * wts[:, None]
        seg = np.repeat(idx, _GL_X.shape[0])
        s_out = np.cumsum(np.bincount(seg, weights=structural, minlength=tau.shape[0])).astype(
            float
        )
        v_out = np.zeros((tau.shape[0], n_c))
        for c in np.flatnonzero(self.sliding & (sigma > 0.0)):
            v_out[:, c] = np.cumsum(np.bincount(seg, weights=visc[:, c], minlength=tau.shape[0]))
        return s_out, v_out


_GL_X, _GL_W = np.polynomial.legendre.leggauss(16)
