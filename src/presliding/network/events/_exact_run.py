"""The event loop of `simulate_network`: decide modes, build a piece, find its event.

State between events: q, q̇, the contact displacements g (held exactly while a contact
sticks), the element deformations e (flattened over the contacts), each contact's mode
s_c ∈ {−1, 0 (stuck), +1} and its last direction of motion (for reversals).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding.network._contacts import Contacts
from presliding.network._matrices import check_dense_size, issparse
from presliding.network.events._contact_problem import redundant_margin, solve_box_qp
from presliding.network.events._events import ROUNDING, AffineEvents, Certificate
from presliding.network.events._piece import Piece, null_space

FloatArray = NDArray[np.float64]


@dataclass
class RunState:
    """The mutable state of the event loop."""

    t: float
    q: FloatArray
    v: FloatArray
    g: FloatArray
    e: FloatArray
    s: FloatArray
    last: FloatArray
    coulomb: FloatArray
    hysteretic: FloatArray
    viscous: FloatArray
    damping: float = 0.0
    work: float = 0.0
    redundant: bool = False
    n_events: int = 0
    transitions: list[tuple[float, int, float]] = field(default_factory=list)
    reversals: list[tuple[float, int, float]] = field(default_factory=list)
    cert: Certificate = field(default_factory=Certificate)


class Network:
    """The structure's constant arrays, and the operations of the event loop on a state."""

    def __init__(self, structure: Any) -> None:
        n, n_c = structure.n_coordinates, structure.n_contacts
        if structure.is_sparse:  # the exact path works on dense matrices
            hint = "The exact path holds dense matrices; simulate_network_moreau takes sparse ones."
            check_dense_size("structure", f"{n} coordinates", n, n_c, hint)
        self.m, self.c, self.k, self.w = (
            np.asarray(x.toarray()) if issparse(x) else np.asarray(x)
            for x in (structure.mass, structure.damping, structure.stiffness, structure.contacts)
        )
        self.cts = Contacts.of(structure.friction)
        self.minv_w = np.linalg.solve(self.m, self.w)
        self.n_c = self.w.shape[1]
        # the largest threshold of each contact: the scale of its deformations' rounding
        self.rmax = np.zeros(self.n_c)
        np.maximum.at(self.rmax, self.cts.owner, self.cts.r)
        # decompositions by stick/slip/elastic pattern: patterns recur in oscillations
        self.cache: dict[bytes, Any] = {}
        self.stick_cache: dict[bytes, Any] = {}

    # ---------------------------------------------------------------- contact forces
    def elastic_forces(self, e: FloatArray) -> FloatArray:
        """F_el,c = Σ_j k_j e_j per contact (last axis of e: elements)."""
        return self.cts.per_contact(self.cts.k * e)

    def decide(self, st: RunState, f: FloatArray, forced: dict[int, float]) -> None:
        """New modes of the contacts at rest (s = 0): the box QP over the Delassus matrix."""
        cts = self.cts
        fel = self.elastic_forces(st.e)
        exact = [c for c, sign in forced.items() if sign == 0.0]  # decided with no tolerance
        for c, sign in forced.items():
            st.s[c] = sign
        zero = np.flatnonzero(st.s == 0.0)
        if zero.size:  # contacts at rest have exactly zero velocity
            mw = self.minv_w[:, zero]
            gmat = self.w[:, zero].T @ mw
            gd = self.w[:, zero].T @ st.v
            if np.any(gd != 0.0):
                st.v = st.v - mw @ np.linalg.lstsq(gmat, gd, rcond=None)[0]
        for _ in range(self.n_c + 1):
            zero = np.flatnonzero(st.s == 0.0)
            if zero.size == 0:
                break
            moving = st.s != 0.0
            gd = self.w.T @ st.v
            lam = np.where(moving, st.s * cts.c1 + fel + cts.sigma * gd, fel)
            lam[zero] = fel[zero]
            r0 = f - self.c @ st.v - self.k @ st.q - self.w @ lam
            mw = self.minv_w[:, zero]
            gmat = self.w[:, zero].T @ mw
            b = mw.T @ r0
            _, acc = solve_box_qp(gmat, b, cts.c1[zero])
            scale = float(np.max(np.abs(b))) + float(np.max(np.abs(gmat))) * float(
                np.max(cts.c1[zero])
            )
            tol = np.where(np.isin(zero, exact), 0.0, 1e-11 * scale)
            new = np.where(acc > tol, 1.0, np.where(acc < -tol, -1.0, 0.0))
            st.s[zero] = new
            if not np.any(new != 0.0):
                break
        stuck = np.flatnonzero(st.s == 0.0)
        if stuck.size > 1 and null_space(self.w[:, stuck], self.w.shape[0])[1] < stuck.size:
            st.redundant = True

    def piece(self, st: RunState, f: FloatArray) -> tuple[Piece, dict[str, Any]]:
        """The closed-form piece from the state, and its per-contact data."""
        cts = self.cts
        sliding = st.s != 0.0
        s_el = st.s[cts.owner]
        elastic = (s_el * st.e < cts.r) & sliding[cts.owner]
        kel = cts.per_contact(np.where(elastic, cts.k, 0.0))
        csat = cts.per_contact(np.where(~elastic & sliding[cts.owner], cts.k * cts.r, 0.0))
        fel0 = self.elastic_forces(st.e)
        lam0 = st.s * cts.c1 + fel0
        dist = np.where(elastic, cts.r - s_el * st.e, np.inf)
        dmin = np.full(self.n_c, np.inf)
        np.minimum.at(dmin, cts.owner, dist)
        stuck = np.flatnonzero(~sliding)
        skey = sliding.tobytes()
        if len(self.cache) > 4096:
            self.cache.clear()
            self.stick_cache.clear()
        if skey not in self.stick_cache:
            ns, rank = null_space(self.w[:, stuck], self.w.shape[0])
            if ns is not None and ns.shape[1] == 0:
                ns = np.zeros((self.w.shape[0], 0))
            smap = snull = None
            if stuck.size:
                mw = self.minv_w[:, stuck]
                smap = np.linalg.pinv(self.w[:, stuck].T @ mw) @ mw.T
                if stuck.size > rank:
                    snull = np.linalg.svd(self.w[:, stuck])[2][rank:].T
            self.stick_cache[skey] = (ns, rank, smap, snull)
        ns, rank, smap, snull = self.stick_cache[skey]
        key = skey + elastic.tobytes()
        pc = Piece(self.m, self.c, self.k, self.w, f, st.q, st.v, sliding, st.s, kel, lam0,
                   cts.sigma, ns, self.cache, key)  # fmt: skip
        info: dict[str, Any] = {
            "sliding": sliding, "elastic": elastic, "kel": kel, "csat": csat, "fel0": fel0,
            "lam0": lam0, "dmin": dmin, "stuck": stuck,
            "redundant": stuck.size > rank,
        }  # fmt: skip
        if stuck.size:
            info["stick_map"] = smap  # λ_S = P·(f − Cq̇ − Kq − W_L λ_L)
            if info["redundant"]:
                info["stick_null"] = snull
        return pc, info

    def contact_values(self, pc: Piece, info: dict[str, Any], st: RunState, tau: FloatArray
                       ) -> dict[str, FloatArray]:  # fmt: skip
        """Samples of the piece at tau: coordinates, contacts, forces (vectorised)."""
        dq, v, a = pc.full(tau)
        gd = v @ self.w
        dg = dq @ self.w
        sl = info["sliding"]
        dg = np.where(sl, dg, 0.0)
        gd = np.where(sl, gd, 0.0)
        fel = info["fel0"] + info["kel"] * dg
        lam = np.where(sl, st.s * self.cts.c1 + fel + self.cts.sigma * gd, fel)
        stuck = info["stuck"]
        margin = np.empty((dq.shape[0], 0))
        if stuck.size:
            q = st.q + dq
            lam_l = np.where(sl, lam, 0.0)
            rhs = pc.f - v @ self.c.T - q @ self.k.T - lam_l @ self.w.T
            lam_s = rhs @ info["stick_map"].T
            fel_s = info["fel0"][stuck]
            if info["redundant"]:  # the min-norm forces if admissible, else the LP's
                margin = np.min(self.cts.c1[stuck] - np.abs(lam_s - fel_s), axis=1)[:, None]
                for i in np.flatnonzero(margin[:, 0] < 0.0):
                    margin[i, 0], lam_s[i] = redundant_margin(
                        lam_s[i], info["stick_null"], fel_s, self.cts.c1[stuck]
                    )
            else:
                margin = self.cts.c1[stuck] - np.abs(lam_s - fel_s)
            lam[:, stuck] = lam_s
        return {"dq": dq, "v": v, "a": a, "dg": dg, "gd": gd, "fel": fel, "lam": lam,
                "margin": margin}  # fmt: skip

    def event_functions(self, pc: Piece, info: dict[str, Any], st: RunState
                        ) -> AffineEvents:  # fmt: skip
        """h(τ) for `scan`: the event functions and which are strict (built once per piece)."""
        if "event_fun" in info:
            return info["event_fun"]
        info["event_fun"] = fun = self._event_functions(pc, info, st)
        return fun

    def _event_functions(self, pc: Piece, info: dict[str, Any], st: RunState) -> AffineEvents:
        """The event functions as affine maps of the piece's native coordinates ξ(τ)."""
        sl = np.flatnonzero(info["sliding"])
        thr = sl[np.isfinite(info["dmin"][sl])]
        n = self.w.shape[0]
        az, azd = pc.maps()
        nt = np.eye(n) if pc.nullsp is None else pc.nullsp.T
        qmap = az @ nt  # Δq = ξ·qmap
        vmap = azd @ nt  # q̇ = ξ·vmap
        dgmap = qmap @ self.w
        gdmap = vmap @ self.w
        s = st.s
        cols = [s[sl] * gdmap[:, sl], -s[thr] * dgmap[:, thr]]
        consts = [np.zeros(sl.size), info["dmin"][thr]]
        stuck = info["stuck"]
        if stuck.size:  # the Coulomb forces τ = λ_S − F_el,S of the stuck contacts
            slide = info["sliding"]
            wl = self.w[:, slide]
            pmat = info["stick_map"].T
            lam_l = dgmap[:, slide] * info["kel"][slide] + gdmap[:, slide] * self.cts.sigma[slide]
            rmap = -vmap @ self.c.T - qmap @ self.k.T - lam_l @ wl.T
            r0 = pc.f - self.k @ st.q - wl @ info["lam0"][slide]
            cols.append(rmap @ pmat)
            consts.append(r0 @ pmat - info["fel0"][stuck])
        c1s = self.cts.c1[stuck]
        # magnitudes of the terms at τ = 0 (their rounding is ε times these)
        slide = info["sliding"]
        fs = np.abs(pc.f) + np.abs(self.k) @ np.abs(st.q) + np.abs(self.w[:, slide]) @ np.abs(
            info["lam0"][slide])  # fmt: skip
        x0, x0d = pc.rounding_scales(fs)
        scale0 = [np.zeros(sl.size), self.rmax[thr]]
        if stuck.size:
            scale0.append(fs @ np.abs(info["stick_map"].T) + np.abs(info["fel0"][stuck]))
        hmat = np.hstack(cols)
        err = (x0 @ np.abs(hmat) + np.concatenate(scale0), x0d @ np.abs(hmat))
        lp = None
        if info["redundant"]:
            fel_s, snull = info["fel0"][stuck], info["stick_null"]

            def lp(tau_s: FloatArray) -> float:
                """The margin of the minimum-norm forces if admissible, else the LP's."""
                low = float(np.min(c1s - np.abs(tau_s)))
                return low if low >= 0.0 else redundant_margin(tau_s + fel_s, snull, fel_s, c1s)[0]

        fun = AffineEvents(pc, hmat, np.concatenate(consts), sl.size + thr.size, c1s, lp, err)
        fun.layout = (sl, thr)
        return fun

    def advance(self, pc: Piece, info: dict[str, Any], st: RunState, tau: float,
                trig: NDArray[np.bool_] | None) -> dict[int, float]:  # fmt: skip
        """Move the state to τ (the end of the piece); returns the forced releases."""
        cts = self.cts
        vals = self.contact_values(pc, info, st, np.array([tau]))
        self.add_energy(pc, info, st, np.array([tau]), vals, into_state=True)
        dg = vals["dg"][0]
        if pc.dim:
            st.q = st.q + vals["dq"][0]
        st.v = vals["v"][0]
        st.g = st.g + dg
        el = info["elastic"]
        e = np.where(el, st.e + dg[cts.owner], st.e)
        s_el = st.s[cts.owner]
        hit = np.zeros(self.n_c, bool)
        forced: dict[int, float] = {}
        if trig is not None:
            sl_idx, thr = self.event_functions(pc, info, st).layout
            n1, n2 = sl_idx.size, thr.size
            stop = sl_idx[trig[:n1]]
            hit[thr[trig[n1 : n1 + n2]]] = True
            st.s[stop] = 0.0
            if trig[n1 + n2 :].any():
                stuck = info["stuck"]
                if info["redundant"]:
                    breaking = stuck  # the whole redundant set is decided again
                    for c in breaking:
                        forced.setdefault(int(c), 0.0)
                else:
                    tau_s = vals["lam"][0, stuck] - info["fel0"][stuck]
                    for c, tsc in zip(stuck[trig[n1 + n2 :]], tau_s[trig[n1 + n2 :]], strict=True):
                        forced[int(c)] = 1.0 if tsc > 0 else -1.0
        dist = cts.r - s_el * st.e
        # an element reaching its threshold is set exactly (also one within rounding of it:
        # of its contact's deformations and of the piece's displacement added to them)
        near = s_el * e >= cts.r - ROUNDING * (self.rmax + np.abs(dg))[cts.owner]
        snap = el & (near | (hit[cts.owner] & (dist == info["dmin"][cts.owner])))
        st.e = np.where(snap, s_el * cts.r, e)
        st.t = st.t + tau
        return forced

    def add_energy(self, pc: Piece, info: dict[str, Any], st: RunState, tau: FloatArray,
                   vals: dict[str, FloatArray], *, into_state: bool = False
                   ) -> dict[str, FloatArray]:  # fmt: skip
        """Cumulative dissipation and work at tau (and into the state at the end)."""
        sl = info["sliding"]
        sdg = np.where(sl, st.s * vals["dg"], 0.0)
        coul = st.coulomb + self.cts.c1 * sdg
        hyst = st.hysteretic + info["csat"] * sdg
        damp, visc = pc.damping_losses(tau, self.cts.sigma)
        visc = st.viscous + visc
        damp = st.damping + damp
        work = st.work + vals["dq"] @ pc.f
        if into_state:
            st.coulomb, st.hysteretic, st.viscous = coul[0], hyst[0], visc[0]
            st.damping, st.work = float(damp[0]), float(work[0])
        return {"coulomb": coul, "hysteretic": hyst, "viscous": visc, "damping": damp,
                "work": work}  # fmt: skip
