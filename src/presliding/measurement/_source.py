"""Where a `Measurement` came from (file, columns, units, factors, window) and its assembly.

`Source` is attached to every `Measurement` built by a reader (`from_csv`,
`from_mat`, `from_dataframe`, `join`) and carried through `window`,
`resample` and `differentiate`, so that a fit report and a model file can
state exactly which columns were used, in which units, with which factors
and on which window.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._axes import AXES
from presliding._validation import as_real_scalar, fmt
from presliding.measurement._units import SI_UNITS, UnitConversion, si_factor

__all__ = [
    "Source",
    "assemble",
    "build",
    "check_distinct_columns",
    "check_signal_names",
    "check_time_lines",
    "time_from_rate",
    "with_time",
]
SIGNALS = tuple(SI_UNITS)  # time first

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Source:
    """Provenance of a measurement's signals.

    Attributes
    ----------
    path : str or None
        The file read (None for a DataFrame or arrays).
    kind : str
        ``"csv"`` (delimited text), ``"mat"``, ``"dataframe"`` or ``"join"``.
    conversions : tuple of UnitConversion
        One per signal read, time included: column, unit, SI unit and factors.
    sample_rate : float or None
        The sample rate [Hz] the time base was built from, when the file has no
        time column.
    window : (float or None, float or None) or None
        The window [s] applied with `Measurement.window`.
    parts : tuple of Source
        The records of a `Measurement.join`.
    notes : tuple of str
        Further steps (rows dropped by a join, interpolation, resampling,
        differentiation with its cut-off).
    roles : tuple of str
        Why each column was taken for its signal, and why the file's other
        columns were not (set by the command line, which finds columns itself).
    """

    path: str | None
    kind: str
    conversions: tuple[UnitConversion, ...] = ()
    sample_rate: float | None = None
    window: tuple[float | None, float | None] | None = None
    parts: tuple[Source, ...] = ()
    notes: tuple[str, ...] = ()
    roles: tuple[str, ...] = ()

    @property
    def units(self) -> dict[str, str]:
        """SI unit of each signal read, by signal name."""
        out = {c.signal: c.si_unit for c in self.conversions}
        for part in self.parts:
            out.update({k: v for k, v in part.units.items() if k not in out})
        return out

    @property
    def axis_read(self) -> str | None:
        """The axis the units read show: ``"rotary"`` (an angle or a torque),
        ``"linear"`` (a length or a force), None when no unit says."""
        given = [c for c in self.all_conversions() if c.signal != "time" and c.unit is not None]
        if not given:
            return None
        return "rotary" if any(c.rotary for c in given) else "linear"

    def axis_conflict(self) -> str:
        """Why the units read do not fit one axis ("" when they do): an angle beside a force,
        a length beside a torque, an angular speed beside a length, ..."""
        given = [c for c in self.all_conversions() if c.signal != "time" and c.unit is not None]
        rotary = [c for c in given if c.rotary]
        linear = [c for c in given if not c.rotary]
        if not rotary or not linear:
            return ""

        def said(c: UnitConversion) -> str:
            return f"`{c.signal}` {c.column!r} is in {c.unit} (SI {c.si_unit})"

        torque = next((c.signal for c in rotary if c.si_unit == "N m"), "applied_force")
        return (
            f"the units read mix a rotary and a linear axis: {said(rotary[0])}, a rotary "
            f"axis, but {said(linear[0])}, a linear one; a rotary axis takes angles and torques "
            "(rad, N m), a linear one lengths and forces (m, N). Correct the unit in the "
            "header or give it with `units` (--units); a torque that drives a linear axis "
            "through a transmission is a force: give its unit N and the ratio with `units` and "
            f"`scale` (--units {torque}=N --scale {torque}=RATIO)"
        )

    def on_axis(self, axis: str) -> Source:
        """The same source with the signals read without a unit labelled in `axis`'s SI units."""
        kind = AXES.index(axis)
        conversions = tuple(
            replace(c, si_unit=SI_UNITS[c.signal][kind]) if c.unit is None else c
            for c in self.conversions
        )
        parts = tuple(p.on_axis(axis) for p in self.parts)
        return replace(self, conversions=conversions, parts=parts)

    @property
    def rotary(self) -> bool:
        """True when the position is an angle (or the forces are torques)."""
        conv = {c.signal: c for c in self.all_conversions()}
        if "position" in conv:
            return conv["position"].rotary
        return any(c.rotary for c in conv.values() if c.signal != "time")

    def all_conversions(self) -> tuple[UnitConversion, ...]:
        """The conversions of this source and of every joined part."""
        out = self.conversions
        for part in self.parts:
            out += part.all_conversions()
        return out

    def with_window(self, start: float | None, end: float | None) -> Source:
        """The same source with a (further) window applied."""
        return replace(self, window=(start, end))

    def with_note(self, note: str) -> Source:
        """The same source with one more processing note."""
        return replace(self, notes=(*self.notes, note))

    def describe(self, roles: bool = True) -> str:
        """Lines stating the file, the columns and units read, the factors and the window
        (and, unless `roles` is False, why each column was or was not taken)."""
        head = {"csv": "text file", "mat": "MATLAB file", "dataframe": "DataFrame",
                "join": "joined records"}.get(self.kind, self.kind)  # fmt: skip
        lines = [f"{head} {self.path}" if self.path else head]
        if self.sample_rate is not None:
            lines.append(f"  time: built from the sample rate {self.sample_rate:.6g} Hz")
        lines += [f"  {c.describe()}" for c in self.conversions]
        for i, part in enumerate(self.parts):
            lines += [f"  record {i}: " + part.describe().replace("\n", "\n  ")]
        if self.window is not None:
            lo, hi = self.window
            lo_text = "start" if lo is None else f"{lo:.6g} s"
            hi_text = "end" if hi is None else f"{hi:.6g} s"
            lines.append(f"  window: {lo_text} to {hi_text}")
        lines += [f"  {note}" for note in self.notes]
        lines += [f"  {role}" for role in self.roles] if roles else []
        return "\n".join(lines)


def _check_names(names: Any, label: str, allow_time: bool = True) -> None:
    allowed = tuple(SI_UNITS) if allow_time else tuple(SI_UNITS)[1:]
    for name in names:
        if name not in allowed:
            raise ValueError(f"{label} names must be among {', '.join(allowed)}; got {name!r}.")


def assemble(
    raw: Mapping[str, tuple[str, FloatArray, str | None]],
    *,
    path: str | None,
    kind: str,
    scale: Mapping[str, Any] | None,
    units: Mapping[str, str | None] | None,
    sample_rate: float | None = None,
    scale_lookup: Any = None,
) -> tuple[dict[str, FloatArray], Source]:
    """Signals in SI, scaled, and their `Source`.

    `raw` maps each signal to (column label, values, unit from the header or
    None). `units` overrides a header's unit (None or "" drops it: the values
    are then taken as SI). `scale` holds a factor per signal (a finite nonzero
    real, or for MATLAB files the name of a scalar variable, resolved by
    `scale_lookup(name, signal)`).
    """
    where = f"{path}: " if path else ""
    if scale is not None and not isinstance(scale, Mapping):
        raise TypeError(f"`scale` must be a mapping of signal names to factors; got {fmt(scale)}.")
    if units is not None and not isinstance(units, Mapping):
        raise TypeError(f"`units` must be a mapping of signal names to units; got {fmt(units)}.")
    scale, units = dict(scale or {}), dict(units or {})
    _check_names(scale, "`scale`")
    _check_names(units, "`units`")
    for label, spec in (("scale", scale), ("units", units)):
        extra = sorted(set(spec) - set(raw))
        if extra:
            raise ValueError(
                f"`{label}` names {extra[0]!r}, which is not read; the signals read are "
                f"{', '.join(raw)}."
            )
    signals, conversions = {}, []
    for sig, (column, values, header_unit) in raw.items():
        unit = units.get(sig, header_unit) or None
        if unit is not None and not isinstance(unit, str):
            raise TypeError(f"`units[{sig!r}]` must be a unit string; got {fmt(unit)}.")
        if unit is None:
            factor, si = 1.0, SI_UNITS[sig][0]
        else:
            factor, si = si_factor(sig, unit, column, where)
        given = scale.get(sig, 1.0)
        source = ""
        if isinstance(given, str):
            if scale_lookup is None:
                raise TypeError(
                    f"`scale[{sig!r}]` must be a real number (names of scalar variables work for "
                    f"MATLAB files only); got {given!r}."
                )
            source, given = f"variable {given}", scale_lookup(given, sig)
        factor_user = as_real_scalar(f"scale[{sig!r}]", given)
        if factor_user == 0.0:
            raise ValueError(f"`scale[{sig!r}]` must be nonzero; got 0.0.")
        out = np.asarray(values, dtype=np.float64) * (factor * factor_user)
        if not np.all(np.isfinite(out)):
            raise ValueError(
                f"{where}`{sig}` overflows when converted (× {factor * factor_user:g}); "
                "check the unit and the scale."
            )
        signals[sig] = out
        conversions.append(UnitConversion(sig, column, unit, si, factor, factor_user, source))
    return signals, Source(path, kind, tuple(conversions), sample_rate)


def time_from_rate(sample_rate: Any, n: int) -> FloatArray:
    """t = 0, 1/rate, 2/rate, ... for n samples (`sample_rate` a positive finite real [Hz])."""
    rate = as_real_scalar("sample_rate", sample_rate)
    if not rate > 0:
        raise ValueError(f"`sample_rate` must be positive; got {fmt(rate)}.")
    return np.arange(n, dtype=np.float64) / rate


def build(cls: type, raw, path, kind, scale, units, sample_rate, lookup=None, axis=None) -> Any:
    """A `Measurement` (`cls`) of the columns `raw` read from `path`, converted by `assemble`.

    Errors of the constructor (time not increasing, ...) are prefixed with the file.
    """
    if sample_rate is not None:
        n = len(next(iter(raw.values()))[1])
        raw = {"time": ("sample rate", time_from_rate(sample_rate, n), None), **raw}
    signals, source = assemble(raw, path=path, kind=kind, scale=scale, units=units,
                               sample_rate=sample_rate, scale_lookup=lookup)  # fmt: skip
    if sample_rate is not None:
        source = replace(source, conversions=source.conversions[1:])
    try:
        return cls(**signals, source=source, axis=axis)
    except ValueError as exc:
        raise ValueError(f"{path or 'df'}: {exc}") from None


def with_time(columns: Mapping[str, Any], time: Any, sample_rate: Any) -> dict[str, Any]:
    """The columns to read: the time column first, unless a sample rate replaces it."""
    if not columns:
        raise ValueError(
            "give at least one signal column, e.g. position=1 or position='x [mm]'; got none."
        )
    if time is not None and sample_rate is not None:
        raise ValueError(
            f"give `time` (a column) or `sample_rate`, not both; got time={time!r} and "
            f"sample_rate={sample_rate!r}."
        )
    if time is None and sample_rate is None:
        raise ValueError("`time` (a column) or `sample_rate` [Hz] must be given; got neither.")
    return dict(columns) if time is None else {"time": time, **columns}


def check_signal_names(names: Mapping[str, Any]) -> None:
    for name in names:
        if name not in SIGNALS[1:]:
            raise ValueError(f"signal names must be among {', '.join(SIGNALS[1:])}; got {name!r}.")


def check_distinct_columns(index: Mapping[str, Any], label: Any = str) -> None:
    """One column for one signal: the same column given to two signals is an error."""
    seen: dict[Any, str] = {}
    for sig, col in index.items():
        if col in seen:
            raise ValueError(
                f"column {label(col)!r} is given to both `{seen[col]}` and `{sig}`; each signal "
                "needs its own column."
            )
        seen[col] = sig


def check_time_lines(table: Any, t: FloatArray, label: str) -> None:
    """Time that does not increase, named by the file's line (not the array index)."""
    bad = ~(np.diff(t) > 0)
    if bad.any():
        i = int(np.argmax(bad)) + 1
        lines = table.row_lines()
        raise ValueError(
            f"{table.path}: line {lines[i]}, column {label!r}: time {fmt(t[i])} does not "
            f"increase (line {lines[i - 1]} has {fmt(t[i - 1])}); time must be strictly "
            "increasing."
        )
