"""An independent, slow reference: parallel elastic-perfectly-plastic springs.

Written from the physics of the Maxwell-slip picture (paper, Section 2), not
from the library's update formula. Spring j (stiffness k_j, break-away force
c_j = k_j r_j, eq. 6) carries the elastic deformation f_j. Every displacement
increment Δy stretches all springs by Δy; a spring whose deformation would
exceed its threshold slips, so its deformation stays at ±r_j (eq. 3, eq. 5).
The friction force is c1·sign(ẏ) plus Σ k_j f_j (eq. 8).

Everything is done one increment and one spring at a time in plain Python
floats, so nothing here shares code with the compiled kernels.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np


@dataclass
class SpringRun:
    """Result of driving the spring bank along a path."""

    elastic: np.ndarray  # Σ k_j f_j at each sample, shape (T,)
    deformation: np.ndarray  # f_j at each sample, shape (T, N)
    direction: np.ndarray  # sign of the last nonzero increment at each sample, shape (T,)

    def play_positions(self, y: Sequence[float]) -> np.ndarray:
        """Positions x_j = y − f_j of the slider ends (the play outputs), shape (T, N)."""
        return np.asarray(y, dtype=float)[:, None] - self.deformation


def drive_springs(
    y: Sequence[float],
    stiffness: Sequence[float],
    threshold: Sequence[float],
    *,
    deformation: Sequence[float] | None = None,
    previous_input: float | None = None,
    direction: float = 0.0,
) -> SpringRun:
    """Drive a bank of elastic-perfectly-plastic springs along the samples ``y``.

    Parameters
    ----------
    y : sequence of float
        Displacement samples; the displacement moves monotonically between them.
    stiffness, threshold : sequences of float
        k_j and r_j of the springs.
    deformation : sequence of float, optional
        Deformations f_j before the first sample (default: all zero, the
        relaxed spring bank).
    previous_input : float, optional
        Displacement at which ``deformation`` holds (default ``y[0]``).
    direction : float
        Sign of the last motion before the first sample (0: none yet).
    """
    ys = [float(v) for v in y]
    ks = [float(v) for v in stiffness]
    rs = [float(v) for v in threshold]
    f = [0.0] * len(ks) if deformation is None else [float(v) for v in deformation]
    prev = ys[0] if previous_input is None else float(previous_input)
    d = float(direction)
    n_time, n_el = len(ys), len(ks)
    elastic = np.empty(n_time)
    deform = np.empty((n_time, n_el))
    dirs = np.empty(n_time)
    for t, yt in enumerate(ys):
        step = yt - prev
        if step > 0:
            d = 1.0
        elif step < 0:
            d = -1.0
        prev = yt
        total = 0.0
        for j in range(n_el):
            stretched = f[j] + step  # every spring follows the common displacement ...
            if stretched > rs[j]:  # ... until its force reaches +c_j: it slips
                stretched = rs[j]
            elif stretched < -rs[j]:  # ... or -c_j
                stretched = -rs[j]
            f[j] = stretched
            deform[t, j] = stretched
            total += ks[j] * stretched
        elastic[t] = total
        dirs[t] = d
    return SpringRun(elastic, deform, dirs)


def virgin_force(u: float, stiffness: Sequence[float], threshold: Sequence[float]) -> float:
    """Initial loading curve of the spring bank: Σ k_j·sign(u)·min(|u|, r_j)."""
    s = 1.0 if u > 0 else (-1.0 if u < 0 else 0.0)
    return s * sum(k * min(abs(u), r) for k, r in zip(stiffness, threshold, strict=True))


def damped_motion(
    mass: float,
    coulomb: float,
    viscous: float,
    stiffness: Sequence[float],
    threshold: Sequence[float],
    deformation: Sequence[float],
    velocity: float,
    force: float,
    t_eval: Sequence[float],
    rtol: float = 1e-13,
) -> tuple[np.ndarray, np.ndarray, float | None]:
    """m·ÿ + c1·Sign(ẏ) + σ·ẏ + Σ k_j f_j = u (u constant) by scipy's DOP853 with events.

    Written from the physics, not from the library's closed forms: between two
    events the mass moves in one direction s, the springs below their threshold
    stretch with the mass and the others slip at ±r_j; the integration stops at
    the velocity zero (then the mass sticks iff |u − Σ k_j f_j| <= c1) and where
    the next spring reaches its threshold. Returns positions and velocities at
    ``t_eval`` (starting at 0 at t = 0) and the stop time (None if moving).
    """
    from scipy.integrate import solve_ivp

    k = [float(v) for v in stiffness]
    r = [float(v) for v in threshold]
    f = [float(v) for v in deformation]
    t_eval = np.asarray(t_eval, dtype=float)
    pos = np.full(t_eval.shape, np.nan)
    vel = np.full(t_eval.shape, np.nan)
    t, y, v = 0.0, 0.0, float(velocity)
    t_end = float(t_eval[-1])
    while t < t_end:
        fel = sum(kj * fj for kj, fj in zip(k, f, strict=True))
        if v == 0.0:
            g = force - fel
            if abs(g) <= coulomb:  # sticks for good (u is constant)
                rest = t_eval >= t
                pos[rest], vel[rest] = y, 0.0
                return pos, vel, t
            s = 1.0 if g > 0 else -1.0
        else:
            s = 1.0 if v > 0 else -1.0
        elastic = [j for j in range(len(k)) if s * f[j] < r[j]]
        k_el = sum(k[j] for j in elastic)
        f_slip = sum(k[j] * f[j] for j in range(len(k)) if j not in elastic)
        f_el0 = sum(k[j] * f[j] for j in elastic)
        gaps = [s * r[j] - f[j] for j in elastic]
        gap = min(gaps, key=abs) if gaps else None

        def rhs(_, x, s=s, f_el0=f_el0, k_el=k_el, f_slip=f_slip):
            return [x[1], (force - coulomb * s - viscous * x[1] - f_slip - f_el0 - k_el * x[0])
                    / mass]  # fmt: skip

        def stop(_, x, s=s):
            return s * x[1]

        stop.terminal, stop.direction = True, -1
        events = [stop]
        if gap is not None:

            def reach(_, x, gap=gap, s=s):
                return s * (x[0] - gap)

            reach.terminal, reach.direction = True, 1
            events.append(reach)
        scale = max(abs(v), 1e-3)
        sol = solve_ivp(rhs, (t, t_end), [0.0, v], method="DOP853", rtol=rtol,
                        atol=[1e-16 * scale, 1e-16 * scale], events=events,
                        dense_output=True)  # fmt: skip
        t_next = float(sol.t[-1])
        inside = (t_eval >= t) & (t_eval <= t_next)
        if inside.any():
            d, w = sol.sol(t_eval[inside])
            pos[inside], vel[inside] = y + d, w
        d_end, v_end = (float(x) for x in sol.y[:, -1])
        hit_stop = sol.t_events[0].size > 0
        hit_gap = len(sol.t_events) > 1 and sol.t_events[1].size > 0
        if hit_gap and not hit_stop:
            d_end = gap
        y += d_end
        for j in elastic:
            f[j] += d_end
            if s * f[j] >= r[j] or (hit_gap and s * r[j] - (f[j] - d_end) == gap):
                f[j] = s * r[j]
        v = 0.0 if hit_stop else v_end
        t = t_next
    return pos, vel, None
