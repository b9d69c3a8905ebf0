"""The stick/slip decision at an instant: one box-constrained QP over the Delassus matrix.

At an instant where the contacts of a set Z have ġ = 0, their Coulomb forces τ_c
(λ_c = τ_c + F_el,c, the stop elements are single-valued and sit in the right-hand
side) and accelerations g̈_Z = b − G·τ, G = W_Zᵀ M⁻¹ W_Z, satisfy

    τ_c ∈ c1_c·Sign(g̈_c)    ⇔    τ = argmin ½ τᵀGτ − bᵀτ  over  |τ_c| <= c1_c,

a convex QP whose g̈ is unique even when G is singular (redundant contacts; then τ is
not). Solved by projected Gauss–Seidel to convergence, then polished exactly on the
active set it found (the free forces from G_FF τ_F = b_F − G_FA τ_A, least squares
when G_FF is singular), with the KKT conditions checked.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import linprog

FloatArray = NDArray[np.float64]


def solve_box_qp(g: FloatArray, b: FloatArray, c1: FloatArray) -> tuple[FloatArray, FloatArray]:
    """(τ, g̈ = b − Gτ) of min ½τᵀGτ − bᵀτ over |τ| <= c1 (G symmetric PSD, diag > 0)."""
    n = b.shape[0]
    if n == 1:
        tau = np.clip(np.array([b[0] / g[0, 0]]), -c1, c1)
        return tau, b - g @ tau
    tau = np.clip(np.linalg.lstsq(g, b, rcond=None)[0], -c1, c1)
    exact, acc, ok = _polish(g, b, c1, tau)  # often the clipped solution's active set is right
    if ok:
        return exact, acc
    diag = np.diag(g)
    for _ in range(2000):
        old = tau.copy()
        for i in range(n):
            t = tau[i] + (b[i] - g[i] @ tau) / diag[i]
            tau[i] = min(max(t, -c1[i]), c1[i])
        if np.max(np.abs(tau - old)) <= 1e-15 * max(float(np.max(c1)), 1.0):
            break
    exact, acc, _ = _polish(g, b, c1, tau)
    return exact, acc


def _polish(g: FloatArray, b: FloatArray, c1: FloatArray, tau: FloatArray
            ) -> tuple[FloatArray, FloatArray, bool]:  # fmt: skip
    """The exact solution on the active set of `tau` if it satisfies KKT (True); else
    `tau` itself (False)."""
    acc = b - g @ tau
    scale = float(np.max(np.abs(b))) + float(np.max(np.abs(g))) * float(np.max(c1)) + 1e-300
    tol = 1e-9 * scale
    upper = (tau >= c1 * (1 - 1e-12)) & (acc > tol)
    lower = (tau <= -c1 * (1 - 1e-12)) & (acc < -tol)
    free = ~(upper | lower)
    exact = tau.copy()
    exact[upper] = c1[upper]
    exact[lower] = -c1[lower]
    if free.any():
        fixed = ~free
        rhs = b[free] - g[np.ix_(free, fixed)] @ exact[fixed]
        exact[free] = np.linalg.lstsq(g[np.ix_(free, free)], rhs, rcond=None)[0]
    acc2 = b - g @ exact
    ok = (
        np.all(np.abs(exact) <= c1 * (1 + 1e-12))
        and np.all(acc2[upper] >= -tol)
        and np.all(acc2[lower] <= tol)
        and np.all(np.abs(acc2[free]) <= tol)
    )
    if ok:
        exact = np.clip(exact, -c1, c1)
        acc2[free] = 0.0
        return exact, acc2, True
    return tau, acc, False


def redundant_margin(lam_p: FloatArray, z: FloatArray, fel: FloatArray, c1: FloatArray
                     ) -> tuple[float, FloatArray]:  # fmt: skip
    """Stick margin of a redundant set: max over y of min_c (c1_c − |λ_p + Z·y − F_el|_c),
    with the forces λ = λ_p + Z·y that attain it (one of the many that hold the structure)."""
    n, d = z.shape
    # variables (y, μ): maximise μ s.t. ±(λ_p + Z y − F_el) + μ <= c1
    cost = np.zeros(d + 1)
    cost[-1] = -1.0
    top = np.hstack([z, np.ones((n, 1))])
    bot = np.hstack([-z, np.ones((n, 1))])
    a = np.vstack([top, bot])
    rhs = np.concatenate([c1 - (lam_p - fel), c1 + (lam_p - fel)])
    res = linprog(cost, A_ub=a, b_ub=rhs, bounds=[(None, None)] * (d + 1), method="highs")
    if not res.success:  # pragma: no cover - the problem is always feasible and bounded
        tau = lam_p - fel
        return float(np.min(c1 - np.abs(tau))), lam_p
    y = res.x[:d]
    return float(res.x[-1]), lam_p + z @ y
