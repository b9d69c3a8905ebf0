"""A model as the TOML text of a model file (`presliding.model_io.model_to_toml`).

The writing half of the model-file schema: each value with its unit in a comment, the units
those of the axis (`presliding._axes`); the schema's tables and keys are shared with the
reader in `presliding.model_io`.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np

from presliding._axes import as_axis, axis_unit
from presliding._model_arrays import number_chunks
from presliding.friction._parts import density_of, elements
from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis.densities import Density, Exponential, PiecewiseConstant, Uniform

__all__ = ["DENSITIES", "MOTION_DEFAULTS", "model_pieces", "model_to_toml"]

#: Density kinds of ``[friction.density]``: class and its keys (required, optional).
DENSITIES: dict[str, tuple[type[Density], tuple[str, ...], tuple[str, ...]]] = {
    "uniform": (Uniform, ("height", "max_threshold"), ()),
    "exponential": (Exponential, ("height", "length"), ("max_threshold",)),
    "piecewise_constant": (PiecewiseConstant, ("breaks", "heights"), ()),
}
MOTION_DEFAULTS: dict[str, Any] = {
    "mass": 1.0,
    "initial_velocity": 0.0,
    "initial_position": 0.0,
    "initial_state": "relaxed",
    "applied_force": 0.0,
    "t_end": 1.0,
    "samples": 2001,
}


@dataclass(frozen=True)
class _ArrayLine:
    """``key = [values]  # comment``, its numbers written in chunks (`number_chunks`)."""

    key: str
    values: np.ndarray
    comment: str

    def pieces(self) -> Iterator[str]:
        yield f"{self.key} = "
        yield from number_chunks(self.values)
        yield f"  # {self.comment}"


_Line = str | _ArrayLine


def _line(key: str, value: Any, comment: str) -> _Line:
    if isinstance(value, np.ndarray):
        return _ArrayLine(key, value, comment)
    return f"{key} = {_toml_value(value)}  # {comment}"


def _density_lines(density: Density, axis: str = "linear") -> list[_Line]:
    for kind, (cls, required, optional) in DENSITIES.items():
        if type(density) is cls:
            lines: list[_Line] = ["", "[friction.density]", f"kind = {_toml_value(kind)}"]
            height, length = axis_unit("density_height", axis), axis_unit("position", axis)
            units = {"height": f"[{height}]", "heights": f"[{height}]", "length": f"[{length}]",
                     "max_threshold": f"[{length}]", "breaks": f"[{length}]"}  # fmt: skip
            for key in (*required, *optional):
                value = getattr(density, key)
                if isinstance(value, float) and value == float("inf"):
                    continue  # the default: untruncated
                lines.append(_line(key, value, units[key]))
            return lines
    raise ValueError(
        f"`model` has a {type(density).__name__} density, which a model file cannot hold; "
        f"use one of {', '.join(DENSITIES)} (or its discretisation)."
    )


def _toml_value(value: Any) -> str:
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    return repr(float(value)) if not isinstance(value, int) else str(value)


#: The quantity of each `[motion]` key, for its unit comment.
_MOTION_QUANTITIES = {"mass": "mass", "initial_velocity": "velocity", "t_end": "time",
                      "initial_position": "position", "applied_force": "force"}  # fmt: skip


def model_to_toml(
    model: PIFriction,
    motion: Any = None,
    measurement: Any = None,
    header: str = "",
    axis: str = "linear",
) -> str:
    """The TOML text of a model (and optional motion settings and measurement terms).

    Units are stated in comments, those of `axis` (``"rotary"``: rad, N m, kg m²);
    `header` (lines of text) is written first as comments (the data, units, ...).
    """
    return "".join(model_pieces(model, motion, measurement, header, axis))


def model_pieces(
    model: PIFriction,
    motion: Any = None,
    measurement: Any = None,
    header: str = "",
    axis: str = "linear",
    data: Any = None,
) -> Iterator[str]:
    """The text of `model_to_toml` in pieces (a long element array in chunks of numbers)."""
    if not isinstance(model, PIFriction):
        raise TypeError(f"`model` must be a PIFriction; got {type(model).__name__}.")
    axis = as_axis(axis)
    force, pos = axis_unit("force", axis), axis_unit("position", axis)
    lines: list[_Line] = [f"# {ln}".rstrip() for ln in header.splitlines()]
    if axis == "rotary":
        lines.append(f"# rotary axis: positions in {pos}, torques in {force}")
    lines += [""] if lines else []
    lines += ["[friction]", f"coulomb = {_toml_value(model.coulomb)}  # c1 [{force}]"]
    if model.is_discrete:
        k, _, c = elements(model)
        lines += [
            _ArrayLine("stiffness", k, f"k_j [{axis_unit('stiffness', axis)}]"),
            _ArrayLine("breakaway", c, f"c_j [{force}]"),
        ]
    if model.viscous:
        lines.append(f"viscous = {_toml_value(model.viscous)}  # σ [{axis_unit('viscous', axis)}]")
    lines += _negative_lines(model, axis)
    if not model.is_discrete:
        lines += _density_lines(density_of(model), axis)
    if motion is not None:
        lines += ["", "[motion]"]
        for key in MOTION_DEFAULTS:
            quantity = _MOTION_QUANTITIES.get(key)
            unit = f"  # [{axis_unit(quantity, axis)}]" if quantity else ""
            lines.append(f"{key} = {_toml_value(getattr(motion, key))}{unit}")
    if measurement is not None:
        offset = _toml_value(measurement.force_offset)
        note = f"F_0 [{force}]: measured force = model force + F_0; simulate applies u - F_0"
        lines += ["", "[measurement]", f"force_offset = {offset}  # {note}"]
    if data is not None:
        from presliding._model_data import data_lines

        lines += data_lines(data)
    for line in lines:
        if isinstance(line, str):
            yield line
        else:
            yield from line.pieces()
        yield "\n"


def _negative_lines(model: PIFriction, axis: str) -> list[_Line]:
    """The negative sides of an asymmetric model (none for a symmetric one)."""
    force, viscous = axis_unit("force", axis), axis_unit("viscous", axis)
    units = {"coulomb_negative": f"c1⁻ [{force}]", "breakaway_negative": f"c_j⁻ [{force}]",
             "viscous_negative": f"σ⁻ [{viscous}]"}  # fmt: skip
    values = {name: getattr(model, name) for name in units}
    return [_line(name, v, units[name]) for name, v in values.items() if v is not None]
