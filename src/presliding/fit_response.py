"""Output-error fit: simulated against measured motion (the paper's experiments, section 4).

The paper identifies m, F_c, c1 and k_2..k_5 of eq. 17 with four elements of
equal break-away force c_j = (F_c − c1)/4 by fitting the simulated velocity
response to the measured one near a full stop. `fit_response` does this with
the exact event-driven simulator (`presliding.motion`), so the fitted response
has no numerical micro-oscillations and sticks exactly.

Scale. With u = 0 throughout, eq. 17 is homogeneous: multiplying the mass and
every force by the same factor leaves the motion unchanged, so only the ratios
F/m are identifiable. This is detected; unless the mass or the Coulomb level is
given, the parameters are reported per unit mass (mass = 1, forces in N/kg,
stiffnesses in N/(m·kg)).

Start. Unless `initial` is given, the start comes from the inverse model: eq. 17
as a linear regression (`presliding.fit_motion`'s machinery) on the measured
velocity, its difference quotient and its integral, with the thresholds on a
grid, merged into the wanted number of elements.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from . import _pi_regression as pr
from ._validation import as_choice, as_positive_scalar
from .fit_presliding import check_enough, check_varies, element_count
from .fitting import FitResult, Solution, Tie, solve_least_squares
from .friction import PIFriction
from .measurement import Measurement
from .operators import PIState

__all__ = ["fit_response"]

FloatArray = NDArray[np.float64]
SIGNALS = ("velocity", "position", "both")


class _Simulator:
    """Sampled response of eq. 17 for a parameter set (exact event method)."""

    def __init__(self, m: Measurement, u: FloatArray, initial_state: str, direction: float):
        from . import motion

        self.motion = motion
        self.t = m.time
        self.u = u
        self.state = initial_state
        self.direction = direction
        n = self.t.shape[0]
        self.dt = (self.t[-1] - self.t[0]) / (n - 1)
        grid = self.t[0] + self.dt * np.arange(n)
        self.uniform = bool(np.max(np.abs(grid - self.t)) <= 1e-9 * self.dt)
        self.constant = bool(np.all(u == u[0]))

    def __call__(
        self, mass: float, c1: float, k: FloatArray, r: FloatArray, y0: float, v0: float
    ) -> tuple[FloatArray, FloatArray, bool]:
        n = self.t.shape[0]
        state: str | PIState = self.state
        if state == "saturated" and (v0 == 0 or np.sign(v0) != self.direction):
            state = PIState.saturated(y0, r, self.direction) if k.size else "relaxed"
        if self.uniform and self.constant and isinstance(state, str):
            y, v = self.motion.free_response(
                mass, c1, k, r, v0, self.dt, n, initial_position=y0,
                initial_state=state, applied_force=float(self.u[0]),
            )  # fmt: skip
            return y, v, bool(np.all(np.isfinite(v)))
        model = PIFriction(c1, k, threshold=r) if k.size else PIFriction(c1)
        force = float(self.u[0]) if self.constant else (self.t, self.u)
        res = self.motion.simulate(
            model, mass, applied_force=force, initial_position=y0, initial_velocity=v0,
            initial_state=state, t_eval=self.t, t_start=float(self.t[0]),
        )  # fmt: skip
        y, v = res.position, res.velocity
        if y.shape[0] < n:
            y = np.concatenate([y, np.full(n - y.shape[0], y[-1])])
            v = np.concatenate([v, np.full(n - v.shape[0], v[-1])])
        return y, v, res.success


def fit_response(
    measurement: Measurement,
    n_elements: int = 4,
    equal_breakaway: bool = True,
    mass: float | None = None,
    *,
    coulomb_level: float | None = None,
    signal: str = "velocity",
    initial_state: str = "saturated",
    initial: Mapping[str, float] | None = None,
    fit_initial: bool = True,
    fixed: Mapping[str, float] | None = None,
    tied: Mapping[str, Tie] | None = None,
    level: float = 0.95,
    max_evaluations: int | None = None,
    tolerance: float = 1e-8,
) -> FitResult:
    """Fit eq. 17 by matching the simulated to the measured motion (output error).

    Parameters
    ----------
    measurement : Measurement
        Time and the measured `velocity` and/or `position`; `applied_force` u
        (held constant between samples, as a digital controller applies it;
        absent = 0). The motion starts at the first sample from the measured
        position (or 0) and velocity (or the difference quotient of the position).
    n_elements : int
        Number N of elasto-plastic elements (the paper: 4).
    equal_breakaway : bool
        Parameters ``mass``, ``coulomb_level`` F_c, ``coulomb`` c1, ``stiffness_j``
        with c_j = (F_c − c1)/N (the paper's choice); False: ``mass``, ``coulomb``,
        ``stiffness_j``, ``breakaway_j``.
    mass : float, optional
        Known mass [kg] (held fixed).
    coulomb_level : float, optional, keyword only
        Known F_c [N] (held fixed; needs ``equal_breakaway=True``).
    signal : {"velocity", "position", "both"}
        What is compared; "both" weighs each by the inverse of its RMS.
    initial_state : {"saturated", "relaxed"}
        Friction memory at the first sample ("saturated": steady sliding before).
    initial : mapping, optional
        Start values by parameter name (others from the default start).
    fit_initial : bool
        Also estimate the initial velocity (parameter ``initial_velocity``) and,
        when the position is compared, the initial position
        (``initial_position``); a noisy first sample would otherwise bias every
        other parameter. False holds them at the first measured sample.
    fixed, tied, level, max_evaluations, tolerance : as in `fit_presliding`

    Returns
    -------
    FitResult
        Against time; parameters per unit mass when u = 0 and neither `mass`
        nor `coulomb_level` is given (said in `message`).
    """
    if not isinstance(measurement, Measurement):
        raise TypeError(f"`measurement` must be a Measurement; got {type(measurement).__name__}.")
    signal = as_choice("signal", signal, SIGNALS)
    initial_state = as_choice("initial_state", initial_state, ("saturated", "relaxed"))
    need = {"velocity": ("velocity",), "position": ("position",), "both": ("velocity", "position")}
    measurement.require(*need[signal], purpose=f"fit_response(signal={signal!r})")
    n = element_count(n_elements, None, 4)
    if coulomb_level is not None and not equal_breakaway:
        raise ValueError("`coulomb_level` can be given only with equal_breakaway=True.")
    m = measurement
    t = m.time
    v = m.velocity if m.velocity is not None else np.gradient(m.position, t)
    y = m.position if m.position is not None else _integral(t, v)
    u = m.applied_force if m.applied_force is not None else np.zeros_like(t)
    check_varies("velocity" if m.velocity is not None else "position", v)
    fixed = dict(fixed or {})
    if mass is not None:
        fixed["mass"] = as_positive_scalar("mass", mass)
    if coulomb_level is not None:
        fixed["coulomb_level"] = as_positive_scalar("coulomb_level", coulomb_level)
    per_unit_mass = not np.any(u) and not ({"mass", "coulomb_level"} & set(fixed))
    if per_unit_mass:
        fixed["mass"] = 1.0
    k_names = [f"stiffness_{j + 1}" for j in range(n)]
    c_names = [f"breakaway_{j + 1}" for j in range(n)]
    names = ["mass", *(["coulomb_level"] if equal_breakaway else []), "coulomb", *k_names]
    names += [] if equal_breakaway else c_names
    names += ["initial_velocity", "initial_position"]
    direction = _initial_direction(v, u)
    if not fit_initial:
        fixed.setdefault("initial_velocity", float(v[0]))
    if not fit_initial or signal == "velocity":
        fixed.setdefault("initial_position", float(y[0]))
    check_enough(t.shape[0], len(names) - len(fixed))
    free_motion = not np.any(u)
    start = _default_start(
        t, y, v, u, n, fixed.get("mass", 1.0 if free_motion else None), equal_breakaway
    )
    if free_motion and "mass" not in fixed and "coulomb_level" in fixed:
        factor = fixed["coulomb_level"] / start["coulomb_level"]
        start = {key: val * factor for key, val in start.items()}
    start.update(initial_velocity=float(v[0]), initial_position=float(y[0]))
    for key, val in dict(initial or {}).items():
        if key not in names:
            raise ValueError(f"`initial` names unknown parameter {key!r}; known: {names}.")
        start[key] = float(val)
    sim = _Simulator(m, u, initial_state, direction)
    weights = _weights(signal, m)
    tiny = np.finfo(float).tiny

    def unpack(p: FloatArray) -> tuple[float, float, FloatArray, FloatArray, float, float]:
        q = dict(zip(names, p, strict=True))
        c1 = max(q["coulomb"], 0.0)
        k = np.maximum([q[x] for x in k_names], tiny)
        if equal_breakaway:
            c = np.full(n, max((q["coulomb_level"] - c1) / max(n, 1), tiny))
        else:
            c = np.maximum([q[x] for x in c_names], tiny)
        return max(q["mass"], tiny), c1, k, c, q["initial_position"], q["initial_velocity"]

    def residual(p: FloatArray) -> FloatArray:
        mass_, c1, k, c, y0, v0 = unpack(p)
        ys, vs, _ = sim(mass_, c1, k, c / k, y0, v0)
        return np.concatenate(
            [w * (s - d) for w, s, d in zip(weights, (vs, ys), (v, y), strict=True) if w]
        )

    bounds = dict.fromkeys(names, (0.0, np.inf))
    bounds["initial_position"] = (-np.inf, np.inf)
    saturated = initial_state == "saturated"
    bounds["initial_velocity"] = (
        (0.0, np.inf) if direction > 0 else (-np.inf, 0.0) if saturated else (-np.inf, np.inf)
    )
    if max_evaluations is None:
        max_evaluations = 50 * len(names)
    sol = solve_least_squares(
        residual, {k: start[k] for k in names}, bounds=bounds, fixed=fixed, tied=tied,
        level=level, max_evaluations=max_evaluations, tolerance=tolerance,
    )  # fmt: skip
    if equal_breakaway and not (set(k_names) & (set(fixed) | set(tied or {}))):
        sol = _stiffest_first(sol, k_names)
    mass_, c1, k, c, y0, v0 = unpack(np.array([sol.values[x] for x in names]))
    ys, vs, ok = sim(mass_, c1, k, c / k, y0, v0)
    model = PIFriction(c1, k, breakaway=c) if n else PIFriction(c1)
    note = ""
    if per_unit_mass:
        note = (
            "; the applied force is zero throughout, so mass and forces are determined only up "
            "to a common factor: they are reported per unit mass (mass = 1; forces in N/kg, "
            "stiffnesses in N/(m·kg)); give `mass` or `coulomb_level` to scale them"
        )
    if not ok and sol.status == "converged":
        sol = replace(sol, status="failed", message="the simulation failed at the optimum")
    sol = replace(sol, message=sol.message + note)
    derived = {"coulomb_level": model.coulomb_level} if not equal_breakaway else {}
    derived.update({f"threshold_{j + 1}": float(x) for j, x in enumerate(c / k)})
    if equal_breakaway and n:
        derived["breakaway_each"] = float(c[0])
    measured, fitted = (y, ys) if signal == "position" else (v, vs)
    return FitResult.from_solution(
        sol, model, t, measured, fitted, kind="output-error response",
        abscissa_label="time [s]", signal_label="position" if signal == "position" else "velocity",
        derived=derived,
    )  # fmt: skip


def _stiffest_first(sol: Solution, k_names: list[str]) -> Solution:
    """Relabel the elements of equal break-away force by decreasing stiffness.

    They are interchangeable, so only the sorted set is meaningful.
    """
    order = np.argsort([-sol.values[x] for x in k_names], kind="stable")
    rename = {k_names[int(j)]: k_names[i] for i, j in enumerate(order)}

    def relabel(d: dict) -> dict:
        out = dict(d)
        out.update({rename[x]: d[x] for x in k_names})
        return out

    return replace(
        sol,
        values=relabel(sol.values),
        standard_error=relabel(sol.standard_error),
        confidence_interval=relabel(sol.confidence_interval),
    )


def _initial_direction(v: FloatArray, u: FloatArray) -> float:
    """Direction of the motion before the first sample (for a saturated start)."""
    for sig in (v[:1], u[:1], v):
        nz = np.flatnonzero(sig)
        if nz.size:
            return float(np.sign(sig[nz[0]]))
    return 1.0  # pragma: no cover - a constant zero velocity is rejected before


def _integral(t: FloatArray, v: FloatArray) -> FloatArray:
    """Cumulative trapezoid integral from 0."""
    return np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(t))])


def _weights(signal: str, m: Measurement) -> tuple[float, float]:
    """Weights of the velocity and position residuals (0 = not compared)."""
    if signal == "velocity":
        return 1.0, 0.0
    if signal == "position":
        return 0.0, 1.0
    rv = float(np.sqrt(np.mean(m.velocity**2)))
    ry = float(np.sqrt(np.mean((m.position - np.mean(m.position)) ** 2)))
    if not (rv > 0 and ry > 0):
        raise ValueError("`velocity` and `position` must vary for signal='both'.")
    return 1.0 / rv, 1.0 / ry


def _default_start(
    t: FloatArray,
    y: FloatArray,
    v: FloatArray,
    u: FloatArray,
    n: int,
    mass: float | None,
    equal_breakaway: bool,
) -> dict[str, float]:
    """Start values from eq. 17 as a regression (inverse model) on the measured motion.

    Eq. 17 integrated in time, m·(v − v0) + ∫(c1·sign v + Σ k_j stop_j) dt = ∫u dt,
    needs no differentiation of a noisy velocity. Bounded linear least squares
    for m, c1 and the stiffnesses of a grid of stops gives a nonparametric
    virgin curve G(s) of the elastic part; the N elements are then fitted to G
    (with equal break-away forces if asked).
    """
    from scipy.optimize import lsq_linear

    a = np.gradient(v, t)
    grid = pr.threshold_grid(y, 32)
    columns = [np.sign(v), *pr.stop_basis(y)(grid)[0].T]
    columns = [_integral(t, c) for c in columns]
    rhs = _integral(t, u) - (0.0 if mass is None else mass * (v - v[0]))
    if mass is None:
        columns.insert(0, v - v[0])
    used = np.ones(t.shape[0], dtype=bool)
    mat = np.column_stack(columns)[used]
    scale = np.linalg.norm(mat, axis=0)
    scale[scale == 0] = 1.0
    ok = used.sum() > mat.shape[1] and np.ptp(y) > 0
    sol = lsq_linear(mat / scale, rhs[used], bounds=(0.0, np.inf)).x / scale if ok else None
    mass_ = (1.0 if mass is None else mass) if sol is None or mass is not None else sol[0]
    if sol is None or not mass_ > 0:
        mass_ = 1.0 if mass is None else mass
        fc = mass_ * float(np.mean(np.abs(a[used]))) if used.any() else 1.0
        c1, weights = 0.5 * fc, np.zeros_like(grid)
    else:
        c1, weights = sol[int(mass is None)], sol[int(mass is None) + 1 :]
    fc = c1 + float(weights @ grid)
    if not fc > 0:
        fc = mass_ * float(np.mean(np.abs(a))) or 1.0
    if not c1 > 0 or c1 >= fc:
        c1 = 0.5 * fc
    start = {"mass": float(mass_), "coulomb": float(c1)}
    if equal_breakaway:
        start["coulomb_level"] = float(fc)
        k = _equal_breakaway_stiffness(grid, weights, (fc - c1) / max(n, 1), n)
    else:
        r, k = pr.merge_grid(grid, np.where(weights > 0, weights, 0.0), n)
        start.update({f"breakaway_{j + 1}": float(x) for j, x in enumerate(k * r)})
    start.update({f"stiffness_{j + 1}": float(x) for j, x in enumerate(k)})
    return start


def _equal_breakaway_stiffness(
    grid: FloatArray, weight: FloatArray, c: float, n: int
) -> FloatArray:
    """Stiffnesses k_j (descending) with Σ_j min(k_j·s, c) closest to G(s) = Σ_g w_g·min(s, r_g)."""
    from scipy.optimize import least_squares

    s = np.geomspace(grid[0] / 4, grid[-1] * 2, 200)
    target = np.minimum(s[:, None], grid[None, :]) @ weight
    # start: element j saturates where G reaches (j + 1/2)·c
    levels = (np.arange(n) + 0.5) * c
    r0 = np.interp(levels, target, s) if np.ptp(target) > 0 else np.geomspace(s[0], s[-1], n)
    r0 = np.maximum(r0, s[0])

    def res(logk: FloatArray) -> FloatArray:
        return np.minimum(np.exp(logk)[None, :] * s[:, None], c).sum(axis=1) - target

    fit = least_squares(res, np.log(c / r0), method="lm", xtol=1e-10)
    return np.sort(np.exp(fit.x))[::-1]
