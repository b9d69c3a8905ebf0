"""Cutting a long record into stops, loops or ramps (`Measurement.segments`).

A rig seldom records one experiment per file: a servo file holds several
decelerations to rest, a joint's file a train of loops or ramps. `segment`
cuts a record into pieces that a pooled fit takes as records, and states what
it cut (`Segments.table`):

- ``"stops"``: each arrival at rest. A stop starts where the input drops to
  its final level (the applied force of the piece; else where the speed peaks
  before the rest), less a lead-in, and ends after the rest has held as long
  as the deceleration took (or where the next motion starts);
- ``"loops"``: from a turning point of the position to the second turning
  point after it (one closed cycle each);
- ``"ramps"``: from one turning point to the next (one monotone run each).

Turning points are reversals of the position by more than a tolerance (by
default three quanta of the position where it is quantised, else 1 % of its
span), so quantisation and noise do not cut a ramp.

The cut is reproducible: `Segments.parameters` holds every value it used (the
defaults resolved for the record: the rest speed, the tolerance), so passing
them back cuts the same pieces, and `Segments.plot` shows the windows on the
whole record. Each option belongs to one kind: ``lead_in`` and ``rest_speed``
to stops, ``tolerance`` to loops and ramps; given to another kind, it is an
error rather than ignored.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from presliding._validation import (
    as_choice,
    as_count,
    as_nonnegative_scalar,
    as_positive_scalar,
    fmt,
)

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["Segments", "segment", "turning_indices"]

FloatArray = NDArray[np.float64]
KINDS = ("stops", "loops", "ramps")


@dataclass(frozen=True)
class Segments:
    """The pieces of a record and what was cut.

    Attributes
    ----------
    records : tuple of Measurement
        The pieces, in time order.
    spans : tuple of (int, int)
        Sample ranges [start, stop) of each piece in the original record.
    kind : str
        ``"stops"``, ``"loops"`` or ``"ramps"``.
    reasons : tuple of str
        Why each piece starts where it does (``"input drop"``, ``"speed peak"``,
        ``"turning point"``).
    source : str
        The record cut (its file, or ``"record"``).
    parameters : dict
        Every value the cut used, defaults resolved for this record: ``kind``,
        ``min_samples``, and for stops ``rest_speed`` [m/s or rad/s] and
        ``lead_in`` [s] (None: a fifth of each deceleration), for loops and
        ramps ``tolerance`` [m or rad]. ``record.segments(**parameters)`` cuts
        the same pieces.
    record : Measurement or None
        The record that was cut (for `plot`).
    """

    records: tuple[Any, ...]
    spans: tuple[tuple[int, int], ...]
    kind: str
    reasons: tuple[str, ...]
    source: str = "record"
    parameters: dict[str, Any] = field(default_factory=dict)
    record: Any = field(default=None, repr=False)

    def __len__(self) -> int:
        return len(self.records)

    def __iter__(self) -> Any:
        return iter(self.records)

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            return self.records[i]
        if isinstance(i, (bool, np.bool_)) or not isinstance(i, (int, np.integer)):
            raise TypeError(f"a segment index must be an integer or a slice; got {fmt(i)}.")
        n = len(self.records)
        if not -n <= i < n:
            raise IndexError(
                f"segment index {int(i)} is out of range: {n} {self.kind} were cut from "
                f"{self.source} (indices 0 to {n - 1}, or -{n} to -1)."
            )
        return self.records[i]

    def table(self) -> list[dict[str, Any]]:
        """One row per piece: number, start and end [s], samples, and why it starts there."""
        return [
            {"segment": i + 1, "start [s]": float(r.time[0]), "end [s]": float(r.time[-1]),
             "samples": int(r.n_samples), "from": why}
            for i, (r, why) in enumerate(zip(self.records, self.reasons, strict=True))
        ]  # fmt: skip

    def describe_parameters(self) -> str:
        """The values the cut used, in words with units (``rest speed 0.0012 m/s, ...``)."""
        p, unit = self.parameters, _unit(self.record, "position")
        if not p:
            return ""
        if p.get("kind") == "stops":
            lead = p.get("lead_in")
            speed = f"{p['rest_speed']:.6g} {_unit(self.record, 'velocity')}"
            lead_text = "a fifth of each deceleration" if lead is None else f"{lead:.6g} s"
            text = f"rest speed {speed}, lead-in {lead_text}"
        else:
            text = f"turning-point tolerance {p['tolerance']:.6g} {unit}"
        return f"{text}, at least {p['min_samples']} samples a piece"

    def report(self) -> str:
        """The table as text, with the parameters of the cut."""
        lines = [f"{len(self)} {self.kind} cut from {self.source}:"]
        if self.parameters:
            lines.append(f"  cut with {self.describe_parameters()}")
        lines += [
            f"  {row['segment']:>3}  {row['start [s]']:>10.6g} s to {row['end [s]']:<10.6g} s"
            f"  {row['samples']:>7} samples  from the {row['from']}"
            for row in self.table()
        ]
        return "\n".join(lines)

    def plot(self, ax: Axes | None = None) -> Axes:
        """The whole record (velocity, else position) with each piece's window shaded and
        numbered, and the applied force where measured; returns the axes."""
        from presliding._figures import new_axes, place_legend

        m = self.record
        if m is None:
            raise ValueError("this `Segments` holds no record to draw; cut it with "
                             "`Measurement.segments`.")  # fmt: skip
        name = "velocity" if m.velocity is not None else "position"
        if name == "velocity" or m.position is not None:
            values = getattr(m, name)
        else:  # only forces: the windows over the applied force
            name, values = "applied_force", m.applied_force
        ax = new_axes(ax)
        ax.plot(m.time, values, color="0.25", lw=1.0, label=name.replace("_", " "))
        for i, (a, b) in enumerate(self.spans):
            ax.axvspan(m.time[a], m.time[b - 1], color=f"C{i % 2}", alpha=0.18, lw=0,
                       label=f"{self.kind} (windows)" if i == 0 else None)  # fmt: skip
            ax.text(0.5 * (m.time[a] + m.time[b - 1]), 0.98, str(i + 1), ha="center",
                    va="top", fontsize="small", transform=ax.get_xaxis_transform())  # fmt: skip
        quantity = "force" if name == "applied_force" else name
        ax.set(xlabel="time [s]", ylabel=f"{name.replace('_', ' ')} [{_unit(m, quantity)}]",
               title=f"{len(self)} {self.kind} cut from {_short(self.source)}")  # fmt: skip
        if name != "applied_force" and m.applied_force is not None:
            twin = ax.twinx()
            twin.plot(m.time, m.applied_force, color="C3", lw=0.8, alpha=0.7)
            twin.set_ylabel(f"applied force [{_unit(m, 'force')}]", color="C3")
            ax.plot([], [], color="C3", lw=0.8, label="applied force (right)")
            # off the data of both axes: right of the twin's labels
            ax.legend(frameon=False, loc="upper left", bbox_to_anchor=(1.1, 1.0),
                      fontsize="small")  # fmt: skip
        else:
            place_legend(ax)
        return ax

    def __repr__(self) -> str:
        return f"Segments({len(self)} {self.kind} of {self.source})"


def _unit(m: Any, quantity: str) -> str:
    return "m" if m is None else m.unit(quantity)


def _short(source: str) -> str:
    from pathlib import Path

    return Path(source).name if source != "record" else source


def turning_indices(y: FloatArray, tolerance: float) -> NDArray[np.int64]:
    """Indices of the turning points of `y`: extremes followed by a retreat > `tolerance`.

    One pass with the running extreme of the current run (a record-length
    scan, not a hot path).
    """
    out: list[int] = []
    direction, ext, lo, hi = 0, 0, 0, 0
    for i in range(1, y.shape[0]):
        yi = y[i]
        if direction == 0:
            hi = i if yi > y[hi] else hi
            lo = i if yi < y[lo] else lo
            if yi - y[lo] > tolerance:
                direction, ext = 1, hi
            elif y[hi] - yi > tolerance:
                direction, ext = -1, lo
        elif direction > 0:
            if yi > y[ext]:
                ext = i
            elif y[ext] - yi > tolerance:
                out.append(ext)
                direction, ext = -1, i
        elif yi < y[ext]:
            ext = i
        elif yi - y[ext] > tolerance:
            out.append(ext)
            direction, ext = 1, i
    return np.asarray(out, dtype=np.int64)


def _tolerance(y: FloatArray) -> float:
    steps = np.abs(np.diff(y))
    steps = steps[steps > 0]
    span = float(np.ptp(y))
    if steps.size:
        quantum = float(np.min(steps))
        # quantised: the steps are whole multiples of the smallest one
        if quantum > 0 and np.allclose(steps / quantum, np.round(steps / quantum), atol=1e-6):
            return 3.0 * quantum
    return 0.01 * span


#: The options of each kind of cut: any other is refused, never ignored.
OPTIONS = {"stops": ("lead_in", "rest_speed"), "loops": ("tolerance",),
           "ramps": ("tolerance",)}  # fmt: skip


def segment(
    m: Any,
    kind: str = "stops",
    *,
    lead_in: float | None = None,
    rest_speed: float | None = None,
    tolerance: float | None = None,
    min_samples: int = 10,
) -> Segments:
    """Cut `m` into pieces (see the module notes and `Measurement.segments`)."""
    kind = as_choice("kind", kind, KINDS)
    given = {"lead_in": lead_in, "rest_speed": rest_speed, "tolerance": tolerance}
    for name, value in given.items():
        if value is not None and name not in OPTIONS[kind]:
            owner = "stops" if name != "tolerance" else "loops and ramps"
            raise ValueError(
                f"`{name}` is an option of cutting {owner}, not {kind} (which take "
                f"{' and '.join(f'`{o}`' for o in OPTIONS[kind])}); got {name}={fmt(value)}."
            )
    least = as_count("min_samples", min_samples, minimum=2)
    label = m.source.path if m.source is not None and m.source.path else "record"
    parameters: dict[str, Any] = {"kind": kind}
    if kind == "stops":
        spans, reasons, rest, lead = _stops(m, lead_in, rest_speed, least)
        parameters.update(lead_in=lead, rest_speed=rest)
    else:
        (y,) = m.require("position", purpose=f"cutting {kind}")
        y = np.asarray(y, dtype=float)
        if not float(np.ptp(y)) > 0:
            raise ValueError(f"{label}: the position never moves (it is constant): there are no "
                             f"{kind} to cut.")  # fmt: skip
        tol = (
            _tolerance(y)
            if tolerance is None
            else as_positive_scalar("tolerance", tolerance, kind="position")
        )
        turns = [0, *turning_indices(y, tol).tolist(), y.shape[0] - 1]
        step = 2 if kind == "loops" else 1
        spans = [(turns[i], turns[i + step] + 1) for i in range(0, len(turns) - step, step)]
        # a piece must have at least `min_samples` samples and travel beyond the tolerance
        # (quantisation jitter at rest is no ramp)
        spans = [s for s in spans if s[1] - s[0] >= least and np.ptp(y[s[0] : s[1]]) > tol]
        reasons = ["turning point"] * len(spans)
        parameters["tolerance"] = tol
    parameters["min_samples"] = least
    if not spans:
        option = "`rest_speed` or `lead_in`" if kind == "stops" else "`tolerance`"
        raise ValueError(
            f"{label}: no {kind} found to cut (the record has {m.n_samples} samples over "
            f"{fmt(m.duration)} s); check the signals, or set {option} or `min_samples`."
        )
    pieces = tuple(m._map(lambda a, s=s: a[s[0] : s[1]], m.time[s[0] : s[1]]) for s in spans)
    if m.source is not None:
        pieces = tuple(
            _noted(p, f"segment {i + 1} of {len(spans)} ({kind}): samples {a} to {b - 1}")
            for i, (p, (a, b)) in enumerate(zip(pieces, spans, strict=True))
        )
    return Segments(pieces, tuple(spans), kind, tuple(reasons), label, parameters, m)


def _noted(m: Any, note: str) -> Any:
    from dataclasses import replace

    return replace(m, source=m.source.with_note(note))


def _stops(m: Any, lead_in: float | None, rest_speed: float | None, min_samples: int) -> Any:
    """(spans, reasons, rest speed, lead-in) of the stops of `m`."""
    t = m.time
    if m.velocity is not None:
        v = np.asarray(m.velocity, dtype=float)
    else:
        (y,) = m.require("position", purpose="cutting stops (or `velocity`)")
        v = np.gradient(np.asarray(y, dtype=float), t)
    width = max(1, min(25, t.shape[0] // 200))
    speed = np.convolve(np.abs(v), np.ones(width) / width, mode="same")
    top = float(np.percentile(speed, 99))
    if not top > 0:
        raise ValueError("the record never moves: there are no stops to cut.")
    rest = 0.02 * top if rest_speed is None else as_positive_scalar("rest_speed", rest_speed)
    moving = speed > rest
    edges = np.flatnonzero(np.diff(moving.astype(np.int8)))
    starts = [0] if moving[0] else []
    starts += [int(e) + 1 for e in edges if not moving[e]]
    ends = [int(e) + 1 for e in edges if moving[e]]  # first sample at rest
    # a motion is a run that reaches a quarter of the top speed: the creep and rebound of
    # presliding after a stop, and noise, are not motions of their own
    runs = [(a, next((e for e in ends if e > a), t.shape[0])) for a in starts]
    runs = [(a, e) for a, e in runs if float(np.max(speed[a:e])) >= 0.25 * top]
    starts, ends = [a for a, _ in runs], [e for _, e in runs if e < t.shape[0]]
    lead = None if lead_in is None else as_nonnegative_scalar("lead_in", lead_in)
    spans: list[tuple[int, int]] = []
    reasons: list[str] = []
    for end in ends:
        begin = max([s for s in starts if s < end], default=0)
        after = next((s for s in starts if s > end), t.shape[0])
        drop, why = _drop(m, v, begin, end)
        held = max((3 * (end - drop)) // 2, min_samples)
        stop = min(after, end + held, t.shape[0], _next_input(m.applied_force, end))
        if lead is None:
            first = max(begin, drop - max((end - drop) // 5, 2))
        else:
            first = int(np.searchsorted(t, t[drop] - lead))
        first = max(first, spans[-1][1] if spans else 0)
        if stop - first >= min_samples:
            spans.append((first, stop))
            reasons.append(why)
    return spans, reasons, rest, lead


def _next_input(u: FloatArray | None, end: int) -> int:
    """The first sample after `end` where the input leaves its level at `end` (else the end)."""
    if u is None or end >= u.shape[0]:
        return end if u is not None else np.iinfo(np.int64).max
    span = float(np.ptp(u))
    away = np.flatnonzero(np.abs(u[end:] - u[end]) > 0.1 * span)
    return end + int(away[0]) if span > 0 and away.size else u.shape[0]


def _drop(m: Any, v: FloatArray, begin: int, end: int) -> tuple[int, str]:
    """Where the deceleration into the rest at `end` starts: the input's drop, else the peak."""
    u = m.applied_force
    if u is not None:
        final = float(u[min(end, u.shape[0] - 1)])
        span = float(np.ptp(u[begin : end + 1])) if end > begin else 0.0
        if span > 0:
            away = np.flatnonzero(np.abs(u[begin:end] - final) > 0.1 * span)
            if away.size:
                return begin + int(away[-1]) + 1, "input drop"
    return begin + int(np.argmax(np.abs(v[begin:end]))) if end > begin else begin, "speed peak"
