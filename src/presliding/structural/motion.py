"""`simulate_structure` and `simulate_ring_down`: exact motion of a jointed structure.

Joints of stops only (Iwan or Jenkins joints: elements, c1 = 0) run on this layer's event
solver (`_joint_run`: closed-form pieces, events to rounding), under no force or the
harmonic force Re(F̂·e^{iΩt}); joints with a Coulomb element (c1 > 0, rigid until they
slip) run on `simulate_network`. A ring-down starts from an impulse along a linear mode
(q = 0, q̇ = ω₀·a·φ, the joints relaxed) or from the mode's quasi-static deflection at
modal amplitude a (the joints on their virgin curves, at rest), and decays freely.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_choice,
    as_count,
    as_positive_scalar,
    as_signal,
    as_state_vector,
    check_size,
)
from presliding.hysteresis._results import ResultMixin
from presliding.measurement import Measurement
from presliding.network import NetworkState, simulate_network
from presliding.structural._joint_run import run
from presliding.structural._pieces import Model, harmonic_force
from presliding.structural.backbone import modal_backbone
from presliding.structural.structure import JointedStructure, as_structure

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["StructureMotion", "simulate_ring_down", "simulate_structure"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False, repr=False)
class StructureMotion(ResultMixin):
    """A simulated motion of a jointed structure, sampled at ``time``.

    Attributes
    ----------
    time : ndarray, shape (T,)
    position, velocity, acceleration : ndarray, shape (T, n)
        q [m], q̇ [m/s], q̈ [m/s²].
    joint_displacement, joint_force : ndarray, shape (T, n_c)
        g = Wᵀq [m] and each joint's force λ_c [N].
    n_events : int
        Events (stops or contacts starting or stopping to slide).
    solver : str
        'joints' (this layer's event solver) or 'network' (`simulate_network`).
    status : str
        'success', or 'event_limit' (max_events reached; the arrays stop there).
    message : str
    """

    time: FloatArray
    position: FloatArray
    velocity: FloatArray
    acceleration: FloatArray
    joint_displacement: FloatArray
    joint_force: FloatArray
    n_events: int
    solver: str
    status: str = "success"
    message: str = ""
    _rows: ClassVar[str] = "time"

    @property
    def success(self) -> bool:
        """True when the whole span was simulated."""
        return self.status == "success"

    def __repr__(self) -> str:
        return (f"StructureMotion(samples={self.time.shape[0]}, n_events={self.n_events}, "
                f"solver={self.solver!r}, status={self.status!r})")  # fmt: skip

    def report(self) -> str:
        """Span, events, and each coordinate's largest displacement."""
        lines = [repr(self), self.message]
        for i in range(self.position.shape[1]):
            lines.append(f"q{i}: max |q| {np.max(np.abs(self.position[:, i])):.6g} m")
        return "\n".join(lines)

    def to_measurement(self, coordinate: int = 0) -> Measurement:
        """One coordinate as a `Measurement` (position, velocity, acceleration)."""
        i = as_count("coordinate", coordinate, maximum=self.position.shape[1] - 1)
        return Measurement(self.time, position=self.position[:, i],
                           velocity=self.velocity[:, i],
                           acceleration=self.acceleration[:, i])  # fmt: skip

    def to_pandas(self) -> Any:
        """One row per sample: q_i, v_i, a_i, g_c, λ_c."""
        import pandas as pd

        from presliding._display import fill_attrs

        cols: dict[str, Any] = {}
        for name, arr in (("position", self.position), ("velocity", self.velocity),
                          ("acceleration", self.acceleration),
                          ("joint_displacement", self.joint_displacement),
                          ("joint_force", self.joint_force)):  # fmt: skip
            for i in range(arr.shape[1]):
                cols[f"{name}_{i}"] = arr[:, i]
        frame = pd.DataFrame(cols, index=pd.Index(self.time, name="time"))
        return fill_attrs(frame, self)

    def plot(self, ax: Axes | None = None) -> Axes:
        """q(t), one line per coordinate."""
        return plot_positions(ax, self.time, self.position)


def plot_positions(ax: Axes | None, time: FloatArray, position: FloatArray) -> Axes:
    """q(t), one line per coordinate, with units (a motion's or an orbit's figure)."""
    from presliding.plotting import new_axes, place_legend

    ax = new_axes(ax)
    for i in range(position.shape[1]):
        ax.plot(time, position[:, i], label=f"q{i}")
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("position q [m]")
    place_legend(ax)
    return ax


def _stop_joints(st: JointedStructure) -> bool:
    return st.is_discrete and all(j.coulomb == 0.0 for j in st.joints)


def simulate_structure(
    structure: JointedStructure | Any,
    t_end: float,
    initial_position: ArrayLike | None = None,
    initial_velocity: ArrayLike | None = None,
    *,
    force: ArrayLike | None = None,
    frequency: float | None = None,
    plastic: ArrayLike | None = None,
    t_eval: ArrayLike | None = None,
    max_events: int = 1_000_000,
) -> StructureMotion:
    """The exact motion of a jointed structure from t = 0 to `t_end`.

    Parameters
    ----------
    structure : JointedStructure or NetworkStructure
        Joints of stops only (c1 = 0) run on the structural event solver; joints that all
        have a Coulomb element (c1 > 0) run on `simulate_network` (free motion only here).
    t_end : float
        End time [s].
    initial_position, initial_velocity : array_like, shape (n,), optional
        q(0) [m], q̇(0) [m/s]; zeros by default.
    force : array_like, shape (n,), real or complex, optional
        F̂ [N] of the harmonic force Re(F̂·e^{iΩt}) (with `frequency` Ω [rad/s]).
    frequency : float, optional
        Ω > 0 [rad/s], with `force`.
    plastic : array_like, shape (n_e,), optional
        The stops' plastic parts x_j at t = 0 [m] (stop joints; default: relaxed at q(0),
        x_j = g_c(0)).
    t_eval : array_like, optional
        Sample times in [0, t_end]; default 2001 uniform samples.
    max_events : int

    Returns
    -------
    StructureMotion
    """
    st = as_structure(structure)
    t_end = as_positive_scalar("t_end", t_end)
    n = st.n_coordinates
    q0 = np.zeros(n) if initial_position is None else as_state_vector(
        "initial_position", initial_position, n)  # fmt: skip
    v0 = np.zeros(n) if initial_velocity is None else as_state_vector(
        "initial_velocity", initial_velocity, n)  # fmt: skip
    times = np.linspace(0.0, t_end, 2001) if t_eval is None else as_signal("t_eval", t_eval)
    if np.any(np.diff(times) < 0) or times[0] < 0 or times[-1] > t_end:
        raise ValueError(f"`t_eval` must be nondecreasing within [0, t_end = {t_end!r}]; got "
                         f"{times[0]!r} to {times[-1]!r}.")  # fmt: skip
    check_size("t_eval", times.shape[0], times.shape[0] * (4 * n + 2 * st.n_contacts))
    max_events = as_count("max_events", max_events, minimum=1)
    if (force is None) != (frequency is None):
        raise ValueError("`force` and `frequency` must be given together (a harmonic force).")
    if _stop_joints(st):
        om = 0.0 if frequency is None else as_positive_scalar("frequency", frequency)
        f_hat = np.zeros(n, complex) if force is None else harmonic_force(force, n)
        md = Model(st, f_hat, om)
        x0 = (st.contacts.T @ q0)[md.owner] if plastic is None else as_state_vector(
            "plastic", plastic, md.n_e)  # fmt: skip
        r = run(md, 0.0, q0, v0, x0, t_end, samples=times, max_events=max_events)
        s = r.samples
        status = r.status
        message = (f"simulated to t = {r.t!r} s in {r.n_events} events (closed-form pieces)."
                   if status == "success" else
                   f"the event limit max_events={max_events} was reached at t = {r.t!r} s; the "
                   f"samples after it are missing.")  # fmt: skip
        return StructureMotion(s["time"], s["position"], s["velocity"], s["acceleration"],
                               s["joint_displacement"], s["joint_force"], r.n_events, "joints",
                               status, message)  # fmt: skip
    if force is not None or plastic is not None:
        raise ValueError(
            "`force` and `plastic` are taken for joints of stops only (c1 = 0); a structure "
            "with Coulomb joints runs on `simulate_network` (give it a NetworkStructure's "
            "forcing)."
        )
    return _network(st, t_end, q0, v0, times, max_events, None)


def _network(
    st: JointedStructure,
    t_end: float,
    q0: FloatArray,
    v0: FloatArray,
    times: FloatArray,
    max_events: int,
    state: NetworkState | None,
) -> StructureMotion:
    res = simulate_network(st.to_network(), t_end, None if state else q0, None if state else v0,
                           state if state is not None else "relaxed", times,
                           max_events=max_events)  # fmt: skip
    return StructureMotion(res.time, res.position, res.velocity, res.acceleration,
                           res.contact_displacement, res.contact_force, res.n_events, "network",
                           res.status, res.message)  # fmt: skip


def simulate_ring_down(
    structure: JointedStructure | Any,
    mode: int,
    amplitude: float,
    duration: float,
    *,
    start: str = "impulse",
    samples_per_period: int = 64,
) -> StructureMotion:
    """A free decay of a linear mode (joints stuck) from an impulse or a deflection.

    Parameters
    ----------
    structure : JointedStructure or NetworkStructure
    mode : int
        The linear mode (0: the lowest), joints stuck.
    amplitude : float
        a > 0 [m·kg^½]: 'impulse' gives q̇(0) = ω₀·a·φ (q = 0, the joints relaxed);
        'deflection' starts at rest from the quasi-static deflection at modal amplitude
        a along M·φ, the joints on their virgin curves (as after a slow static push).
    duration : float
        t_end [s].
    start : {'impulse', 'deflection'}
    samples_per_period : int
        Uniform samples per period of the linear mode.

    Returns
    -------
    StructureMotion
    """
    st = as_structure(structure)
    as_choice("start", start, ("impulse", "deflection"))
    a = as_positive_scalar("amplitude", amplitude, kind="modal amplitude")
    duration = as_positive_scalar("duration", duration)
    w0, phi = st.mode(mode)
    per = as_count("samples_per_period", samples_per_period, minimum=4)
    count = math.ceil(duration * w0 / (2 * math.pi) * per) + 1
    check_size("samples", count, count * 4 * st.n_coordinates)
    times = np.linspace(0.0, duration, count)
    n = st.n_coordinates
    if start == "impulse":
        if _stop_joints(st):
            return simulate_structure(st, duration, np.zeros(n), w0 * a * phi, t_eval=times)
        return _network(st, duration, np.zeros(n), w0 * a * phi, times, 1_000_000, None)
    q0 = modal_backbone(st, mode, [a]).deflection[0]
    g = st.contacts.T @ q0
    if _stop_joints(st):
        md = Model(st, np.zeros(n, complex), 0.0)
        e = np.clip(g[md.owner], -md.er, md.er)  # the stops on their virgin curve
        return simulate_structure(st, duration, q0, np.zeros(n), plastic=g[md.owner] - e,
                                  t_eval=times)  # fmt: skip
    k = np.concatenate([np.asarray(j.stiffness) for j in st.joints])
    r = np.concatenate([np.asarray(j.threshold) for j in st.joints])
    owner = np.concatenate([np.full(j.n_elements, c) for c, j in enumerate(st.joints)])
    state = NetworkState(time=0.0, position=q0, velocity=np.zeros(n), contact_displacement=g,
                         deformation=np.clip(g[owner], -r, r) if k.size else np.zeros(0),
                         mode=np.zeros(st.n_contacts), last_direction=np.sign(g))  # fmt: skip
    return _network(st, duration, q0, np.zeros(n), times, 1_000_000, state)
