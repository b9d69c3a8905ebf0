"""Events of a piece: located on a grid of the closed form, then refined to ~1e-14 s.

The event functions h(τ) of a piece (an event when h <= 0; a stuck contact's margin
when h < 0):

* a sliding contact's velocity s_c·ġ_c (it comes to rest);
* a sliding contact's distance to its nearest element threshold, d_c − s_c·Δg_c (an
  element starts to slide);
* a stuck contact's stick margin c1_c − |λ_c − F_el,c| (break-away), or for a redundant
  stick set the largest margin any force distribution holding the structure leaves.

The grid step is half of 1/ω_max (ω_max the largest frequency of the piece) or a
32nd of the horizon; the first grid interval where an event function triggers is
refined by Brent's method (scipy.optimize.brentq, xtol 1e-15 s, rtol 4ε) when its
ends have strict opposite signs, else by bisection on the trigger itself.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

FloatArray = NDArray[np.float64]
BLOCK = 32


def scan(fun: Any, horizon: float, omega_max: float) -> tuple[float, NDArray[np.bool_]] | None:
    """The first time in (0, horizon] where `fun(τ)` (shape (T, F): event functions, and a
    mask of which are strict) triggers, with the functions that trigger there; None if none.
    """
    if horizon <= 0.0:
        return None
    h = horizon / BLOCK
    if omega_max > 0.0:
        h = min(h, 0.5 / omega_max)
    lo = 0.0
    while lo < horizon:
        grid = lo + h * np.arange(1, BLOCK + 1)
        grid[grid >= horizon] = horizon
        grid = np.unique(grid)
        vals, strict = fun(grid)
        if vals.shape[1] == 0:
            return None
        trig = np.where(strict, vals < 0.0, vals <= 0.0)
        rows = np.flatnonzero(trig.any(axis=1))
        if rows.size:
            i = int(rows[0])
            a = lo if i == 0 else float(grid[i - 1])
            b = float(grid[i])
            # the candidate whose linear interpolation crosses first is refined first
            prev = fun(np.array([a]))[0][0] if i == 0 else vals[i - 1]
            cand = trig[i]
            with np.errstate(divide="ignore", invalid="ignore"):
                frac = np.where(cand, prev / (prev - vals[i]), np.inf)
            first = np.zeros_like(cand)
            first[int(np.argmin(np.where(np.isnan(frac), 0.0, frac)))] = True
            return _refine(fun, a, b, first)
        lo = float(grid[-1])
    return None


def _triggered(fun: Any, t: float) -> NDArray[np.bool_]:
    vals, strict = fun(np.array([t]))
    return np.where(strict, vals[0] < 0.0, vals[0] <= 0.0)


def _refine(fun: Any, a: float, b: float, cand: NDArray[np.bool_]
            ) -> tuple[float, NDArray[np.bool_]]:  # fmt: skip
    """The earliest trigger time in (a, b] among the candidate functions.

    A function that triggers at the earliest time found so far is refined too (a
    contact's distance to its threshold decreases only while it slides the same way,
    so it may have crossed and come back within the interval, before its velocity
    event); repeated until no function triggers earlier.
    """
    best, best_j = b, -1
    done = np.zeros(cand.shape[0], bool)
    fa_all = fun(np.array([a]))[0][0] if a > 0.0 else None
    todo = cand.copy()
    while True:
        for j in (int(i) for i in np.flatnonzero(todo)):
            done[j] = True
            t = _root(fun, j, a, best, fa_all)
            if t < best or best_j < 0:
                best, best_j = t, j
        mask = _triggered(fun, best)
        todo = mask & ~done
        if not todo.any():
            break
    if best_j >= 0:
        mask[best_j] = True
    return best, mask


def _root(fun: Any, j: int, a: float, b: float, fa_all: Any) -> float:
    """The first time in (a, b] where function j triggers (b if only there)."""
    lo, hi = a, b
    column = getattr(fun, "column", None)
    if column is not None:
        h = column(j)
    else:

        def h(t: float) -> float:
            return float(fun(np.array([t]))[0][0, j])

    fa = h(lo) if fa_all is None else float(fa_all[j])
    fb = h(hi)
    if not fb <= 0.0:  # triggered only at the strict side (-0.0 / 0.0): keep hi
        return hi
    if fa > 0.0 and fb < 0.0:
        # the root to ~1e-15 s: the event happens there (its function is zero to
        # rounding; the event is applied exactly: snapped threshold, zero velocity)
        t = brentq(h, lo, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200)
        if t > a:
            return float(t)
    for _ in range(200):  # bisection on the trigger (a start at h = 0, a touch of zero)
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if _triggered(fun, mid)[j]:
            hi = mid
        else:
            lo = mid
    return hi
