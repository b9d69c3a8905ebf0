"""Periodic orbits by shooting on the exact event solver, and their continuation.

The unknowns are the state Z₀ = (q, q̇, x) at t = 0 (the forcing's phase); the residual
is Z(T) − Z₀ over one period T = 2π/Ω, and its Jacobian Φ − I is exact (the monodromy
matrix Φ from the pieces' closed-form transitions and the events' saltations,
`_joint_run`). A stop that does not slide along the orbit keeps its plastic part x_j
(a family of orbits shifted by it): its x_j is held and left out of the unknowns.

Continuation in a parameter p (the frequency Ω or the force's scale): pseudo-arclength,
the tangent the null vector of [Φ − I, ∂R/∂p] (∂R/∂p exact too: the particular
solution's derivative carried through the pieces and saltations, plus the period's),
steps in variables scaled by the orbit's size and the parameter's range, adapted to the
corrector's iterations.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from presliding.structural._joint_run import Run, run, start_modes
from presliding.structural._pieces import Model, Piece

FloatArray = NDArray[np.float64]


@dataclass
class Point:
    """A periodic orbit: its parameter, start state, residual, multipliers and run."""

    parameter: float
    omega: float
    z: FloatArray
    residual: float
    multipliers: NDArray[np.complex128]
    iterations: int
    run: Run


class Shooter:
    """Periodic orbits of one structure as a function of a parameter p.

    `model(p)` gives the model (forcing) at p; `frequency` is True when p is the forcing
    frequency Ω (else p scales the force, Ω fixed).
    """

    def __init__(self, model: Callable[[float], Model], frequency: bool) -> None:
        self.model, self.frequency = model, frequency

    def omega(self, p: float) -> float:
        return self.model(p).omega

    def flow(self, z: FloatArray, p: float, transition: bool = False) -> tuple[FloatArray, Run]:
        md = self.model(p)
        n = md.n
        period = 2.0 * math.pi / md.omega
        d_force = None if self.frequency else md.force / p
        r = run(md, 0.0, z[:n], z[n : 2 * n], z[2 * n :], period, transition=transition,
                d_force=d_force, d_omega=1.0 if self.frequency else 0.0)  # fmt: skip
        if r.status != "success":
            raise RuntimeError("the event limit was reached within one period")
        return np.r_[r.q, r.v, r.x], r

    def parameter_derivative(self, p: float, r: Run) -> FloatArray:
        """∂R/∂p of the last run: at fixed time, plus Ż(T)·dT/dp when p is Ω."""
        assert r.derivative is not None
        if not self.frequency:
            return r.derivative
        md = self.model(p)
        pc = Piece(md, r.t, r.q, r.v, r.x, r.sliding)
        _, v, a = pc.state(np.array([0.0]))
        xdot = np.where(r.sliding != 0, (md.w.T @ r.v)[md.owner], 0.0)
        zdot = np.r_[v[0], a[0], xdot]
        return r.derivative + zdot * (-2.0 * math.pi / md.omega**2)

    def consistent(self, z: FloatArray, p: float) -> FloatArray:
        """Z with the stops' plastic parts within their thresholds."""
        md = self.model(p)
        n = md.n
        x, _, _ = start_modes(md, z[:n], z[n : 2 * n], z[2 * n :])
        return np.r_[z[: 2 * n], x]

    def scale(self, z: FloatArray, p: float) -> float:
        n = self.model(p).n
        om = self.omega(p)
        return max(float(np.max(np.abs(z[:n]))), float(np.max(np.abs(z[n : 2 * n]))) / om,
                   float(np.max(np.abs(z[2 * n :]), initial=0.0)), 1e-300)  # fmt: skip

    def residual(self, z: FloatArray, p: float, transition: bool = False) -> tuple[
        FloatArray, Run, NDArray[np.bool_]
    ]:  # fmt: skip
        """(Z(T) − Z₀, the run, the free unknowns)."""
        z = self.consistent(z, p)
        zt, r = self.flow(z, p, transition)
        n = self.model(p).n
        assert r.slid is not None
        free = np.r_[np.ones(2 * n, dtype=bool), r.slid]
        return zt - z, r, free

    def newton(self, z: FloatArray, p: float, tol: float, max_iter: int = 30) -> Point | None:
        """A periodic orbit at fixed p from the guess z (None: no convergence)."""
        z = self.consistent(z, p)
        last = np.inf
        for it in range(max_iter):
            res, r, free = self.residual(z, p, transition=True)
            err = float(np.max(np.abs(res))) / self.scale(z, p)
            if err <= tol:
                return self._point(z, p, res, r, free, it)
            if err > 4.0 * last:  # diverging: the guess is too far
                return None
            last = err
            assert r.transition is not None
            jac = r.transition[np.ix_(free, free)] - np.eye(int(free.sum()))
            step = np.linalg.lstsq(jac, -res[free], rcond=None)[0]
            z = z.copy()
            z[free] += step
            z = self.consistent(z, p)
        return None

    def _point(self, z: FloatArray, p: float, res: FloatArray, r: Run, free: NDArray[np.bool_],
               iterations: int) -> Point:  # fmt: skip
        assert r.transition is not None
        mult = np.linalg.eigvals(r.transition[np.ix_(free, free)]).astype(np.complex128)
        mult = mult[np.argsort(-np.abs(mult))]
        return Point(p, self.omega(p), z, float(np.max(np.abs(res))), mult, iterations, r)

    def relax(self, z: FloatArray, p: float, periods: int) -> FloatArray:
        """Z after `periods` periods of free running (a guess near a stable orbit)."""
        z = self.consistent(z, p)
        for _ in range(periods):
            z, _ = self.flow(z, p)
        return z


def _tangent(jac: FloatArray, prev: FloatArray | None) -> FloatArray:
    """The unit null vector of the bordered Jacobian [Φ − I, ∂R/∂p], oriented along prev.

    Where a stop starts to slide elsewhere in the period the curve of orbits has a corner,
    which can turn the tangent by more than 90° while the parameter keeps its direction
    (a V in the steep variables); when the tangent turns by more than 25°, the parameter's
    direction (not the dot product) orients it, unless the parameter barely moves (a
    fold, passed smoothly)."""
    _, _, vt = np.linalg.svd(jac)
    t = vt[-1] / np.linalg.norm(vt[-1])
    if prev is None:
        return t
    prev = prev / np.linalg.norm(prev)
    dot = float(t @ prev)
    if abs(dot) < 0.9 and abs(t[-1]) > 1e-3 and abs(prev[-1]) > 1e-3:
        return t if t[-1] * prev[-1] > 0 else -t
    return t if dot >= 0 else -t


def continuation(
    shooter: Shooter, start: Point, end: float, *, step: float, max_points: int, tol: float,
    max_step: float, min_step: float,
) -> tuple[list[Point], str]:  # fmt: skip
    """Points from `start` until the parameter passes `end` (status 'success'), or the
    point limit ('point_limit'), or the step falls below `min_step` ('step_too_small')."""
    points = [start]
    p_range = abs(end - start.parameter)
    direction = 1.0 if end > start.parameter else -1.0
    prev_t: FloatArray | None = None
    ds = step
    while len(points) < max_points:
        cur = points[-1]
        zs = max(shooter.scale(cur.z, cur.parameter), 1e-300)
        n = shooter.model(cur.parameter).n
        w = np.full(cur.z.shape[0] + 1, 1.0 / zs)  # scaled variables: q, x by the orbit's
        w[n : 2 * n] /= cur.omega  # size, q̇ by its size times Ω, p by its range
        w[-1] = 1.0 / p_range
        jac, free = _bordered(shooter, cur, w)
        t = _tangent(jac, None if prev_t is None else prev_t[np.r_[free, True]])
        if prev_t is None and t[-1] * direction < 0:
            t = -t  # the first step towards `end`
        full_t = np.zeros(cur.z.shape[0] + 1)
        full_t[np.r_[free, True]] = t
        tries = 0
        while True:
            new = _correct(shooter, cur, full_t, ds, w, tol)
            if new is None and tries >= 2 and abs(full_t[-1]) > 1e-3:
                new = _natural(shooter, cur, full_t, ds, w, tol)  # across a kink of the flow
            if new is not None:
                break
            ds *= 0.5
            tries += 1
            if ds < min_step:
                return points, "step_too_small"
        points.append(new[0])
        prev_t = full_t
        ds = min(ds * (1.5 if new[1] <= 3 else 1.0 if new[1] <= 5 else 0.7), max_step)
        if (new[0].parameter - end) * direction >= 0:
            return points, "success"
    return points, "point_limit"


def _natural(shooter: Shooter, cur: Point, t: FloatArray, ds: float, w: FloatArray,
             tol: float) -> tuple[Point, int] | None:  # fmt: skip
    """A step at the predicted parameter held fixed (Newton on the state alone): where a
    stop starts or stops sliding elsewhere in the period the flow has a kink, which the
    bordered corrector can cross back and forth; away from a fold the parameter is a
    good coordinate there."""
    y = np.r_[cur.z, cur.parameter] + ds * t / w
    try:
        pt = shooter.newton(y[:-1], float(y[-1]), tol, max_iter=12)
    except (RuntimeError, ValueError, np.linalg.LinAlgError):
        return None
    return None if pt is None else (pt, pt.iterations)


def _bordered(shooter: Shooter, cur: Point, w: FloatArray) -> tuple[FloatArray, NDArray[np.bool_]]:
    """[Φ − I, ∂R/∂p] in the scaled variables, the free unknowns' columns."""
    res, r, free = shooter.residual(cur.z, cur.parameter, transition=True)
    assert r.transition is not None
    dp = shooter.parameter_derivative(cur.parameter, r)
    jac = np.c_[r.transition - np.eye(res.shape[0]), dp][np.ix_(free, np.r_[free, True])]
    # scaled variables y = w·Y: the columns divided by w, the rows (residuals of Z) by w_z
    jac = jac / w[np.r_[free, True]][None, :] * w[: res.shape[0]][free][:, None]
    return jac, free


def _correct(shooter: Shooter, cur: Point, t: FloatArray, ds: float, w: FloatArray,
             tol: float) -> tuple[Point, int] | None:  # fmt: skip
    """Pseudo-arclength corrector from the predictor Y + ds·t (scaled): Newton on
    [R(Y); tᵀ·(w·(Y − Y_pred))] = 0, each step halved until the residual falls (a kink of
    the flow where a stop starts to slide elsewhere in the period would make a full step
    jump across it and back); None when it does not converge in 10 iterations."""
    n_z = cur.z.shape[0]
    y = np.r_[cur.z, cur.parameter] + ds * t / w
    y_pred = y.copy()
    y[:n_z] = shooter.consistent(y[:n_z], float(y[-1]))
    try:
        res, r, fr = shooter.residual(y[:n_z], float(y[-1]), transition=True)
    except (RuntimeError, ValueError, np.linalg.LinAlgError):
        return None
    err = float(np.max(np.abs(res))) / shooter.scale(y[:n_z], float(y[-1]))
    for it in range(1, 11):
        p = float(y[-1])
        cols = np.r_[fr, True]  # the stops sliding along this orbit (the set may change)
        assert r.transition is not None
        dp = shooter.parameter_derivative(p, r)
        jac = np.c_[r.transition - np.eye(n_z), dp][np.ix_(fr, cols)]
        big = np.vstack([jac, (t * w)[cols]])
        rhs = np.r_[-res[fr], -(t * w) @ (y - y_pred)]
        try:
            delta = np.linalg.solve(big, rhs)
        except np.linalg.LinAlgError:
            return None
        for alpha in (1.0, 0.5, 0.25, 0.125, 0.0625):
            trial = y.copy()
            trial[cols] += alpha * delta
            trial[:n_z] = shooter.consistent(trial[:n_z], float(trial[-1]))
            try:
                res_t, r_t, fr_t = shooter.residual(trial[:n_z], float(trial[-1]), True)
            except (RuntimeError, ValueError, np.linalg.LinAlgError):
                continue
            err_t = float(np.max(np.abs(res_t))) / shooter.scale(trial[:n_z], float(trial[-1]))
            if err_t < err or err_t <= tol:
                break
        else:
            return None
        y, res, r, fr, err = trial, res_t, r_t, fr_t, err_t
        if err <= tol:
            return shooter._point(y[:n_z], float(y[-1]), res, r, fr, it), it
    return None
