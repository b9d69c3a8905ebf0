"""The ``[data]`` table of a model file: how the fitted records were read.

``presliding fit`` states here the columns it took for each signal (found by
name, by unit or given with ``--columns``), the units and factors it was told,
the sample rate, the text options and the cut into segments, so that
``presliding predict`` reads new records of the same rig the same way (and says
where it cannot). Every key is optional; an unknown key is an error, as
everywhere in a model file::

    [data]
    columns = { time = "Time [s]", position = "Position [mm]", applied_force = "Force [N]" }
    units = { position = "mm" }          # units given besides the headers' (--units)
    scale = { applied_force = -1.0 }     # factors (--scale; a MAT variable's name)
    sample_rate = 1000.0                 # [Hz], for files without a time column
    decimal = ","                        # the decimal mark of text files
    header = false                       # text files without a header line
    axis = "rotary"
    segments = { kind = "stops", lead_in = 0.02 }   # the cut (--segments and its options)
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import Any

__all__ = ["SIGNALS", "DataSettings", "data_from_table", "data_lines"]

#: The signals a column can hold.
SIGNALS = ("time", "position", "velocity", "acceleration", "applied_force", "friction_force")
#: The options of a cut into segments (`presliding.measurement.Measurement.segments`).
SEGMENT_KEYS = ("kind", "lead_in", "rest_speed", "tolerance", "min_samples")
_KEYS = ("columns", "units", "scale", "sample_rate", "decimal", "header", "axis", "segments")


@dataclass(frozen=True)
class DataSettings:
    """The ``[data]`` table: how the records of a fit were read (module notes).

    Attributes
    ----------
    columns : dict signal -> str or int
        The column (a header name, a 0-based index, a MAT variable) of each signal.
    units, scale : dict signal -> str, float or str
        Units and factors given besides the file's own (a scale may name a MAT variable).
    sample_rate : float or None
        [Hz] of files without a time column.
    decimal : str or None
    header : bool or None
    axis : str or None
    segments : dict
        The cut: ``kind`` and the options given (`Measurement.segments`); empty for none.
    """

    columns: dict[str, str | int] = field(default_factory=dict)
    units: dict[str, str] = field(default_factory=dict)
    scale: dict[str, float | str] = field(default_factory=dict)
    sample_rate: float | None = None
    decimal: str | None = None
    header: bool | None = None
    axis: str | None = None
    segments: dict[str, Any] = field(default_factory=dict)

    @property
    def empty(self) -> bool:
        """True when the table states nothing (a model file written by hand)."""
        return self == DataSettings()


def _fail(where: str, key: str, rule: str, value: Any) -> ValueError:
    return ValueError(f"{where}`data.{key}` must be {rule}; got {value!r}.")


def _signal_table(where: str, key: str, value: Any, kinds: tuple[type, ...]) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise _fail(where, key, "a table of signal names", value)
    for signal, item in value.items():
        if signal not in SIGNALS:
            raise _fail(where, f"{key}.{signal}", f"a signal among {', '.join(SIGNALS)}", signal)
        ok = isinstance(item, kinds) and not isinstance(item, bool)
        if not ok or (isinstance(item, float) and not math.isfinite(item)):
            names = " or ".join("a string" if k is str else "a number" for k in kinds)
            raise _fail(where, f"{key}.{signal}", names, item)
    return dict(value)


def data_from_table(table: Any, where: str = "") -> DataSettings:
    """The `DataSettings` of a ``[data]`` table (every key checked; `where` prefixes errors)."""
    if not isinstance(table, dict):
        raise ValueError(f"{where}`data` must be a table; got {type(table).__name__}.")
    unknown = sorted(set(table) - set(_KEYS))
    if unknown:
        raise ValueError(
            f"{where}unknown key `data.{unknown[0]}`; allowed keys are {', '.join(_KEYS)}."
        )
    out: dict[str, Any] = {
        "columns": _signal_table(where, "columns", table.get("columns", {}), (str, int)),
        "units": _signal_table(where, "units", table.get("units", {}), (str,)),
        "scale": _signal_table(where, "scale", table.get("scale", {}), (int, float, str)),
    }
    rate = table.get("sample_rate")
    if rate is not None and (isinstance(rate, bool) or not isinstance(rate, (int, float))
                             or not (math.isfinite(rate) and rate > 0)):  # fmt: skip
        raise _fail(where, "sample_rate", "a positive number [Hz]", rate)
    out["sample_rate"] = None if rate is None else float(rate)
    for key, rule, ok in (
        ("decimal", "'.' or ','", lambda v: v in (".", ",")),
        ("header", "true or false", lambda v: isinstance(v, bool)),
        ("axis", "'linear' or 'rotary'", lambda v: v in ("linear", "rotary")),
    ):
        value = table.get(key)
        if value is not None and not ok(value):
            raise _fail(where, key, rule, value)
        out[key] = value
    cut = table.get("segments", {})
    if not isinstance(cut, dict) or (cut and cut.get("kind") not in ("stops", "loops", "ramps")):
        raise _fail(where, "segments", "a table with kind 'stops', 'loops' or 'ramps'", cut)
    bad = sorted(set(cut) - set(SEGMENT_KEYS))
    if bad:
        raise _fail(where, f"segments.{bad[0]}", f"one of {', '.join(SEGMENT_KEYS)}", bad[0])
    for key, value in cut.items():
        if key != "kind" and (isinstance(value, bool) or not isinstance(value, (int, float))
                              or not math.isfinite(value)):  # fmt: skip
            raise _fail(where, f"segments.{key}", "a finite number", value)
    out["segments"] = dict(cut)
    return DataSettings(**out)


def _value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)
    return str(value) if isinstance(value, int) else repr(float(value))


def _inline(table: dict[str, Any]) -> str:
    return "{ " + ", ".join(f"{k} = {_value(v)}" for k, v in table.items()) + " }"


def data_lines(data: DataSettings) -> list[str]:
    """The lines of the ``[data]`` table (none when `data` states nothing)."""
    if data.empty:
        return []
    lines = ["", "[data]  # how the records were read: presliding predict reads new ones alike"]
    for key in ("columns", "units", "scale", "segments"):
        if getattr(data, key):
            lines.append(f"{key} = {_inline(getattr(data, key))}")
    for key in ("sample_rate", "decimal", "header", "axis"):
        if getattr(data, key) is not None:
            lines.append(f"{key} = {_value(getattr(data, key))}")
    return lines
