"""Compiled primitives of the densities μ of the general PI operator (eq. 10).

Every density is handed to compiled code as arrays, never as a Python object,
and is evaluated only through its primitives::

    M1(r) = ∫_0^r s dμ(s),   M2(r) = ∫_0^r s² dμ(s),   T(r) = μ((r, R])

(see `densities`). The memory kernels of `_general_pi` call the scalar
``_prim``; the `Density` methods call the vectorised ``evaluate``.

Density specification (arrays in, no Python objects)
----------------------------------------------------
``kind`` (int64), ``par`` (float64[:]) and ``tab`` (float64[:, :], C order), with
``par[0] = R`` (may be inf) for every kind:

* ``DISCRETE`` (0): ``tab`` rows: sorted thresholds (+ inf pad), prefix Σ k r,
  prefix Σ k r², suffix Σ k (length N + 1).
* ``UNIFORM`` (1): ``par = [R, a]``, dμ/dr = a on [0, R].
* ``EXPONENTIAL`` (2): ``par = [R, a, b]``, dμ/dr = a·exp(−r/b) on [0, R].
* ``PIECEWISE`` (3): ``tab`` rows: breaks (m + 1), heights (m, padded), M1, M2 and
  T at the breaks.
* ``TABULATED`` (4): ``par = [R, h]``; ``tab`` rows on the uniform grid r_i = i·h:
  r, dμ/dr, M1, M2, T; cubic Hermite interpolation between nodes.
* ``POWER`` (5): ``par = [R, a, χ]``, dμ/dr = a·r^χ on (0, R] (χ > −2), plus a
  point mass ``tab[0, 0]`` at R (the Iwan family: Segalman, the microslip bar).
* ``MINDLIN`` (6): ``par = [R, a]``, dμ/dr = a·(1 − r/R)^(−1/2) on [0, R)
  (the Cattaneo–Mindlin sphere), in the cancellation-free variable
  u = 1 − √(1 − r/R) = (r/R)/(1 + √(1 − r/R)).

Functions for other compiled code
---------------------------------
* ``primitives(kind, par, tab, r) -> (M1, M2, T)``
* ``evaluate(kind, par, tab, r, which, out)``: M1, M2 or T at every r of an array.
* ``discrete_lookup(tab, r, which)``: the same for ``DISCRETE`` in numpy (a table
  lookup, the same values: building a finite-element model compiles nothing).
* ``_unpack(par) -> (R, p1, p2)`` and ``_prim(kind, R, p1, p2, tab, r, want_m2)``:
  the scalar form used inside the time loops (parameters unpacked once).
"""

from __future__ import annotations

import math

import numpy as np

from presliding.hysteresis._jit import JitFlags, njit

DISCRETE, UNIFORM, EXPONENTIAL, PIECEWISE, TABULATED, POWER, MINDLIN = 0, 1, 2, 3, 4, 5, 6
# Flags and small integer arguments of compiled helpers are passed as
# np.bool_(...) / np.int64(...) rather than literal constants: numba compiles one
# specialisation per literal value, which costs seconds on a cold cache.
_JIT: JitFlags = {"cache": True, "nogil": True}


# ---------------------------------------------------------------------- primitives
@njit(**_JIT)
def _gamma_lower(s, x, e):  # pragma: no cover - compiled
    """γ(s, x) = ∫_0^x t^(s−1) e^(−t) dt for s = 2, 3, accurate for small x; e = exp(−x)."""
    if x > 700.0:
        return 1.0 if s == 2 else 2.0
    if x < 1.0:
        term = 1.0 / s
        acc = term
        for k in range(1, 40):
            term *= x / (s + k)
            acc += term
            if term < 1e-18 * acc:
                break
        return x**s * e * acc
    if s == 2:
        return 1.0 - e * (1.0 + x)
    return 2.0 - e * (2.0 + x * (2.0 + x))


@njit(**_JIT)
def _search(tab, row, n, r):  # pragma: no cover - compiled
    """Number of entries of the sorted tab[row, :n] that are <= r."""
    lo, hi = 0, n
    while lo < hi:
        mid = (lo + hi) >> 1
        if tab[row, mid] <= r:
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(**_JIT)
def _power(big_r, a, chi, mass, r):  # pragma: no cover - compiled
    """(M1, M2, T) of a·r^χ on (0, R] plus the point mass `mass` at R (r <= R)."""
    if r >= big_r:
        m1 = a * big_r ** (chi + 2.0) / (chi + 2.0) + mass * big_r
        return m1, a * big_r ** (chi + 3.0) / (chi + 3.0) + mass * big_r * big_r, 0.0
    if r <= 0.0:
        t = math.inf if chi <= -1.0 else a * big_r ** (chi + 1.0) / (chi + 1.0) + mass
        return 0.0, 0.0, t
    return (
        a * r ** (chi + 2.0) / (chi + 2.0),
        a * r ** (chi + 3.0) / (chi + 3.0),
        a * (big_r ** (chi + 1.0) - r ** (chi + 1.0)) / (chi + 1.0) + mass,
    )


@njit(**_JIT)
def _mindlin(big_r, a, r):  # pragma: no cover - compiled
    """(M1, M2, T) of a·(1 − r/R)^(−1/2) on [0, R) (r <= R), without cancellation."""
    x = r / big_r
    w = math.sqrt(max(1.0 - x, 0.0))
    u = x / (1.0 + w)  # 1 − √(1 − x)
    rr = big_r * big_r
    m1 = a * rr * u * u * (2.0 - 2.0 * u / 3.0)
    m2 = a * rr * big_r * u * u * u * (8.0 / 3.0 - 2.0 * u + 0.4 * u * u)
    return m1, m2, 2.0 * a * big_r * w


@njit(**_JIT)
def _unpack(par):  # pragma: no cover - compiled
    """(R, p1, p2): the density parameters as scalars (0.0 where a kind has none)."""
    p1 = par[1] if par.shape[0] > 1 else 0.0
    p2 = par[2] if par.shape[0] > 2 else 0.0
    return par[0], p1, p2


@njit(**_JIT)
def _prim(kind, big_r, p1, p2, tab, r, want_m2):  # pragma: no cover - compiled
    """(M1(r), M2(r), T(r)) from the scalar parameters of `_unpack` and the table.

    Without `want_m2` the exponential density leaves M2 out (returns 0.0 for it).
    """
    if r < 0.0:
        r = 0.0
    if kind == DISCRETE:
        i = _search(tab, 0, tab.shape[1] - 1, r)
        return tab[1, i], tab[2, i], tab[3, i]
    if kind == PIECEWISE:
        m = tab.shape[1] - 1
        if r >= big_r:
            return tab[2, m], tab[3, m], 0.0
        i = _search(tab, 0, m + 1, r) - 1
        if i < 0:
            return 0.0, 0.0, tab[4, 0]
        b0, hgt = tab[0, i], tab[1, i]
        dr = r - b0
        m1 = tab[2, i] + hgt * dr * (r + b0) * 0.5
        m2 = tab[3, i] + hgt * dr * (r * r + r * b0 + b0 * b0) / 3.0
        t = tab[4, i + 1] + hgt * (tab[0, i + 1] - r)
        return m1, m2, t
    if r > big_r:
        r = big_r
    if kind == UNIFORM:
        a = p1
        return 0.5 * a * r * r, a * r * r * r / 3.0, a * (big_r - r)
    if kind == EXPONENTIAL:
        a, b = p1, p2
        x = r / b
        e = math.exp(-x)
        tail = 0.0 if big_r == math.inf else math.exp(-big_r / b)
        return (
            a * b * b * _gamma_lower(np.int64(2), x, e),
            a * b * b * b * _gamma_lower(np.int64(3), x, e) if want_m2 else 0.0,
            a * b * (e - tail) if x < big_r / b else 0.0,
        )
    if kind == POWER:
        return _power(big_r, p1, p2, tab[0, 0], r)
    if kind == MINDLIN:
        return _mindlin(big_r, p1, r)
    # TABULATED: cubic Hermite with the exact derivatives r^k·dμ/dr at the nodes
    h = p1
    n = tab.shape[1] - 1
    i = min(int(r / h), n - 1)
    t = (r - tab[0, i]) / h
    t2 = t * t
    h00 = (2.0 * t - 3.0) * t2 + 1.0
    h10 = ((t - 2.0) * t + 1.0) * t * h
    h01 = (3.0 - 2.0 * t) * t2
    h11 = (t - 1.0) * t2 * h
    r0, r1 = tab[0, i], tab[0, i + 1]
    f0, f1 = tab[1, i], tab[1, i + 1]
    m1 = h00 * tab[2, i] + h10 * r0 * f0 + h01 * tab[2, i + 1] + h11 * r1 * f1
    m2 = h00 * tab[3, i] + h10 * r0 * r0 * f0 + h01 * tab[3, i + 1] + h11 * r1 * r1 * f1
    tt = h00 * tab[4, i] - h10 * f0 + h01 * tab[4, i + 1] - h11 * f1
    return m1, m2, tt


@njit(**_JIT)
def primitives(kind, par, tab, r):  # pragma: no cover - compiled
    """(M1(r), M2(r), T(r)) = (∫_0^r s dμ, ∫_0^r s² dμ, μ((r, R]))."""
    big_r, p1, p2 = _unpack(par)
    return _prim(kind, big_r, p1, p2, tab, r, np.bool_(True))


def discrete_lookup(tab: np.ndarray, r: np.ndarray, which: int) -> np.ndarray:
    """M1, M2 or T (which = 1, 2, 3) of a ``DISCRETE`` table at every r >= 0 (no NaN):
    `_prim`'s binary search (entries <= r) as numpy's, the same rows read."""
    n = tab.shape[1] - 1
    return tab[which, np.searchsorted(tab[0, :n], r, side="right")]


@njit(**_JIT)
def evaluate(kind, par, tab, r, which, out):  # pragma: no cover - compiled
    """Vectorised primitive: which = 1 (M1), 2 (M2) or 3 (T) at every r."""
    big_r, p1, p2 = _unpack(par)
    for i in range(r.shape[0]):
        m1, m2, t = _prim(kind, big_r, p1, p2, tab, r[i], np.bool_(True))
        out[i] = m1 if which == 1 else (m2 if which == 2 else t)
