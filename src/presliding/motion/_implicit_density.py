"""Implicit time stepping of eq. 17 for a friction model with a density μ (eq. 10).

The motion m·ÿ + c1·Sign(ẏ) + σ·ẏ + F_el(y) ∋ u(t) with the general PI operator
F_el(y) = ∫ (y − x(y, r)) dμ(r), evaluated exactly from its memory of turning
inputs (`_general_pi`). Each step of size h solves the monotone inclusion for
the new velocity v'

    m·(v' − v)/h + σ·v' + F_el(y + h·v') + c1·Sign(v') ∋ u

exactly, Sign(0) = [−1, 1] being the set-valued sign:

* v' = 0 iff |g| <= c1 with g = m·v/h + u − F_el(y): the mass sticks, its
  position and the memory are not touched (zero creep, bit for bit);
* otherwise v' = s·d/h with s = sign(g) and d > 0 the root of

      φ(d) = (m/h² + σ/h)·d + s·(F_el(y + s·d) − F_el(y)) − (|g| − c1) = 0

  (the viscous term σ·v' = σ·s·d/h enters linearly; σ·0 = 0 at rest).

The trial force F_el(y + s·d) and its slope T(ρ) come from `force_at` (pure:
the memory is not changed by a trial). Along one Masing branch s·F_el is
nondecreasing and concave in d (the slope T(ρ) = μ((ρ, R]) falls as the front ρ
advances), so φ is increasing and concave: Newton's method from a point left of
the root stays left of it and increases monotonically to it. It starts at
d0 = b/(m/h² + T(ρ_now)) <= root and is safeguarded by the bracket
[d0, b·h²/m] (bisection where a step would leave it), to full precision; d > 0
always, so v' has the sign of g. The step is then committed with
`advance_dissipating`, which also returns the energy the sliding stops dissipate.

Backward Euler on the velocity: first order in h, stable for any h. Per step
the energy balance misses the numerical dissipation ½·m·(v' − v)² + O(h²); the
energy never grows (the scheme dissipates at least the physical friction).
"""

from __future__ import annotations

from typing import Any

import numba as nb
import numpy as np
from numpy.typing import NDArray

from presliding._validation import fmt
from presliding.hysteresis import _general_pi as gk
from presliding.hysteresis._density_primitives import primitives
from presliding.hysteresis.general_pi import MemoryState
from presliding.hysteresis.operators import PIState
from presliding.motion._forcing import Forcing

FloatArray = NDArray[np.float64]
_JIT = {"cache": True, "nogil": True}
_EPS = 2.220446049250313e-16
_MAX_ITER = 200


@nb.njit(**_JIT)
def solve_step(b, s, mh2, slope0, fel, head, stack, kind, par, tab):  # pragma: no cover
    """Root d > 0 of mh2·d + s·(F_el(y + s·d) − F_el(y)) = b > 0 (y = head[0]).

    ``mh2`` = m/h² + σ/h, the inertia and the viscous term of the step.

    ``slope0`` is dF/dy on the branch leaving y in direction s (T(0) = μ([0, R])
    after a reversal); ``fel`` = F_el(y).
    """
    y = head[0]
    lo = 0.0
    hi = b / mh2
    d = b / (mh2 + slope0)
    for _ in range(_MAX_ITER):
        f, sl = gk.force_at(y + s * d, head, stack, kind, par, tab)
        phi = mh2 * d + s * (f - fel) - b
        if phi < 0.0:
            lo = d
        elif phi > 0.0:
            hi = d
        else:
            break
        dn = d - phi / (mh2 + sl)
        if not (dn > lo and dn < hi):  # also catches a NaN
            dn = 0.5 * (lo + hi)
        if dn == d or hi - lo <= 2.0 * _EPS * hi:
            break
        d = dn
    return d


@nb.njit(**_JIT)
def _grow_rev(rev):  # pragma: no cover - compiled
    new = np.empty((2 * rev.shape[0], 2))
    new[: rev.shape[0]] = rev
    return new


@nb.njit(**_JIT)
def run_density(  # pragma: no cover - compiled
    m, c1, sigma, head, stack, kind, par, tab, v, last_dir, t_grid, u_mid, out_idx,
    o_y, o_v, o_a, o_fric, o_fel, o_eel, o_dis, o_vis, o_work,
):  # fmt: skip
    """Step from t_grid[0] to t_grid[-1] with u = u_mid[i] on step i.

    The position is the memory's last input head[0]; head and stack are the
    working memory (updated in place; the final stack is returned, it may have
    grown). Sample q is the state after grid point out_idx[q] (0: the initial
    state; its o_a/o_fric entries are left to the caller). Returns (stack,
    reversals (n, 2) as rows (time, position), rest_start (nan if moving at the
    end), v, last_dir, dissipated, work, viscous dissipation).
    """
    n_steps = t_grid.shape[0] - 1
    n_out = out_idx.shape[0]
    t_total = primitives(kind, par, tab, 0.0)[2]  # μ([0, R]): slope after a reversal
    fel, slope = gk.force_at(head[0], head, stack, kind, par, tab)
    dis = 0.0
    vis = 0.0
    work = 0.0
    rev = np.empty((64, 2))
    n_rev = 0
    rest_start = np.nan
    q = _record(0, head, stack, kind, par, tab, fel, v, out_idx, 0, dis, vis, work,
                o_y, o_v, o_fel, o_eel, o_dis, o_vis, o_work)  # fmt: skip
    h_prev = -1.0
    inv_h = m_h = mh2 = 0.0
    for i in range(n_steps):
        h = t_grid[i + 1] - t_grid[i]
        if h != h_prev:
            h_prev = h
            inv_h = 1.0 / h
            m_h = m * inv_h
            mh2 = m_h * inv_h + sigma * inv_h  # m/h² + σ/h
        u = u_mid[i]
        g = m_h * v + u - fel
        if abs(g) <= c1:  # sticks: the position and the memory stay exactly as they are
            v_new = 0.0
            if rest_start != rest_start:
                rest_start = t_grid[i]
        else:
            s = 1.0 if g > 0.0 else -1.0
            slope0 = slope if s == head[1] else t_total
            y_old = head[0]
            d = solve_step(abs(g) - c1, s, mh2, slope0, fel, head, stack, kind, par, tab)
            fel, slope, dplastic, stack = gk.advance_dissipating(
                y_old + s * d, head, stack, kind, par, tab
            )
            v_new = d * s * inv_h
            dis += c1 * d + dplastic
            vis += sigma * d * d * inv_h
            work += u * s * d
            if s != last_dir:
                if last_dir != 0.0:
                    if n_rev == rev.shape[0]:
                        rev = _grow_rev(rev)
                    rev[n_rev, 0] = t_grid[i]
                    rev[n_rev, 1] = y_old
                    n_rev += 1
                last_dir = s
            rest_start = np.nan
        if q < n_out and out_idx[q] == i + 1:
            acc = (v_new - v) * inv_h
            q0 = q
            q = _record(i + 1, head, stack, kind, par, tab, fel, v_new, out_idx, q, dis, vis,
                        work, o_y, o_v, o_fel, o_eel, o_dis, o_vis, o_work)  # fmt: skip
            for p in range(q0, q):
                o_a[p] = acc
                o_fric[p] = u - m * acc
        v = v_new
    return stack, rev[:n_rev].copy(), rest_start, v, last_dir, dis, work, vis


@nb.njit(**_JIT)
def _record(i, head, stack, kind, par, tab, fel, v, out_idx, q, dis, vis, work,
            o_y, o_v, o_fel, o_eel, o_dis, o_vis, o_work):  # fmt: skip  # pragma: no cover
    """Write the samples that fall on grid point i; returns the next sample index."""
    if q >= out_idx.shape[0] or out_idx[q] != i:
        return q
    eel = gk.elastic_energy(head, stack, kind, par, tab)
    while q < out_idx.shape[0] and out_idx[q] == i:
        o_y[q] = head[0]
        o_v[q] = v
        o_fel[q] = fel
        o_eel[q] = eel
        o_dis[q] = dis
        o_vis[q] = vis
        o_work[q] = work
        q += 1
    return q


# ---------------------------------------------------------------------- set-up and runner
def initial_memory(
    model: Any, initial_state: Any, y0: float, v0: float, u0: float
) -> tuple[MemoryState, float]:
    """The memory at the start of a density model, and the last motion direction."""
    vdir = float(np.sign(v0))
    if isinstance(initial_state, MemoryState):
        if initial_state.last_input != y0:
            raise ValueError(
                "`initial_state.last_input` must equal `initial_position`; got "
                f"{fmt(initial_state.last_input)} and {fmt(y0)}."
            )
        return initial_state, vdir if vdir != 0 else initial_state.direction
    if isinstance(initial_state, PIState):
        raise TypeError(
            "`initial_state` of a model with a continuous density must be 'relaxed', "
            "'saturated' or a MemoryState; got a PIState."
        )
    if isinstance(initial_state, str) and initial_state == "relaxed":
        return model.relaxed_state(y0), vdir
    if isinstance(initial_state, str) and initial_state == "saturated":
        from presliding.motion._run import saturation_direction

        s = saturation_direction(vdir, u0)
        return model.saturated_state(y0, s), s
    if not isinstance(initial_state, str):
        raise TypeError(
            "`initial_state` must be 'relaxed', 'saturated' or a MemoryState; got "
            f"{type(initial_state).__name__}."
        )
    raise ValueError(
        "`initial_state` must be 'relaxed', 'saturated' or a MemoryState; got "
        f"{fmt(initial_state)}."
    )


def run(
    density: Any,
    c1: float,
    m: float,
    state: MemoryState,
    v0: float,
    last_dir: float,
    forcing: Forcing,
    times: FloatArray,
    t0: float,
    t_end: float,
    h: float,
    sigma: float = 0.0,
) -> dict[str, Any]:
    """Run the density stepper on a grid through the sample times; a dict of outputs.

    ``sigma`` is the viscous coefficient σ >= 0 (default 0, eq. 17 as written).

    Works for every `Density`, a `Discrete` one included (it then reproduces the
    finite-element stepper of `_implicit` to rounding).
    """
    from presliding.motion._run import implicit_grid, initial_acceleration

    grid, out_idx = implicit_grid(t0, t_end, times, h)
    u_mid = forcing(0.5 * (grid[1:] + grid[:-1]))
    kind, par, tab = density._kind, density._par, density._tab
    head, stack = state.working_memory(density)
    e0 = 0.5 * m * v0 * v0 + float(gk.elastic_energy(head, stack, kind, par, tab))
    fel0 = float(gk.force_at(head[0], head, stack, kind, par, tab)[0])
    o = [np.zeros(times.shape[0]) for _ in range(9)]
    stack, rev, stop, v, d, _, _, _ = run_density(
        m, c1, sigma, head, stack, kind, par, tab, v0, last_dir, grid, u_mid, out_idx, *o
    )
    y_o, v_o, a_o, fric_o, fel_o, eel_o, dis_o, vis_o, work_o = o
    applied = forcing(times)
    at_start = out_idx == 0
    if at_start.any():
        a_o[at_start] = initial_acceleration(m, c1, fel0, v0, float(applied[0]), sigma)
        fric_o[at_start] = applied[0] - m * a_o[at_start]
    y = float(head[0])
    return {
        "n": times.shape[0], "position": y_o, "velocity": v_o, "acceleration": a_o,
        "elastic": fel_o, "applied": applied, "friction": fric_o, "e_el": eel_o,
        "dissipated": dis_o, "viscous": vis_o, "work": work_o, "rev_t": rev[:, 0].copy(),
        "rev_y": rev[:, 1].copy(), "stop": stop, "y": y, "v": v, "dir": d,
        "count": grid.shape[0] - 1, "status": 0, "e0": e0,
        "final_state": MemoryState.from_working_memory(head, stack),
        "message": f"{grid.shape[0] - 1} implicit steps of at most {h:.3g} "
        f"(exact continuous operator)",
    }  # fmt: skip
