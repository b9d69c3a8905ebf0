"""Levenberg–Marquardt with box bounds on the normal equations, for large pooled fits.

scipy's trust-region reflective method factors the whole Jacobian (an SVD of
n residuals × p parameters) at every iteration, or solves the step with LSMR;
for a pooled fit (n = 20 000, p = 67) either costs seconds. The normal
equations are small (p × p) and cheap to form, and the columns are scaled
(the largest norm seen so far, as MINPACK's ``mode=1``), so the damped step

    (JᵀJ + λ·D²) δ = −Jᵀr

is solved accurately in milliseconds. Bounds: a parameter on a bound whose
gradient pushes it outward is held (an active set), and the step is projected
onto the box; the damping λ follows Nielsen's rule (the gain ratio ρ of the
actual to the predicted decrease). Stopping tests as in MINPACK: relative
decrease of the cost (ftol), relative step (xtol) and the largest cosine
between the residual and a free column (gtol).
"""

from __future__ import annotations

import functools
import itertools
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np
from numpy.typing import NDArray
from scipy import sparse

FloatArray = NDArray[np.float64]


@dataclass
class LMResult:
    """Outcome, with the attributes of scipy's OptimizeResult that the fits read."""

    x: FloatArray
    fun: FloatArray
    jac: Any  # the last Jacobian, as `jac` gave it (dense, or a scipy.sparse matrix)
    nfev: int
    status: int  # 0: evaluation limit, 1: gtol, 2: ftol, 3: xtol
    message: str
    active_mask: NDArray[np.int_]  # −1 on a lower bound, 1 on an upper one, 0 inside


@dataclass
class _State:
    """The iterate of `levenberg_marquardt` and what it keeps between steps."""

    x: FloatArray
    r: FloatArray
    cost: float
    J: Any
    A: FloatArray  # JᵀJ
    g: FloatArray  # Jᵀr
    norms: FloatArray  # column norms of J
    d: FloatArray  # column scales (the largest norm seen)
    lam: float
    nu: float = 2.0
    nfev: int = 1


_MESSAGES = {
    0: "the evaluation limit was reached",
    1: "`gtol` termination condition is satisfied",
    2: "`ftol` termination condition is satisfied",
    3: "`xtol` termination condition is satisfied",
}


def levenberg_marquardt(
    fun: Callable[[FloatArray], FloatArray],
    jac: Callable[[FloatArray], Any],  # a dense array or a scipy.sparse matrix
    x0: FloatArray,
    lower: FloatArray,
    upper: FloatArray,
    *,
    ftol: float,
    xtol: float,
    gtol: float,
    max_nfev: int | None,
    step_limit: Callable[[FloatArray], FloatArray] | None = None,
) -> LMResult:
    """Minimise ½‖fun(x)‖² within lower <= x <= upper (module notes).

    `step_limit(x)` gives the largest change of each parameter in one step (a
    trust box the step is clipped to). The residual of a fit with stiction is
    only piecewise smooth (a reversal appears or a stop moves across a sample),
    and a parameter the data hardly see (a preload erased by the first slide)
    would otherwise take a step the linear model cannot judge.
    """
    max_nfev = 100 * x0.shape[0] if max_nfev is None else max_nfev
    state = _start(fun, jac, x0, lower, upper)
    status = 0
    while state.nfev < max_nfev:
        free = _free_or_stationary(state, lower, upper, gtol)
        if free is None:
            status = 1
            break
        status = _iterate(state, fun, jac, free, lower, upper, step_limit, ftol, xtol)
        if status:
            break
    active = np.where(state.x <= lower, -1, np.where(state.x >= upper, 1, 0))
    return LMResult(state.x, state.r, state.J, state.nfev, status, _MESSAGES[status], active)


def _start(fun: Callable, jac: Callable, x0: FloatArray, lower: FloatArray,
           upper: FloatArray) -> _State:  # fmt: skip
    """The first iterate: the start clipped to the box, its residual and normal equations."""
    x = np.clip(x0, lower, upper)
    r = fun(x)
    if not np.all(np.isfinite(r)):
        raise ValueError("the residual is not finite at the start")
    J = jac(x)
    A, g, norms = structured_normal(J, r)
    d = np.where(norms == 0, 1.0, norms)
    lam = 1e-3 * float(np.max(np.diag(A) / d**2))
    return _State(x, r, 0.5 * float(r @ r), J, A, g, norms, d, lam)


def _free_or_stationary(state: _State, lower: FloatArray, upper: FloatArray,
                        gtol: float) -> NDArray[np.bool_] | None:  # fmt: skip
    """The gradient test: None when the iterate is stationary (a zero residual, every
    parameter held on a bound, or no free column's cosine with the residual above
    `gtol`); else the parameters free to move (a bound holds one pushed outward)."""
    rn = float(np.sqrt(2 * state.cost))
    g = state.g
    held = ((state.x <= lower) & (g > 0)) | ((state.x >= upper) & (g < 0))
    free = ~held
    cosines = np.abs(g[free]) / (state.norms[free] * rn + 1e-300)
    if rn == 0.0 or not free.any() or float(np.max(cosines, initial=0.0)) <= gtol:
        return None
    return free


def _iterate(
    state: _State, fun: Callable, jac: Callable, free: Any, lower: FloatArray,
    upper: FloatArray, step_limit: Any, ftol: float, xtol: float,
) -> int:  # fmt: skip
    """One damped step tried and accepted or rejected (Nielsen's rule for λ); returns
    the termination status it reached (2: ftol, 3: xtol), 0 to go on."""
    step = _damped_step(state.A, state.g, state.d, state.lam, free)
    if step_limit is not None:
        limit = step_limit(state.x)
        step = np.clip(step, -limit, limit)
    x_new = np.clip(state.x + step, lower, upper)
    step = x_new - state.x
    d = state.d
    small = float(np.linalg.norm(d * step)) <= xtol * (float(np.linalg.norm(d * state.x)) + xtol)
    predicted = -float(state.g @ step + 0.5 * step @ state.A @ step)
    r_new = fun(x_new)
    state.nfev += 1
    cost_new = 0.5 * float(r_new @ r_new) if np.all(np.isfinite(r_new)) else np.inf
    rho = (state.cost - cost_new) / predicted if predicted > 0 else -1.0
    if not (rho > 0 and cost_new < state.cost):
        if small:
            return 3
        state.lam *= state.nu
        state.nu *= 2.0
        return 0
    decrease = state.cost - cost_new
    state.x, state.r, state.cost = x_new, r_new, cost_new
    if decrease <= ftol * (cost_new + decrease) and rho > 0.25:
        return 2
    if small:
        return 3
    state.J = jac(state.x)
    state.A, state.g, state.norms = structured_normal(state.J, state.r)
    state.d = np.maximum(state.d, state.norms)
    state.lam *= max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3)
    state.nu = 2.0
    return 0


def _damped_step(A: FloatArray, g: FloatArray, d: FloatArray, lam: float, free: Any) -> FloatArray:
    """The solution of (A + λ·D²) δ = −g on the free parameters (0 for the held ones)."""
    step = np.zeros_like(g)
    mat = A[np.ix_(free, free)] + lam * np.diag(d[free] ** 2)
    try:
        step[free] = np.linalg.solve(mat, -g[free])
    except np.linalg.LinAlgError:
        step[free] = -np.linalg.lstsq(mat, g[free], rcond=None)[0]
    return step


def structured_normal(J: Any, r: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """JᵀJ (dense), Jᵀr and the column norms, for a dense or a CSC Jacobian.

    A CSC Jacobian of a pooled fit has full columns (shared parameters) and
    columns that share one block of rows (a record's own parameters): JᵀJ is
    assembled from those blocks, never from a sparse product. The structure is
    the same at every iterate of a solve: its analysis (`_Layout`) is kept for
    the next call with the same structure.
    """
    if not sparse.issparse(J):
        A = J.T @ J
        return A, J.T @ r, np.sqrt(np.maximum(np.diag(A), 0.0))
    J = J.tocsc()
    n, p = J.shape
    ptr, val = J.indptr, J.data
    lay = block_layout(J)
    F = np.empty((n, lay.full.shape[0]))
    for c, j in enumerate(lay.full):  # rows of a full column are 0..n−1 in order
        F[:, c] = val[ptr[j] : ptr[j + 1]]
    A = np.zeros((p, p))
    A[np.ix_(lay.full, lay.full)] = F.T @ F
    g = np.zeros(p)
    g[lay.full] = F.T @ r
    if lay.blocks is None:  # blocks that overlap (ties across records): a sparse product
        others = lay.others
        sub = J[:, others]
        A[np.ix_(others, others)] = (sub.T @ sub).toarray()
        A[np.ix_(lay.full, others)] = (sub.T @ F).T
        A[np.ix_(others, lay.full)] = A[np.ix_(lay.full, others)].T
        g[others] = sub.T @ r
        return A, g, np.sqrt(np.maximum(np.diag(A), 0.0))
    full = lay.full
    for cols, rows, at in lay.blocks:
        if at is None:
            P = np.column_stack([val[ptr[j] : ptr[j + 1]] for j in cols])
        else:  # consecutive columns of equal rows: one stretch of the values
            P = np.ascontiguousarray(val[ptr[at.start] : ptr[at.stop]].reshape(len(cols), -1).T)
        cross = F[rows].T @ P
        if at is None:
            A[np.ix_(cols, cols)] = P.T @ P
            A[np.ix_(full, cols)] = cross
            A[np.ix_(cols, full)] = cross.T
        else:  # consecutive columns: plain slices
            A[at, at] = P.T @ P
            A[full, at] = cross
            A[at, full] = cross.T
        g[cols] = P.T @ r[rows]
    return A, g, np.sqrt(np.maximum(np.diag(A), 0.0))


@dataclass(frozen=True)
class _Layout:
    """The structure of a pooled CSC Jacobian (`structured_normal`)."""

    indptr: NDArray[np.int_]
    indices: NDArray[np.int_]
    full: NDArray[np.int_]  # columns with every row, in order
    others: NDArray[np.int_]  # the other nonzero columns
    #: (columns, their rows as a slice or indices, the columns as a slice or None) of every
    #: block of columns sharing their rows; None when blocks overlap
    blocks: list[tuple[NDArray[np.int_], Any, slice | None]] | None


_LAYOUTS: list[_Layout] = []  # the last structure analysed (one)


def block_layout(J: Any) -> _Layout:
    """The analysis of a CSC Jacobian's structure, reused while it stays the same."""
    ptr, idx = J.indptr, J.indices
    for lay in _LAYOUTS:
        same_ptr = lay.indptr is ptr or np.array_equal(lay.indptr, ptr)
        if same_ptr and (lay.indices is idx or np.array_equal(lay.indices, idx)):
            return lay
    n = J.shape[0]
    nnz = np.diff(ptr)
    full = np.flatnonzero(nnz == n)
    full = np.array([j for j in full if np.array_equal(idx[ptr[j] : ptr[j + 1]], np.arange(n))],
                    dtype=np.int_)  # fmt: skip
    taken = set(full.tolist())
    others = np.array([j for j in range(J.shape[1]) if nnz[j] > 0 and j not in taken],
                      dtype=np.int_)  # fmt: skip
    found: dict[tuple, list[int]] = {}
    for j in others:
        first, last = idx[ptr[j]], idx[ptr[j + 1] - 1]
        found.setdefault((int(first), int(last), int(nnz[j])), []).append(int(j))
    spans = sorted((first, last) for first, last, _ in found)
    disjoint = all(b[0] > a[1] for a, b in itertools.pairwise(spans))
    same = disjoint and all(
        np.array_equal(idx[ptr[j] : ptr[j + 1]], idx[ptr[cols[0]] : ptr[cols[0] + 1]])
        for cols in found.values()
        for j in cols
    )
    blocks: list | None = None
    if same:
        blocks = []
        for (first, last, count), cols in found.items():
            rows: Any = idx[ptr[cols[0]] : ptr[cols[0] + 1]].copy()
            if last - first + 1 == count and np.all(np.diff(rows) == 1):  # contiguous rows
                rows = slice(first, last + 1)
            c = np.array(cols, dtype=np.int_)
            at = slice(cols[0], cols[-1] + 1) if cols[-1] - cols[0] + 1 == len(cols) else None
            blocks.append((c, rows, at))
    lay = _Layout(ptr.copy(), idx.copy(), full, others, blocks)
    _LAYOUTS[:] = [lay]
    return lay


_CONTROLLER: list[Any] = []  # the threadpool controller, made at first use (it scans libraries)


def one_blas_thread() -> Any:
    """A context in which BLAS runs on one thread (threadpoolctl).

    A fit's linear algebra is tall and thin (dot products of residuals, normal
    equations), far too small to gain from threads; and right after a parallel
    compiled call (a Jacobian's trial points) the compiled kernels' threads still
    hold the cores, so a threaded BLAS call waits for them: a dot product of 40 000
    residuals took 16 ms instead of 0.1 ms on two cores. The controller is made once
    (`threadpoolctl.threadpool_limits` scans the loaded libraries at every call).
    """
    if not _CONTROLLER:
        from threadpoolctl import ThreadpoolController

        _CONTROLLER.append(ThreadpoolController())
    return _CONTROLLER[0].limit(limits=1, user_api="blas")


F = TypeVar("F", bound=Callable[..., Any])


def on_one_blas_thread(function: F) -> F:
    """`function` run inside `one_blas_thread` (the steps of a fit that call the solver and
    take dot products of residuals between its calls)."""

    @functools.wraps(function)
    def run(*args: Any, **kwargs: Any) -> Any:
        with one_blas_thread():
            return function(*args, **kwargs)

    return run  # type: ignore[return-value]


def free_limit(pm: Any, step_limit: Any) -> Any:
    """A step limit of the free parameters (of the map `pm`) from one of every parameter."""
    if step_limit is None:
        return None
    weight = np.abs(pm.matrix)

    def limit(x: FloatArray) -> FloatArray:
        full = step_limit(pm.full(x))
        with np.errstate(divide="ignore"):
            per = np.where(weight > 0, full[:, None] / np.where(weight > 0, weight, 1.0), np.inf)
        return per.min(axis=0)

    return limit
