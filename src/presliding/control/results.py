"""Results of closed loops: `LoopResult` (a `MotionResult` with the control signal) and
`LoopBatch` (many gain sets), and the measured limit cycle of a loop."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from presliding._display import figures_of, fill_attrs, result_html, short_repr
from presliding._interop import require
from presliding._validation import as_real_scalar, as_real_vector, check_same_length, fmt
from presliding.hysteresis._results import deprecated_code
from presliding.motion.results import STATUS_SUCCESS, MotionResult, motion_status

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

FloatArray = NDArray[np.float64]

__all__ = ["LoopBatch", "LoopResult", "MeasuredCycle", "measure_limit_cycle"]


class MeasuredCycle(NamedTuple):
    """An oscillation measured from turning points (`measure_limit_cycle`).

    A named tuple (amplitude, frequency, cycles, trend) that also follows the
    result convention: ``success`` is True when cycles were measured; ``status``
    is "steady" (swing changing by less than 2 %), "changing" (growing or
    decaying) or "none" (fewer than two full cycles in the window).
    """

    amplitude: float  #: half the mean swing between consecutive turning points [m]
    frequency: float  #: 2π over the mean time between every second turning point [rad/s]
    cycles: int  #: full cycles measured
    trend: float  #: last swing over first swing, minus 1 (0: steady; < 0: decaying)

    @property
    def steady(self) -> bool:
        """At least two cycles whose swing changes by less than 2 % over the window."""
        return self.cycles >= 2 and abs(self.trend) < 0.02

    @property
    def success(self) -> bool:
        """True when at least one full cycle was measured."""
        return self.cycles > 0

    @property
    def status(self) -> str:
        """One of "steady", "changing" or "none"."""
        return "none" if not self.cycles else ("steady" if self.steady else "changing")

    @property
    def message(self) -> str:
        """The measured cycle in words."""
        if not self.cycles:
            return "fewer than two full cycles after the start of the window"
        return (f"{self.cycles} cycles of amplitude {self.amplitude:.6g} m at "
                f"{self.frequency:.6g} rad/s, swing changing by {self.trend:+.1%}")  # fmt: skip

    def report(self) -> str:
        """A one-line summary."""
        return f"Measured oscillation: {self.status} ({self.message})"

    def to_dict(self) -> dict[str, Any]:
        """The figures and the status as plain values."""
        return {**self._asdict(), "status": self.status, "success": self.success,
                "message": self.message}  # fmt: skip

    def to_pandas(self) -> Any:
        """A one-row DataFrame of the figures and the status."""
        pd = require("pandas", "`to_pandas()`")

        frame = pd.DataFrame([self.to_dict()])
        return fill_attrs(frame, self, units={"amplitude": "m", "frequency": "rad/s"})

    def __repr__(self) -> str:
        return short_repr(self)

    def _repr_html_(self) -> str:
        """The status, amplitude, frequency, cycles and trend, for notebooks."""
        return result_html(self, figures_of(self, units={"amplitude": "m"}))

    def plot(self, ax: Axes | None = None) -> Axes:
        """The measured cycle as its first harmonic A·sin(ωt) over the cycles measured."""
        from presliding.plotting import new_axes

        ax = new_axes(ax)
        if self.cycles:
            t = np.linspace(0.0, 2.0 * np.pi * self.cycles / self.frequency, 200 * self.cycles)
            ax.plot(t, self.amplitude * np.sin(self.frequency * t), color="C0", lw=1.2)
        ax.set(xlabel="time from the window's start [s]", ylabel="position [m]",
               title=f"measured oscillation: {self.status}")  # fmt: skip
        return ax


def measure_limit_cycle(
    reversal_times: FloatArray, reversal_positions: FloatArray, after: float
) -> MeasuredCycle:
    """Amplitude, angular frequency, cycles and trend of the oscillation after time `after`.

    From the exact turning points: the amplitude is half the mean distance between
    consecutive turning points, the period the mean time between every second one,
    the trend the relative change of the swing from the first to the last pair of
    turning points. NaN (0 cycles, status "none") when fewer than two full cycles
    follow `after`; a window that starts after the last turning point given is an error.
    """
    t_all = as_real_vector("reversal_times", reversal_times, allow_empty=True)
    y_all = as_real_vector("reversal_positions", reversal_positions, allow_empty=True)
    check_same_length(reversal_times=t_all, reversal_positions=y_all)
    start = as_real_scalar("after", after)
    if t_all.shape[0] and start > t_all.max():
        raise ValueError(
            f"`after` must not lie after the last turning point t = {fmt(t_all.max())} s (the "
            f"window would hold none); got {fmt(start)}."
        )
    return _measure(t_all, y_all, start)


def _measure(t_all: FloatArray, y_all: FloatArray, after: float) -> MeasuredCycle:
    keep = t_all >= after
    t, y = t_all[keep], y_all[keep]
    if t.shape[0] < 5:
        return MeasuredCycle(float("nan"), float("nan"), 0, float("nan"))
    swing = np.abs(np.diff(y))
    amplitude = 0.5 * float(np.mean(swing))
    period = float(np.mean(t[2:] - t[:-2]))
    first, last = swing[:2].mean(), swing[-2:].mean()
    trend = float(last / first - 1.0) if first > 0 else float("nan")
    return MeasuredCycle(amplitude, 2.0 * np.pi / period, (t.shape[0] - 1) // 2, trend)


@dataclass(frozen=True, eq=False, repr=False)
class LoopResult(MotionResult):
    """A sampled-data closed loop (`simulate_loop`): the motion and the control signal.

    The motion fields are those of `MotionResult`, sampled at ``time`` (the
    sample instants, or `substeps` samples per period); ``applied_force`` is the
    held force u there. Beside them:

    Attributes
    ----------
    control_time : ndarray, shape (K + 1,)
        The sample instants t_k = t_start + k·dt.
    control : ndarray, shape (K + 1,)
        u_k, the controller's output (saturated, feedforward included) [N].
    reference : ndarray, shape (K + 1,)
        r_k [m].
    measured : ndarray, shape (K + 1,)
        y_k, the position the controller read [m].
    feedforward : ndarray, shape (K + 1,)
        u_ff,k [N] (zeros when none was given).
    controller : PID or DiscreteController
    status : str
        As for `MotionResult`: "success" or "event_limit" (the event limit
        `max_events` was reached; the samples stop there).
    """

    control_time: FloatArray
    control: FloatArray
    reference: FloatArray
    measured: FloatArray
    feedforward: FloatArray
    controller: Any

    @property
    def error(self) -> FloatArray:
        """e_k = r_k − y_k at the sample instants [m]."""
        return self.reference - self.measured

    def limit_cycle(self, after: float | None = None) -> MeasuredCycle:
        """The oscillation after `after` [s] (default: half way through the run): amplitude
        [m], angular frequency [rad/s], cycles and trend (see `measure_limit_cycle`)."""
        t0, t1 = float(self.time[0]), float(self.time[-1])
        start = 0.5 * (t0 + t1) if after is None else as_real_scalar("after", after)
        if start > t1:
            raise ValueError(
                f"`after` must not lie after the end of the run t = {fmt(t1)} s; got {fmt(start)}."
            )
        return _measure(self.reversal_times, self.reversal_positions, start)

    def plot(self, ax: Axes | None = None, *, kind: str = "tracking") -> Axes:
        """Position and reference over time ("tracking"), the error ("error"), the control
        signal ("control"), or a `MotionResult` kind ("time", "phase", "loop")."""
        from presliding.plotting import new_axes, place_legend

        if kind in ("time", "phase", "loop"):
            return super().plot(ax, kind=kind)
        if kind not in ("tracking", "error", "control"):
            raise ValueError(
                "`kind` must be one of 'tracking', 'error', 'control', 'time', 'phase', 'loop'; "
                f"got {fmt(kind)}."
            )
        ax = new_axes(ax)
        if kind == "tracking":
            ax.step(self.control_time, self.reference, where="post", color="k", lw=1.0,
                    label="reference r")  # fmt: skip
            ax.plot(self.time, self.position, color="C0", lw=1.2, label="position y")
            ax.set_ylabel("position [m]")
        elif kind == "error":
            ax.plot(self.control_time, self.error, color="C3", lw=1.0, label="error r − y")
            ax.set_ylabel("error [m]")
        else:
            ax.step(self.control_time, self.control, where="post", color="C2", lw=1.0,
                    label="control u")  # fmt: skip
            ax.plot(self.time, self.friction_force, color="C1", lw=1.0, label="friction F")
            ax.set_ylabel("force [N]")
        ax.set_xlabel("time t [s]")
        place_legend(ax, fontsize=8)
        return ax

    def report(self) -> str:
        """The motion's report and the tracking figures."""
        e = self.error
        lines = [
            super().report(),
            f"  controller {self.controller!r}",
            f"  {self.control_time.shape[0]} samples of dt = {self.controller.dt:g} s; "
            f"|u| max {np.max(np.abs(self.control)):.6g} N",
            f"  error: rms {np.sqrt(np.mean(e * e)):.6g} m, max |e| {np.max(np.abs(e)):.6g} m, "
            f"final {e[-1]:.6g} m",
        ]
        cyc = self.limit_cycle()
        if cyc.cycles:
            kind = "steady" if cyc.steady else f"swing changing by {cyc.trend:+.1%}"
            lines.append(
                f"  oscillation (second half): amplitude {cyc.amplitude:.6g} m, frequency "
                f"{cyc.frequency:.6g} rad/s ({cyc.cycles} cycles, {kind})"
            )
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """The sampled signals and the summary as plain Python/numpy values."""
        return {
            "time": self.time, "position": self.position, "velocity": self.velocity,
            "acceleration": self.acceleration, "friction_force": self.friction_force,
            "applied_force": self.applied_force, "control_time": self.control_time,
            "control": self.control, "reference": self.reference, "measured": self.measured,
            "feedforward": self.feedforward, "reversal_times": self.reversal_times,
            "reversal_positions": self.reversal_positions, "stop_time": self.stop_time,
            "status": str(self.status), "success": self.success, "message": self.message,
            "n_events": self.n_events, "mass": self.mass,
        }  # fmt: skip

    def to_pandas(self) -> Any:
        """A DataFrame of the controller's samples (time index t_k): r, y, e, u, u_ff."""
        pd = require("pandas", "`to_pandas()`")

        frame = pd.DataFrame(
            {"reference": self.reference, "position": self.measured, "error": self.error,
             "control": self.control, "feedforward": self.feedforward},
            index=pd.Index(self.control_time, name="time"),
        )  # fmt: skip
        return fill_attrs(frame, self, units={"error": "m", "position": "m"})


@dataclass(frozen=True, eq=False)
class LoopBatch:
    """Closed loops of many gain sets (`simulate_loop_batch`), e.g. for a tuning map.

    Attributes
    ----------
    kp, ki, kd : ndarray, shape (B,)
        The gains of each member.
    time : ndarray, shape (K + 1,)
        The sample instants.
    position, control : ndarray, shape (B, K + 1) or None
        y_k and u_k of each member (None with ``outputs="summary"``; NaN after a
        member's failure).
    error_rms, error_max, half_range : ndarray, shape (B,)
        rms and max |r_k − y_k| and half the range of y_k over the instants from
        `settle_time` on (half_range: the amplitude of a hunting cycle).
    n_reversals : ndarray of int, shape (B,)
    final_position, final_velocity : ndarray, shape (B,)
    member_status : ndarray of str, shape (B,)
        Each member's status: "success", "event_limit" (the event limit was
        reached) or "overflow" (the loop left the floating-point range: unstable
        gains; its summaries are NaN).
    settle_time : float
    message : str
    status : str
        "success" when every member succeeded, else the first failed member's
        status (as `MotionBatch.status`). Formerly the array of integer codes:
        `status_code` still gives it, deprecated.
    """

    kp: FloatArray
    ki: FloatArray
    kd: FloatArray
    time: FloatArray
    position: FloatArray | None
    control: FloatArray | None
    error_rms: FloatArray
    error_max: FloatArray
    half_range: FloatArray
    n_reversals: NDArray[np.int64]
    final_position: FloatArray
    final_velocity: FloatArray
    member_status: NDArray[np.str_]
    settle_time: float
    message: str

    def __post_init__(self) -> None:
        object.__setattr__(self, "member_status", np.asarray(self.member_status, dtype=np.str_))

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
        codes = np.where(self.member_status == STATUS_SUCCESS, 0, -1).astype(np.int64)
        return deprecated_code(codes, "'success' or 'event_limit'")

    def plot(self, ax: Axes | None = None, *, kind: str = "error_rms") -> Axes:
        """A summary ("error_rms", "error_max", "half_range") against the member index, or
        the positions of all members over time ("position")."""
        from presliding.plotting import new_axes

        ax = new_axes(ax)
        if kind == "position":
            if self.position is None:
                raise ValueError("`kind` 'position' needs outputs='full'; got a summary batch.")
            ax.plot(self.time, self.position.T, lw=0.8)
            ax.set(xlabel="time t [s]", ylabel="position y [m]")
            return ax
        if kind not in ("error_rms", "error_max", "half_range"):
            raise ValueError(
                "`kind` must be 'error_rms', 'error_max', 'half_range' or 'position'; got "
                f"{fmt(kind)}."
            )
        ax.plot(np.arange(self.kp.shape[0]), getattr(self, kind), "o-", ms=3)
        ax.set(xlabel="gain set [index]", ylabel=f"{kind.replace('_', ' ')} [m]", yscale="log")
        return ax

    def report(self) -> str:
        """A readable summary."""
        n = self.kp.shape[0]
        best = int(np.nanargmin(self.error_rms)) if np.any(np.isfinite(self.error_rms)) else 0
        return "\n".join([
            f"{n} closed loops, {self.time.shape[0]} samples each; {self.message}",
            f"  after t = {self.settle_time:g} s: rms error {np.nanmin(self.error_rms):.6g} .. "
            f"{np.nanmax(self.error_rms):.6g} m, half range of y "
            f"{np.nanmin(self.half_range):.6g} .. {np.nanmax(self.half_range):.6g} m",
            f"  smallest rms error: kp = {self.kp[best]:g} N/m, ki = {self.ki[best]:g} N/(m s), "
            f"kd = {self.kd[best]:g} N s/m",
        ])  # fmt: skip

    def to_dict(self) -> dict[str, Any]:
        """The per-member summaries (and signals, when kept) as plain values."""
        return {
            "kp": self.kp, "ki": self.ki, "kd": self.kd, "time": self.time,
            "position": self.position, "control": self.control, "error_rms": self.error_rms,
            "error_max": self.error_max, "half_range": self.half_range,
            "n_reversals": self.n_reversals, "final_position": self.final_position,
            "final_velocity": self.final_velocity, "member_status": self.member_status,
            "status": str(self.status), "settle_time": self.settle_time, "success": self.success,
            "message": self.message,
        }  # fmt: skip

    def to_pandas(self) -> Any:
        """One row per gain set: gains, summaries, status."""
        pd = require("pandas", "`to_pandas()`")

        cols = ("kp", "ki", "kd", "error_rms", "error_max", "half_range", "n_reversals",
                "final_position", "final_velocity", "member_status")  # fmt: skip
        frame = pd.DataFrame({c: getattr(self, c) for c in cols})
        frame.attrs.update(settle_time=self.settle_time)
        return fill_attrs(frame, self, units={"error_rms": "m", "error_max": "m"})

    def __repr__(self) -> str:
        return short_repr(self)

    def _repr_html_(self) -> str:
        """The status, the summaries' ranges and the best gain set, for notebooks."""
        figures = figures_of(self, ("time", "error_rms", "error_max", "half_range",
                                    "n_reversals", "settle_time"))  # fmt: skip
        ok = np.isfinite(self.error_rms)
        best = int(np.nanargmin(self.error_rms)) if np.any(ok) else None
        rows = []
        if best is not None:
            rows = [("kp", f"{self.kp[best]:.6g}", "N/m"),
                    ("ki", f"{self.ki[best]:.6g}", "N/(m s)"),
                    ("kd", f"{self.kd[best]:.6g}", "N s/m"),
                    ("error rms", f"{self.error_rms[best]:.6g}", "m")]  # fmt: skip
        return result_html(
            self,
            [("gain sets", str(self.kp.shape[0]), ""), *figures],
            (("smallest rms error", "value", "unit"), rows) if rows else None,
        )
