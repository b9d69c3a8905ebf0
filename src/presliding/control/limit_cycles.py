"""Limit cycles (hunting) of a loop with PI friction by harmonic balance.

The friction force F enters the loop as a local feedback around the mass:
m·ÿ = u − F, u = −C(s)·y (r = 0). Seen from F, the linear part of the loop is

    G(s) = P(s) / (1 + P(s)·C(s)),      P(s) = 1/(m·s²)  (or any plant force → position),

and a limit cycle y ≈ A·sin ωt solves the harmonic balance

    G(jω)·N(A) = −1,                                          (N: `describing_function`)

i.e. the Nyquist curve of G meets the curve −1/N(A). Friction dissipates (Im N > 0,
−1/N in the second quadrant), so G must enter that quadrant: for a PID on a mass
this happens only when the loop without friction is unstable (ki·m > kd·kp), as
with a PI controller; the friction's presliding stiffness and c1 then hold small
motions while large ones grow, or settle on a cycle.

Stability of a cycle (Loeb's criterion, computed directly): near (A*, ω*) the
root s of 1 + G(s)·N(A) = 0 that sits at jω* moves with A as
ds/dA = −G·N'(A) / (G'(s)·N); the cycle is stable when Re ds/dA < 0 (a larger
amplitude is damped, a smaller one grows).

A sampled PID (`PID` with ``dt``) enters as its continuous form C(s) with the
zero-order hold's half-sample delay e^{−s·dt/2}; the describing function
assumes near-sinusoidal motion, which long rests (stick-slip) violate.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import root

from presliding._validation import as_positive_scalar, as_real_vector, check_size, fmt
from presliding.control.controllers import PID, DiscreteController
from presliding.control.cycles import LimitCycles
from presliding.control.describing import describing_function, friction_model
from presliding.friction._parts import density_of

__all__ = ["predict_limit_cycles"]

FloatArray = NDArray[np.float64]


def _lti_response(system: Any, name: str) -> tuple[Callable[[Any], Any], Any]:
    """G(s) as a function of complex s (continuous), and the python-control object."""
    from presliding.control._optional import python_control as _control

    ct = _control()
    if isinstance(system, (int, float, np.floating)) and not isinstance(system, bool):
        m = as_positive_scalar(name, system)
        sys_ = ct.tf([1.0], [m, 0.0, 0.0])
    elif isinstance(system, ct.LTI):
        sys_ = system
    else:
        raise TypeError(
            f"`{name}` must be a python-control LTI system or a mass [kg]; got "
            f"{type(system).__name__}."
        )
    if sys_.ninputs != 1 or sys_.noutputs != 1:
        raise ValueError(f"`{name}` must be single-input single-output; got "
                         f"{sys_.ninputs} inputs and {sys_.noutputs} outputs.")  # fmt: skip
    tf = ct.tf(sys_)
    num, den = np.asarray(tf.num[0][0], dtype=float), np.asarray(tf.den[0][0], dtype=float)

    def rational(z):
        return np.polyval(num, z) / np.polyval(den, z)

    if sys_.isdtime(strict=True):
        dt = float(sys_.dt)
        return (lambda s: rational(np.exp(np.asarray(s) * dt))), sys_
    return rational, sys_


def _controller_response(controller: Any) -> Callable[[Any], Any]:
    if isinstance(controller, PID):
        c, _ = _lti_response(controller.continuous(), "controller")
        dt = controller.dt
        return lambda s: c(s) * np.exp(-np.asarray(s) * dt / 2.0)
    if isinstance(controller, DiscreteController):
        raise TypeError(
            "`controller` must be a PID or a python-control LTI system; for a "
            "DiscreteController pass control.ss(A, B, C, D, dt) of its error input."
        )
    return _lti_response(controller, "controller")[0]


def linear_part(plant_or_loop: Any, controller: Any = None,
                viscous: float = 0.0) -> Callable[[Any], Any]:  # fmt: skip
    """G(s) seen by the friction: P/(1 + P·(C + σs)), or the loop given, with σ folded in."""
    g, _ = _lti_response(plant_or_loop, "plant_or_loop")
    c = None if controller is None else _controller_response(controller)

    def response(s):
        s = np.asarray(s, dtype=complex)
        p = g(s)
        if c is not None:
            return p / (1.0 + p * (c(s) + viscous * s))
        return p / (1.0 + viscous * s * p) if viscous else p

    return response


def _logpolar(z: Any) -> tuple[FloatArray, FloatArray]:
    return np.log(np.abs(z)), np.mod(np.angle(z), 2 * np.pi)


def _candidates(za: Any, zb: Any) -> list[tuple[int, int, float, float]]:
    """Starting points (i, j, fraction along a, along b) where two polylines (complex) cross
    or come close.

    The curves are compared in log-polar form (log|z|, arg z in [0, 2π)), so that
    magnitudes over many decades are resolved; segments across arg = 0 are skipped
    (−1/N lies in the upper half-plane). Close approaches (local minima of the
    distance below 0.1) catch crossings at a grazing angle, which the polylines
    may miss; Newton's method decides.
    """
    (xa, ya), (xb, yb) = _logpolar(za), _logpolar(zb)
    ok_a = np.abs(np.diff(ya)) < np.pi
    ok_b = np.abs(np.diff(yb)) < np.pi
    p = np.stack([xa[:-1], ya[:-1]], 1)[:, None, :]
    r = np.stack([np.diff(xa), np.diff(ya)], 1)[:, None, :]
    q = np.stack([xb[:-1], yb[:-1]], 1)[None, :, :]
    s = np.stack([np.diff(xb), np.diff(yb)], 1)[None, :, :]
    cross = r[..., 0] * s[..., 1] - r[..., 1] * s[..., 0]
    qp = q - p
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (qp[..., 0] * s[..., 1] - qp[..., 1] * s[..., 0]) / cross
        u = (qp[..., 0] * r[..., 1] - qp[..., 1] * r[..., 0]) / cross
    hit = (t >= 0) & (t <= 1) & (u >= 0) & (u <= 1) & ok_a[:, None] & ok_b[None, :]
    out = [(int(i), int(j), float(t[i, j]), float(u[i, j])) for i, j in np.argwhere(hit)]
    dist = np.hypot(xa[:, None] - xb[None, :], ya[:, None] - yb[None, :])
    nearest = dist.min(axis=0)
    at = dist.argmin(axis=0)
    for j in range(1, nearest.shape[0] - 1):
        left, right = nearest[j - 1], nearest[j + 1]
        if nearest[j] < 0.1 and nearest[j] <= min(left, right) and nearest[j] < max(left, right):
            out.append((int(min(at[j], za.shape[0] - 2)), j, 0.0, 0.0))
    return out


def _range(name: str, value: Any) -> tuple[float, float] | None:
    """A searched range (low, high) with 0 < low < high, checked on entry (None: default)."""
    if value is None:
        return None
    pair = as_real_vector(name, value)
    if pair.shape[0] != 2 or not 0 < pair[0] < pair[1]:
        raise ValueError(f"`{name}` must be a range (low, high) with 0 < low < high; got "
                         f"{fmt(pair)}.")  # fmt: skip
    return float(pair[0]), float(pair[1])


def _grid(given: tuple[float, float] | None, default: tuple[float, float], num: int) -> FloatArray:
    lo, hi = default if given is None else given
    return np.geomspace(lo, hi, num, dtype=np.float64)


def _default_frequencies(g: Callable[[Any], Any], plant_or_loop: Any, controller: Any):
    from presliding.control._optional import python_control as _control

    ct = _control()
    scales = []
    for sys_ in (plant_or_loop, controller):
        if isinstance(sys_, PID):
            sys_ = sys_.continuous()
        if isinstance(sys_, ct.LTI):
            for z in np.concatenate([np.atleast_1d(sys_.poles()), np.atleast_1d(sys_.zeros())]):
                mag = abs(np.log(z) / sys_.dt) if sys_.isdtime(strict=True) else abs(z)
                if np.isfinite(mag) and mag > 0:
                    scales.append(mag)
    if isinstance(controller, PID) and isinstance(plant_or_loop, (int, float)):
        m = float(plant_or_loop)
        scales += [np.sqrt(max(controller.kp, 1e-300) / m), np.sqrt(controller.ki / m)]
    scales = [s for s in scales if s > 0] or [1.0]
    hi = 100.0 * max(scales)
    if isinstance(controller, PID):
        hi = min(hi, np.pi / controller.dt)
    return 1e-2 * min(scales), hi


def predict_limit_cycles(
    plant_or_loop: Any,
    model: Any,
    controller: Any = None,
    *,
    amplitudes: ArrayLike | None = None,
    frequencies: ArrayLike | None = None,
    points: int = 600,
) -> LimitCycles:
    """Limit cycles of a loop with PI friction: solutions of G(jω)·N(A) = −1.

    Parameters
    ----------
    plant_or_loop : python-control LTI or float
        With `controller`: the plant from force to position (a float is a mass m:
        P = 1/(m s²)). Without: the linear part G seen by the friction force
        (force → position, negative feedback), e.g. ``control.feedback(P, C)``.
    model : PIFriction or CoulombFriction
        The friction (finite elements or a density).
    controller : PID or python-control LTI, optional
        C(s) from the position error to the force. A `PID` enters as its
        continuous form with the zero-order hold's delay dt/2.
    amplitudes, frequencies : (low, high), keyword only
        Ranges searched [m, rad/s]; defaults from the thresholds and the loop's
        poles and zeros.
    points : int, keyword only
        Grid points per curve before the intersections are refined (Newton).

    Returns
    -------
    LimitCycles
        The cycles (amplitude, frequency, stable), the curves for the plot, status.
    """
    fr = friction_model(model)
    if isinstance(points, bool) or not isinstance(points, int) or points < 20:
        raise ValueError(f"`points` must be an integer >= 20; got {fmt(points)}.")
    # the crossings are searched among all pairs of segments: about 12 arrays points × points
    check_size("points", points, points**2, what="pairs of curve points", item_bytes=12 * 8)
    a_range, w_range = _range("amplitudes", amplitudes), _range("frequencies", frequencies)
    g = linear_part(plant_or_loop, controller, float(getattr(fr, "viscous", 0.0) or 0.0))
    if fr.is_discrete and fr.n_elements:
        r = np.asarray(fr.threshold)
        a_default = (1e-3 * float(r.min()), 1e3 * float(r.max()))
    elif not fr.is_discrete:
        dens = density_of(fr)
        big = dens.max_threshold
        big = big if np.isfinite(big) else 40.0 * float(dens.M1(np.inf) / max(
            dens.total_stiffness, 1e-300))  # fmt: skip
        a_default = (1e-4 * big, 1e4 * big)
    else:
        a_default = (1e-9, 1e3)
    amps = _grid(a_range, a_default, points)
    omegas = _grid(w_range, _default_frequencies(g, plant_or_loop, controller), points)
    n_a = describing_function(fr, amps)
    g_w = g(1j * omegas)
    found: list[tuple[float, float, bool]] = []  # amplitude, frequency, stable
    for i, j, t, u in _candidates(g_w, -1.0 / n_a):
        w0 = omegas[i] * (omegas[i + 1] / omegas[i]) ** t
        a0 = amps[j] * (amps[j + 1] / amps[j]) ** u
        if any(abs(np.log(a0 / a)) < 0.02 and abs(np.log(w0 / w)) < 0.02 for a, w, _ in found):
            continue  # a start next to a cycle already found
        sol = _refine(g, fr, a0, w0, (amps[0], amps[-1]), (omegas[0], omegas[-1]))
        if sol is not None and not any(
            abs(sol[0] - a) <= 1e-6 * a and abs(sol[1] - w) <= 1e-6 * w for a, w, _ in found
        ):
            found.append((*sol, _stable(g, fr, *sol)))
    found.sort()
    amp = np.array([f[0] for f in found])
    freq = np.array([f[1] for f in found])
    stable = np.array([f[2] for f in found], dtype=bool)
    n_stable = int(stable.sum())
    if found:
        status = "predicted"
        message = (f"{len(found)} limit cycle(s) predicted, {n_stable} stable; the describing "
                   "function assumes near-sinusoidal motion (long rests violate it)")  # fmt: skip
    else:
        status = "none"
        message = ("no limit cycle predicted: the Nyquist curve of G does not meet −1/N(A) for "
                   f"A in [{amps[0]:.3g}, {amps[-1]:.3g}] m")  # fmt: skip
    return LimitCycles(amplitude=amp, frequency=freq, stable=stable, amplitudes=amps,
                       minus_inverse_df=-1.0 / n_a, frequencies=omegas, loop_response=g_w,
                       status=status, message=message, model=fr)  # fmt: skip


def _refine(g, model, a0: float, w0: float, a_range, w_range) -> tuple[float, float] | None:
    """Newton on (log A, log ω) of log(−G·N) = 0 within the searched ranges; None if it
    does not converge there."""
    lo = np.log([a_range[0], w_range[0]])
    hi = np.log([a_range[1], w_range[1]])

    def resid(x):
        xc = np.clip(x, lo, hi)
        z = -complex(g(1j * np.exp(xc[1]))) * describing_function(model, np.exp(xc[0]))
        lz = np.log(z)
        return [lz.real + 10.0 * float(np.sum(np.abs(x - xc))), lz.imag]

    sol = root(resid, [np.log(a0), np.log(w0)], method="hybr", options={"xtol": 1e-13})
    a, w = float(np.exp(sol.x[0])), float(np.exp(sol.x[1]))
    inside = bool(np.all(sol.x >= lo) and np.all(sol.x <= hi))
    check = abs(complex(g(1j * w)) * describing_function(model, a) + 1.0) if inside else 1.0
    return (a, w) if sol.success and check < 1e-8 else None


def _stable(g, model, a: float, w: float) -> bool:
    """Loeb's criterion: Re ds/dA < 0 with ds/dA = −G·N'(A)/(G'(s)·N), s = jω."""
    h = 1e-6
    dn = (describing_function(model, a * (1 + h)) - describing_function(model, a * (1 - h))) / (
        2 * h * a)  # fmt: skip
    dg = (complex(g(1j * w * (1 + h))) - complex(g(1j * w * (1 - h)))) / (2j * h * w)
    ds = -complex(g(1j * w)) * dn / (dg * describing_function(model, a))
    return bool(ds.real < 0)
