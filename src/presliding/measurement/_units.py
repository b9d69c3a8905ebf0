"""Units in column headers: ``Position [mm]``, ``x (um)``, ``torque [mN m]`` → SI factors.

A header (or a DataFrame column name) may end in a unit in square brackets or
parentheses. `parse_header` splits it off; `si_factor` parses it with pint and
returns the factor that converts the column to SI (s, m, m/s, m/s², N; rad,
rad/s, rad/s², N m for rotary signals). pint is imported only here, and only
when a unit is parsed, so ``import presliding`` stays fast.

Rules:

- every signal has the SI units of its kind: ``time`` [s]; ``position`` [m]
  or [rad]; ``velocity`` [m/s] or [rad/s]; ``acceleration`` [m/s²] or
  [rad/s²]; ``applied_force`` and ``friction_force`` [N] or [N m];
- a unit pint does not know is an error naming the column and the unit;
- a unit of another dimension (a length on a force column, a plain number,
  a temperature) is an error naming the column, the unit and what is expected;
- spellings common on rigs are accepted: ``µm``/``μm``/``um``, ``N·m``,
  ``N*m``, ``N.m``, ``Nm``, ``mNm``, ``m/s^2``, ``m/s²``, ``deg``, ``rpm``.
"""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass
from typing import Any

__all__ = [
    "SI_UNITS",
    "UnitConversion",
    "header_unit",
    "is_quantity",
    "parameter_units",
    "parse_header",
    "quantity_to_si",
    "si_factor",
]

#: SI unit of each signal: (translational, rotary).
SI_UNITS: dict[str, tuple[str, str]] = {
    "time": ("s", "s"),
    "position": ("m", "rad"),
    "velocity": ("m/s", "rad/s"),
    "acceleration": ("m/s^2", "rad/s^2"),
    "applied_force": ("N", "N m"),
    "friction_force": ("N", "N m"),
}
# dimension of each signal: exponents of (mass, length, time) and of the radian
_DIMENSIONS: dict[str, tuple[tuple[int, int, int, int], ...]] = {
    "time": ((0, 0, 1, 0),),
    "position": ((0, 1, 0, 0), (0, 0, 0, 1)),
    "velocity": ((0, 1, -1, 0), (0, 0, -1, 1)),
    "acceleration": ((0, 1, -2, 0), (0, 0, -2, 1)),
    "applied_force": ((1, 1, -2, 0), (1, 2, -2, 0)),
    "friction_force": ((1, 1, -2, 0), (1, 2, -2, 0)),
}
_WHAT = {
    "time": "a time (s, ms, us, min)",
    "position": "a length (m, mm, um, in) or an angle (rad, deg, turn)",
    "velocity": "a speed (m/s, mm/s) or an angular speed (rad/s, deg/s, rpm)",
    "acceleration": "an acceleration (m/s^2) or an angular one (rad/s^2)",
    "applied_force": "a force (N, mN, uN, kN, lbf) or a torque (N m, mN m)",
    "friction_force": "a force (N, mN, uN, kN, lbf) or a torque (N m, mN m)",
}
_HEADER = re.compile(r"^(?P<base>.*?)\s*(?:\[(?P<sq>[^\[\]]*)\]|\((?P<par>[^()]*)\))\s*$")
# torque written without a separator: Nm, mNm, kNm, uNm, µNm
_TORQUE = re.compile(r"^([munµμk]?)Nm$")


@dataclass(frozen=True)
class UnitConversion:
    """How one column was converted on reading.

    Attributes
    ----------
    signal : str
        The signal name (``"position"``, ...).
    column : str
        The column (header name, variable name, or ``"column 1"``).
    unit : str or None
        The unit read from the header (or given), None when there was none.
    si_unit : str
        The SI unit the values are in after conversion.
    factor : float
        The unit's factor to SI (1 without a unit).
    scale : float
        The user's extra factor (``scale=``/``--scale``), applied on top.
    scale_source : str
        Where the scale came from ("" for none, or e.g. "variable gtau").
    """

    signal: str
    column: str
    unit: str | None
    si_unit: str
    factor: float = 1.0
    scale: float = 1.0
    scale_source: str = ""

    @property
    def total(self) -> float:
        """The factor applied to the column: unit factor × scale."""
        return self.factor * self.scale

    @property
    def rotary(self) -> bool:
        """True for an angle, an angular speed or acceleration, or a torque."""
        return self.si_unit in ("rad", "rad/s", "rad/s^2", "N m")

    def describe(self) -> str:
        """One line, e.g. ``position: 'Position [mm]' in mm → m (× 0.001)``."""
        text = f"{self.signal}: {self.column!r}"
        if self.unit is None:
            text += f" taken as {self.si_unit} (no unit given)"
        elif self.factor == 1.0:
            text += f" in {self.unit} (SI: {self.si_unit})"
        else:
            text += f" in {self.unit} → {self.si_unit} (× {self.factor:.6g})"
        if self.scale != 1.0 or self.scale_source:
            src = f" ({self.scale_source})" if self.scale_source else ""
            text += f", scaled × {self.scale:.6g}{src}"
        return text


def parse_header(name: str) -> tuple[str, str | None]:
    """Split ``"Position [mm]"`` into ``("Position", "mm")``; no unit gives None.

    The unit is the text of a last pair of square brackets or parentheses;
    empty brackets count as no unit.
    """
    match = _HEADER.match(name.strip())
    if match is None:
        return name.strip(), None
    unit = match.group("sq") if match.group("sq") is not None else match.group("par")
    unit = unit.strip()
    return match.group("base").strip(), unit or None


def header_unit(name: str, where: str = "") -> str | None:
    """The unit of a column header (`parse_header`); an unclosed bracket is an error.

    ``"Position [mm"`` would otherwise be read as a column without a unit, in
    SI, a factor of 1000 off without a word. Empty brackets (``"Time []"``)
    pair up: they say "no unit".
    """
    unit = parse_header(name)[1]
    if unit is None and _HEADER.match(name.strip()) is None and any(m in name for m in "[]()"):
        raise ValueError(
            f"{where}column {name!r}: its unit's brackets do not pair up; write the unit as "
            "'Name [unit]' or 'Name (unit)', or give it with `units` (--units)."
        )
    return unit


def is_quantity(value: Any) -> bool:
    """True for a pint Quantity (of any registry)."""
    return all(hasattr(value, a) for a in ("magnitude", "units", "dimensionality", "to"))


def quantity_to_si(signal: str, value: Any) -> tuple[Any, str]:
    """The magnitude of a pint Quantity `value` in the SI unit of `signal`, and that unit.

    The dimension is checked (a length for a position, a force or a torque for
    a force, ...): ``Q_(y_mm, "mm")`` becomes metres, never millimetres taken
    as metres.
    """
    unit = str(value.units)
    factor, si = si_factor(signal, unit if unit != "dimensionless" else "1", f"`{signal}`")
    return value.magnitude * factor, si


@functools.lru_cache(maxsize=1)
def _registry() -> Any:
    import pint

    return pint.UnitRegistry()


def _normalise(unit: str) -> str:
    text = unit.strip()
    for a, b in (("·", "*"), ("⋅", "*"), ("×", "*"), ("²", "^2"), ("³", "^3"), ("μ", "u"),
                 ("µ", "u")):  # fmt: skip
        text = text.replace(a, b)
    compact = text.replace(" ", "")
    if _TORQUE.match(compact):
        return _TORQUE.sub(r"\1N*m", compact)
    return re.sub(r"(?<=[A-Za-z])\.(?=[A-Za-z])", "*", text)  # N.m


@functools.lru_cache(maxsize=256)
def _parse(unit: str) -> tuple[float, tuple[int, int, int, int]] | None:
    """(factor to mass-length-time-radian base units, exponents), None if unknown."""
    ureg = _registry()
    try:
        quantity = ureg.parse_expression(_normalise(unit))
    except Exception:  # pint raises several types (undefined unit, syntax, token errors)
        return None
    if not isinstance(quantity, ureg.Quantity):
        quantity = ureg.Quantity(quantity)  # a bare number such as "1"
    try:
        root = quantity.to_root_units()
    except Exception:  # non-multiplicative units (degC) and the like
        return (float("nan"), (99, 99, 99, 99))
    exps = {"gram": 0, "meter": 0, "second": 0, "radian": 0}
    for name, power in root.unit_items():
        if name not in exps or power != int(power):
            return (float("nan"), (99, 99, 99, 99))
        exps[name] = int(power)
    factor = float(root.magnitude) * 1e-3 ** exps["gram"]  # root mass unit is the gram
    return factor, (exps["gram"], exps["meter"], exps["second"], exps["radian"])


def si_factor(signal: str, unit: str, column: str, where: str = "") -> tuple[float, str]:
    """The factor converting `unit` to the SI unit of `signal`, and that SI unit.

    Parameters
    ----------
    signal : str
        One of ``SI_UNITS``.
    unit : str
        The unit text (e.g. ``"mm"``, ``"mN m"``, ``"deg/s"``).
    column : str
        The column it came from, named in errors.
    where : str
        The file, named in errors (e.g. ``"data.csv: "``).

    Raises
    ------
    ValueError
        For a unit pint does not know, or one of another dimension.
    """
    parsed = _parse(unit)
    if parsed is None:
        raise ValueError(
            f"{where}column {column!r} of `{signal}`: the unit {unit!r} is not a known unit; "
            f"give the unit of the values (units={{{signal!r}: 'mm'}}, --units {signal}=mm) "
            "or leave it out of the header and use `scale`."
        )
    factor, dims = parsed
    for kind, want in enumerate(_DIMENSIONS[signal]):
        if dims == want and factor > 0:
            return factor, SI_UNITS[signal][kind]
    raise ValueError(
        f"{where}column {column!r} of `{signal}`: the unit {unit!r} is not {_WHAT[signal]}; "
        "check the column chosen for this signal and its header."
    )


#: Units of fit parameters by name (translational, rotary).
_PARAMETER_UNITS = {
    "mass": ("kg", "kg m^2"),
    "coulomb": ("N", "N m"),
    "coulomb_level": ("N", "N m"),
    "coulomb_negative": ("N", "N m"),
    "coulomb_level_negative": ("N", "N m"),
    "viscous": ("N s/m", "N m s/rad"),
    "viscous_negative": ("N s/m", "N m s/rad"),
    "offset": ("N", "N m"),
    "stiffness": ("N/m", "N m/rad"),
    "breakaway": ("N", "N m"),
    "threshold": ("m", "rad"),
    "initial_velocity": ("m/s", "rad/s"),
    "initial_position": ("m", "rad"),
    "max_elastic_force": ("N", "N m"),
    "initial_stiffness": ("N/m", "N m/rad"),
    "breakaway_each": ("N", "N m"),
    "stribeck_drop": ("N", "N m"),
    "stribeck_velocity": ("m/s", "rad/s"),
    "static_level": ("N", "N m"),
    "static": ("N", "N m"),
    "lag_time": ("s", "s"),
    "damping": ("N s/m", "N m s/rad"),
    "creep_compliance": ("m/N", "rad/(N m)"),
    "creep_time": ("s", "s"),
}


def parameter_units(names: Any, rotary: bool = False) -> dict[str, str]:
    """SI units of fit parameters by name (``stiffness_2`` → ``N/m``); unknown names skipped."""
    out = {}
    for name in names:
        base = re.sub(r"_\d+$", "", name)
        if base in _PARAMETER_UNITS:
            out[name] = _PARAMETER_UNITS[base][int(rotary)]
    return out
