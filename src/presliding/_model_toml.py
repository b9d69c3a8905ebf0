"""A model as the TOML text of a model file (`presliding.model_io.model_to_toml`).

The writing half of the model-file schema: each value with its unit in a comment, the units
those of the axis (`presliding._axes`); the schema's tables and keys are shared with the
reader in `presliding.model_io`.
"""

from __future__ import annotations

import contextlib
import json
from typing import Any

from presliding._axes import as_axis, axis_unit
from presliding.friction._parts import density_of, elements
from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis.densities import Density, Exponential, PiecewiseConstant, Uniform

__all__ = ["DENSITIES", "MOTION_DEFAULTS", "model_to_toml"]

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


def _density_lines(density: Density, axis: str = "linear") -> list[str]:
    for kind, (cls, required, optional) in DENSITIES.items():
        if type(density) is cls:
            lines = ["", "[friction.density]", f"kind = {_toml_value(kind)}"]
            height, length = axis_unit("density_height", axis), axis_unit("position", axis)
            units = {"height": f"[{height}]", "heights": f"[{height}]", "length": f"[{length}]",
                     "max_threshold": f"[{length}]", "breaks": f"[{length}]"}  # fmt: skip
            for key in (*required, *optional):
                value = getattr(density, key)
                if isinstance(value, float) and value == float("inf"):
                    continue  # the default: untruncated
                value = value.tolist() if hasattr(value, "tolist") else value
                lines.append(f"{key} = {_toml_value(value)}  # {units[key]}")
            return lines
    raise ValueError(
        f"`model` has a {type(density).__name__} density, which a model file cannot hold; "
        f"use one of {', '.join(DENSITIES)} (or its discretisation)."
    )


def _toml_value(value: Any) -> str:
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, (list, tuple)):
        with contextlib.suppress(TypeError):  # floats only (long element arrays): one join
            return "[" + ", ".join(map(float.__repr__, value)) + "]"
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
    if not isinstance(model, PIFriction):
        raise TypeError(f"`model` must be a PIFriction; got {type(model).__name__}.")
    axis = as_axis(axis)
    force, pos = axis_unit("force", axis), axis_unit("position", axis)
    lines = [f"# {ln}".rstrip() for ln in header.splitlines()]
    if axis == "rotary":
        lines.append(f"# rotary axis: positions in {pos}, torques in {force}")
    lines += [""] if lines else []
    lines += ["[friction]", f"coulomb = {_toml_value(model.coulomb)}  # c1 [{force}]"]
    if model.is_discrete:
        k, _, c = elements(model)
        lines += [
            f"stiffness = {_toml_value(k.tolist())}  # k_j [{axis_unit('stiffness', axis)}]",
            f"breakaway = {_toml_value(c.tolist())}  # c_j [{force}]",
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
    return "\n".join(lines) + "\n"


def _negative_lines(model: PIFriction, axis: str) -> list[str]:
    """The negative sides of an asymmetric model (none for a symmetric one)."""
    force, viscous = axis_unit("force", axis), axis_unit("viscous", axis)
    units = {"coulomb_negative": f"c1⁻ [{force}]", "breakaway_negative": f"c_j⁻ [{force}]",
             "viscous_negative": f"σ⁻ [{viscous}]"}  # fmt: skip
    values = {name: getattr(model, name) for name in units}
    return [f"{name} = {_toml_value(v.tolist() if hasattr(v, 'tolist') else v)}  # {units[name]}"
            for name, v in values.items() if v is not None]  # fmt: skip
