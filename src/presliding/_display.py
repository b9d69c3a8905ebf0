"""How results show themselves: a short ``repr``, an HTML table for notebooks, ``df.attrs``.

Every public result (`MotionResult`, `FitResult`, `LimitCycles`, `SweepResult`, ...)
shows itself the same way:

- ``repr(result)``: the class, its status and message, then its fields, each
  array summarised by shape, dtype and range; never more than `REPR_LIMIT`
  characters, so a notebook cell or a log line stays readable;
- ``result._repr_html_()``: the status (coloured by success), the message, the
  key figures with units and, where the result has one, its parameter table with
  units (a fit's parameters, a model's coulomb level, stiffnesses, thresholds);
- ``result.to_pandas().attrs``: ``success``, ``status``, ``message``, the
  ``units`` of the columns and, where there is a model, its ``model`` (repr)
  and ``parameters`` (plain numbers and lists; a part such as a density as one
  line of its fields with their units, `describe_part`).

Models and data (`PIFriction`, `Measurement`) show themselves in a notebook with
`model_html`: their key figures, then their parameters, each with its unit.

Units are the package's SI units, found from the field's name (``stop_time`` [s],
``rest_position`` [m], ``elastic_forces`` [N]); a result with other units (a
rotary fit) passes its own.
A result's figure follows the rules of `presliding._figures`. This module is shared
ground: it imports no layer.
"""

from __future__ import annotations

import dataclasses
import html
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np

__all__ = [
    "REPR_LIMIT",
    "describe_part",
    "figures_of",
    "fill_attrs",
    "model_html",
    "model_parameters",
    "result_html",
    "short_repr",
    "summarise",
    "unit_of",
]  # fmt: skip

#: The longest ``repr`` of a result, in characters.
REPR_LIMIT = 1000

#: SI unit of a quantity by the last word of its name (plural or not).
_UNITS = {
    "time": "s", "period": "s", "elapsed": "s", "position": "m", "displacement": "m",
    "amplitude": "m", "threshold": "m", "velocity": "m/s", "acceleration": "m/s²",
    "force": "N", "coulomb": "N", "breakaway": "N", "level": "N", "mass": "kg",
    "stiffness": "N/m", "viscous": "N s/m", "frequency": "rad/s", "frequencies": "rad/s",
    "work": "J", "energy": "J", "dissipated": "J", "kinetic": "J", "elastic": "J",
    "rms": "m", "max": "m", "range": "m", "reference": "m", "measured": "m", "control": "N",
    "feedforward": "N", "estimate": "m", "height": "N/m²", "length": "m", "breaks": "m",
    "strength": "N/m",
}  # fmt: skip
#: Names whose last word misleads (counts, ratios, labels).
_UNITLESS = ("n_", "nrmse", "relative", "ratio", "trend", "discrepancy", "tolerance", "kp",
             "ki", "kd", "status", "message")  # fmt: skip


def unit_of(name: str) -> str:
    """The SI unit of a quantity named `name` (``"stop_time"`` → ``"s"``), or ``""``."""
    low = name.lower()
    if low.startswith(_UNITLESS):
        return ""
    if low.startswith("energy_"):
        return "J"
    word = low.rsplit("_", 1)[-1]
    for key in (word, word[:-1] if word.endswith("s") else word, word.removesuffix("es")):
        if key in _UNITS:
            return _UNITS[key]
    return ""


def _number(value: Any) -> str:
    if isinstance(value, bool | np.bool_):
        return str(bool(value))
    if isinstance(value, int | np.integer):
        return str(int(value))
    return f"{float(value):.6g}"


def summarise(value: Any, width: int = 72) -> str:
    """A short text for a value: a number, a summary of an array (shape, dtype, range),
    a dict or sequence by its length, anything else by its repr cut at `width` characters."""
    if isinstance(value, np.ndarray):
        flat = value.ravel()
        if value.ndim <= 1 and value.size <= 4 and value.dtype.kind in "biuf":
            return "[" + ", ".join(_number(v) for v in flat) + "]"
        shape = "×".join(str(n) for n in value.shape) or "scalar"
        text = f"<array {shape} {value.dtype.name}"
        if value.dtype.kind in "iuf" and flat.size:
            finite = flat[np.isfinite(flat)] if value.dtype.kind == "f" else flat
            if finite.size:
                text += f", {_number(np.min(finite))} … {_number(np.max(finite))}"
        elif value.dtype.kind == "c" and flat.size:
            text += f", |z| ≤ {_number(np.max(np.abs(flat)))}"
        return text + ">"
    if isinstance(value, bool | int | float | np.number):
        return _number(value)
    if isinstance(value, list | tuple) and len(value) > 4:
        return f"<{type(value).__name__} of {len(value)}>"
    if isinstance(value, Mapping):  # up to 8 entries, then how many more
        items = [f"{k!r}: {summarise(v, 24)}" for k, v in list(value.items())[:8]]
        more = f", … {len(value) - 8} more" if len(value) > 8 else ""
        text = "{" + ", ".join(items) + more + "}"
        width = max(width, 320)
    else:
        text = repr(value)
    return text if len(text) <= width else text[: width - 1] + "…"


def _fields(obj: Any) -> list[str]:
    """The names a result shows: its dataclass fields (those kept in repr) or tuple fields."""
    if dataclasses.is_dataclass(obj):
        return [f.name for f in dataclasses.fields(obj) if f.repr and not f.name.startswith("_")]
    return list(getattr(obj, "_fields", ()))


def short_repr(obj: Any, names: Iterable[str] | None = None) -> str:
    """``Class(status=..., message=..., field=summary, ...)`` in at most `REPR_LIMIT` characters."""
    names = [
        n for n in (_fields(obj) if names is None else names) if n not in ("status", "message")
    ]
    parts = []
    for key in ("status", "message"):
        if hasattr(obj, key):
            parts.append(f"{key}={summarise(str(getattr(obj, key)), 160)!s}")
    parts += [f"{n}={summarise(getattr(obj, n))}" for n in names]
    head = f"{type(obj).__name__}("
    out, used = [], len(head) + 1
    for i, part in enumerate(parts):
        more = f", … {len(parts) - i} more"
        if used + len(part) + 2 + len(more) > REPR_LIMIT:
            out.append(more.removeprefix(", "))
            break
        out.append(part)
        used += len(part) + 2
    return head + ", ".join(out) + ")"


def model_parameters(model: Any) -> dict[str, Any]:
    """A model's parameters as plain values (numbers, lists; other objects as their repr)."""
    if model is None or not dataclasses.is_dataclass(model) or isinstance(model, type):
        return {}
    out: dict[str, Any] = {}
    for f in dataclasses.fields(model):
        value = getattr(model, f.name)
        if value is None:
            continue
        if isinstance(value, np.ndarray):
            out[f.name] = value.tolist() if value.size <= 64 else summarise(value)
        elif isinstance(value, bool | int | float | str | np.number):
            out[f.name] = value.item() if isinstance(value, np.generic) else value
        elif dataclasses.is_dataclass(value) and not isinstance(value, type):
            out[f.name] = describe_part(value)
        else:
            out[f.name] = summarise(value)
    return out


def describe_part(part: Any) -> str:
    """A part of a model (a dataclass, such as a density) in one line: its class, then each
    field with its unit (``Uniform: height = 3.5e+07 N/m², max_threshold = 0.0002 m``);
    arrays of more than four values by their count and range."""
    items = []
    for f in dataclasses.fields(part):
        if not f.repr or f.name.startswith("_"):
            continue
        value = getattr(part, f.name)
        if isinstance(value, np.ndarray) and value.size > 4 and value.dtype.kind in "iuf":
            text = f"{value.size} values, {_number(value.min())} … {_number(value.max())}"
        else:
            text = summarise(value, 48)
        unit = unit_of(f.name)
        items.append(f"{f.name} = {text}{' ' + unit if unit else ''}")
    return f"{type(part).__name__}: " + ", ".join(items)


def figures_of(obj: Any, names: Iterable[str] | None = None,
               units: Mapping[str, str] | None = None) -> list[tuple[str, str, str]]:  # fmt: skip
    """(name, value, unit) of a result's fields: numbers as they are, arrays summarised."""
    units = units or {}
    rows = []
    for n in _fields(obj) if names is None else names:
        if n in ("status", "message", "model") or not hasattr(obj, n):
            continue
        value = getattr(obj, n)
        if isinstance(value, np.ndarray) and value.ndim == 0:
            value = value.item()
        plain = (
            isinstance(value, bool | int | float | str | np.number | np.ndarray) or value is None
        )
        if plain:
            unit = units.get(n, unit_of(n))
            text = "—" if value is None else summarise(value)
            rows.append((n, text, "" if isinstance(value, bool | str) else unit))
    return sorted(rows, key=lambda row: row[1].startswith("<array"))  # numbers first


def _table(columns: Sequence[str], rows: Iterable[Sequence[Any]]) -> str:
    head = "".join(f"<th style='text-align:left'>{html.escape(c)}</th>" for c in columns)
    body = "".join(
        "<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>" for row in rows
    )
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def _model_rows(model: Any) -> list[tuple[str, str, str]]:
    rows = []
    for name, value in model_parameters(model).items():
        text = (", ".join(_number(v) for v in value[:8]) + (" …" if len(value) > 8 else "")
                if isinstance(value, list) else value if isinstance(value, str)
                else summarise(value))  # fmt: skip
        rows.append((name, text, unit_of(name)))
    return rows


def model_html(obj: Any, figures: Sequence[tuple[str, str, str]], title: str | None = None,
               parameters: bool = True) -> str:  # fmt: skip
    """The HTML of a model or of data (no status): its class, key `figures` (name, value,
    unit) and, with `parameters`, each of its parameters with its unit."""
    parts = ["<div class='presliding-model'>",
             f"<p><strong>{html.escape(title or type(obj).__name__)}</strong></p>"]  # fmt: skip
    if figures:
        parts.append(_table(("quantity", "value", "unit"), figures))
    rows = _model_rows(obj) if parameters else []
    if rows:
        parts.append(_table(("parameter", "value", "unit"), rows))
    parts.append("</div>")
    return "\n".join(parts)


def result_html(
    obj: Any,
    figures: Sequence[tuple[str, str, str]] | None = None,
    table: tuple[Sequence[str], Sequence[Sequence[Any]]] | None = None,
    title: str | None = None,
    show_model: bool = True,
) -> str:
    """The HTML of a result: title, status (green on success), message, key figures with
    units, the given `table` and (with `show_model`) the model's parameter table."""
    success = bool(getattr(obj, "success", True))
    colour = "#1a7f37" if success else "#b35900"
    status = html.escape(str(getattr(obj, "status", "")))
    message = html.escape(str(getattr(obj, "message", "")))
    parts = [
        "<div class='presliding-result'>",
        f"<p><strong>{html.escape(title or type(obj).__name__)}</strong> "
        f"<span style='color:{colour};font-weight:bold'>{status}</span></p>",
    ]
    if message:
        parts.append(f"<p style='margin-top:0'>{message}</p>")
    rows = figures_of(obj) if figures is None else figures
    if rows:
        parts.append(_table(("quantity", "value", "unit"), rows))
    if table is not None:
        parts.append(_table(*table))
    model = getattr(obj, "model", None)
    if show_model and model is not None:
        parts.append(f"<p>model: <code>{html.escape(summarise(model, 200))}</code></p>")
        model_rows = _model_rows(model)
        if model_rows:
            parts.append(_table(("parameter", "value", "unit"), model_rows))
    parts.append("</div>")
    return "\n".join(parts)


def fill_attrs(frame: Any, obj: Any, units: Mapping[str, str] | None = None,
               model: Any = None) -> Any:  # fmt: skip
    """Put a result's ``success``, ``status``, ``message``, column ``units`` and its model's
    ``model`` (repr) and ``parameters`` into ``frame.attrs``; returns the frame."""
    units = dict(units or {})
    for col in [*frame.columns, *(n for n in frame.index.names if n is not None)]:
        units.setdefault(str(col), unit_of(str(col)))
    frame.attrs.update(
        success=bool(getattr(obj, "success", True)),
        status=str(getattr(obj, "status", "")),
        message=str(getattr(obj, "message", "")),
        units={k: v for k, v in units.items() if v},
    )
    model = getattr(obj, "model", None) if model is None else model
    if model is not None:
        frame.attrs["model"] = summarise(model, 400)
        frame.attrs["parameters"] = model_parameters(model)
    return frame


def fit_html(fit: Any) -> str:
    """The HTML of a fit (a `FitResult`): quality figures, then each parameter's value,
    unit, standard error and interval, fixed/tied/at-bound notes and derived quantities."""
    figures = [
        ("samples", str(fit.measured.shape[0]), ""),
        ("records", str(max(len(fit.records), 1)), ""),
        ("residual RMS", f"{fit.residual_rms:.4g}", fit.signal_unit),
        ("NRMSE", f"{100 * fit.nrmse:.3f}", "%"),
        ("explained variance", f"{100 * (1 - fit.relative_residual**2):.3f}", "%"),
        ("evaluations", str(fit.n_evaluations), ""),
    ]
    rows = []
    for n, v in fit.parameters.items():
        lo, hi = fit.confidence_interval[n]
        note = "fixed" if n in fit.fixed else ("tied" if n in fit.tied else "")
        note += " at bound" if n in fit.at_bounds else ""
        rows.append((n, f"{v:.6g}", fit.units.get(n, ""), f"{fit.standard_error[n]:.3g}",
                     f"[{lo:.6g}, {hi:.6g}]", note.strip()))  # fmt: skip
    rows += [(n, f"{v:.6g}", fit.units.get(n, ""), "", "", "derived")
             for n, v in fit.derived.items()]  # fmt: skip
    interval = f"{100 * fit.confidence_level:g} % interval"
    table = (("parameter", "value", "unit", "std. error", interval, ""), rows)
    return result_html(fit, figures, table, title=f"{fit.kind} fit (FitResult)", show_model=False)
