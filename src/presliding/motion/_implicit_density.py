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

The trial force F_el(y + s·d) and its slope T(ρ) follow from the memory in
closed form. Along one Masing branch s·F_el is nondecreasing and concave in d
(the slope T(ρ) = μ((ρ, R]) falls as the front ρ advances), so φ is increasing
and concave: Newton's method from a point left of the root stays left of it
and increases monotonically to it. It starts at d0 = b/(m/h² + T(ρ_now)) <=
root and is safeguarded by the bracket [0, b·h²/m] (bisection where a step
would leave it), to full precision; d > 0 always, so v' has the sign of g. The
step is then committed, with the energy the sliding stops dissipate. Trials
and commit are fused into one compiled loop with the memory in local
variables (`presliding.motion._density_loop`); steps are uniform and samples
between grid points are read off the step that contains them.

Backward Euler on the velocity: first order in h, stable for any h. Per step
the energy balance misses the numerical dissipation ½·m·(v' − v)² + O(h²); the
energy never grows (the scheme dissipates at least the physical friction).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._validation import fmt
from presliding.hysteresis import _general_pi as gk
from presliding.hysteresis._density_primitives import EXPONENTIAL, PIECEWISE, TABULATED, UNIFORM
from presliding.hysteresis.general_pi import MemoryState
from presliding.hysteresis.operators import PIState
from presliding.motion._density_loop import run_fused
from presliding.motion._forcing import Forcing

FloatArray = NDArray[np.float64]


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


def density_bound(density: Any) -> float:
    """An upper bound of dμ/dr (inf for point masses), for the end of the Newton steps."""
    kind, par, tab = density._kind, density._par, density._tab
    if kind in (UNIFORM, EXPONENTIAL):
        return float(par[1])
    if kind == PIECEWISE:
        return float(np.max(tab[1, : tab.shape[1] - 1]))
    if kind == TABULATED:
        return 2.0 * float(np.max(np.abs(tab[1])))  # with room for the cubic interpolation
    return np.inf


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
    n_steps: int,
    sigma: float = 0.0,
) -> dict[str, Any]:
    """Run the fused density stepper: n_steps equal steps, samples read off the steps.

    ``last_dir`` is the trajectory's last direction (0: none; for counting
    reversals); ``sigma`` the viscous coefficient σ >= 0. Works for every
    `Density`, a `Discrete` one included (it then reproduces the finite-element
    stepper of `_implicit_loop` to rounding).
    """
    from presliding.motion._run import (
        REVERSAL_CAPACITY,
        applied_force_at,
        motion_overflow,
        start_implicit_samples,
    )

    u_kind, u_t, u_val, u_mid = forcing.loop_form(t0, t_end, n_steps)
    kind, par, tab = density._kind, density._par, density._tab
    head, stack = state.working_memory(density)
    e0 = 0.5 * m * v0 * v0 + float(gk.elastic_energy(head, stack, kind, par, tab))
    fel0 = float(gk.force_at(head[0], head, stack, kind, par, tab)[0])
    cap = REVERSAL_CAPACITY
    head0, stack0 = head, stack
    while True:  # again with room for every reversal if there were more (rare)
        head, stack = head0.copy(), stack0.copy()
        o = [np.empty(times.shape[0]) for _ in range(9)]
        rev = np.empty((2, cap))
        stack, n_rev, stop, v, d, _, _, _ = run_fused(
            m, c1, sigma, head, stack, kind, par, tab, density_bound(density), v0, last_dir, t0,
            t_end, n_steps,
            u_kind, u_t, u_val, u_mid, times, *o, *rev,
        )  # fmt: skip
        if n_rev <= cap:
            break
        cap = n_rev
    y_o, v_o, a_o, fric_o, fel_o, eel_o, dis_o, vis_o, work_o = o
    applied = applied_force_at(forcing, u_kind, u_t, u_val, times)
    start_implicit_samples(times, t0, a_o, fric_o, applied, m, c1, fel0, v0, sigma)
    y = float(head[0])
    if not (np.isfinite(y) and np.isfinite(v)):
        motion_overflow(t_end)
    h = (t_end - t0) / n_steps
    return {
        "n": times.shape[0], "time": times, "position": y_o, "velocity": v_o,
        "acceleration": a_o, "elastic": fel_o, "applied": applied, "friction": fric_o,
        "e_el": eel_o, "dissipated": dis_o, "viscous": vis_o, "work": work_o,
        "rev_t": rev[0, :n_rev].copy(), "rev_y": rev[1, :n_rev].copy(), "stop": stop, "y": y,
        "v": v, "dir": d, "count": n_steps, "status": 0, "e0": e0, "t_end": t_end,
        "final_state": MemoryState.from_working_memory(head, stack),
        "message": f"{n_steps} implicit steps of {h:.3g} (exact continuous operator)",
    }  # fmt: skip
