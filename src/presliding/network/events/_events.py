"""Events of a piece, certified: every event function's first trigger isolated on cells.

The event functions h(τ) of a piece (an event when h <= 0; a stuck contact's margin
when h < 0) are affine in the piece's native coordinates ξ(τ) (modes, or the damped
first-order state), so each is a closed form with known rates and amplitudes:

* a sliding contact's velocity s_c·ġ_c (it comes to rest);
* a sliding contact's distance to its nearest element threshold, d_c − s_c·Δg_c (an
  element starts to slide);
* a stuck contact's stick margin c1_c − |τ_c| (break-away), split into its two smooth
  sides c1_c ∓ τ_c; for a redundant stick set, the largest margin any force distribution
  holding the structure leaves (a linear programme, 1-Lipschitz in the forces τ).

`scan` walks (0, horizon] cell by cell. On a cell [a, b] every smooth side h has values
and slopes at both ends and its second derivative in [P − T, P + T]
(`presliding.network.events._piece.Piece.curvature`: from the modal amplitudes, |h''| <=
Σ|A_i|·ω_i²), so h >= the quadratic lower bound from each end over its half of the cell.
A cell is certified free of events when every side's bound is >= 0 and no side triggers
at b; it holds exactly one root of a side that triggers at b when that side's slope is
certified negative over the cell (its upper bound from both ends < 0); otherwise the cell
is halved (and the next grows again). A cell at the time resolution (XTOL + RTOL·τ) that
is still undecided holds a trigger to that resolution (a start, a touch of zero) or, with
no trigger at its end, a graze of zero within the rounding of the closed form.
The isolated roots are refined by Brent's method (xtol 1e-15 s, rtol 4ε), the others by
bisection on the trigger. `Certificate` counts how each piece's cells and event were
certified.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

FloatArray = NDArray[np.float64]
XTOL = 1e-15
RTOL = 4.0 * np.finfo(float).eps
#: The rounding of a closed form's value, relative to the magnitudes of its terms.
ROUNDING = 64.0 * np.finfo(float).eps


@dataclass
class Certificate:
    """How a run's events were certified (counts over its pieces).

    ``cells``: cells proved free of events; ``isolated``: events at a root isolated on
    a cell (one sign change, slope of one sign: exactly one root), refined by Brent's
    method; ``resolved``: events at a trigger found on a cell at the time resolution
    (~1e-15 s: an event at the start of a piece, a touch of zero); ``grazes``: cells at
    the time resolution where a function came within rounding of zero without
    triggering; ``ends``: pieces ended by a change of the force or the end of the run,
    their whole span certified free of events.
    """

    cells: int = 0
    isolated: int = 0
    resolved: int = 0
    grazes: int = 0
    ends: int = 0

    def add(self, counts: Any) -> None:
        """Add counts (cells, isolated, resolved, grazes, ends) from the compiled loop."""
        self.cells += int(counts[0])
        self.isolated += int(counts[1])
        self.resolved += int(counts[2])
        self.grazes += int(counts[3])
        self.ends += int(counts[4])

    def counts(self) -> dict[str, int]:
        """The counts by name (a result's ``certification``)."""
        return {"cells": self.cells, "isolated": self.isolated, "resolved": self.resolved,
                "grazes": self.grazes, "ends": self.ends}  # fmt: skip


class AffineEvents:
    """The event functions of a piece, h = ξ(τ)·H + h0 (with the margins' |·|), and their
    smooth sides for `scan`.

    ``hmat`` (2·dim, F'), ``h0`` (F'): the velocity and threshold functions (the first
    ``n_lin``) and the stuck contacts' Coulomb forces τ (the rest), ``c1s`` their bounds.
    With ``lp`` (a redundant stick set) the margins are one function, ``lp(τ_row)``: its
    side is not smooth (bounded through its Lipschitz constant 1 in the forces), and the
    sides c1 ∓ τ of the minimum-norm forces are kept as auxiliary sides (where they all
    hold, the margin is positive: the linear programme's optimum is at least theirs).
    """

    def __init__(self, piece: Any, hmat: FloatArray, h0: FloatArray, n_lin: int,
                 c1s: FloatArray, lp: Any = None, scales: Any = None) -> None:  # fmt: skip
        self.pc, self.hmat, self.h0, self.n_lin, self.c1s, self.lp = piece, hmat, h0, n_lin, c1s, lp
        n_m = h0.shape[0] - n_lin
        self.n_m = n_m
        # sides: the linear functions, then c1 − τ and c1 + τ of every margin
        self.col = np.concatenate([np.arange(n_lin), np.repeat(np.arange(n_lin, n_lin + n_m), 2)])
        self.sign = np.concatenate([np.ones(n_lin), np.tile([-1.0, 1.0], n_m)])
        self.off = np.concatenate([np.zeros(n_lin), np.repeat(c1s, 2)])
        self.owner = np.minimum(self.col, n_lin) if lp is not None else self.col.copy()
        self.n_functions = n_lin + (1 if (lp is not None and n_m) else n_m)
        self.strict = np.arange(self.n_functions) >= n_lin
        self._fixed = None if piece.damped else piece.curvature(hmat, 0.0, 0.0)
        self.layout: tuple[Any, Any] = (None, None)  # (sliding, threshold) contacts
        # the rounding of each side's value and slope at τ = 0 (from the magnitudes of
        # the terms it is computed from)
        s0, s1 = scales if scales is not None else (np.abs(h0), np.zeros_like(h0))
        self.err = ROUNDING * (s0[self.col] + self.off)
        self.err_rate = ROUNDING * s1[self.col]

    def __call__(self, tau: FloatArray) -> tuple[FloatArray, NDArray[np.bool_]]:
        vals = self.pc.native(tau) @ self.hmat + self.h0
        n_lin = self.n_lin
        if self.lp is None:
            if self.n_m:
                vals[:, n_lin:] = self.c1s - np.abs(vals[:, n_lin:])
            return vals, self.strict
        out = vals[:, : self.n_functions].copy()
        if self.n_m:
            out[:, n_lin] = [self.lp(row) for row in vals[:, n_lin:]]
        return out, self.strict

    def column(self, j: int) -> Any:
        """Function j alone, at one time (for the root refinement; the same products)."""
        hmat, pc = self.hmat, self.pc
        if j < self.n_lin:
            cj = self.h0[j]
            return lambda t: float((pc.native_one(t)[None, :] @ hmat)[0, j] + cj)
        if self.lp is not None:
            return lambda t: float(self(np.array([t]))[0][0, j])
        c1j, cj = self.c1s[j - self.n_lin], self.h0[j]
        return lambda t: float(c1j - abs((pc.native_one(t)[None, :] @ hmat)[0, j] + cj))

    def sides(self, t: float) -> tuple[FloatArray, FloatArray, float]:
        """(h, h') of every side at one time, and the redundant margin there (nan: none)."""
        raw = self.pc.native_one(t) @ self.hmat + self.h0
        rate = self.pc.native_rate(t) @ self.hmat
        margin = np.nan
        if self.lp is not None and self.n_m:
            margin = float(self.lp(raw[self.n_lin :]))
        return self.sign * raw[self.col] + self.off, self.sign * rate[self.col], margin

    def bounds(self, a: float, b: float) -> tuple[FloatArray, FloatArray]:
        """(lo, hi): every side's second derivative lies in [lo, hi] on [a, b]."""
        p, t = self._fixed if self._fixed is not None else self.pc.curvature(self.hmat, a, b)
        return self.sign * p[self.col] - t[self.col], self.sign * p[self.col] + t[self.col]


def _lowest(h: FloatArray, d: FloatArray, k: FloatArray, ell: float) -> FloatArray:
    """min over δ ∈ [0, ℓ] of h + d·δ + k·δ²/2 (elementwise)."""
    low = np.minimum(h, h + d * ell + 0.5 * k * ell * ell)
    inner = (k > 0.0) & (d < 0.0) & (-d < k * ell)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(inner, np.minimum(low, h - d * d / (2.0 * k)), low)


def scan(fun: AffineEvents, horizon: float, omega_max: float, cert: Certificate
         ) -> tuple[float, NDArray[np.bool_]] | None:  # fmt: skip
    """The first time in (0, horizon] where an event function triggers, with the functions
    that trigger there; None if none (certified: see the module notes)."""
    if horizon <= 0.0:
        return None
    if fun.n_functions == 0:
        cert.ends += 1
        return None
    strict = fun.strict[fun.owner]
    aux = fun.lp is not None and fun.n_m > 0  # the sides n_lin.. are auxiliary
    n_lin = fun.n_lin
    width = horizon if omega_max <= 0.0 else min(horizon, 0.5 / omega_max)
    a = 0.0
    ha, da, ma = fun.sides(0.0)
    # a side at zero to rounding that stays there (to rounding) or moves away starts
    # there: it is lifted by its rounding for this piece (its trigger then is a value
    # below zero by more than rounding); one at or below zero that moves on triggers
    start = (np.abs(ha) <= fun.err) & (da >= -fun.err_rate)
    if aux:
        start[n_lin:] = False
    lift = np.where(start, fun.err, 0.0)
    ha = ha + lift
    raise_f = np.zeros(fun.n_functions)  # the functions as the refinement sees them
    np.maximum.at(raise_f, fun.owner, lift)
    trig_a = np.where(strict, ha < 0.0, ha <= 0.0)
    while True:
        b = min(a + width, horizon)
        ell = 0.5 * (b - a)
        hb, db, mb = fun.sides(b)
        hb = hb + lift
        lo, hi = fun.bounds(a, b)
        trig_b = np.where(strict, hb < 0.0, hb <= 0.0)
        low = np.minimum(_lowest(ha, da, lo, ell), _lowest(hb, -db, lo, ell))
        safe = ~trig_b & (low >= 0.0)
        slope = np.maximum(np.maximum(da, da + hi * ell), np.maximum(db, db - lo * ell))
        isolated = trig_b & ~trig_a & (slope < 0.0)
        lp_trig = False
        if aux:  # the redundant margin: its minimum-norm sides, or its Lipschitz bound
            lp_trig = mb < 0.0
            ok = safe[n_lin:].all() or (not lp_trig and min(ma, mb) >= _lipschitz(fun, a, b))
            safe[n_lin:] = ok
            isolated[n_lin:] = False
        if safe.all():
            cert.cells += 1
            if b >= horizon:
                cert.ends += 1
                return None
            a, ha, da, ma = b, hb, db, mb
            trig_a[:] = False
            width *= 2.0
            continue
        if np.all(safe | isolated):
            cert.isolated += 1
            return _refine(fun, a, b, _functions(fun, isolated), raise_f)
        if b - a <= XTOL + RTOL * b:
            if aux:
                trig_b[n_lin:] = False
            if trig_b.any() or lp_trig:
                cert.resolved += 1
                cand = _functions(fun, trig_b)
                if lp_trig:
                    cand[n_lin] = True
                return _refine(fun, a, b, cand, raise_f)
            cert.grazes += 1
            a, ha, da, ma = b, hb, db, mb
            trig_a[:] = False
            continue
        width = 0.5 * (b - a)


def _lipschitz(fun: AffineEvents, a: float, b: float) -> float:
    """A bound of the redundant margin's change over half of [a, b] (1-Lipschitz in the
    forces τ: the largest |τ'| on the cell, times half its length)."""
    p, t = fun.pc.curvature(fun.hmat[:, fun.n_lin :], a, b)
    ell = 0.5 * (b - a)
    ra = np.abs(fun.pc.native_rate(a) @ fun.hmat[:, fun.n_lin :])
    rb = np.abs(fun.pc.native_rate(b) @ fun.hmat[:, fun.n_lin :])
    return float(np.max(np.maximum(ra, rb) + (np.abs(p) + t) * ell, initial=0.0)) * ell


def _functions(fun: AffineEvents, sides: NDArray[np.bool_]) -> NDArray[np.bool_]:
    out = np.zeros(fun.n_functions, bool)
    out[fun.owner[sides]] = True
    return out


def _triggered(fun: Any, t: float, lift: FloatArray) -> NDArray[np.bool_]:
    vals, strict = fun(np.array([t]))
    vals = vals[0] + lift
    return np.where(strict, vals < 0.0, vals <= 0.0)


def _refine(fun: Any, a: float, b: float, cand: NDArray[np.bool_], lift: FloatArray
            ) -> tuple[float, NDArray[np.bool_]]:  # fmt: skip
    """The earliest trigger time in (a, b] among the candidate functions, and the functions
    that trigger there (a function that triggers at the earliest time found so far, within
    rounding, is refined too, until none triggers earlier). `lift`: each function's lift
    at the start of the piece (a function that starts at zero to rounding triggers only
    below its rounding)."""
    best, best_j = b, -1
    done = np.zeros(cand.shape[0], bool)
    fa_all = fun(np.array([a]))[0][0] + lift
    todo = cand.copy()
    while True:
        for j in (int(i) for i in np.flatnonzero(todo)):
            done[j] = True
            t = _root(fun, j, a, best, float(fa_all[j]), float(lift[j]))
            if t < best or best_j < 0:
                best, best_j = t, j
        mask = _triggered(fun, best, lift)
        todo = mask & ~done
        if not todo.any():
            break
    if best_j >= 0:
        mask[best_j] = True
    return best, mask


def _root(fun: Any, j: int, a: float, b: float, fa: float, lift: float) -> float:
    """The first time in (a, b] where function j (raised by `lift`) triggers (b if only
    there)."""
    lo, hi = a, b
    col = fun.column(j)

    def h(t: float) -> float:
        return col(t) + lift

    fb = h(hi)
    if not fb <= 0.0:  # triggered only at the strict side (-0.0 / 0.0): keep hi
        return hi
    if fa > 0.0 and fb < 0.0:
        # the root to ~1e-15 s: the event happens there (its function is zero to
        # rounding; the event is applied exactly: snapped threshold, zero velocity)
        t = brentq(h, lo, hi, xtol=XTOL, rtol=RTOL, maxiter=200)
        if t > a:
            return float(t)
    strict = bool(fun.strict[j])
    for _ in range(200):  # bisection on the trigger (a start at h = 0, a touch of zero)
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        val = h(mid)
        if (val < 0.0) if strict else (val <= 0.0):
            hi = mid
        else:
            lo = mid
    return hi
