"""Separable least squares for models linear in all but the PI thresholds (section 4).

Each fit of this family has the form

    target ≈ X·θ + Σ_j k_j g(r_j)          (eq. 17, or the force of eq. 8)

with fixed regressors X (acceleration, sign of the velocity, velocity, a
constant), linear parameters θ and stiffnesses k_j, and a basis g that depends
nonlinearly on the thresholds r_j only: the stop outputs y − x_j(y, r_j) for a
force-displacement record, or min(s, r_j) for a virgin curve. The fit runs in
two stages, as the paper suggests: bounded linear least squares (NNLS for the
stiffnesses) on a dense geometric grid of thresholds gives a start, the grid
elements carrying weight are merged into the wanted number of elements, and
nonlinear least squares over θ, k and r refines it with the exact Jacobian
(∂g/∂r is ±1 or 0 for both bases). This module holds the bases, the grids and
the compiled kernels; the fit itself is the problem of `_separable_problem`.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from presliding.hysteresis._fused import batch_loss, batch_loss_parallel
from presliding.hysteresis._jit import njit

FloatArray = NDArray[np.float64]
Basis = Callable[[FloatArray], tuple[FloatArray, FloatArray]]
DEFAULT_GRID = 48


@njit(cache=True)
def _stop_sensitivity(y, threshold, f_out, s_out):  # pragma: no cover - compiled
    """Stop outputs f_j = y − x_j (relaxed at y[0]) and their derivatives ∂f_j/∂r_j.

    After the play x_j was last dragged by the lower edge (x = y − r) the stop
    output is y − y_drag + r, so ∂f/∂r = +1; after the upper edge, −1; before
    the first drag, 0 (the relaxed start does not depend on r).
    """
    n_el = threshold.shape[0]
    x = np.full(n_el, y[0])
    side = np.zeros(n_el)
    for t in range(y.shape[0]):
        yt = y[t]
        for j in range(n_el):
            lo = yt - threshold[j]
            hi = yt + threshold[j]
            xj = x[j]
            if lo > xj:
                xj = lo
                side[j] = 1.0
            elif hi < xj:
                xj = hi
                side[j] = -1.0
            x[j] = xj
            f_out[t, j] = yt - xj
            s_out[t, j] = side[j]


@njit(cache=True)
def reversal_indices(y, tol):  # pragma: no cover - compiled
    """Indices of the turning points of y: extremes left by more than `tol`.

    The last sample of a plateau at an extreme is taken as the turning point.
    """
    out = np.empty(y.shape[0], dtype=np.int64)
    n = 0
    d = 0
    ext = y[0]
    ext_i = 0
    for t in range(1, y.shape[0]):
        v = y[t]
        if d == 0:
            if abs(v - y[0]) > tol:
                d = 1 if v > y[0] else -1
                ext = v
                ext_i = t
        elif d > 0:
            if v >= ext:
                ext = v
                ext_i = t
            elif ext - v > tol:
                out[n] = ext_i
                n += 1
                d = -1
                ext = v
                ext_i = t
        else:
            if v <= ext:
                ext = v
                ext_i = t
            elif v - ext > tol:
                out[n] = ext_i
                n += 1
                d = 1
                ext = v
                ext_i = t
    return out[:n]


def batch_stop_loss(
    y: FloatArray,
    target: FloatArray,
    threshold: FloatArray,
    weight: FloatArray,
    linear: FloatArray | None = None,
    *,
    design: FloatArray | None = None,
    offset: FloatArray | None = None,
    skip: int = 0,
    parallel: bool = False,
) -> FloatArray:
    """Σ_t (a_b·z + o_b + Σ_j w_bj (y − x_bj) − target)² of B PI operators, relaxed at y[0].

    ``threshold`` and ``weight`` have shape (B, N) (one operator per row),
    ``linear`` (a_b) and ``offset`` (o_b) shape (B,) (default 0), ``design``
    the signal z (default y). The first `skip` samples run the operators but
    add nothing (a burn-in). The loss is accumulated inside the compiled time
    loop (`presliding.hysteresis._fused.batch_loss`), so no (T × B) output is formed;
    ``parallel`` splits the batch over the cores. Inputs are trusted (finite,
    thresholds > 0): this is the inner loop of a fit.
    """
    y = np.ascontiguousarray(y, dtype=np.float64)
    z = y if design is None else np.ascontiguousarray(design, dtype=np.float64)
    target = np.ascontiguousarray(target, dtype=np.float64)
    r = np.ascontiguousarray(np.transpose(threshold), dtype=np.float64)
    w = np.ascontiguousarray(np.transpose(weight), dtype=np.float64)
    n_batch = r.shape[1]
    a = np.zeros(n_batch) if linear is None else np.ascontiguousarray(linear, dtype=np.float64)
    o = np.zeros(n_batch) if offset is None else np.ascontiguousarray(offset, dtype=np.float64)
    x = np.full(r.shape, y[0])
    loss = np.zeros(n_batch)
    kernel = batch_loss_parallel if parallel else batch_loss
    if skip > 0:  # run the memory through the burn-in, then start counting
        kernel(y[:skip], z[:skip], target[:skip], r, w, a, o, x, loss)
        loss[:] = 0.0
    if skip < y.shape[0]:
        kernel(y[skip:], z[skip:], target[skip:], r, w, a, o, x, loss)
    return loss


def stop_basis(y: FloatArray) -> Basis:
    """The stop-operator basis along the path y, relaxed at y[0]."""
    y = np.ascontiguousarray(y, dtype=np.float64)

    def basis(r: FloatArray) -> tuple[FloatArray, FloatArray]:
        f = np.empty((y.shape[0], r.shape[0]))
        s = np.empty_like(f)
        _stop_sensitivity(y, np.ascontiguousarray(r, dtype=np.float64), f, s)
        return f, s

    return basis


def virgin_basis(s: FloatArray) -> Basis:
    """The virgin-curve basis min(s, r_j) for s >= 0 (the elastic part of F_v)."""
    s = np.asarray(s, dtype=np.float64)[:, None]

    def basis(r: FloatArray) -> tuple[FloatArray, FloatArray]:
        return np.minimum(s, r[None, :]), (s > r[None, :]).astype(np.float64)

    return basis


def largest_threshold(y: FloatArray) -> float:
    """The largest threshold of an element relaxed at y[0] that slides along y at all: the
    largest excursion max |y − y[0]| (a larger one never leaves its start: a linear spring,
    the same column for any larger threshold)."""
    y = np.asarray(y, dtype=float)
    return float(np.max(np.abs(y - y[0]))) if y.size else 0.0


def threshold_grid(y: FloatArray, size: int = DEFAULT_GRID) -> FloatArray:
    """Geometric grid from about two input quanta to half the input range of a path."""
    steps = np.abs(np.diff(y))
    steps = steps[steps > 0]
    span = float(np.ptp(y))
    return geometric_grid(2.0 * float(np.min(steps)), 0.5 * span, span, size)


def geometric_grid(lo: float, hi: float, span: float, size: int = DEFAULT_GRID) -> FloatArray:
    """Geometric grid on [lo, hi], lo raised to at least 1e-5·span."""
    lo = max(lo, span * 1e-5)
    if not hi > lo:
        lo = hi / 100.0
    return np.geomspace(lo, hi, size, dtype=np.float64)


def merge_grid(grid: FloatArray, weight: FloatArray, n: int) -> tuple[FloatArray, FloatArray]:
    """Merge the weighted grid thresholds into n elements (stiffness-weighted in log r).

    Neighbouring grid points carrying weight are merged pairwise, closest in
    log r first, until n remain; if fewer than n carry weight, the widest gaps
    between the chosen thresholds (and the grid ends) are filled with weak
    elements so that the nonlinear stage starts from n distinct thresholds.
    """
    active = weight > 0
    r = list(np.log(grid[active]))
    k = list(weight[active])
    while len(r) > n:
        i = int(np.argmin(np.diff(r)))
        w = k[i] + k[i + 1]
        r[i] = (k[i] * r[i] + k[i + 1] * r[i + 1]) / w
        k[i] = w
        del r[i + 1], k[i + 1]
    weak = 1e-3 * (float(np.sum(weight)) or 1.0) / max(n, 1)
    ends = [float(np.log(grid[0])), float(np.log(grid[-1]))]
    while len(r) < n:
        pts = sorted([*r, *ends])
        gaps = np.diff(pts)
        i = int(np.argmax(gaps))
        new = 0.5 * (pts[i] + pts[i + 1])
        r.append(new)
        k.append(weak)
        order = np.argsort(r)
        r, k = [r[j] for j in order], [k[j] for j in order]
    return np.exp(np.array(r)), np.array(k)


def element_names(n: int) -> tuple[list[str], list[str]]:
    """Parameter names of the elastic elements, numbered from 1."""
    return [f"stiffness_{j + 1}" for j in range(n)], [f"threshold_{j + 1}" for j in range(n)]
