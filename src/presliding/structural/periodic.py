"""`periodic_orbit`, `frequency_response`, `force_response`: exact periodic responses.

A structure with joints of stops (Iwan or Jenkins joints: elements, c1 = 0) under the
harmonic force f(t) = s·Re(F̂·e^{iΩt}) (a real F̂: s·F̂·cos Ωt). Periodic orbits are found
by shooting on the exact event solver (each piece in closed form, each event to rounding),
with the exact monodromy matrix as the Newton Jacobian; its eigenvalues are the Floquet
multipliers. Curves of orbits follow the frequency Ω (`frequency_response`) or the
force's scale s (`force_response`) by pseudo-arclength continuation (`_shooting`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import as_count, as_positive_scalar, as_real_array, fmt
from presliding.structural._joint_run import run
from presliding.structural._orbit import Orbit
from presliding.structural._pieces import Model, harmonic_force
from presliding.structural._shooting import Point, Shooter, continuation
from presliding.structural.periodic_results import FrequencyResponse, PeriodicOrbit
from presliding.structural.structure import JointedStructure, as_structure

__all__ = ["force_response", "frequency_response", "periodic_orbit"]

FloatArray = NDArray[np.float64]

#: Largest |Floquet multiplier| of an orbit called stable.
STABLE = 1.0 + 1e-9


def _model(structure: Any, force: Any, frequency: float) -> tuple[JointedStructure, Model]:
    st = as_structure(structure)
    return st, Model(st, harmonic_force(force, st.n_coordinates), frequency)


def _start(shooter: Shooter, st: JointedStructure, p: float, tol: float,
           initial: ArrayLike | None) -> Point | None:  # fmt: skip
    """The first orbit: from `initial`, else the stuck structure's linear response; failing
    that, after free running to let the transient decay."""
    md = shooter.model(p)
    n = md.n
    if initial is not None:
        z = as_real_array("initial_state", initial).reshape(-1)
        if z.shape != (2 * n + md.n_e,):
            raise ValueError(
                f"`initial_state` must have shape ({2 * n + md.n_e},) (q, q̇ and the stops' "
                f"plastic parts); got {z.shape}."
            )
    else:
        om = md.omega
        dyn = st.stuck_stiffness() - om**2 * st.mass + 1j * om * np.asarray(st.damping)
        amp = np.linalg.solve(dyn, md.force)
        z = np.r_[amp.real, (1j * om * amp).real, np.zeros(md.n_e)]
    found = shooter.newton(z, p, tol)
    for periods in (20, 200):
        if found is not None:
            break
        found = shooter.newton(shooter.relax(z, p, periods), p, tol)
    return found


def _orbit(shooter: Shooter, pt: Point) -> tuple[Orbit, Any]:
    md = shooter.model(pt.parameter)
    n = md.n
    period = 2.0 * math.pi / md.omega
    r = run(md, 0.0, pt.z[:n], pt.z[n : 2 * n], pt.z[2 * n :], period, keep=True)
    return Orbit(r.pieces, period), r


def periodic_orbit(
    structure: JointedStructure | Any,
    force: ArrayLike,
    frequency: float,
    *,
    initial_state: ArrayLike | None = None,
    harmonics: int = 7,
    samples: int = 512,
    tol: float = 1e-12,
) -> PeriodicOrbit:
    """The periodic orbit of a structure with stop joints under f(t) = Re(F̂·e^{iΩt}).

    Parameters
    ----------
    structure : JointedStructure
        Joints of stops only (finite elements, c1 = 0), stiffness K positive definite.
    force : array_like, shape (n,), real or complex
        F̂ [N]; a real vector gives F̂·cos(Ωt).
    frequency : float
        Ω > 0 [rad/s].
    initial_state : array_like, shape (2n + n_e,), optional
        A guess of (q, q̇, x) at t = 0; default the stuck structure's linear response,
        and free running if Newton does not converge from it.
    harmonics : int
        Exact Fourier coefficients Q_0..Q_H reported (H = `harmonics`).
    samples : int
        Samples of the period in ``time`` and ``position``.
    tol : float
        Newton stops at max|Z(T) − Z(0)| <= tol times the orbit's size.

    Returns
    -------
    PeriodicOrbit
    """
    om = as_positive_scalar("frequency", frequency)
    tol = as_positive_scalar("tol", tol)
    st, md = _model(structure, force, om)
    shooter = Shooter(lambda p: md.with_forcing(md.force, p), frequency=True)
    pt = _start(shooter, st, om, tol, initial_state)
    if pt is None:
        raise ValueError(
            f"no periodic orbit found at `frequency` {om!r} rad/s: Newton did not converge "
            f"from the linear response nor after 200 periods of free running."
        )
    orbit, _ = _orbit(shooter, pt)
    t = np.linspace(0.0, orbit.period, as_count("samples", samples, minimum=2))
    q, v = orbit.state(t)
    stable = bool(np.max(np.abs(pt.multipliers), initial=0.0) <= STABLE)
    return PeriodicOrbit(
        time=t, position=q, velocity=v, frequency=om, initial_state=pt.z,
        amplitude=orbit.amplitude(), harmonics=orbit.harmonics(as_count("harmonics", harmonics)),
        multipliers=pt.multipliers, stable=stable, residual=pt.residual, iterations=pt.iterations,
        message=(f"periodic to {pt.residual:.2g} in {pt.iterations} Newton iteration(s); "
                 f"{'stable' if stable else 'unstable'} (largest |multiplier| "
                 f"{np.max(np.abs(pt.multipliers), initial=0.0):.6g})."),
    )  # fmt: skip


def _curve(shooter: Shooter, st: JointedStructure, start: float, end: float, *, parameter: str,
           freq_of: Any, scale_of: Any, step: float | None, max_points: int, tol: float,
           initial: ArrayLike | None) -> FrequencyResponse:  # fmt: skip
    max_points = as_count("max_points", max_points, minimum=2)
    first = _start(shooter, st, start, tol, initial)
    if first is None:
        return _empty(shooter, parameter, "no_start",
                      f"no periodic orbit found at the start {start!r}.")  # fmt: skip
    step = 0.02 if step is None else as_positive_scalar("step", step)
    points, status = continuation(shooter, first, end, step=step, max_points=max_points,
                                  tol=tol, max_step=4.0 * step, min_step=1e-6 * step)  # fmt: skip
    amps, first_h, n_ev = [], [], []
    for pt in points:
        orbit, r = _orbit(shooter, pt)
        amps.append(orbit.amplitude())
        first_h.append(np.abs(orbit.harmonics(1)[1]))
        n_ev.append(r.n_events)
    mult = np.array([np.max(np.abs(p.multipliers), initial=0.0) for p in points])
    par = np.array([p.parameter for p in points])
    messages = {"success": f"{len(points)} orbits from {start!r} to {end!r}.",
                "point_limit": f"stopped at {par[-1]!r} after max_points={max_points} orbits.",
                "step_too_small": f"the continuation's step fell below its minimum at "
                                  f"{par[-1]!r} (a sharp turn of the curve)."}  # fmt: skip
    return FrequencyResponse(
        frequency=np.array([freq_of(p) for p in par]), scale=np.array([scale_of(p) for p in par]),
        amplitude=np.array(amps), first_harmonic=np.array(first_h), stable=mult <= STABLE,
        max_multiplier=mult, residual=np.array([p.residual for p in points]),
        n_events=np.array(n_ev, dtype=np.int64), initial_state=np.array([p.z for p in points]),
        parameter=parameter, status=status,
        message=messages[status] + f" Largest residual {max(p.residual for p in points):.2g}.",
    )  # fmt: skip


def _empty(shooter: Shooter, parameter: str, status: str, message: str) -> FrequencyResponse:
    md = shooter.model(1.0)
    n, big = md.n, 2 * md.n + md.n_e
    z = np.zeros(0)
    return FrequencyResponse(z, z, np.zeros((0, n)), np.zeros((0, n)), np.zeros(0, dtype=bool),
                             z, z, np.zeros(0, dtype=np.int64), np.zeros((0, big)),
                             parameter=parameter, status=status, message=message)  # fmt: skip


def _pair(name: str, value: Any) -> tuple[float, float]:
    pair = as_real_array(name, value).reshape(-1)
    if pair.shape != (2,) or not np.all(pair > 0) or pair[0] == pair[1]:
        raise ValueError(f"`{name}` must be two different positive numbers (start, end); got "
                         f"{fmt(value)}.")  # fmt: skip
    return float(pair[0]), float(pair[1])


def frequency_response(
    structure: JointedStructure | Any,
    force: ArrayLike,
    frequencies: Sequence[float],
    *,
    scale: float = 1.0,
    step: float | None = None,
    max_points: int = 1000,
    tol: float = 1e-12,
    initial_state: ArrayLike | None = None,
) -> FrequencyResponse:
    """The frequency response curve: periodic orbits from Ω = start to end, continued.

    Pseudo-arclength continuation of the orbits of `periodic_orbit` in Ω (folds and the
    corners where a stop starts sliding elsewhere in the period are followed), each orbit
    exact and its stability from its Floquet multipliers.

    Parameters
    ----------
    structure : JointedStructure
    force : array_like, shape (n,), real or complex
        F̂ [N]; the force is s·Re(F̂·e^{iΩt}).
    frequencies : (float, float)
        Start and end of Ω [rad/s] (either order).
    scale : float
        s > 0, the force's scale.
    step : float, optional
        First arclength step in variables scaled by the orbit's size and the range
        (default 0.02); steps adapt between 1e-6 and 4 times it.
    max_points : int
        Stop after this many orbits (status 'point_limit').
    tol : float
        Every orbit periodic to tol times its size.
    initial_state : array_like, optional
        A guess of the first orbit's (q, q̇, x) at t = 0.

    Returns
    -------
    FrequencyResponse
    """
    start, end = _pair("frequencies", frequencies)
    s = as_positive_scalar("scale", scale)
    tol = as_positive_scalar("tol", tol)
    st, md = _model(structure, force, start)
    shooter = Shooter(lambda p: md.with_forcing(s * md.force, p), frequency=True)
    return _curve(shooter, st, start, end, parameter="frequency", freq_of=lambda p: p,
                  scale_of=lambda p: s, step=step, max_points=max_points, tol=tol,
                  initial=initial_state)  # fmt: skip


def force_response(
    structure: JointedStructure | Any,
    force: ArrayLike,
    frequency: float,
    scales: Sequence[float],
    *,
    step: float | None = None,
    max_points: int = 1000,
    tol: float = 1e-12,
    initial_state: ArrayLike | None = None,
) -> FrequencyResponse:
    """Periodic orbits at one Ω as the force's scale s goes from start to end, continued.

    Parameters as `frequency_response`, with `frequency` Ω [rad/s] fixed and `scales`
    (start, end) of s > 0.

    Returns
    -------
    FrequencyResponse
        With ``parameter`` 'scale'.
    """
    om = as_positive_scalar("frequency", frequency)
    start, end = _pair("scales", scales)
    tol = as_positive_scalar("tol", tol)
    st, md = _model(structure, force, om)
    shooter = Shooter(lambda p: md.with_forcing(p * md.force, om), frequency=False)
    return _curve(shooter, st, start, end, parameter="scale", freq_of=lambda p: om,
                  scale_of=lambda p: p, step=step, max_points=max_points, tol=tol,
                  initial=initial_state)  # fmt: skip
