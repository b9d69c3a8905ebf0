"""Compiled stick/slip decision at an instant: the box QP over the Delassus matrix.

The compiled counterpart of `presliding.network.events._contact_problem.solve_box_qp` (the same
steps: the clipped least-squares start polished on its active set, else projected
Gauss–Seidel to convergence and polished), and the decision of the contacts at rest
(`decide`) that the event loop of `presliding.network.events._exact_kernel` calls at every
event. Arrays are checked by the caller before these run.
"""

from __future__ import annotations

import numpy as np
from numba import njit

EPS = np.finfo(np.float64).eps


@njit(cache=True, error_model="numpy")
def lstsq(a, b):  # pragma: no cover - compiled
    """Least squares a·x ≈ b (numpy's default rcond: ε·max(shape))."""
    rcond = EPS * max(a.shape[0], a.shape[1])
    return np.linalg.lstsq(a, b, rcond)[0]


@njit(cache=True, error_model="numpy")
def take_columns(a, idx):  # pragma: no cover - compiled
    """a[:, idx] as a new contiguous array."""
    out = np.empty((a.shape[0], idx.shape[0]))
    for j in range(idx.shape[0]):
        out[:, j] = a[:, idx[j]]
    return out


@njit(cache=True, error_model="numpy")
def _polish(g, b, c1, tau):  # pragma: no cover - compiled
    n = b.shape[0]
    acc = b - g @ tau
    scale = np.max(np.abs(b)) + np.max(np.abs(g)) * np.max(c1) + 1e-300
    tol = 1e-9 * scale
    upper = (tau >= c1 * (1 - 1e-12)) & (acc > tol)
    lower = (tau <= -c1 * (1 - 1e-12)) & (acc < -tol)
    free = ~(upper | lower)
    exact = tau.copy()
    for i in range(n):
        if upper[i]:
            exact[i] = c1[i]
        elif lower[i]:
            exact[i] = -c1[i]
    fi = np.flatnonzero(free)
    if fi.shape[0]:
        xi = np.flatnonzero(~free)
        rhs = b[fi].copy()
        for a in range(fi.shape[0]):
            for k in range(xi.shape[0]):
                rhs[a] -= g[fi[a], xi[k]] * exact[xi[k]]
        gff = np.empty((fi.shape[0], fi.shape[0]))
        for a in range(fi.shape[0]):
            for k in range(fi.shape[0]):
                gff[a, k] = g[fi[a], fi[k]]
        sol = lstsq(gff, rhs)
        for a in range(fi.shape[0]):
            exact[fi[a]] = sol[a]
    acc2 = b - g @ exact
    ok = True
    for i in range(n):
        if abs(exact[i]) > c1[i] * (1 + 1e-12):
            ok = False
        if upper[i] and acc2[i] < -tol:
            ok = False
        if lower[i] and acc2[i] > tol:
            ok = False
        if free[i] and abs(acc2[i]) > tol:
            ok = False
    if ok:
        for i in range(n):
            exact[i] = min(max(exact[i], -c1[i]), c1[i])
            if free[i]:
                acc2[i] = 0.0
        return exact, acc2, True
    return tau, acc, False


@njit(cache=True, error_model="numpy")
def box_qp(g, b, c1):  # pragma: no cover - compiled
    """(τ, g̈ = b − Gτ) of min ½τᵀGτ − bᵀτ over |τ| <= c1 (G symmetric PSD, diag > 0)."""
    n = b.shape[0]
    if n == 1:
        t = min(max(b[0] / g[0, 0], -c1[0]), c1[0])
        tau = np.array([t])
        return tau, b - g @ tau
    tau = lstsq(g, b)
    for i in range(n):
        tau[i] = min(max(tau[i], -c1[i]), c1[i])
    exact, acc, ok = _polish(g, b, c1, tau)
    if ok:
        return exact, acc
    stop = 1e-15 * max(np.max(c1), 1.0)
    for _ in range(2000):
        change = 0.0
        for i in range(n):
            t = tau[i] + (b[i] - g[i] @ tau) / g[i, i]
            t = min(max(t, -c1[i]), c1[i])
            change = max(change, abs(t - tau[i]))
            tau[i] = t
        if change <= stop:
            break
    exact, acc, _ = _polish(g, b, c1, tau)
    return exact, acc


@njit(cache=True, error_model="numpy")
def per_contact(values, owner, n_c):  # pragma: no cover - compiled
    """Σ of element values over each contact's elements."""
    out = np.zeros(n_c)
    for j in range(values.shape[0]):
        out[owner[j]] += values[j]
    return out


@njit(cache=True, error_model="numpy")
def decide(q, v, s, e, f, forced, k, w, minv_w, c1, sigma, ek, owner, reps, group, alpha,
           gc1, cmat, damped):  # pragma: no cover - compiled  # fmt: skip
    """New modes s of the contacts at rest (in place; v projected onto their constraint).

    ``forced``: NaN, or the mode a contact is given (0: decided with no tolerance).
    Contacts with parallel columns (``group``: the index of each contact's group,
    ``reps`` its first contact, w_c = ``alpha``_c·w_rep) are decided together as one
    combined contact with the bound ``gc1`` = Σ|α_c|·c1_c; a contact alone in its
    group is decided as itself. Returns the new velocity.
    """
    n_c = w.shape[1]
    fel = per_contact(ek * e, owner, n_c)
    exact = np.zeros(n_c, np.bool_)
    for c in range(n_c):
        if not np.isnan(forced[c]):
            s[c] = forced[c]
            exact[c] = forced[c] == 0.0
    for c in range(n_c):  # the group moves as its first contact
        s[c] = np.sign(alpha[c]) * s[reps[group[c]]]
    zero = reps[s[reps] == 0.0]
    if zero.shape[0]:
        mw = take_columns(minv_w, zero)
        wz = take_columns(w, zero)
        gd = wz.T @ v
        if np.any(gd != 0.0):
            v = v - mw @ lstsq(wz.T @ mw, gd)
    for _ in range(n_c + 1):
        zero = reps[s[reps] == 0.0]
        if zero.shape[0] == 0:
            break
        gd = w.T @ v
        lam = fel.copy()
        for c in range(n_c):
            if s[c] != 0.0:
                lam[c] = s[c] * c1[c] + fel[c] + sigma[c] * gd[c]
        r0 = f - k @ q - w @ lam
        if damped:
            r0 -= cmat @ v
        mw = take_columns(minv_w, zero)
        gmat = take_columns(w, zero).T @ mw
        b = mw.T @ r0
        c1z = gc1[group[zero]]
        _, acc = box_qp(gmat, b, c1z)
        scale = np.max(np.abs(b)) + np.max(np.abs(gmat)) * np.max(c1z)
        moved = False
        for a in range(zero.shape[0]):
            tol = 0.0 if exact[zero[a]] else 1e-11 * scale
            new = 1.0 if acc[a] > tol else (-1.0 if acc[a] < -tol else 0.0)
            for c in range(n_c):
                if group[c] == group[zero[a]]:
                    s[c] = np.sign(alpha[c]) * new
            moved = moved or new != 0.0
        if not moved:
            break
    return v
