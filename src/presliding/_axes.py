"""Axis kinds and the units of each quantity on them: one home for unit labels.

A rig's axis is *linear* (a slide: m, N, kg, N s/m, N/m) or *rotary* (a joint
or a motor shaft: rad, N m, kg m², N m s/rad, N m/rad). The equations are the
same (eq. 17 with a torque, an angle and an inertia); only the labels differ.
Measurements carry their axis (`presliding.measurement.Measurement.axis`),
fits, reports, figures and model files take their unit labels from here.
"""

from __future__ import annotations

import re
from typing import Any

from presliding._validation import as_choice

__all__ = ["AXES", "QUANTITY_UNITS", "as_axis", "axis_unit", "on_axis"]

AXES = ("linear", "rotary")

#: SI unit of each quantity: (linear, rotary).
QUANTITY_UNITS: dict[str, tuple[str, str]] = {
    "time": ("s", "s"),
    "position": ("m", "rad"),
    "velocity": ("m/s", "rad/s"),
    "acceleration": ("m/s^2", "rad/s^2"),
    "force": ("N", "N m"),
    "mass": ("kg", "kg m^2"),
    "viscous": ("N s/m", "N m s/rad"),
    "stiffness": ("N/m", "N m/rad"),
    "density_height": ("N/m^2", "N m/rad^2"),
    "energy": ("J", "J"),
}

# linear unit label → rotary label, for labels written in linear SI units
_TO_ROTARY = {lin: rot for lin, rot in QUANTITY_UNITS.values() if lin != rot}
_TO_ROTARY.update({
    "N/m²": "N m/rad²", "m/s²": "rad/s²", "N/kg": "N m/(kg m^2)", "N/(m kg)": "N m/(rad kg m^2)",
    "N s/(m kg)": "N m s/(rad kg m^2)", "N/(m^2 kg)": "N m/(rad^2 kg m^2)",
})  # fmt: skip


def as_axis(value: Any, name: str = "axis") -> str:
    """``"linear"`` or ``"rotary"``; anything else is a ValueError naming `name`."""
    return as_choice(name, value, AXES)


def axis_unit(quantity: str, axis: str = "linear") -> str:
    """The SI unit of `quantity` (a key of `QUANTITY_UNITS`) on `axis`."""
    if quantity not in QUANTITY_UNITS:
        raise ValueError(
            f"`quantity` must be one of {', '.join(QUANTITY_UNITS)}; got {quantity!r}."
        )
    return QUANTITY_UNITS[quantity][AXES.index(as_axis(axis))]


def on_axis(unit: str, axis: str = "linear") -> str:
    """A unit label written for a linear axis, relabelled for `axis`.

    ``on_axis("N/m", "rotary")`` is ``"N m/rad"``; a label without a linear
    unit in it (``"s"``, ``"1"``, ``"J"``) is returned as it is. Labels with
    a bracketed unit, such as ``"position [m]"``, are relabelled inside the
    brackets.
    """
    if as_axis(axis) == "linear" or not unit:
        return unit
    bracket = re.fullmatch(r"(?P<head>.*\[)(?P<unit>[^\[\]]*)(?P<tail>\].*)", unit)
    if bracket:
        return bracket["head"] + on_axis(bracket["unit"], axis) + bracket["tail"]
    return _TO_ROTARY.get(unit.strip(), unit)
