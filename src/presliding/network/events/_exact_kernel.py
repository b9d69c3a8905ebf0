"""The compiled event loop of `simulate_network` (undamped and damped structures).

One call runs every event: the stick/slip decision at rest (`_kernel_contacts.decide`),
the closed-form piece (`_kernel_piece.build_piece`), its first event
(`_kernel_events.find_event`), the samples inside the piece and the move of the state
to the event, with the same rules as the operations of `presliding.network.events._exact_run`
(which run redundant stick sets and damped pieces without a well-conditioned modal
form). Damped pieces (C or a sliding contact's σ_v acting on the motion) are the
complex modes of `_kernel_damped`, with their dissipation in closed form. The samples
go into one array, one row per sample time, columns `ROW_LAYOUT` (sizes in coordinates
n and contacts n_c). Status codes: 0 the end was reached, 1 the event limit, 2 a
redundant stick set or ill-conditioned damped modes met (the caller runs the general
loop instead).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from presliding.network.events._kernel_contacts import decide
from presliding.network.events._kernel_damped import dissipation
from presliding.network.events._kernel_events import find_event
from presliding.network.events._kernel_piece import (
    P_ALPHA,
    P_B,
    P_C1S,
    P_CSAT,
    P_DAMPED,
    P_DIM,
    P_DMIN,
    P_DP,
    P_DQ,
    P_ELASTIC,
    P_FEL0,
    P_GFEL,
    P_GROUP,
    P_GSIZE,
    P_KEL,
    P_LAM,
    P_NLIN,
    P_RV,
    P_SL,
    P_SLIDING,
    P_SMAP,
    P_STUCK,
    P_THR,
    ROUNDING,
    build_piece,
    modal,
    parallel_groups,
)

ROW_LAYOUT = (("q", "n"), ("v", "n"), ("a", "n"), ("f", "n"), ("g", "c"), ("gd", "c"),
              ("lam", "c"), ("fel", "c"), ("mode", "c"), ("coulomb", "c"),
              ("hysteretic", "c"), ("viscous", "c"), ("kinetic", 1), ("potential", 1),
              ("elastic", 1), ("damping", 1), ("work", 1))  # fmt: skip


def row_width(n: int, n_c: int) -> int:
    """Columns of a sample row."""
    return sum(n if s == "n" else n_c if s == "c" else 1 for _, s in ROW_LAYOUT)


@njit(cache=True, error_model="numpy")
def _values(pc, tau, q, s, f, k, w, c1, sigma, cmat, bufs):  # pragma: no cover - compiled
    """Δq, q̇, q̈, Δg, ġ, F_el, λ of the piece at τ (into bufs)."""
    eta, etad, etadd, dq, vv, aa, dg, gd, fel, lam, rhs, tg = bufs
    d = pc[P_DIM]
    modal(pc, tau, eta, etad, etadd)
    b = pc[P_B]
    n, n_c = w.shape
    for i in range(n):
        x, y, z = 0.0, 0.0, 0.0
        for j in range(d):
            x += b[i, j] * eta[j]
            y += b[i, j] * etad[j]
            z += b[i, j] * etadd[j]
        dq[i], vv[i], aa[i] = x, y, z
    sliding, kel, fel0 = pc[P_SLIDING], pc[P_KEL], pc[P_FEL0]
    for c in range(n_c):
        x, y = 0.0, 0.0
        if sliding[c]:
            for i in range(n):
                x += dq[i] * w[i, c]
                y += vv[i] * w[i, c]
        dg[c], gd[c] = x, y
        fel[c] = fel0[c] + kel[c] * x
        lam[c] = s[c] * c1[c] + fel[c] + sigma[c] * y if sliding[c] else fel[c]
    stuck = pc[P_STUCK]
    if stuck.shape[0]:
        for i in range(n):
            r = f[i]
            for j in range(n):
                r -= k[i, j] * (q[j] + dq[j] if d else q[j])
            for c in range(n_c):
                if sliding[c]:
                    r -= w[i, c] * lam[c]
            for j in range(n):  # zero but for dashpots
                r -= cmat[i, j] * vv[j]
            rhs[i] = r
        smap, gfel, gc1 = pc[P_SMAP], pc[P_GFEL], pc[P_C1S]
        group, alpha, gsize = pc[P_GROUP], pc[P_ALPHA], pc[P_GSIZE]
        for r in range(smap.shape[0]):
            tg[r] = smap[r] @ rhs  # λ_r, then the group's Coulomb force T_r
            for a in range(stuck.shape[0]):
                if group[a] == r and gsize[r] == 1:
                    lam[stuck[a]] = tg[r]
            tg[r] -= gfel[r]
        for a in range(stuck.shape[0]):
            r, c = group[a], stuck[a]
            if gsize[r] > 1:  # each at the same fraction of its c1
                lam[c] = fel[c] + np.sign(alpha[a]) * c1[c] * (tg[r] / gc1[r])


@njit(cache=True, error_model="numpy")
def _record(pc, t, t1, at_end, filled, times, rec, q, g, e, s, coul, hyst, visc, damp, work,
            f, m, k, w, c1, sigma, cmat, ek, owner, bufs):  # pragma: no cover  # fmt: skip
    """The samples of the piece in [t, t1) (or [t, t1] at the end); the new fill count."""
    i1 = np.searchsorted(times, t1, side="right") if at_end else np.searchsorted(times, t1)
    n, n_c = w.shape
    dq, vv, aa, dg, gd, fel, lam = bufs[3], bufs[4], bufs[5], bufs[6], bufs[7], bufs[8], bufs[9]
    elastic, csat, d = pc[P_ELASTIC], pc[P_CSAT], pc[P_DIM]
    qq = np.empty(n)
    dv = np.zeros(n_c)
    for i in range(filled, i1):
        _values(pc, times[i] - t, q, s, f, k, w, c1, sigma, cmat, bufs)
        dd = 0.0
        if pc[P_DAMPED] and pc[P_DIM]:
            dd = dissipation(pc[P_LAM], pc[P_DP], pc[P_DQ], pc[P_RV], sigma, times[i] - t, dv)
        row = rec[i]
        for j in range(n):
            qq[j] = q[j] + dq[j] if d else q[j]
        row[:n], row[n : 2 * n], row[2 * n : 3 * n], row[3 * n : 4 * n] = qq, vv, aa, f
        o = 4 * n
        for c in range(n_c):
            sdg = s[c] * dg[c] if s[c] != 0.0 else 0.0
            row[o + c], row[o + n_c + c], row[o + 2 * n_c + c] = g[c] + dg[c], gd[c], lam[c]
            row[o + 3 * n_c + c], row[o + 4 * n_c + c] = fel[c], s[c]
            row[o + 5 * n_c + c] = coul[c] + c1[c] * sdg
            row[o + 6 * n_c + c] = hyst[c] + csat[c] * sdg
            row[o + 7 * n_c + c] = visc[c] + dv[c]
        o += 8 * n_c
        el = 0.0
        for j in range(ek.shape[0]):
            ej = e[j] + dg[owner[j]] if elastic[j] else e[j]
            el += ej * ej * ek[j]
        row[o] = 0.5 * (vv @ (m @ vv))
        row[o + 1] = 0.5 * (qq @ (k @ qq))
        row[o + 2] = 0.5 * el
        row[o + 3] = damp + dd
        row[o + 4] = work + dq @ f
    return max(filled, i1)


@njit(cache=True, error_model="numpy")
def _advance(pc, tau, mask, found, q, v, g, e, s, coul, hyst, visc, work, damp, forced, f, k,
             w, c1, sigma, cmat, ek, er, owner, cgroup, bufs):  # pragma: no cover  # fmt: skip
    """Move the state to the end τ of the piece (in place); the work, the damping
    dissipation and the new velocity."""
    _values(pc, tau, q, s, f, k, w, c1, sigma, cmat, bufs)
    if pc[P_DAMPED] and pc[P_DIM]:
        dv = np.zeros(w.shape[1])
        damp += dissipation(pc[P_LAM], pc[P_DP], pc[P_DQ], pc[P_RV], sigma, tau, dv)
        visc += dv
    dq, vv, dg, tg = bufs[3], bufs[4], bufs[6], bufs[11]
    n_c = w.shape[1]
    for c in range(n_c):
        if s[c] != 0.0:
            coul[c] += c1[c] * (s[c] * dg[c])
            hyst[c] += pc[P_CSAT][c] * (s[c] * dg[c])
    work = work + dq @ f
    if pc[P_DIM]:
        q += dq
    g += dg
    elastic, dmin = pc[P_ELASTIC], pc[P_DMIN]
    s_el = s[owner]
    hit = np.zeros(n_c, np.bool_)
    if found:
        sl, thr, stuck, n_lin = pc[P_SL], pc[P_THR], pc[P_STUCK], pc[P_NLIN]
        stop = np.zeros(n_c, np.bool_)
        for a in range(sl.shape[0]):
            if mask[a]:  # a group of parallel contacts stops together
                stop[cgroup[sl[a]]] = True
        for c in range(n_c):
            if stop[cgroup[c]]:
                s[c] = 0.0
        for a in range(thr.shape[0]):
            if mask[sl.shape[0] + a]:
                hit[thr[a]] = True
        group, alpha = pc[P_GROUP], pc[P_ALPHA]
        for a in range(stuck.shape[0]):
            if mask[n_lin + group[a]]:
                forced[stuck[a]] = np.sign(alpha[a]) * (1.0 if tg[group[a]] > 0 else -1.0)
    rmax = np.zeros(n_c)  # the scale of a contact's deformations (and of their rounding)
    for j in range(ek.shape[0]):
        rmax[owner[j]] = max(rmax[owner[j]], er[j])
    for j in range(ek.shape[0]):
        if elastic[j]:
            dist = er[j] - s_el[j] * e[j]
            ej = e[j] + dg[owner[j]]
            near = s_el[j] * ej >= er[j] - ROUNDING * (rmax[owner[j]] + abs(dg[owner[j]]))
            if near or (hit[owner[j]] and dist == dmin[owner[j]]):
                ej = s_el[j] * er[j]
            e[j] = ej
    return work, damp, vv.copy()


@njit(cache=True, error_model="numpy")
def _push(buf, count, a, b, c):  # pragma: no cover - compiled
    if count == buf.shape[0]:
        bigger = np.empty((2 * count, 3))
        bigger[:count] = buf
        buf = bigger
    buf[count, 0], buf[count, 1], buf[count, 2] = a, b, c
    return buf, count + 1


@njit(cache=True, error_model="numpy")
def run_events(t, q, v, g, e, s, last, coul, hyst, visc, work, damp, iu, ft, fv, t_end, times,
               rec, m, k, w, minv_w, c1, sigma, cmat, ek, er, owner, max_events
               ):  # pragma: no cover - compiled  # fmt: skip
    """The event loop from the state (q, g, e, s, last, coul, hyst, visc updated in place);
    damped when `cmat` or `sigma` is not zero.

    Returns (status, t, v, work, damping dissipation, events, samples filled,
    transitions (t, c, s), reversals (t, c, g), whether a group of parallel contacts
    stuck, the certificate's counts (cells, isolated, resolved, grazes, ends)).
    """
    damped = np.any(cmat != 0.0) or np.any(sigma != 0.0)
    n, n_c = w.shape
    d_max = n
    bufs = (np.empty(d_max), np.empty(d_max), np.empty(d_max), np.empty(n), np.empty(n),
            np.empty(n), np.empty(n_c), np.empty(n_c), np.empty(n_c), np.empty(n_c),
            np.empty(n), np.empty(n_c))  # fmt: skip
    forced = np.full(n_c, np.nan)
    reps, group, alpha, gsize = parallel_groups(w, np.arange(n_c))
    gc1 = np.zeros(reps.shape[0])
    for c in range(n_c):
        gc1[group[c]] += c1[c] if gsize[group[c]] == 1 else abs(alpha[c]) * c1[c]
    prev = s.copy()
    tr, n_tr = np.empty((16, 3)), 0
    rv, n_rv = np.empty((16, 3)), 0
    events, filled, first, status, grouped = 0, 0, True, -1, False
    counts = np.zeros(5, np.int64)
    while status < 0:
        f = fv[iu]
        v = decide(q, v, s, e, f, forced, k, w, minv_w, c1, sigma, ek, owner, reps, group, alpha,
                   gc1, cmat, damped)  # fmt: skip
        forced[:] = np.nan
        for c in range(n_c):
            if first:
                tr, n_tr = _push(tr, n_tr, t, c, s[c])
                if s[c] != 0.0:
                    last[c] = s[c]
            elif s[c] != prev[c]:
                tr, n_tr = _push(tr, n_tr, t, c, s[c])
                if s[c] != 0.0:
                    if last[c] != 0.0 and s[c] != last[c]:
                        rv, n_rv = _push(rv, n_rv, t, c, g[c])
                    last[c] = s[c]
        first = False
        prev[:] = s
        t1 = min(ft[iu + 1] if iu + 1 < ft.shape[0] else np.inf, t_end)
        pc, redundant, in_group = build_piece(q, v, s, e, f, m, k, w, minv_w, c1, ek, er, owner,
                                              cmat, sigma, damped)  # fmt: skip
        if redundant:
            status = 2
            break
        grouped = grouped or in_group
        tau, mask = find_event(pc, t1 - t, counts)
        found = tau >= 0.0
        at_end = (not found) and t1 >= t_end
        if not found:
            tau = t1 - t
        filled = _record(pc, t, t + tau, at_end, filled, times, rec, q, g, e, s, coul, hyst,
                         visc, damp, work, f, m, k, w, c1, sigma, cmat, ek, owner,
                         bufs)  # fmt: skip
        work, damp, v = _advance(pc, tau, mask, found, q, v, g, e, s, coul, hyst, visc, work,
                                 damp, forced, f, k, w, c1, sigma, cmat, ek, er, owner, group,
                                 bufs)  # fmt: skip
        if found:
            t = t + tau
        else:
            t = t1
            if at_end:
                status = 0
                break
            iu += 1
        events += 1
        if events >= max_events:
            status = 1
    return (status, t, v, work, damp, events, filled, tr[:n_tr].copy(), rv[:n_rv].copy(),
            grouped, counts)  # fmt: skip
