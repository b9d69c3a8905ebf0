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

The density enters as the arrays ``kind``, ``par``, ``tab`` documented in
`_density_primitives`, which also holds the primitives M1, M2, T themselves.

Memory (the kernel's working copy of a `MemoryState`)
-----------------------------------------------------
``head`` float64[4] = [last input, direction (−1/0/+1), base input, n levels];
``stack`` float64[cap, 4], row k = [e_k, outer radius, M1(outer radius), P_k].
``base`` may be ±inf: saturated memory of an unbounded density.

Functions for other compiled code
---------------------------------
* ``force_at(y, head, stack, kind, par, tab) -> (force, slope)`` — the force the
  memory gives at a trial input y reached monotonically from head[0]; pure.
* ``advance(y, head, stack, kind, par, tab) -> (force, stack)`` — commits one
  sample: updates ``head`` and ``stack`` in place; the returned stack is a new,
  larger array only when the old one was full.
* ``run(y, head, stack, kind, par, tab, out, dissipated) -> stack`` — the time
  loop; ``dissipated`` is an empty array or receives the cumulative dissipated
  energy ∫ M1(ρ)|dy| of the stops.

All of ``run``, ``advance``, ``advance_dissipating`` and ``force_at`` are one
compiled loop, ``_walk``: the memory lives in local variables, the density
parameters are unpacked into scalars once (``_unpack``), and the per-sample
update calls nothing but the scalar primitive ``_prim`` (and ``_reversal_level``
at a reversal). Each call of a compiled function with array arguments costs
reference counting per array (about 10 ns each), so a time loop must not call
out per sample with the arrays; single calls (trials of an implicit step) pay
it once per call.
* ``elastic_energy(head, stack, kind, par, tab) -> float`` — ½∫ f² dμ.
* ``relaxed_memory(position, capacity)``, ``saturated_memory(position, direction,
  R, capacity)`` -> (head, stack).
"""

from __future__ import annotations

import math

import numpy as np

from presliding.hysteresis._density_primitives import _prim, _unpack, primitives
from presliding.hysteresis._jit import JitFlags, njit

_JIT: JitFlags = {"cache": True, "nogil": True}


# ---------------------------------------------------------------------- memory
@njit(**_JIT)
def _q(rho, m1r, m2r, kind, big_r, p1, p2, tab):  # pragma: no cover - compiled
    """Q(ρ) = ρ·M1(ρ) − M2(ρ) = ∫_0^ρ M1 (M1 constant beyond R); m1r, m2r = M1(R), M2(R)."""
    if rho >= big_r:
        return (rho - big_r) * m1r + big_r * m1r - m2r
    m1, m2, _ = _prim(kind, big_r, p1, p2, tab, rho, np.bool_(True))
    return rho * m1 - m2


@njit(**_JIT)
def _reversal_level(last, d, base, n, stack, kind, big_r, p1, p2, tab):  # pragma: no cover
    """The level a reversal at `last` (after motion in direction d) opens.

    Returns (base, n, outer radius, M1(outer), P): the base and level count
    change only when the reversal comes after a motion that saturated every
    stop (the older memory is then forgotten).
    """
    if n == 0:
        e, rho = base, abs(last - base)
    else:
        e, rho = stack[n - 1, 0], 0.5 * abs(last - stack[n - 1, 0])
    if rho >= big_r:
        # Every element slides in direction d: forget the older memory. The level
        # is then computed from the new base exactly as `replay` computes it from a
        # `MemoryState` (|last − base| may differ from R by rounding), so that a
        # chunked run equals the whole run bit for bit.
        base = last - d * big_r
        n = 0
        e, rho = base, abs(last - base)
        if rho >= big_r:
            return base, 0, big_r, _prim(kind, big_r, p1, p2, tab, big_r, np.bool_(False))[0], 0.0
    m1, _, t = _prim(kind, big_r, p1, p2, tab, rho, np.bool_(False))
    force = d * m1 if n == 0 else d * (2.0 * m1 - stack[n - 1, 2]) + stack[n - 1, 3]
    if rho > 0.0:  # 0·T(0) = 0, also where T(0) = inf
        force += (last - e) * t
    return base, n, rho, m1, force - d * m1


@njit(**_JIT)
def _grow(stack):  # pragma: no cover - compiled
    new = np.empty((2 * stack.shape[0] + 8, 4))
    # an element loop, not a slice assignment: the latter compiles numba's
    # shape-mismatch error message (string formatting), seconds on a cold cache
    for k in range(stack.shape[0]):
        for c in range(4):
            new[k, c] = stack[k, c]
    return new


# Modes of `_walk`. Callers pass them as np.int64(...), not as literal
# constants, so that `_walk` is compiled once for all of them (a literal
# argument would compile one specialisation per value).
_RUN, _ONE, _TRIAL = 0, 1, 2


@njit(**_JIT)
def _walk(y, y_one, head, stack, kind, par, tab, out, dissipated, mode):  # pragma: no cover
    """The one sample update, as a flat loop with the memory in local variables.

    mode _RUN: the samples y (out[t] = force; cumulative dissipation into
    `dissipated` when it is not empty); _ONE: the single sample y_one with its
    dissipation; _TRIAL: y_one without committing anything (head and stack
    are only read; y, out and dissipated are unused in both single modes).
    Committing modes update head and stack (grown when full). Returns (force,
    slope dF/dy, dissipated energy, stack) of the last sample.

    Per sample: the direction s of the increment; at a reversal the level it
    opens (kept in local variables, written to the stack only if it survives
    the sample); the levels the input wipes out (in pairs); the force of the
    level reached, in closed form from the primitives; optionally the stops'
    dissipation ∫ M1(ρ)|dy| = Q(ρ_end) − Q(ρ_start) per level, doubled on a
    level where |dy| = 2·dρ.
    """
    single = mode != _RUN
    commit = mode != _TRIAL
    with_diss = mode == _ONE or (mode == _RUN and dissipated.shape[0] > 0)
    big_r, p1, p2 = _unpack(par)
    last, d, base, n = head[0], head[1], head[2], int(head[3])
    m1r = m2r = 0.0
    if with_diss:
        m1r, m2r, _ = _prim(kind, big_r, p1, p2, tab, big_r, np.bool_(True))
    force = slope = acc = 0.0
    count = 1 if single else y.shape[0]
    for t in range(count):
        if commit and n >= stack.shape[0]:
            stack = _grow(stack)
        yv = y_one if single else y[t]
        if yv > last:
            s = 1.0
        elif yv < last:
            s = -1.0
        else:
            s = d
        top = n  # levels, the one a reversal opens included
        p_out = p_m1 = p_p = 0.0
        if s != d and d != 0.0:
            base, n, p_out, p_m1, p_p = _reversal_level(
                last, d, base, n, stack, kind, big_r, p1, p2, tab
            )
            top = n + 1
        rho0 = 0.0  # the front at `last` (0 right after a reversal)
        diss = 0.0
        if with_diss and top == n:
            rho0 = abs(last - base) if n == 0 else 0.5 * abs(last - stack[n - 1, 0])
        while top > 0:
            if top > n:
                e, outer = last, p_out
            else:
                e, outer = stack[top - 1, 0], stack[top - 1, 1]
            if 0.5 * abs(yv - e) < outer:
                break
            if with_diss:
                q_out = _q(outer, m1r, m2r, kind, big_r, p1, p2, tab)
                diss += 2.0 * (q_out - _q(rho0, m1r, m2r, kind, big_r, p1, p2, tab))
                rho0 = outer if top == 1 else stack[top - 2, 1]
            top = 0 if top == 1 else top - 2
        if top == 0:
            e = base
            rho = abs(yv - base)
            m1, _, slope = _prim(kind, big_r, p1, p2, tab, rho, np.bool_(False))
            force = s * m1
            if with_diss:
                if rho0 == math.inf:
                    diss += m1r * abs(yv - last)
                else:
                    diss += _q(rho, m1r, m2r, kind, big_r, p1, p2, tab) - _q(
                        rho0, m1r, m2r, kind, big_r, p1, p2, tab
                    )
        else:
            if top > n:
                e, m1o, p = last, p_m1, p_p
                if commit:
                    stack[n, 0] = last
                    stack[n, 1] = p_out
                    stack[n, 2] = p_m1
                    stack[n, 3] = p_p
            else:
                e, m1o, p = stack[top - 1, 0], stack[top - 1, 2], stack[top - 1, 3]
            rho = 0.5 * abs(yv - e)
            m1, _, slope = _prim(kind, big_r, p1, p2, tab, rho, np.bool_(False))
            force = s * (2.0 * m1 - m1o) + p
            if with_diss:
                q_rho = _q(rho, m1r, m2r, kind, big_r, p1, p2, tab)
                diss += 2.0 * (q_rho - _q(rho0, m1r, m2r, kind, big_r, p1, p2, tab))
        if rho < big_r:
            if rho > 0.0:  # (y − e)·T(ρ) = 0 at ρ = 0, also where T(0) = inf (microslip bar)
                force += (yv - e) * slope
        else:
            slope = 0.0
        n, d, last = top, s, yv
        acc += diss
        if not single:
            out[t] = force
            if with_diss:
                dissipated[t] = acc
    if commit:
        head[0] = last
        head[1] = d
        head[2] = base
        head[3] = n
    return force, slope, acc, stack


@njit(**_JIT)
def _push(head, stack, kind, par, tab):  # pragma: no cover - compiled
    """Reversal at the last input: push it as a new level; returns the (grown) stack."""
    if int(head[3]) >= stack.shape[0]:
        stack = _grow(stack)
    big_r, p1, p2 = _unpack(par)
    y = head[0]
    base, n, outer, m1o, p = _reversal_level(
        y, head[1], head[2], int(head[3]), stack, kind, big_r, p1, p2, tab
    )
    stack[n, 0] = y
    stack[n, 1] = outer
    stack[n, 2] = m1o
    stack[n, 3] = p
    head[2] = base
    head[3] = n + 1
    return stack


@njit(**_JIT)
def advance(y, head, stack, kind, par, tab):  # pragma: no cover - compiled
    """Commit the sample y; return (force, stack)."""
    force, _, _, stack = _walk(head, y, head, stack, kind, par, tab, head, head, np.int64(_ONE))
    return force, stack


@njit(**_JIT)
def advance_dissipating(y, head, stack, kind, par, tab):  # pragma: no cover - compiled
    """Commit the sample y; return (force, slope, dissipated energy, stack)."""
    return _walk(head, y, head, stack, kind, par, tab, head, head, np.int64(_ONE))


@njit(**_JIT)
def force_at(y, head, stack, kind, par, tab):  # pragma: no cover - compiled
    """(force, slope dF/dy) at a trial input y; head and stack are left untouched."""
    force, slope, _, _ = _walk(head, y, head, stack, kind, par, tab, head, head, np.int64(_TRIAL))
    return force, slope


@njit(**_JIT)
def run(y, head, stack, kind, par, tab, out, dissipated):  # pragma: no cover - compiled
    """Time loop: out[t] = F(y[t]); cumulative dissipation when len(dissipated) > 0."""
    return _walk(y, 0.0, head, stack, kind, par, tab, out, dissipated, np.int64(_RUN))[3]


# ---------------------------------------------------------------------- energy
@njit(**_JIT)
def _square_integral(alpha, beta, lo, hi, kind, par, tab):  # pragma: no cover
    """∫_(lo, hi] (α + β r)² dμ(r), zero where the interval lies beyond R."""
    big_r = par[0]
    if lo >= big_r or hi <= lo:
        return 0.0
    m1a, m2a, ta = primitives(kind, par, tab, lo)
    m1b, m2b, tb = primitives(kind, par, tab, hi)
    return alpha * alpha * (ta - tb) + 2.0 * alpha * beta * (m1b - m1a) + beta * beta * (m2b - m2a)


@njit(**_JIT)
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


@njit(**_JIT)
def relaxed_memory(position, capacity):  # pragma: no cover - compiled
    """Virgin memory at `position`: f = 0 for every threshold."""
    head = np.empty(4)
    head[0], head[1], head[2], head[3] = position, 0.0, position, 0.0
    return head, np.empty((max(capacity, 4), 4))


@njit(**_JIT)
def saturated_memory(position, direction, big_r, capacity):  # pragma: no cover
    """Every stop saturated after motion in `direction`: f = direction·r on [0, R]."""
    head = np.empty(4)
    head[0], head[1], head[3] = position, direction, 0.0
    head[2] = -direction * math.inf if big_r == math.inf else position - direction * big_r
    return head, np.empty((max(capacity, 4), 4))


@njit(**_JIT)
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
