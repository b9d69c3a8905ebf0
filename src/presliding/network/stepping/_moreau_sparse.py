"""The compiled Moreau–Jean loop of a sparse structure: Gauss–Seidel on the velocities.

The step of `presliding.network.stepping._moreau_kernel` (the θ-method for the smooth forces, the
contacts at the end of the step) without the Delassus matrix, whose inverse Ŵ⁻¹ is dense
even for a chain: the new velocity v' minimises the strictly convex

    ½·v'ᵀŴv' − b̃ᵀv' + Σ_c Ψ_c(w_cᵀv'),    Ŵ = M + hθ·C + h²θ²·K,
    b̃ = Ŵ·v + h·(f − C·v − K·(q + hθ·v)),   ∂Ψ_c(u) = h·λ_c(u)

and, each contact acting on one coordinate (w_c = α_c·e_i, at most one per coordinate),
the non-smooth part is separable: Gauss–Seidel over the coordinates, each one's 1-D
inclusion Ŵ_ii·x + α·h·λ(α·x) ∋ r_i solved exactly (`local_step`: a stuck contact's
coordinate is 0.0 exactly, so nothing creeps), converges to the minimiser (block
coordinate descent with a separable non-smooth part). A sweep costs the nonzeros of Ŵ:
memory and time per step are linear in the size of a banded structure.
"""

from __future__ import annotations

import numpy as np

from presliding.hysteresis._jit import JitFlags, njit
from presliding.network.stepping._moreau_kernel import (
    contacts_step,
    elastic_forces,
    local_step,
    matvec,
    sample,
)

_JIT: JitFlags = {"cache": True, "error_model": "numpy"}


@njit(**_JIT)
def primal_loop(  # pragma: no cover - compiled
    n_steps, h, theta, t0, q, v, g, e, p,
    w_p, w_i, w_v, c_p, c_i, c_v, k_p, k_i, k_v, f_t, f_v, contact_of, alpha,
    c1, sig, ek, er, estart, tol, max_sweeps, every,
    o_q, o_v, o_a, o_g, o_lam, o_fel, o_ee, o_mode, o_en, o_sd,
):  # fmt: skip
    """Run n_steps steps from the state (q, v, g, e, p updated in place); samples every
    `every` steps into o_* (row 0 is the start). ``contact_of[i]``: the contact on
    coordinate i (−1: none), ``alpha[c]`` its w_c entry. Returns (sweeps used at most,
    steps whose Gauss–Seidel stopped at max_sweeps)."""
    n = q.shape[0]
    n_c = g.shape[0]
    rhs, tmp, tmp2, vn, diag = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.zeros(n)
    u, fel0, gcc, vold = np.zeros(n_c), np.empty(n_c), np.empty(n_c), v.copy()
    for i in range(n):
        for k in range(w_p[i], w_p[i + 1]):
            if w_i[k] == i:
                diag[i] += w_v[k]
    for i in range(n):  # a contact's G_cc = α²/Ŵ_ii
        if contact_of[i] >= 0:
            gcc[contact_of[i]] = alpha[contact_of[i]] ** 2 / diag[i]
    coul, hyst, visc = np.zeros(n_c), np.zeros(n_c), np.zeros(n_c)
    damp, work = 0.0, 0.0
    most, capped, iu = 0, 0, 0
    for step in range(n_steps):
        t = t0 + (step + theta) * h
        while iu + 1 < f_t.shape[0] and f_t[iu + 1] <= t:
            iu += 1
        # b̃ = Ŵ·v + h·(f − C·v − K·(q + hθ·v))
        matvec(c_p, c_i, c_v, v, tmp)
        for i in range(n):
            tmp2[i] = q[i] + h * theta * v[i]
        matvec(k_p, k_i, k_v, tmp2, rhs)
        for i in range(n):
            rhs[i] = h * (f_v[iu, i] - tmp[i] - rhs[i])
        matvec(w_p, w_i, w_v, v, tmp)
        for i in range(n):
            rhs[i] += tmp[i]
            vn[i] = 2.0 * v[i] - vold[i]  # warm start: the velocity extrapolated
        elastic_forces(ek, e, estart, fel0)
        sweeps = 0
        scale = 1e-300
        for c in range(n_c):
            scale = max(scale, abs(p[c]))
        while True:
            sweeps += 1
            change_v, change_p, top = 0.0, 0.0, 1e-300
            for i in range(n):
                r = rhs[i]
                for k in range(w_p[i], w_p[i + 1]):
                    if w_i[k] != i:
                        r -= w_v[k] * vn[w_i[k]]
                c = contact_of[i]
                if c < 0:
                    x = r / diag[i]
                else:
                    a = alpha[c]
                    uc, pc = local_step(a * r / diag[i], gcc[c], h, c1[c], sig[c], ek, er, e,
                                        estart[c], estart[c + 1], fel0[c])  # fmt: skip
                    x = uc / a
                    change_p = max(change_p, abs(pc - p[c]))
                    scale = max(scale, abs(pc))
                    p[c] = pc
                    u[c] = uc
                change_v = max(change_v, abs(x - vn[i]))
                top = max(top, abs(x))
                vn[i] = x
            if change_p <= tol * scale and change_v <= tol * top:
                break
            if sweeps >= max_sweeps:
                capped += 1
                break
        most = max(most, sweeps)
        for i in range(n):
            vold[i] = v[i]
            vt = theta * vn[i] + (1.0 - theta) * v[i]
            tmp2[i] = (vn[i] - v[i]) / h
            tmp[i] = vt
            q[i] += h * vt
            work += h * vt * f_v[iu, i]
            v[i] = vn[i]
        matvec(c_p, c_i, c_v, tmp, rhs)
        for i in range(n):
            damp += h * tmp[i] * rhs[i]
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
