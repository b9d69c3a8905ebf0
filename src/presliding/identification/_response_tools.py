"""Helpers of `fit_response`: the compiled response simulator and the start.

`Simulator` samples the exact event solution of eq. 17 (`presliding.motion._event`)
for a parameter vector with no Python work per time step and little per call;
`default_start` builds start values from eq. 17 as a regression (inverse model).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from presliding.identification import _pi_regression as pr
from presliding.identification.measurement import Measurement
from presliding.motion import _event
from presliding.motion._forcing import as_forcing

FloatArray = NDArray[np.float64]
MAX_EVENTS = 10_000_000


class Simulator:
    """Sampled response of eq. 17 (exact event method) under the measured force u.

    u is held constant between samples (zero-order hold). ``initial_state``
    "saturated" deforms every element to its threshold in `direction` (steady
    sliding before the first sample), "relaxed" deforms none.
    """

    def __init__(self, m: Measurement, u: FloatArray, initial_state: str, direction: float):
        self.t = np.ascontiguousarray(m.time)
        t0, t_end = float(self.t[0]), float(self.t[-1])
        self.u_t, self.u_val = as_forcing((self.t, u), "zoh", t0).pieces(t0, t_end)
        self.t_end = t_end
        self.saturated = initial_state == "saturated"
        self.direction = direction
        self.rev = np.empty((2, 16))

    def __call__(
        self, mass: float, c1: float, k: FloatArray, r: FloatArray, y0: float, v0: float,
        times: FloatArray | None = None,
    ) -> tuple[FloatArray, FloatArray, bool]:  # fmt: skip
        """Position, velocity at `times` (default: every sample) and whether it succeeded."""
        times = self.t if times is None else times
        n = times.shape[0]
        s = float(np.sign(v0))
        f = self.direction * r if self.saturated else np.zeros_like(r)
        last_dir = s if s != 0 else (self.direction if self.saturated else 0.0)
        out = np.empty((8, n))
        res = _event.run_events(
            mass, c1, k, r, np.ascontiguousarray(f), y0, v0, last_dir, self.u_t, self.u_val,
            times, self.t_end, MAX_EVENTS, *out, self.rev[0], self.rev[1],
        )  # fmt: skip
        status, filled = int(res[0]), int(res[1])
        y, v = out[0], out[1]
        if filled < n:
            y[filled:], v[filled:] = (y[filled - 1], v[filled - 1]) if filled else (y0, v0)
        return y, v, status == 0 and bool(np.all(np.isfinite(v)))


def initial_direction(v: FloatArray, u: FloatArray) -> float:
    """Direction of the motion before the first sample (for a saturated start)."""
    for sig in (v[:1], u[:1], v):
        nz = np.flatnonzero(sig)
        if nz.size:
            return float(np.sign(sig[nz[0]]))
    return 1.0  # pragma: no cover - a constant zero velocity is rejected before


def integral(t: FloatArray, v: FloatArray) -> FloatArray:
    """Cumulative trapezoid integral from 0."""
    return np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(t))])


def weights(signal: str, m: Measurement) -> tuple[float, float]:
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


def default_start(
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
    columns = [integral(t, c) for c in columns]
    rhs = integral(t, u) - (0.0 if mass is None else mass * (v - v[0]))
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
        k = equal_breakaway_stiffness(grid, weights, (fc - c1) / max(n, 1), n)
    else:
        r, k = pr.merge_grid(grid, np.where(weights > 0, weights, 0.0), n)
        start.update({f"breakaway_{j + 1}": float(x) for j, x in enumerate(k * r)})
    start.update({f"stiffness_{j + 1}": float(x) for j, x in enumerate(k)})
    return start


def equal_breakaway_stiffness(grid: FloatArray, weight: FloatArray, c: float, n: int) -> FloatArray:
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
