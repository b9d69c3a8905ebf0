"""The inner optimisation of a profile point: Levenberg–Marquardt with per-record steps.

With the profiled parameter held, the others are re-optimised. In a record-pooled fit they
are the shared parameters and each record's own block (initial position, velocity,
preload), and given the shared ones the records are independent: a record's rows of the
residual depend on the shared parameters and its own block only. The residual of a fit with
stiction is only piecewise smooth, and one record in a nonlinear corner (a preload near
saturation, a stop moving across a sample) makes the step of all parameters fail its gain
test; a plain Levenberg–Marquardt then raises λ for every parameter, and stops on its step
or cost tolerance far from the minimum (the profile stalls at the start, on the scale of the
interval's threshold). So each iteration here takes the full damped step

    (JᵀJ + λ·D²) δ = −Jᵀr

and, where it fails, the records' own steps (A_bb + λ_b·D_b²) δ_b = −g_b with the shared
parameters held: one evaluation of all records, each record's step kept where its own rows'
cost fell (its λ_b lowered) and refused elsewhere (λ_b raised). A dense Jacobian (no
records) is the plain method.

The stopping test is absolute and set by the caller in the cost's own units (a share of the
profile threshold P_crit): the iteration stops when a full step was accepted whose decrease
is below `tol`, or when the gradient's cosine with every free column is below 1e-10. A
tolerance relative to the cost or to the scaled parameter vector (MINPACK's ftol and xtol)
stops a stalled iteration as converged: the cost of a pooled fit is 10⁴–10⁵ times the
threshold, and the parameters differ by ten orders of magnitude in scale.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import sparse

from presliding.identification.solve._structured_lm import block_layout, structured_normal

FloatArray = NDArray[np.float64]

__all__ = ["Inner", "cost", "minimise"]


@dataclass
class Inner:
    """The outcome: the point, its cost r·r, evaluations, whether it converged, and the
    decrease of r·r the Gauss–Newton model still predicts there (inf: not known)."""

    x: FloatArray
    cost: float
    nfev: int
    converged: bool
    remaining: float = np.inf


def _blocks(J: Any) -> list[tuple[NDArray[np.int_], Any]]:
    """(columns, rows) of each record's block of a pooled CSC Jacobian; [] otherwise."""
    if not sparse.issparse(J):
        return []
    lay = block_layout(J.tocsc())
    if lay.blocks is None:
        return []
    return [(cols, rows) for cols, rows, _ in lay.blocks]


def _step(A: FloatArray, g: FloatArray, d2: FloatArray, lam: float, free: Any) -> FloatArray:
    out = np.zeros_like(g)
    if not np.any(free):
        return out
    mat = A[np.ix_(free, free)] + lam * np.diag(d2[free])
    try:
        out[free] = np.linalg.solve(mat, -g[free])
    except np.linalg.LinAlgError:
        out[free] = -np.linalg.lstsq(mat, g[free], rcond=None)[0]
    return out


def cost(r: FloatArray) -> float:
    """r·r, inf where the model fails (a residual not finite)."""
    return float(r @ r) if np.all(np.isfinite(r)) else np.inf


def minimise(
    fun: Callable[[FloatArray], FloatArray], jac: Callable[[FloatArray], Any], x0: FloatArray,
    lower: FloatArray, upper: FloatArray, *, tol: float, max_nfev: int,
    step_limit: Callable[[FloatArray], FloatArray] | None = None,
) -> Inner:  # fmt: skip
    """Minimise r·r within the box from `x0` (module notes); `tol` is absolute in r·r."""
    x = np.clip(x0, lower, upper)
    r = fun(x)
    c = cost(r)
    if not np.isfinite(c):
        return Inner(x, np.inf, 1, False)
    it = _Iterate(jac, x, r)
    nfev, lam, nu, remaining = 1, -1.0, 2.0, np.inf
    lam_b: dict[int, float] = {}
    blocks = _blocks(it.J)
    while nfev < max_nfev:
        A, g, d2 = it.A, it.g, it.d2
        if lam < 0:
            lam = 1e-3 * float(np.max(np.diag(A) / d2))
        held = ((x <= lower) & (g > 0)) | ((x >= upper) & (g < 0))
        free = ~held
        cos = np.abs(g[free]) / (it.norms[free] * np.sqrt(c) + 1e-300)
        remaining = -float(g @ _step(A, g, d2, 1e-12, free))  # the Gauss–Newton decrease
        if (
            c == 0.0
            or not free.any()
            or float(np.max(cos, initial=0.0)) <= 1e-10
            or (remaining <= tol)
        ):
            if it.fresh:
                return Inner(x, c, nfev, True, remaining)
            it.refresh(x, r)
            continue
        limit = step_limit(x) if step_limit is not None else None
        step = _step(A, g, d2, lam, free)
        if limit is not None:
            step = np.clip(step, -limit, limit)
        xn = np.clip(x + step, lower, upper)
        step = xn - x
        if not np.any(step) or not np.isfinite(lam):  # no step left to try
            break
        predicted = -float(2.0 * g @ step + step @ A @ step)
        rn_new = fun(xn)
        nfev += 1
        cn = cost(rn_new)
        rho = (c - cn) / predicted if predicted > 0 else -1.0
        if rho > 0 and cn < c:
            x, r, c = xn, rn_new, cn
            lam *= max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3)
            nu = 2.0
            it.moved(x, r, good=rho > 0.25)
            continue
        if not it.fresh:  # the Jacobian of an earlier point: refreshed before λ is raised
            it.refresh(x, r)
            continue
        lam *= nu
        nu = min(2.0 * nu, 1e3)
        if blocks and predicted > 0:  # the records' own steps, the shared ones held
            x, r, c, nfev, accepted = _record_steps(
                fun, x, r, c, nfev, A, g, d2, free, blocks, lam_b, limit, lower, upper
            )
            if accepted:
                it.moved(x, r, good=True)
    return Inner(x, c, nfev, False, remaining)


class _Iterate:
    """The Jacobian and normal equations of the iteration, refreshed lazily: after an
    accepted step whose gain ratio was good, the Jacobian of the earlier point is kept and
    only the gradient Jᵀr is updated (a residual evaluation costs a fraction of a Jacobian
    of a pooled fit); it is evaluated again where a step fails or the gain was poor."""

    def __init__(self, jac: Callable[[FloatArray], Any], x: FloatArray, r: FloatArray):
        self.jac = jac
        self.d2 = np.zeros(x.shape[0])
        self.refresh(x, r)

    def refresh(self, x: FloatArray, r: FloatArray) -> None:
        self.J = self.jac(x)
        self.A, self.g, self.norms = structured_normal(self.J, r)
        self.d2 = np.maximum(self.d2, self.norms**2)
        self.d2 = np.where(self.d2 > 0, self.d2, 1.0)
        self.fresh = True

    def moved(self, x: FloatArray, r: FloatArray, good: bool) -> None:
        if not good:
            self.refresh(x, r)
            return
        self.g = np.asarray(self.J.T @ r, dtype=float)
        self.fresh = False


def _record_steps(
    fun: Callable, x: FloatArray, r: FloatArray, c: float, nfev: int, A: FloatArray,
    g: FloatArray, d2: FloatArray, free: Any, blocks: list, lam_b: dict[int, float],
    limit: FloatArray | None, lower: FloatArray, upper: FloatArray,
) -> tuple[FloatArray, FloatArray, float, int, bool]:  # fmt: skip
    """Every record's own damped step in one evaluation; each kept where its rows' cost fell."""
    xn = x.copy()
    for b, (cols, _) in enumerate(blocks):
        sub = np.zeros(x.shape[0], dtype=bool)
        sub[cols] = free[cols]
        if not sub.any():
            continue
        if b not in lam_b:
            lam_b[b] = 1e-3 * float(np.max(np.diag(A)[sub] / d2[sub]))
        step = _step(A, g, d2, lam_b[b], sub)[cols]
        if limit is not None:
            step = np.clip(step, -limit[cols], limit[cols])
        xn[cols] = x[cols] + step
    xn = np.clip(xn, lower, upper)
    rn = fun(xn)
    nfev += 1
    accepted = False
    out_x, out_r = x.copy(), r.copy()
    for b, (cols, rows) in enumerate(blocks):
        if b not in lam_b:
            continue
        old, new = r[rows], rn[rows]
        if np.all(np.isfinite(new)) and float(new @ new) < float(old @ old):
            out_x[cols] = xn[cols]
            out_r[rows] = new
            lam_b[b] /= 3.0
            accepted = True
        else:
            lam_b[b] *= 4.0
    if not accepted:
        return x, r, c, nfev, False
    return out_x, out_r, cost(out_r), nfev, True
