"""Result records of `presliding.network`: `NetworkResult`, `NetworkEnergy`, `NetworkState`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from presliding.hysteresis._results import ResultMixin

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["NetworkEnergy", "NetworkResult", "NetworkState"]

FloatArray = NDArray[np.float64]

#: Statuses of a network motion.
STATUS_SUCCESS = "success"
STATUS_EVENT_LIMIT = "event_limit"


@dataclass(frozen=True, eq=False)
class NetworkState:
    """The state of a structure with contacts at one time (pass it on to continue a run).

    ``deformation`` holds the element deformations e_j = g_c − x_j of all contacts one
    after the other (contact 0's elements first); ``mode`` the contacts' modes (−1, +1
    sliding in that direction, 0 stuck); ``last_direction`` the last direction of motion
    of each contact (0: none yet), so that a reversal across two runs is counted.
    """

    time: float
    position: FloatArray
    velocity: FloatArray
    contact_displacement: FloatArray
    deformation: FloatArray
    mode: FloatArray
    last_direction: FloatArray


@dataclass(frozen=True, eq=False)
class NetworkEnergy:
    """Energy along the motion (per contact where it belongs to a contact), sampled like it.

    ``kinetic`` ½q̇ᵀMq̇, ``potential`` ½qᵀKq, ``elastic`` ½Σ k_j e_j² (all elements),
    ``coulomb`` (T, n_c) c1_c·∫|dg_c|, ``hysteretic`` (T, n_c) Σ c_j·∫|dx_j| of the sliding
    elements, ``viscous`` (T, n_c) σ_v,c·∫ġ_c² dt, ``damping`` ∫q̇ᵀCq̇ dt, ``work`` ∫fᵀdq,
    ``residual`` = kinetic + potential + elastic + all dissipation − work − ``initial``
    (zero to rounding: every term is in closed form).
    """

    kinetic: FloatArray
    potential: FloatArray
    elastic: FloatArray
    coulomb: FloatArray
    hysteretic: FloatArray
    viscous: FloatArray
    damping: FloatArray
    work: FloatArray
    initial: float

    @property
    def dissipated(self) -> FloatArray:
        """All dissipation (contacts and structural damping), shape (T,)."""
        return (
            self.coulomb.sum(axis=1) + self.hysteretic.sum(axis=1) + self.viscous.sum(axis=1)
            + self.damping
        )  # fmt: skip

    @property
    def residual(self) -> FloatArray:
        """The balance: stored + dissipated − work − initial, shape (T,)."""
        return (
            self.kinetic
            + self.potential
            + self.elastic
            + self.dissipated
            - self.work
            - (self.initial)
        )

    @property
    def max_relative_residual(self) -> float:
        """max |residual| over max(initial energy, max |work|)."""
        scale = max(self.initial, float(np.max(np.abs(self.work), initial=0.0)))
        return 0.0 if scale == 0.0 else float(np.max(np.abs(self.residual), initial=0.0)) / scale

    def to_dict(self) -> dict[str, Any]:
        """The terms by name (arrays), with ``dissipated`` and ``residual``."""
        out = {k: getattr(self, k) for k in ("kinetic", "potential", "elastic", "damping",
                                               "work", "dissipated", "residual")}  # fmt: skip
        for k in ("coulomb", "hysteretic", "viscous"):
            arr = getattr(self, k)
            for c in range(arr.shape[1]):
                out[f"{k}_{c}"] = arr[:, c]
        out["initial"] = self.initial
        return out


@dataclass(frozen=True, eq=False)
class NetworkResult(ResultMixin):
    """A simulated motion of a structure with friction contacts, sampled at ``time``.

    Attributes
    ----------
    time : ndarray, shape (T,)
    position, velocity, acceleration, applied_force : ndarray, shape (T, n)
        q [m], q̇ [m/s], q̈ [m/s²], f [N].
    contact_displacement, contact_velocity : ndarray, shape (T, n_c)
        g = Wᵀq [m] (held exactly while a contact sticks), ġ [m/s].
    contact_force, elastic_force : ndarray, shape (T, n_c)
        λ_c = c1_c σ_c + F_el,c + σ_v,c ġ_c and F_el,c [N].
    contact_mode : ndarray, shape (T, n_c)
        −1 or +1 sliding that way, 0 stuck.
    stick_intervals : list of ndarray (K, 2)
        Per contact, the [start, end] of every stick [s].
    reversal_times, reversal_displacements : list of ndarray
        Per contact, where its sliding direction reversed (turning points).
    stop_times : ndarray, shape (n_c,)
        Per contact, the start of the stick that lasts to the end (nan if sliding then).
    energy : NetworkEnergy
    final_state : NetworkState
    forces_unique : bool
        False when contacts stuck together redundantly (forces not unique).
    status : str
        "success"; "event_limit" (the exact path reached `max_events`: the samples stop
        there); "not_converged" (Moreau–Jean: a step's Gauss–Seidel reached
        `max_sweeps`; the message counts them).
    message : str
    success : bool
        True when `status` is "success".
    n_events : int
        Events (exact path) or steps (Moreau–Jean).
    method : str
        "event" or "moreau".
    certification : dict or None
        How the exact path certified its events (None for Moreau–Jean): ``cells``
        proved free of events (every event function's lower bound over the cell, from
        its values, slopes and a bound of its second derivative from the modal
        amplitudes, is nonnegative), ``isolated`` events (a root isolated on its cell:
        one sign change and a slope of one sign, refined by Brent's method),
        ``resolved`` events (a trigger found on a cell of the time resolution, ~1e-15 s:
        an event at the start of a piece), ``ends`` (pieces ended by a change of f or
        the end, their whole span proved free of events) and ``grazes`` (cells at the
        time resolution where a function came within rounding of zero, not an event).
    """

    time: FloatArray
    position: FloatArray
    velocity: FloatArray
    acceleration: FloatArray
    applied_force: FloatArray
    contact_displacement: FloatArray
    contact_velocity: FloatArray
    contact_force: FloatArray
    elastic_force: FloatArray
    contact_mode: FloatArray
    stick_intervals: list[FloatArray]
    reversal_times: list[FloatArray]
    reversal_displacements: list[FloatArray]
    stop_times: FloatArray
    energy: NetworkEnergy
    final_state: NetworkState
    forces_unique: bool
    status: str
    message: str
    n_events: int
    method: str
    structure: Any
    certification: dict[str, int] | None = None

    @property
    def success(self) -> bool:
        """True when `status` is "success"."""
        return self.status == STATUS_SUCCESS

    @property
    def n_reversals(self) -> NDArray[np.int64]:
        """Reversals per contact."""
        return np.array([r.shape[0] for r in self.reversal_times], dtype=np.int64)

    def to_dict(self) -> dict[str, Any]:
        """The fields by name (arrays per coordinate/contact as columns ``name_i``)."""
        out = super().to_dict()
        for name in ("position", "velocity", "acceleration", "applied_force",
                     "contact_displacement", "contact_velocity", "contact_force",
                     "elastic_force", "contact_mode"):  # fmt: skip
            arr = out.pop(name)
            for i in range(arr.shape[1]):
                out[f"{name}_{i}"] = arr[:, i]
        out.pop("structure", None)
        out.pop("final_state", None)
        return out

    def to_pandas(self) -> Any:
        """A DataFrame of the samples (one column per coordinate/contact), with ``attrs``."""
        frame = super().to_pandas()
        frame.attrs.update(n_events=self.n_events, forces_unique=self.forces_unique,
                           method=self.method)  # fmt: skip
        return frame

    def report(self) -> str:
        """A readable summary."""
        lines = [
            f"network motion ({self.method}): {self.status}",
            f"  {self.message}",
            f"  coordinates {self.position.shape[1]}, contacts {self.contact_force.shape[1]}, "
            f"events {self.n_events}, t = {self.time[0]:.6g} .. {self.time[-1]:.6g} s",
            f"  energy balance: max |residual| / scale = {self.energy.max_relative_residual:.2e}",
            *([] if self.certification is None else [f"  {_certified(self.certification)}"]),
            "  contact  reversals  stop time [s]   Coulomb [J]   hysteretic [J]  viscous [J]",
        ]
        for c in range(self.contact_force.shape[1]):
            stop = self.stop_times[c]
            lines.append(
                f"  {c:7d}  {self.n_reversals[c]:9d}  "
                f"{'moving' if np.isnan(stop) else f'{stop:.6g}':>13s}   "
                f"{self.energy.coulomb[-1, c]:11.4g}   {self.energy.hysteretic[-1, c]:14.4g}"
                f"  {self.energy.viscous[-1, c]:11.4g}"
            )
        return "\n".join(lines)

    def __repr__(self) -> str:
        return (
            f"NetworkResult(status={self.status!r}, method={self.method!r}, "
            f"n={self.position.shape[1]}, n_contacts={self.contact_force.shape[1]}, "
            f"samples={self.time.shape[0]}, n_events={self.n_events})"
        )

    def plot(self, ax: Axes | None = None, *, kind: str = "time") -> Axes:
        """Contact displacements over time ("time"), contact force against displacement
        per contact ("hysteresis"), the stick/slip timeline ("timeline") or the energy
        terms ("energy")."""
        from presliding.network._plots import plot_network

        return plot_network(self, kind=kind, ax=ax)


def _certified(counts: dict[str, int]) -> str:
    return (
        f"events certified: {counts['isolated']} isolated (one root on its cell), "
        f"{counts['resolved']} resolved to 1e-15 s, {counts['ends']} piece ends; "
        f"{counts['cells']} cells proved free of events, {counts['grazes']} grazes of zero "
        "within rounding"
    )


def _intervals(transitions: list[tuple[float, int, float]], c: int, t_end: float) -> FloatArray:
    out: list[tuple[float, float]] = []
    start: float | None = None
    for t, cc, s in transitions:
        if cc != c:
            continue
        if s == 0.0 and start is None:
            start = t
        elif s != 0.0 and start is not None:
            if t > start:
                out.append((start, t))
            start = None
    if start is not None:
        out.append((start, t_end))
    return np.array(out, dtype=float).reshape(-1, 2)


def build_result(structure: Any, net: Any, st: Any, out: Any, status: str, message: str,
                 e_initial: float, t0: float, method: str = "event") -> NetworkResult:  # fmt: skip
    """The result of a run from its state and samples."""
    k = out.filled
    n_c = structure.n_contacts
    stick = [_intervals(st.transitions, c, st.t) for c in range(n_c)]
    stops = np.array([s[-1, 0] if s.shape[0] and st.s[c] == 0.0 and s[-1, 1] == st.t
                      else np.nan for c, s in enumerate(stick)])  # fmt: skip
    rev_t = [np.array([t for t, cc, _ in st.reversals if cc == c]) for c in range(n_c)]
    rev_g = [np.array([g for _, cc, g in st.reversals if cc == c]) for c in range(n_c)]
    energy = NetworkEnergy(out.kinetic[:k], out.potential[:k], out.elastic[:k],
                           out.coulomb[:k], out.hysteretic[:k], out.viscous[:k],
                           out.damping[:k], out.work[:k], e_initial)  # fmt: skip
    final = NetworkState(st.t, st.q.copy(), st.v.copy(), st.g.copy(), st.e.copy(), st.s.copy(),
                         st.last.copy())  # fmt: skip
    return NetworkResult(
        time=out.time[:k], position=out.q[:k], velocity=out.v[:k], acceleration=out.a[:k],
        applied_force=out.f[:k], contact_displacement=out.g[:k], contact_velocity=out.gd[:k],
        contact_force=out.lam[:k], elastic_force=out.fel[:k], contact_mode=out.mode[:k],
        stick_intervals=stick, reversal_times=rev_t, reversal_displacements=rev_g,
        stop_times=stops, energy=energy, final_state=final, forces_unique=not st.redundant,
        status=status, message=message, n_events=st.n_events, method=method,
        structure=structure, certification=st.cert.counts(),
    )  # fmt: skip
