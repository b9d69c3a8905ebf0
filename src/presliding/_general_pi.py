"""Compiled kernels of the exact general Prandtl–Ishlinskii operator (eqs. 10, 11).

The elastic force of a continuum of stops with distribution μ on [0, R] is
F = ∫ f(y, r) dμ(r) with f = y − x(y, r) (eq. 11). For an input reached from a
relaxed (or saturated) start the deformation profile r ↦ f(r) is piecewise
linear, fixed by the stack of alternating dominant turning inputs e_1, ..., e_n
(wiping-out property). With motion direction d, the front ρ = |y − e_n|/2 (or
|y − base| on the virgin branch) separates the sliding elements (f = d·r for
r <= ρ) from the sticking ones, whose play outputs are frozen. Level k of the
stack covers the radii (ρ_k, ρ_{k−1}] where f = δ_k·r + (y − e_k), δ_k the
direction in which e_k was reached; beyond the outermost radius f = y − base.

The force of the top level in closed form, with M1(ρ) = ∫_0^ρ s dμ and
T(ρ) = μ((ρ, R]) (the stiffness still sticking), is::

    F(y) = d·(2·M1(ρ) − M1(ρ_out)) + (y − e)·T(ρ) + P          (top level)
    F(y) = d·M1(ρ) + (y − base)·T(ρ)                            (virgin branch)

where ρ_out is the level's outer radius and P = ∫_{ρ_out}^R f dμ at the
moment e was reached. Every sample costs O(1) primitive evaluations plus the
levels it wipes out. The slope dF/dy = T(ρ) (eq. 7: T(0) = μ([0, R]) right after
a reversal).

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

Memory (the kernel's working copy of a `MemoryState`)
-----------------------------------------------------
``head`` float64[4] = [last input, direction (−1/0/+1), base input, n levels];
``stack`` float64[cap, 4], row k = [e_k, outer radius, M1(outer radius), P_k].
``base`` may be ±inf: saturated memory of an unbounded density.

Functions for other compiled code
---------------------------------
* ``primitives(kind, par, tab, r) -> (M1, M2, T)``
* ``force_at(y, head, stack, kind, par, tab) -> (force, slope)`` — the force the
  memory gives at a trial input y reached monotonically from head[0]; pure.
* ``advance(y, head, stack, kind, par, tab) -> (force, stack)`` — commits one
  sample: updates ``head`` and ``stack`` in place; the returned stack is a new,
  larger array only when the old one was full.
* ``run(y, head, stack, kind, par, tab, out, dissipated) -> stack`` — the time
  loop; ``dissipated`` is an empty array or receives the cumulative dissipated
  energy ∫ M1(ρ)|dy| of the stops.
* ``elastic_energy(head, stack, kind, par, tab) -> float`` — ½∫ f² dμ.
* ``relaxed_memory(position, capacity)``, ``saturated_memory(position, direction,
  R, capacity)`` -> (head, stack).
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

DISCRETE, UNIFORM, EXPONENTIAL, PIECEWISE, TABULATED = 0, 1, 2, 3, 4
_JIT = {"cache": True, "nogil": True}


# ---------------------------------------------------------------------- primitives
@nb.njit(**_JIT)
def _gamma_lower(s, x):  # pragma: no cover - compiled
    """γ(s, x) = ∫_0^x t^(s−1) e^(−t) dt for s = 2, 3, accurate for small x."""
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
        return x**s * math.exp(-x) * acc
    e = math.exp(-x)
    if s == 2:
        return 1.0 - e * (1.0 + x)
    return 2.0 - e * (2.0 + x * (2.0 + x))


@nb.njit(**_JIT)
def _search(row, n, r):  # pragma: no cover - compiled
    """Number of entries of the sorted row[:n] that are <= r."""
    lo, hi = 0, n
    while lo < hi:
        mid = (lo + hi) >> 1
        if row[mid] <= r:
            lo = mid + 1
        else:
            hi = mid
    return lo


@nb.njit(**_JIT)
def primitives(kind, par, tab, r):  # pragma: no cover - compiled
    """(M1(r), M2(r), T(r)) = (∫_0^r s dμ, ∫_0^r s² dμ, μ((r, R]))."""
    big_r = par[0]
    if r < 0.0:
        r = 0.0
    if kind == DISCRETE:
        n = tab.shape[1] - 1
        i = _search(tab[0], n, r)
        return tab[1, i], tab[2, i], tab[3, i]
    if kind == PIECEWISE:
        m = tab.shape[1] - 1
        if r >= big_r:
            return tab[2, m], tab[3, m], 0.0
        i = _search(tab[0], m + 1, r) - 1
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
        a = par[1]
        return 0.5 * a * r * r, a * r * r * r / 3.0, a * (big_r - r)
    if kind == EXPONENTIAL:
        a, b = par[1], par[2]
        x = r / b
        tail = 0.0 if big_r == math.inf else math.exp(-big_r / b)
        return (
            a * b * b * _gamma_lower(2, x),
            a * b * b * b * _gamma_lower(3, x),
            a * b * (math.exp(-x) - tail) if x < big_r / b else 0.0,
        )
    # TABULATED: cubic Hermite with the exact derivatives r^k·dμ/dr at the nodes
    h = par[1]
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


@nb.njit(**_JIT)
def evaluate(kind, par, tab, r, which, out):  # pragma: no cover - compiled
    """Vectorised primitive: which = 1 (M1), 2 (M2) or 3 (T) at every r."""
    for i in range(r.shape[0]):
        m1, m2, t = primitives(kind, par, tab, r[i])
        out[i] = m1 if which == 1 else (m2 if which == 2 else t)


# ---------------------------------------------------------------------- memory
@nb.njit(**_JIT)
def _level_force(y, d, e, m1o, p, full, kind, par, tab):  # pragma: no cover
    """Force and slope on a level with turning input e (full: the virgin branch)."""
    big_r = par[0]
    rho = abs(y - e) if full else 0.5 * abs(y - e)
    m1, _, t = primitives(kind, par, tab, rho)
    force = d * m1 if full else d * (2.0 * m1 - m1o) + p
    if rho < big_r:
        force += (y - e) * t
    else:
        t = 0.0
    return force, t, rho


@nb.njit(**_JIT)
def _grow(stack):  # pragma: no cover - compiled
    new = np.empty((2 * stack.shape[0] + 8, 4))
    new[: stack.shape[0]] = stack
    return new


@nb.njit(**_JIT)
def _push(head, stack, kind, par, tab):  # pragma: no cover - compiled
    """Reversal at the last input: push it as a new level; returns the (grown) stack."""
    if int(head[3]) >= stack.shape[0]:
        stack = _grow(stack)
    _push_into(head, stack, kind, par, tab)
    return stack


@nb.njit(**_JIT)
def _push_into(head, stack, kind, par, tab):  # pragma: no cover - compiled
    """Reversal at the last input: push it as a new level (capacity for one more level)."""
    y, d, n = head[0], head[1], int(head[3])
    big_r = par[0]
    if n == 0:
        force, _, rho = _level_force(y, d, head[2], 0.0, 0.0, True, kind, par, tab)
    else:
        force, _, rho = _level_force(
            y, d, stack[n - 1, 0], stack[n - 1, 2], stack[n - 1, 3], False, kind, par, tab
        )
    if rho >= big_r:
        # Every element slides in direction d: forget the older memory.
        head[2] = y - d * big_r
        n = 0
        rho, m1o, p = big_r, primitives(kind, par, tab, big_r)[0], 0.0
    else:
        m1o = primitives(kind, par, tab, rho)[0]
        p = force - d * m1o
    stack[n, 0] = y
    stack[n, 1] = rho
    stack[n, 2] = m1o
    stack[n, 3] = p
    head[3] = n + 1


@nb.njit(**_JIT)
def _wipe_and_force(y, s, last, base, stack, n, kind, par, tab, diss):  # pragma: no cover
    """Pop the levels that input y wipes out; return (force, slope, n, dissipated).

    ``diss`` < 0 skips the dissipation integral ∫ M1(ρ)|dy| (from `last` to y).
    """
    rho0 = -1.0
    if diss >= 0.0:
        rho0 = abs(last - base) if n == 0 else 0.5 * abs(last - stack[n - 1, 0])
    while n > 0:
        rho = 0.5 * abs(y - stack[n - 1, 0])
        outer = stack[n - 1, 1]
        if rho < outer:
            break
        if diss >= 0.0:
            diss += 2.0 * _q_diff(rho0, outer, kind, par, tab)
            rho0 = outer if n == 1 else stack[n - 2, 1]
        n = 0 if n == 1 else n - 2
    if n == 0:
        force, slope, rho = _level_force(y, s, base, 0.0, 0.0, True, kind, par, tab)
        if diss >= 0.0:
            if rho0 == math.inf:
                diss += primitives(kind, par, tab, par[0])[0] * abs(y - last)
            else:
                diss += _q_diff(rho0, rho, kind, par, tab)
    else:
        e, m1o, p = stack[n - 1, 0], stack[n - 1, 2], stack[n - 1, 3]
        force, slope, rho = _level_force(y, s, e, m1o, p, False, kind, par, tab)
        if diss >= 0.0:
            diss += 2.0 * _q_diff(rho0, rho, kind, par, tab)
    return force, slope, n, diss


@nb.njit(**_JIT)
def _q_diff(rho_a, rho_b, kind, par, tab):  # pragma: no cover - compiled
    """∫_{ρa}^{ρb} M1(ρ) dρ with Q(ρ) = ρ·M1(ρ) − M2(ρ) (M1 constant beyond R)."""
    big_r = par[0]
    m1r, m2r, _ = primitives(kind, par, tab, big_r)
    qa = _q(rho_a, big_r, m1r, m2r, kind, par, tab)
    qb = _q(rho_b, big_r, m1r, m2r, kind, par, tab)
    return qb - qa


@nb.njit(**_JIT)
def _q(rho, big_r, m1r, m2r, kind, par, tab):  # pragma: no cover - compiled
    if rho >= big_r:
        return (rho - big_r) * m1r + big_r * m1r - m2r
    m1, m2, _ = primitives(kind, par, tab, rho)
    return rho * m1 - m2


@nb.njit(**_JIT)
def advance(y, head, stack, kind, par, tab):  # pragma: no cover - compiled
    """Commit the sample y; return (force, stack)."""
    if int(head[3]) >= stack.shape[0]:
        stack = _grow(stack)
    force, _, _ = _advance(y, head, stack, kind, par, tab, -1.0)
    return force, stack


@nb.njit(**_JIT)
def _advance(y, head, stack, kind, par, tab, diss):  # pragma: no cover - compiled
    """One sample; the stack must have room for one more level."""
    last, d = head[0], head[1]
    if y > last:
        s = 1.0
    elif y < last:
        s = -1.0
    else:
        s = d
    if s != d and d != 0.0:
        _push_into(head, stack, kind, par, tab)
    n = int(head[3])
    force, slope, n, diss = _wipe_and_force(y, s, last, head[2], stack, n, kind, par, tab, diss)
    head[0] = y
    head[1] = s
    head[3] = n
    return force, slope, diss


@nb.njit(**_JIT)
def force_at(y, head, stack, kind, par, tab):  # pragma: no cover - compiled
    """(force, slope dF/dy) at a trial input y; head and stack are left untouched."""
    last, d, n = head[0], head[1], int(head[3])
    if y > last:
        s = 1.0
    elif y < last:
        s = -1.0
    else:
        s = d
    if s == d or d == 0.0:
        force, slope, _, _ = _wipe_and_force(y, s, last, head[2], stack, n, kind, par, tab, -1.0)
        return force, slope
    # Reversal at `last`: the pushed level exists only in these local variables.
    big_r = par[0]
    base = head[2]
    if n == 0:
        f_last, _, rho = _level_force(last, d, base, 0.0, 0.0, True, kind, par, tab)
    else:
        f_last, _, rho = _level_force(
            last, d, stack[n - 1, 0], stack[n - 1, 2], stack[n - 1, 3], False, kind, par, tab
        )
    if rho >= big_r:
        base = last - d * big_r
        n = 0
        rho, m1o, p = big_r, primitives(kind, par, tab, big_r)[0], 0.0
    else:
        m1o = primitives(kind, par, tab, rho)[0]
        p = f_last - d * m1o
    if 0.5 * abs(y - last) < rho:
        force, slope, _ = _level_force(y, s, last, m1o, p, False, kind, par, tab)
        return force, slope
    # The new level and the one below it are wiped (or the virgin branch resumes).
    if n == 0:
        force, slope, _ = _level_force(y, s, base, 0.0, 0.0, True, kind, par, tab)
        return force, slope
    force, slope, _, _ = _wipe_and_force(y, s, last, base, stack, n - 1, kind, par, tab, -1.0)
    return force, slope


@nb.njit(**_JIT)
def run(y, head, stack, kind, par, tab, out, dissipated):  # pragma: no cover - compiled
    """Time loop: out[t] = F(y[t]); cumulative dissipation when len(dissipated) > 0."""
    with_diss = dissipated.shape[0] > 0
    acc = 0.0
    for t in range(y.shape[0]):
        if int(head[3]) >= stack.shape[0]:
            stack = _grow(stack)
        if with_diss:
            force, _, inc = _advance(y[t], head, stack, kind, par, tab, 0.0)
            acc += inc
            dissipated[t] = acc
        else:
            force, _, _ = _advance(y[t], head, stack, kind, par, tab, -1.0)
        out[t] = force
    return stack


# ---------------------------------------------------------------------- energy
@nb.njit(**_JIT)
def _square_integral(alpha, beta, lo, hi, kind, par, tab):  # pragma: no cover
    """∫_(lo, hi] (α + β r)² dμ(r), zero where the interval lies beyond R."""
    big_r = par[0]
    if lo >= big_r or hi <= lo:
        return 0.0
    m1a, m2a, ta = primitives(kind, par, tab, lo)
    m1b, m2b, tb = primitives(kind, par, tab, hi)
    return alpha * alpha * (ta - tb) + 2.0 * alpha * beta * (m1b - m1a) + beta * beta * (m2b - m2a)


@nb.njit(**_JIT)
def elastic_energy(head, stack, kind, par, tab):  # pragma: no cover - compiled
    """Stored elastic energy ½∫ f(r)² dμ(r) of the memory (eq. after 12)."""
    y, d, base, n = head[0], head[1], head[2], int(head[3])
    big_r = par[0]
    front = abs(y - base) if n == 0 else 0.5 * abs(y - stack[n - 1, 0])
    acc = primitives(kind, par, tab, min(front, big_r))[1]
    inner = front
    delta = -d
    for k in range(n - 1, -1, -1):
        outer = stack[k, 1]
        acc += _square_integral(y - stack[k, 0], delta, inner, outer, kind, par, tab)
        inner = outer
        delta = -delta
    if inner < big_r:
        acc += _square_integral(y - base, 0.0, inner, math.inf, kind, par, tab)
    return 0.5 * acc


@nb.njit(**_JIT)
def relaxed_memory(position, capacity):  # pragma: no cover - compiled
    """Virgin memory at `position`: f = 0 for every threshold."""
    head = np.empty(4)
    head[0], head[1], head[2], head[3] = position, 0.0, position, 0.0
    return head, np.empty((max(capacity, 4), 4))


@nb.njit(**_JIT)
def saturated_memory(position, direction, big_r, capacity):  # pragma: no cover
    """Every stop saturated after motion in `direction`: f = direction·r on [0, R]."""
    head = np.empty(4)
    head[0], head[1], head[3] = position, direction, 0.0
    head[2] = -direction * math.inf if big_r == math.inf else position - direction * big_r
    return head, np.empty((max(capacity, 4), 4))


@nb.njit(**_JIT)
def replay(last, direction, base, turning, kind, par, tab):  # pragma: no cover
    """Working memory of a profile given by its base and turning inputs.

    The base alone is a virgin branch (or, for base = ±inf, saturation); the
    turning inputs and then `last` are fed to it as samples.
    """
    head = np.empty(4)
    head[2], head[3] = base, 0.0
    if math.isinf(base):
        head[0] = turning[0] if turning.shape[0] > 0 else last
        head[1] = -math.copysign(1.0, base)
    else:
        head[0], head[1] = base, 0.0
    stack = np.empty((turning.shape[0] + 4, 4))
    for k in range(turning.shape[0]):
        _, stack = advance(turning[k], head, stack, kind, par, tab)
    _, stack = advance(last, head, stack, kind, par, tab)
    head[1] = direction
    return head, stack
