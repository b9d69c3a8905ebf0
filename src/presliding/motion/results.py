"""Result records of `presliding.motion`: `MotionResult` (with its `MotionEnergy`),
`MotionBatch` and `FreeResponse`."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from presliding.hysteresis._results import ResultMixin, Status, deprecated_code
from presliding.hysteresis.general_pi import MemoryState
from presliding.hysteresis.operators import PIState

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

FloatArray = NDArray[np.float64]

#: The statuses of a motion (`MotionResult`, `FreeResponse`, a `MotionBatch` member).
STATUS_SUCCESS = "success"
#: The event limit (`max_events`) was reached; the samples stop where the run stopped.
STATUS_EVENT_LIMIT = "event_limit"
#: The accuracy target `rtol`/`atol` was not met within the step limit.
STATUS_ACCURACY_NOT_MET = "accuracy_not_met"
#: A member of a closed-loop batch left the floating-point range (an unstable loop).
STATUS_OVERFLOW = "overflow"
#: Each status by its integer code of earlier releases (0 success, negative failure).
STATUSES = {0: STATUS_SUCCESS, -1: STATUS_EVENT_LIMIT, -2: STATUS_ACCURACY_NOT_MET,
            -3: STATUS_OVERFLOW}  # fmt: skip
_CODES = {name: code for code, name in STATUSES.items()}
_NAMES = "'success', 'event_limit', 'accuracy_not_met' or 'overflow'"


def motion_status(status: int | str) -> Status:
    """The string status of a motion from its integer code (or its name)."""
    if isinstance(status, str):
        if status not in _CODES:
            raise ValueError(f"`status` must be one of {_NAMES}; got {status!r}.")
        return Status(status, _CODES[status])
    return Status(STATUSES[int(status)], int(status))


def member_statuses(codes: NDArray[Any]) -> NDArray[np.str_]:
    """The string statuses of a batch's members from their integer codes."""
    return np.array([STATUSES[int(c)] for c in np.ravel(codes)], dtype=np.str_)


def _codes(statuses: NDArray[np.str_]) -> NDArray[np.int64]:
    """The integer codes of an array of motion statuses."""
    return np.array([_CODES[str(s)] for s in np.ravel(statuses)], dtype=np.int64).reshape(
        np.shape(statuses)
    )


@dataclass(frozen=True, eq=False)
class MotionEnergy:
    """Energy along a motion, sampled like the motion (the energy after eq. 12).

    ``kinetic`` ½·m·v², ``elastic`` ½·Σ k_j f_j² (½·∫ f² dμ for a density),
    ``dissipated`` by the Coulomb element and the sliding elements
    (c1·|dy| + Σ c_j·|dx_j|, rate independent), ``viscous`` by the viscous term
    (σ·∫ẏ² dt; zeros when σ = 0), ``work`` of u (∫u dy),
    ``residual`` = kinetic + elastic + dissipated + viscous − work − ``initial``:
    zero to rounding for the event method (its viscous part is a quadrature of
    the closed-form velocity, independent of the other terms); for the implicit
    method it equals minus the numerical dissipation of the scheme (O(h)).
    """

    kinetic: FloatArray
    elastic: FloatArray
    dissipated: FloatArray
    work: FloatArray
    residual: FloatArray
    initial: float
    viscous: FloatArray = field(default_factory=lambda: np.empty(0))  # zeros when not given

    def __post_init__(self) -> None:
        if self.viscous is None or (self.viscous.size == 0 < self.dissipated.size):
            object.__setattr__(self, "viscous", np.zeros_like(self.dissipated))

    def to_dict(self) -> dict[str, Any]:
        """The energy terms by name (arrays), ``initial`` and ``total_dissipated``."""
        return {
            "kinetic": self.kinetic, "elastic": self.elastic, "dissipated": self.dissipated,
            "viscous": self.viscous, "total_dissipated": self.total_dissipated,
            "work": self.work, "residual": self.residual, "initial": self.initial,
        }  # fmt: skip

    @property
    def total_dissipated(self) -> FloatArray:
        """All the energy the friction took: ``dissipated + viscous``."""
        return self.dissipated + self.viscous

    @property
    def max_relative_residual(self) -> float:
        """max |residual| over max(initial energy, max |work|), a scale-free balance check."""
        scale = max(self.initial, float(np.max(np.abs(self.work), initial=0.0)))
        if scale == 0.0:
            return 0.0
        return float(np.max(np.abs(self.residual), initial=0.0)) / scale


@dataclass(frozen=True, eq=False, repr=False)
class MotionResult(ResultMixin):
    """A simulated motion of a mass with PI friction (eq. 17), sampled at ``time``.

    Attributes
    ----------
    time, position, velocity, acceleration : ndarray, shape (T,)
        Samples [s, m, m/s, m/s²].
    friction_force : ndarray, shape (T,)
        c1·s + σ·ẏ + F_el with s ∈ Sign(ẏ) and σ the viscous coefficient, equal to
        u − m·ÿ (at rest: exactly u) [N].
    elastic_force : ndarray, shape (T,)
        F_el = Σ k_j (y − x_j) [N].
    applied_force : ndarray, shape (T,)
        u at the sample times [N].
    reversal_times, reversal_positions : ndarray
        Where the velocity changes sign: a new motion phase opposite to the
        previous one (the turning points; for the implicit method, to the step).
        A start from rest is not a reversal.
    stop_time : float or None
        Start of the rest lasting until the end (see the module notes); None if the
        mass moves at the end.
    rest_position : float or None
        Position at rest, None if it does not stop.
    energy : MotionEnergy
    final_state : PIState or MemoryState
        The friction memory at the end (pass it on to continue); a MemoryState
        for a model with a continuous density.
    final_velocity : float
    success : bool
        True when `status` is "success".
    status : str
        "success"; "event_limit" (`max_events` reached: the samples stop where the
        simulation stopped); "accuracy_not_met" (the accuracy target `rtol`/`atol`
        was not met within the step limit). Module constants `STATUS_SUCCESS`,
        `STATUS_EVENT_LIMIT`, `STATUS_ACCURACY_NOT_MET`. Formerly an int
        (0, -1, -2): `status_code` still gives it, deprecated.
    message : str
    method : str
        "event" or "implicit".
    n_events : int
        Events (event method) or steps (implicit method).
    error_estimate : float or None
        Implicit method with an accuracy target (`rtol`/`atol` of `simulate`):
        the step-doubling estimate of the largest position error at the samples
        [m]; None otherwise.
    """

    time: FloatArray
    position: FloatArray
    velocity: FloatArray
    acceleration: FloatArray
    friction_force: FloatArray
    elastic_force: FloatArray
    applied_force: FloatArray
    reversal_times: FloatArray
    reversal_positions: FloatArray
    stop_time: float | None
    rest_position: float | None
    energy: MotionEnergy
    final_state: PIState | MemoryState
    final_velocity: float
    status: str
    message: str
    method: str
    n_events: int
    mass: float
    model: Any
    error_estimate: float | None = field(default=None, kw_only=True)

    def __post_init__(self) -> None:
        object.__setattr__(self, "status", motion_status(self.status))

    @property
    def success(self) -> bool:
        """True when `status` is "success"."""
        return str(self.status) == STATUS_SUCCESS

    @property
    def status_code(self) -> int:
        """Deprecated: the integer status of earlier releases (0, -1, -2); use `status`."""
        return int(deprecated_code(_CODES[str(self.status)], _NAMES))

    @property
    def n_reversals(self) -> int:
        """Number of motion reversals (turning points before the stop)."""
        return int(self.reversal_times.shape[0])

    def plot(self, ax: Axes | None = None, *, kind: str = "time") -> Axes:
        """Velocity over time ("time"), phase portrait ("phase") or force loop ("loop")."""
        from presliding.plotting import plot_motion

        return plot_motion(self, kind=kind, ax=ax)

    def report(self) -> str:
        """A readable summary of the motion."""
        lines = [
            f"Motion of a mass m = {self.mass:g} kg with {self.model!r}",
            f"  method {self.method}: {self.n_events} "
            + ("events" if self.method == "event" else "steps")
            + f"; status {self.status} ({self.message})",
            f"  time {self.time[0]:g} .. {self.time[-1]:g} s ({self.time.shape[0]} samples)",
        ]
        if self.stop_time is None:
            lines.append(f"  moving at the end: velocity {self.final_velocity:.6g} m/s")
        else:
            lines.append(
                f"  stops at t = {self.stop_time:.12g} s at position {self.rest_position:.12g} m"
            )
        if self.error_estimate is not None:
            lines.append(f"  position error estimate (step doubling): {self.error_estimate:.3g} m")
        lines.append(f"  reversals: {self.n_reversals}")
        for t, y in zip(self.reversal_times[:10], self.reversal_positions[:10], strict=True):
            lines.append(f"    t = {t:.12g} s  y = {y:.12g} m")
        if self.n_reversals > 10:
            lines.append(f"    ... {self.n_reversals - 10} more")
        e = self.energy
        viscous = f" (+ viscous {e.viscous[-1]:.6g} J)" if np.any(e.viscous) else ""
        lines.append(
            f"  energy: initial {e.initial:.6g} J, dissipated {e.dissipated[-1]:.6g} J{viscous}, "
            f"work of u {e.work[-1]:.6g} J, balance residual {e.max_relative_residual:.2e} "
            "(relative)"
        )
        return "\n".join(lines)


@dataclass(frozen=True, eq=False, repr=False)
class MotionBatch(ResultMixin):
    """Many exact motions on one time grid (`presliding.motion.simulate_batch`).

    Attributes
    ----------
    time : ndarray, shape (T,)
    position, velocity : ndarray, shape (B, T)
    stop_time : ndarray, shape (B,)
        Start of the final rest; ``inf`` where the member still moves at the end.
    n_reversals : ndarray of int, shape (B,)
    final_position, final_velocity : ndarray, shape (B,)
    member_status : ndarray of str, shape (B,)
        Each member's status: "success" or "event_limit" (that member's samples
        after the limit are not computed and hold ``nan``).
    message : str
    status : str
        "success" when every member succeeded, else the status of the first
        member that did not (a str, like `MotionResult.status`; ``success`` is
        True exactly when it is "success"). Formerly `status` was the array
        of integer codes: `status_code` still gives it, deprecated.

    ``to_pandas()`` has one row per member (stop time, reversals, final
    position and velocity, status).
    """

    _rows = "stop_time"
    _rows_are_index = False

    time: FloatArray
    position: FloatArray
    velocity: FloatArray
    stop_time: FloatArray
    n_reversals: NDArray[np.int64]
    final_position: FloatArray
    final_velocity: FloatArray
    member_status: NDArray[np.str_]
    message: str

    def __post_init__(self) -> None:
        member = np.asarray(self.member_status)
        if member.dtype.kind in "iu":  # integer codes
            member = member_statuses(member)
        object.__setattr__(self, "member_status", member.astype(np.str_))

    @property
    def status(self) -> str:
        """The overall status: "success" when every member succeeded, else the first failure's."""
        failed = self.member_status[self.member_status != STATUS_SUCCESS]
        return motion_status(str(failed[0]) if failed.size else STATUS_SUCCESS)

    @property
    def success(self) -> bool:
        """True when every member succeeded."""
        return bool(np.all(self.member_status == STATUS_SUCCESS))

    @property
    def status_code(self) -> NDArray[np.int64]:
        """Deprecated: the integer status of each member (0 or -1); use `member_status`."""
        return deprecated_code(_codes(self.member_status), _NAMES)

    @property
    def stopped(self) -> NDArray[np.bool_]:
        """Members at rest at the end."""
        return np.isfinite(self.stop_time)

    def plot(self, ax: Axes | None = None, *, kind: str = "velocity") -> Axes:
        """Velocities ("velocity") or positions ("position") of all members over time."""
        from presliding.plotting import plot_batch

        return plot_batch(self, kind=kind, ax=ax)

    def report(self) -> str:
        """A readable summary."""
        n = self.position.shape[0]
        st = self.stop_time[self.stopped]
        lines = [
            f"{n} motions, {self.time.shape[0]} samples each; {self.message}",
            f"  at rest at the end: {int(self.stopped.sum())} of {n}",
        ]
        if st.size:
            lines.append(f"  stop times: {np.min(st):.6g} .. {np.max(st):.6g} s")
        lines.append(
            f"  reversals: {int(np.min(self.n_reversals))} .. {int(np.max(self.n_reversals))}"
        )
        return "\n".join(lines)


@dataclass(frozen=True, eq=False, repr=False)
class FreeResponse(ResultMixin):
    """Exact samples of one motion at t = i·time_step (`presliding.motion.free_response`).

    Attributes
    ----------
    time, position, velocity : ndarray, shape (T,)
        Samples [s, m, m/s]; T = n_samples on success. When the event limit is
        reached (status "event_limit") only the samples before it are computed, and the
        arrays end there (T < n_samples).
    stop_time : float or None
        Start of the final rest; None if the mass moves at the end.
    n_reversals : int
    status : str
        "success" or "event_limit" (the event limit was reached). Formerly an
        int (0, -1): `status_code` still gives it, deprecated.
    message : str
    """

    time: FloatArray
    position: FloatArray
    velocity: FloatArray
    stop_time: float | None
    n_reversals: int
    status: str
    message: str

    def __post_init__(self) -> None:
        object.__setattr__(self, "status", motion_status(self.status))

    @property
    def success(self) -> bool:
        """True when `status` is "success"."""
        return str(self.status) == STATUS_SUCCESS

    @property
    def status_code(self) -> int:
        """Deprecated: the integer status of earlier releases (0, -1); use `status`."""
        return int(deprecated_code(_CODES[str(self.status)], _NAMES))

    def plot(self, ax: Axes | None = None) -> Axes:
        """Velocity over time, the stop marked."""
        from presliding.plotting import plot_free_response

        return plot_free_response(self, ax=ax)

    def report(self) -> str:
        """A readable summary."""
        n = self.time.shape[0]
        span = f", t = {self.time[0]:g} .. {self.time[-1]:g} s" if n else ""
        lines = [
            f"Free response: {n} samples{span}; status {self.status} ({self.message})",
            f"  reversals: {self.n_reversals}",
        ]
        if not self.success:
            lines.append(
                "  not solved to the end: the samples end where the event limit stopped it"
            )
        elif self.stop_time is None:
            lines.append(f"  moving at the end: velocity {self.velocity[-1]:.6g} m/s")
        else:
            lines.append(
                f"  stops at t = {self.stop_time:.12g} s at position {self.position[-1]:.12g} m"
            )
        return "\n".join(lines)
