"""Exact half swings of a free mass with PI friction by the work-energy balance.

Between two turning points the mass moves monotonically in direction s and
    ½·m·v(u)² = K − W(u),   W(u) = ∫_0^u (c1 + s·F_el(y_a + s·w)) dw,
with u the distance travelled; F_el follows one Masing branch of the memory, so
s·F_el is nondecreasing in u and W is convex: the turning point is the unique
u > 0 with W(u) = K.

* Finite elements: s·F_el is piecewise linear in u (element j starts to slide
  after u_j = r_j − s·f_j), so W is piecewise quadratic and the root is the
  stable root of one quadratic — exact to rounding.
* A density: on a level of the memory (see `_general_pi`) with front ρ,
  |dy| = 2·dρ and s·F_el = 2·Φv(ρ) − M1(ρ_out) + s·P, with Φv(ρ) = M1(ρ) + ρ·T(ρ)
  the elastic virgin curve; hence W = 2(c1 − M1(ρ_out) + s·P)·Δρ + 4·ΔV with

      V(ρ) = ∫_0^ρ Φv = ρ·M1(ρ) − M2(ρ)/2 + ρ²·T(ρ)/2

  (on the virgin branch |dy| = dρ and W = c1·Δρ + ΔV). When the front reaches
  the level's outer radius the level is wiped out and the walk continues one
  level down; the root on the final level is found with `scipy.optimize.brentq`.

`ElementWalk` and `DensityWalk` carry the memory (element deformations, or the
turning-point memory of a density) from one half swing to the next.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from presliding.hysteresis import _general_pi as gk
from presliding.hysteresis._density_primitives import primitives
from presliding.hysteresis.densities import Density
from presliding.hysteresis.general_pi import MemoryState
from presliding.hysteresis.operators import PIState

FloatArray = NDArray[np.float64]
_EPS = np.finfo(np.float64).eps


def quadratic_step(q0: float, b: float, delta: float) -> float:
    """Smallest w >= 0 with q0·w + b·w²/2 = delta (delta >= 0, b >= 0), stably."""
    if b == 0.0:
        return delta / q0
    disc = math.sqrt(max(q0 * q0 + 2.0 * b * delta, 0.0))
    if q0 >= 0.0:
        return 2.0 * delta / (q0 + disc) if delta > 0 else 0.0
    return (disc - q0) / b


def element_swing(
    stiffness: FloatArray,
    threshold: FloatArray,
    coulomb: float,
    deform: FloatArray,
    s: float,
    kinetic: float,
) -> tuple[float, bool]:
    """Distance u > 0 to the next stop of a finite-element model, and whether any element slid.

    ``deform`` are the element deformations f_j at the start, ``s`` the direction
    of motion and ``kinetic`` the kinetic energy there (0 at a reversal).
    """
    g = s * deform
    ub = threshold - g  # distance after which element j slides
    order = np.argsort(ub, kind="stable")
    k, c, b = stiffness[order], (stiffness * threshold)[order], ub[order]
    n = k.shape[0]
    cum_k = np.concatenate([[0.0], np.cumsum(k)])
    cum_c = np.concatenate([[0.0], np.cumsum(c)])
    cum_kg = np.concatenate([[0.0], np.cumsum(k * g[order])])
    sticking_k = cum_k[-1] - cum_k  # B_i for the interval after i breakpoints
    # q at the start of interval i (u = b_(i−1), b_(−1) = 0) and at its end.
    starts = np.concatenate([[0.0], b])
    q_start = coulomb + cum_c + (cum_kg[-1] - cum_kg) + sticking_k * starts
    work = 0.0
    for i in range(n + 1):
        lo = starts[i]
        hi = b[i] if i < n else math.inf
        q_lo, slope = q_start[i], sticking_k[i]
        if hi > lo:
            if math.isfinite(hi):
                w_hi = work + 0.5 * (hi - lo) * (2.0 * q_lo + slope * (hi - lo))
            else:
                w_hi = math.inf
            if w_hi >= kinetic and hi > 0:
                u = lo + quadratic_step(q_lo, slope, kinetic - work)
                slid = bool(n and u > b[0] * (1 + 8 * _EPS))
                return u, slid
            work = w_hi
    raise RuntimeError("no turning point found")  # pragma: no cover - W grows without bound


def check_reach(model: Any, state: PIState | MemoryState, mass: float, velocity: float) -> None:
    """The free motion from `state` with speed `velocity` stays in the floating-point range.

    Its energy E = ½·m·v0² + ½∫ f² dμ must be finite, and so must the reach
    |y0| + 2·u_max, where u_max bounds every half swing: moving a distance u
    from any memory (|f(r)| <= r), a stop r slides after at most 2r and then
    dissipates r per unit length and stiffness, so for any ρ and u >= 2ρ the
    dissipation is at least (c1 + M1(ρ))·u − 2·M2(ρ), and it cannot exceed E:

        u_max = 2ρ + (E + 2·M2(ρ)) / (c1 + M1(ρ)),   ρ = R (or 4·F_m/μ([0, R]) if R = inf).
    """
    from presliding._validation import check_finite_derived

    dens = model.density
    if isinstance(state, PIState):
        f = state.deformation
        stored = 0.5 * float(np.sum(model.stiffness * f * f)) if f.shape[0] else 0.0
    else:
        head, stack = state.working_memory(dens)
        stored = float(gk.elastic_energy(head, stack, dens._kind, dens._par, dens._tab))
    energy = 0.5 * mass * velocity * velocity + stored  # Python floats: overflow gives inf
    check_finite_derived("energy ½·m·v0² + ½∫ f² dμ", energy, ("mass", "initial_velocity"))
    big_r = dens._big_r
    rho = big_r if math.isfinite(big_r) else 4.0 * dens.max_elastic_force / dens.total_stiffness
    rate = model.coulomb + (float(dens.M1(rho)) if rho > 0 else 0.0)
    if not rate > 0:  # pragma: no cover - every model has c1 > 0 or stops that slide
        return
    u_max = 2.0 * rho + (energy + 2.0 * (float(dens.M2(rho)) if rho > 0 else 0.0)) / rate
    reach = abs(state.last_input) + 2.0 * u_max
    check_finite_derived(
        "reach |y0| + 2·u_max of the free motion (u_max bounds each swing by its energy)",
        reach,
        ("initial_velocity", "initial_position"),
    )


class DensitySwing:
    """Half swings of a mass with a density model (the level walk of the module notes)."""

    def __init__(self, density: Density, coulomb: float) -> None:
        self.density = density
        self.c1 = coulomb
        self.big_r = density._big_r
        self.fm = density.max_elastic_force
        self.scale = self.fm / density.total_stiffness  # a natural threshold length
        self.m1r = self.fm
        self.m2r = float(density.M2(self.big_r)) if math.isfinite(self.big_r) else 0.0

    def prims(self, rho: float) -> tuple[float, float, float]:
        d = self.density
        return primitives(d._kind, d._par, d._tab, rho)

    def v(self, rho: float) -> float:
        """V(ρ) = ∫_0^ρ Φv, linear beyond R."""
        if rho >= self.big_r:
            return self.big_r * self.m1r - 0.5 * self.m2r + self.m1r * (rho - self.big_r)
        m1, m2, t = self.prims(rho)
        return rho * m1 - 0.5 * m2 + 0.5 * rho * rho * t

    def phi_v(self, rho: float) -> float:
        """Φv(ρ) = M1(ρ) + ρ·T(ρ), the elastic virgin curve (F_m beyond R)."""
        if rho >= self.big_r:
            return self.m1r
        m1, _, t = self.prims(rho)
        return m1 + rho * t

    def swing(
        self, head: FloatArray, stack: FloatArray, s: float, kinetic: float
    ) -> tuple[float, float]:
        """(position of the next stop, front radius there) moving in direction s.

        ``head``/``stack`` is the working memory with the motion already in
        direction s (a reversal pushed); nothing is modified.
        """
        t, base, c1 = int(head[3]), head[2], self.c1
        rho_a = abs(head[0] - base) if t == 0 else 0.5 * abs(head[0] - stack[t - 1, 0])
        while t > 0:
            e, outer, m1o, p = stack[t - 1]
            lin = 2.0 * (c1 - m1o + s * p)
            va = self.v(rho_a)

            def work(rho: float, lin: float = lin, va: float = va, ra: float = rho_a) -> float:
                return lin * (rho - ra) + 4.0 * (self.v(rho) - va)

            if math.isfinite(outer):
                w_out = work(outer)
                if w_out < kinetic:
                    kinetic -= w_out
                    rho_a = outer if t == 1 else stack[t - 2, 1]
                    t = 0 if t == 1 else t - 2
                    continue
            d0 = lin + 4.0 * self.phi_v(rho_a)
            rho = self._root(work, d0, lin + 4.0 * self.m1r, rho_a, outer, kinetic)
            return e + 2.0 * s * rho, rho
        if math.isinf(base):
            dist = kinetic / (c1 + self.fm)
            return head[0] + s * dist, math.inf
        va = self.v(rho_a)

        def work0(rho: float) -> float:
            return c1 * (rho - rho_a) + self.v(rho) - va

        d0 = c1 + self.phi_v(rho_a)
        rho = self._root(work0, d0, c1 + self.m1r, rho_a, math.inf, kinetic)
        return base + s * rho, rho

    def _root(self, work, d0, slope_beyond_r, rho_a, hi, kinetic) -> float:
        """Root ρ > ρa of work(ρ) = kinetic on [ρa, hi]; work is convex, work(ρa) = 0.

        ``d0`` is work'(ρa); with kinetic = 0 (at rest at a reversal, d0 < 0) the
        trivial root ρa is divided out.
        """
        if not math.isfinite(hi):
            r_end = max(rho_a, self.big_r)
            if math.isfinite(r_end):
                w_end = work(r_end)
                if w_end < kinetic or (kinetic == 0 and w_end <= 0 and r_end > rho_a):
                    # Beyond R every stop slides: the work is linear there.
                    return r_end + (kinetic - w_end) / slope_beyond_r
                hi = r_end
            else:
                hi = rho_a + self.scale
                while work(hi) < kinetic or (kinetic == 0 and work(hi) <= 0):
                    hi = rho_a + 2.0 * (hi - rho_a)
        xtol = 1e-15 * max(hi, self.scale)
        if kinetic > 0:
            if work(hi) == kinetic:
                return hi
            return brentq(lambda r: work(r) - kinetic, rho_a, hi, xtol=xtol, rtol=4 * _EPS)
        if d0 >= 0:  # pragma: no cover - no net force to move
            return rho_a
        if work(hi) == 0.0:
            return hi
        return brentq(
            lambda r: work(r) / (r - rho_a) if r > rho_a else d0,
            rho_a,
            hi,
            xtol=xtol,
            rtol=4 * _EPS,
        )


class ElementWalk:
    """Half swings of a finite-element model on its element deformations."""

    def __init__(self, model: Any, state: PIState) -> None:
        self.model = model
        self.position = state.last_input
        self.deform = state.deformation.copy()
        self.direction = state.direction
        self.min_threshold = model.density.min_threshold

    def force(self) -> float:
        return float(self.model.stiffness @ self.deform)

    def swing(self, s: float, kinetic: float) -> bool:
        m = self.model
        if m.n_elements == 0:
            u, slid = kinetic / m.coulomb, False
            self.position += s * u
            self.direction = s
            return slid
        u, slid = element_swing(m.stiffness, m.threshold, m.coulomb, self.deform, s, kinetic)
        self.deform = s * np.minimum(s * self.deform + u, m.threshold)
        self.position += s * u
        self.direction = s
        return slid

    def state(self) -> PIState:
        return PIState(self.position, self.position - self.deform, self.direction)


class DensityWalk:
    """Half swings of a density model on its turning-point memory."""

    def __init__(self, model: Any, state: MemoryState) -> None:
        self.model = model
        self.dens = model.density
        self.head, self.stack = state.working_memory(self.dens)
        self.swinger = DensitySwing(self.dens, model.coulomb)
        self.min_threshold = self.dens.min_threshold

    @property
    def position(self) -> float:
        return float(self.head[0])

    def force(self) -> float:
        d = self.dens
        f, _ = gk.force_at(self.head[0], self.head, self.stack, d._kind, d._par, d._tab)
        return float(f)

    def swing(self, s: float, kinetic: float) -> bool:
        d = self.dens
        if self.head[1] != 0.0 and self.head[1] != s:
            self.stack = gk._push(self.head, self.stack, d._kind, d._par, d._tab)
        self.head[1] = s
        y, rho = self.swinger.swing(self.head, self.stack, s, kinetic)
        _, self.stack = gk.advance(y, self.head, self.stack, d._kind, d._par, d._tab)
        self.head[1] = s
        return rho > self.min_threshold

    def state(self) -> MemoryState:
        return MemoryState.from_working_memory(self.head, self.stack)
