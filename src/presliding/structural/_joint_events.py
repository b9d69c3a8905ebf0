"""Events of a piece of a jointed structure: located on a grid of the closed form, refined.

Per joint c, with its stops' plastic parts x_j fixed while elastic:

* a sliding joint's velocity s_c·ġ_c reaching 0 (its sliding stops stick: a reversal),
  also where it dips to 0 between grid points (a minimum of s_c·ġ_c inside a cell);
* the distance to the nearest threshold, U_c − g_c and g_c − L_c with
  U_c = min(x_j + r_j), L_c = max(x_j − r_j) over its elastic stops (a stop starts to
  slide).

The grid has 16 points per period of the fastest motion of the piece; in each grid cell
where a joint's velocity changes sign the extremum of g_c is found (Brent) and its
distance to the thresholds checked, so a threshold touched between grid points is not
missed. The first event is refined by Brent's method to ~1e-15 of its time.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from presliding.structural._pieces import Piece

FloatArray = NDArray[np.float64]
BLOCK = 48
POINTS_PER_PERIOD = 16


def _limits(piece: Piece) -> tuple[FloatArray, FloatArray, FloatArray]:
    """(U_c, L_c, s_c): the thresholds' positions of the elastic stops and the sliding
    direction of each joint (0: none sliding)."""
    md = piece.model
    el = piece.elastic
    up = np.full(md.n_c, np.inf)
    low = np.full(md.n_c, -np.inf)
    np.minimum.at(up, md.owner[el], (piece.x0 + md.er)[el])
    np.maximum.at(low, md.owner[el], (piece.x0 - md.er)[el])
    s = np.zeros(md.n_c)
    np.add.at(s, md.owner, piece.sliding)
    return up, low, np.sign(s)


def next_event(piece: Piece, horizon: float) -> tuple[float, int, int] | None:
    """(τ, joint, kind) of the first event in (0, horizon]; kind 1: a stop reaches its upper
    threshold, −1: its lower one, 0: a sliding joint comes to rest. None if none."""
    up, low, s = _limits(piece)
    h = min(2.0 * np.pi / max(piece.omega_max, 1e-300) / POINTS_PER_PERIOD, horizon / 4.0)
    lo = 0.0
    g_lo, gd_lo, gdd_lo = (x[0] for x in piece.contacts(np.array([0.0])))
    while lo < horizon:
        grid = np.minimum(lo + h * np.arange(1, BLOCK + 1), horizon)
        grid = np.unique(grid)
        g, gd, gdd = piece.contacts(grid)
        block = (np.r_[lo, grid], np.vstack([g_lo, g]), np.vstack([gd_lo, gd]),
                 np.vstack([gdd_lo, gdd]))  # fmt: skip
        found = _first(piece, block, up, low, s)
        if found is not None:
            return found
        lo, g_lo, gd_lo, gdd_lo = float(grid[-1]), g[-1], gd[-1], gdd[-1]
    return None


def _first(piece: Piece, block: tuple[FloatArray, ...], up: FloatArray, low: FloatArray,
           s: FloatArray) -> tuple[float, int, int] | None:  # fmt: skip
    """The earliest event on the grid block (t, g, ġ, g̈), refined."""
    t, g, gd, gdd = block
    best: tuple[float, int, int] | None = None
    # a sliding joint's velocity s·ġ: positive, then <= 0
    vel = s * gd
    cross_v = (vel[:-1] > 0) & (vel[1:] <= 0) & (s != 0)
    # thresholds: the margins positive, then <= 0; or an extremum inside a cell beyond them
    m_up, m_low = up - g, g - low
    cross_u = (m_up[:-1] > 0) & (m_up[1:] <= 0)
    cross_l = (m_low[:-1] > 0) & (m_low[1:] <= 0)
    turn = (np.sign(gd[:-1]) != np.sign(gd[1:])) & np.isfinite(up - low)
    # a sliding joint's velocity dipping to zero between grid points: a minimum of s·ġ
    acc = s * gdd
    dip = (vel[:-1] > 0) & (vel[1:] > 0) & (acc[:-1] < 0) & (acc[1:] > 0) & (s != 0)
    rows = np.flatnonzero((cross_v | cross_u | cross_l | turn | dip).any(axis=1))
    for i in rows:
        if best is not None and t[i] >= best[0]:
            break
        a, b = float(t[i]), float(t[i + 1])
        for c in range(g.shape[1]):
            for kind, flag in ((0, cross_v[i, c]), (1, cross_u[i, c]), (-1, cross_l[i, c])):
                if flag:
                    tau = _root(piece, c, kind, up[c], low[c], s[c], a, b)
                    best = _earlier(best, (tau, c, kind))
            if turn[i, c] and not (cross_u[i, c] or cross_l[i, c]):
                hit = _grazing(piece, c, up[c], low[c], a, b)
                if hit is not None:
                    best = _earlier(best, (hit[0], c, hit[1]))
            if dip[i, c]:
                rest = _dip(piece, c, s[c], a, b)
                if rest is not None:
                    best = _earlier(best, (rest, c, 0))
    return best


def _earlier(best: Any, cand: tuple[float, int, int]) -> tuple[float, int, int]:
    return cand if best is None or cand[0] < best[0] else best


def _fun(piece: Piece, c: int, kind: int, up: float, low: float, s: float) -> Any:
    def f(tau: float) -> float:
        g, gd, _ = piece.contacts(np.array([tau]))
        if kind == 0:
            return float(s * gd[0, c])
        return float(up - g[0, c]) if kind == 1 else float(g[0, c] - low)

    return f


def _root(piece: Piece, c: int, kind: int, up: float, low: float, s: float, a: float,
          b: float) -> float:  # fmt: skip
    f = _fun(piece, c, kind, up, low, s)
    fa, fb = f(a), f(b)
    if fa > 0.0 and fb < 0.0:
        return float(brentq(f, a, b, xtol=1e-15 * max(b, 1e-300), rtol=4 * np.finfo(float).eps))
    return b if fb <= 0.0 and fa > 0.0 else a


def _dip(piece: Piece, c: int, s: float, a: float, b: float) -> float | None:
    """A sliding joint at rest at a minimum of s·ġ_c inside (a, b) (no sign change at the
    grid): the first zero of s·ġ_c before that minimum."""

    def acc(tau: float) -> float:
        return float(s * piece.contacts(np.array([tau]))[2][0, c])

    t_min = float(brentq(acc, a, b, xtol=1e-15 * max(b, 1e-300), rtol=4 * np.finfo(float).eps))
    vel = _fun(piece, c, 0, 0.0, 0.0, s)
    if vel(t_min) > 0.0:
        return None
    return _root(piece, c, 0, 0.0, 0.0, s, a, t_min)


def _grazing(piece: Piece, c: int, up: float, low: float, a: float,
             b: float) -> tuple[float, int] | None:  # fmt: skip
    """A threshold reached at an extremum of g_c inside (a, b) (no sign change at the grid)."""
    vel = _fun(piece, c, 0, up, low, 1.0)
    va, vb = vel(a), vel(b)
    if not (va * vb < 0.0):
        return None
    t_ext = float(brentq(vel, a, b, xtol=1e-15 * max(b, 1e-300), rtol=4 * np.finfo(float).eps))
    g_ext = float(piece.contacts(np.array([t_ext]))[0][0, c])
    kind = 1 if va > 0 else -1  # a maximum (ġ from + to −) can reach the upper threshold
    margin = (up - g_ext) if kind == 1 else (g_ext - low)
    if margin > -1e-12 * (abs(g_ext) + abs(up - low)):  # not beyond it (rounding of a start)
        return None
    return _root(piece, c, kind, up, low, 1.0, a, t_ext), kind
