"""Model files: friction parameters, mass and simulation settings in TOML (or JSON).

Schema (units in brackets; any consistent unit set works, SI shown)::

    [friction]
    coulomb = 0.5                  # c1 [N], Coulomb element (eq. 8)
    stiffness = [500.0, 10.0, 4.0] # k_j [N/m]
    breakaway = [1.0, 1.0, 1.0]    # c_j [N]; or threshold = [...] r_j [m] (eq. 6)
    viscous = 0.0                  # σ [N s/m], optional viscous term σ·ẏ (default 0)
    # optional, asymmetric friction (the values above are then for sliding in +y): for −y
    # coulomb_negative = 0.4, breakaway_negative (or threshold_negative) = [...], viscous_negative

    [friction.density]             # instead of stiffness/breakaway: a continuous μ (eq. 10)
    kind = "uniform"               # height a [N/m^2], max_threshold R [m]
    # kind = "exponential"         # height a [N/m^2], length b [m], max_threshold R [m]
    #                              #   (optional; default inf: untruncated)
    # kind = "piecewise_constant"  # breaks [m] (m + 1 values), heights [N/m^2] (m values)

    [motion]                       # optional: what `presliding simulate` runs
    mass = 1.0                     # m [kg]
    initial_velocity = 1.0         # [m/s]
    initial_position = 0.0         # [m]
    initial_state = "relaxed"      # "relaxed" or "saturated"
    applied_force = 0.0            # u [N], constant (a CSV can be given on the command line)
    t_end = 2.0                    # [s]
    samples = 2001                 # output samples on [0, t_end] (at most 10,000,000)

    [measurement]                  # optional: terms a fit identified besides friction
    force_offset = -3.16           # F_0 [N]: measured force = model force + F_0

    [data]                         # optional: how `presliding fit` read its records
    columns = { time = "Time [s]", position = "Position [mm]", applied_force = "Force [N]" }
    # (and units, scale, sample_rate, decimal, header, axis, segments: `DataSettings`)

A JSON file with the same structure is accepted too. Unknown keys are errors,
so a misspelt parameter is never ignored; every number must be finite. Comment
lines at the head of a file written by `presliding fit` state the data, units
and conversions the model was identified from.

Sign of the offset: a fit of eq. 17 with an offset explains the measured force
as u = m·ÿ + F + F_0, so only u − F_0 acts on the mass; `presliding simulate`
therefore applies u − F_0 (the constant `motion.applied_force`, or the samples
of ``--applied-force``, minus `force_offset`).
"""

from __future__ import annotations

import json
import math
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from presliding._io import atomic_path
from presliding._model_arrays import loads_toml
from presliding._model_data import DataSettings, data_from_table
from presliding._model_toml import DENSITIES as _DENSITIES
from presliding._model_toml import MOTION_DEFAULTS as _MOTION_DEFAULTS
from presliding._model_toml import model_pieces, model_to_toml
from presliding._validation import check_time_span, check_type, fmt
from presliding.friction.pi_friction import PIFriction

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = [
    "MAX_SAMPLES",
    "DataSettings",
    "MeasurementTerms",
    "ModelFile",
    "MotionSettings",
    "load_model",
    "model_from_tables",
    "model_to_toml",
    "read_tables",
    "save_model",
]

_NEGATIVE = ("coulomb_negative", "breakaway_negative", "threshold_negative", "viscous_negative")
_FRICTION_KEYS = {"coulomb", "stiffness", "breakaway", "threshold", "density", "viscous",
                  *_NEGATIVE}  # fmt: skip
#: Most output samples a model file may ask for (each is 6 floats in memory and a CSV row).
MAX_SAMPLES = 10_000_000
_MEASUREMENT_KEYS = {"force_offset"}


class ModelFileError(ValueError):
    """A model file that cannot be read: the message names the file and the field."""


@dataclass(frozen=True)
class MotionSettings:
    """The `[motion]` table: mass and the free/forced motion to simulate."""

    mass: float = 1.0
    initial_velocity: float = 0.0
    initial_position: float = 0.0
    initial_state: str = "relaxed"
    applied_force: float = 0.0
    t_end: float = 1.0
    samples: int = 2001
    #: The keys the file gave (the others hold their defaults).
    given: frozenset[str] = field(default=frozenset(), compare=False, repr=False)


@dataclass(frozen=True)
class MeasurementTerms:
    """The `[measurement]` table: terms of the measured force besides friction.

    Attributes
    ----------
    force_offset : float
        F_0 [N]: the measured force is the model's force plus F_0 (eq. 17 with
        an offset: u = m·ÿ + F + F_0), so a simulation applies u − F_0.
    """

    force_offset: float = 0.0


@dataclass(frozen=True)
class ModelFile:
    """A friction model, its motion settings and measurement terms as read from a file."""

    model: PIFriction
    motion: MotionSettings
    measurement: MeasurementTerms = MeasurementTerms()
    data: DataSettings = field(default_factory=DataSettings)


def _as_path(path: Any) -> Path:
    """A model file's path: a str or os.PathLike, else a TypeError naming what was given."""
    if isinstance(path, bool) or not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"`path` must be a file path (str or os.PathLike); got {fmt(path)}.")
    return Path(path)


def _read_mapping(path: Path) -> dict[str, Any]:
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise ModelFileError(f"{path}: no such file.") from None
    except OSError as exc:
        raise ModelFileError(f"{path}: cannot be read ({exc.strerror}).") from None
    try:  # a byte-order mark is not part of the text; long element arrays: see loads_toml
        if path.suffix.lower() == ".json":
            data = json.loads(raw.decode("utf-8-sig"))
        else:
            data = loads_toml(raw)
    except (json.JSONDecodeError, tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        kind = "JSON" if path.suffix.lower() == ".json" else "TOML"
        raise ModelFileError(f"{path}: not valid {kind} ({exc}).") from None
    if not isinstance(data, dict):
        raise ModelFileError(f"{path}: the top level must be a table; got {type(data).__name__}.")
    return data


def _table(path: Path, data: dict[str, Any], name: str, allowed: set[str]) -> dict[str, Any]:
    table = data.get(name, {})
    if not isinstance(table, dict):
        raise ModelFileError(f"{path}: `{name}` must be a table; got {type(table).__name__}.")
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise ModelFileError(
            f"{path}: unknown key `{name}.{unknown[0]}`; allowed keys are "
            f"{', '.join(sorted(allowed))}."
        )
    return table


def load_model(path: str | Path) -> ModelFile:
    """Read a model file (TOML, or JSON by its suffix); see the module docstring.

    Raises
    ------
    ModelFileError
        (a ValueError) naming the file and the field for any problem.
    """
    path = _as_path(path)
    data = _read_mapping(path)
    unknown = sorted(set(data) - {"friction", "motion", "measurement", "data"})
    if unknown:
        raise ModelFileError(
            f"{path}: unknown table `{unknown[0]}`; allowed tables are friction, motion, "
            "measurement, data."
        )
    spec = model_from_tables(path, data)
    if "data" not in data:
        return spec
    try:
        settings = data_from_table(data["data"], f"{path}: ")
    except ValueError as exc:
        raise ModelFileError(str(exc)) from None
    return ModelFile(spec.model, spec.motion, spec.measurement, settings)


def read_tables(path: str | Path) -> dict[str, Any]:
    """The top-level tables of a TOML file (or JSON, by its suffix), unchecked.

    For files that hold a model beside tables of their own (e.g. a sweep
    specification): pass the result to `model_from_tables`.

    Raises
    ------
    ModelFileError
        (a ValueError) naming the file for a missing, unreadable or invalid file.
    """
    return _read_mapping(_as_path(path))


def model_from_tables(path: str | Path, data: dict[str, Any]) -> ModelFile:
    """The model and motion settings of the `friction` and `motion` tables of `data`.

    Validates them exactly as `load_model` does (other tables are left to the
    caller); `path` names the file in the error messages.

    Raises
    ------
    ModelFileError
        (a ValueError) naming the file and the field for any problem.
    """
    path = Path(path)
    if "friction" not in data:
        raise ModelFileError(f"{path}: missing table `friction` (with coulomb, stiffness, ...).")
    fr = _table(path, data, "friction", _FRICTION_KEYS)
    if "coulomb" not in fr:
        raise ModelFileError(f"{path}: missing `friction.coulomb` (the Coulomb element c1, N).")
    try:
        if "density" in fr:
            model = _density_model(path, fr)
        else:
            model = PIFriction(
                fr["coulomb"],
                fr.get("stiffness", []),
                fr.get("breakaway"),
                threshold=fr.get("threshold"),
                viscous=fr.get("viscous", 0.0),
                **{name: fr.get(name) for name in _NEGATIVE},  # asymmetric friction
            )
    except (TypeError, ValueError) as exc:
        if isinstance(exc, ModelFileError):
            raise
        raise ModelFileError(f"{path}: [friction] {exc}") from None
    mo = {**_MOTION_DEFAULTS, **_table(path, data, "motion", set(_MOTION_DEFAULTS))}
    for key, default in _MOTION_DEFAULTS.items():
        value = mo[key]
        ok = (
            isinstance(value, str)
            if isinstance(default, str)
            else isinstance(value, (int, float)) and not isinstance(value, bool)
        )
        if not ok:
            want = "a string" if isinstance(default, str) else "a number"
            raise ModelFileError(f"{path}: `motion.{key}` must be {want}; got {value!r}.")
        if not isinstance(value, str) and not math.isfinite(value):
            raise ModelFileError(f"{path}: `motion.{key}` must be finite; got {value!r}.")
    if not float(mo["mass"]) > 0:
        raise ModelFileError(f"{path}: `motion.mass` must be positive; got {mo['mass']!r}.")
    if not float(mo["t_end"]) > 0:
        raise ModelFileError(f"{path}: `motion.t_end` must be positive; got {mo['t_end']!r}.")
    try:
        check_time_span("motion.t_end", mo["t_end"], float(mo["t_end"]))
    except ValueError as exc:
        raise ModelFileError(f"{path}: {exc}") from None
    if int(mo["samples"]) != mo["samples"] or mo["samples"] < 2:
        raise ModelFileError(
            f"{path}: `motion.samples` must be a whole number >= 2; got {mo['samples']!r}."
        )
    if mo["samples"] > MAX_SAMPLES:
        raise ModelFileError(
            f"{path}: `motion.samples` must be at most {MAX_SAMPLES:,} (the output would need "
            f"{48 * mo['samples'] / 1e9:.3g} GB); got {mo['samples']!r}."
        )
    if mo["initial_state"] not in ("relaxed", "saturated"):
        raise ModelFileError(
            f"{path}: `motion.initial_state` must be 'relaxed' or 'saturated'; "
            f"got {mo['initial_state']!r}."
        )
    values: dict[str, Any] = {k: (int(v) if k == "samples" else v) for k, v in mo.items()}
    written = _table(path, data, "motion", set(_MOTION_DEFAULTS))
    settings = MotionSettings(**values, given=frozenset(written))
    me = _table(path, data, "measurement", _MEASUREMENT_KEYS)
    offset = me.get("force_offset", 0.0)
    if (
        isinstance(offset, bool)
        or not isinstance(offset, (int, float))
        or not math.isfinite(offset)
    ):
        raise ModelFileError(
            f"{path}: `measurement.force_offset` must be a finite number; got {offset!r}."
        )
    return ModelFile(model, settings, MeasurementTerms(float(offset)))


def _density_model(path: Path, fr: dict[str, Any]) -> PIFriction:
    """The model of a ``[friction.density]`` table (no elements beside it)."""
    both = sorted({"stiffness", "breakaway", "threshold"} & set(fr))
    if both:
        raise ModelFileError(
            f"{path}: `friction.{both[0]}` and `friction.density` exclude each other; give "
            "the elements or a density."
        )
    table = fr["density"]
    if not isinstance(table, dict):
        raise ModelFileError(
            f"{path}: `friction.density` must be a table; got {type(table).__name__}."
        )
    kind = table.get("kind")
    if kind not in _DENSITIES:
        raise ModelFileError(
            f"{path}: `friction.density.kind` must be one of {', '.join(_DENSITIES)}; got {kind!r}."
        )
    cls, required, optional = _DENSITIES[kind]
    unknown = sorted(set(table) - {"kind", *required, *optional})
    if unknown:
        raise ModelFileError(
            f"{path}: unknown key `friction.density.{unknown[0]}` for kind {kind!r}; allowed "
            f"keys are {', '.join(('kind', *required, *optional))}."
        )
    missing = [k for k in required if k not in table]
    if missing:
        raise ModelFileError(
            f"{path}: missing `friction.density.{missing[0]}` (kind {kind!r} needs "
            f"{', '.join(required)})."
        )
    try:
        density = cls(**{k: table[k] for k in (*required, *optional) if k in table})
    except (TypeError, ValueError) as exc:
        raise ModelFileError(f"{path}: [friction.density] {exc}") from None
    return PIFriction(fr["coulomb"], density=density, viscous=fr.get("viscous", 0.0))


def save_model(
    path: str | Path,
    model: PIFriction,
    motion: MotionSettings | None = None,
    *,
    measurement: MeasurementTerms | None = None,
    header: str = "",
    overwrite: bool = False,
    axis: str = "linear",
    data: DataSettings | None = None,
) -> None:
    """Write a model file atomically (temporary file, then rename).

    `measurement` adds the `[measurement]` table, `data` the `[data]` table (how
    the records were read), `header` comment lines at the top, `axis` the units
    of the comments. An existing file is replaced only with ``overwrite=True``. The file
    is TOML: a `path` with another suffix than ``.toml`` (a ``.json`` one, which
    `load_model` would read as JSON) is refused.
    """
    check_type("model", model, PIFriction)
    if motion is not None:
        check_type("motion", motion, MotionSettings)
    path = _as_path(path)
    if path.suffix.lower() not in (".toml", ""):
        raise ValueError(
            f"`path` must name a TOML file (suffix .toml): save_model writes TOML with "
            f"comments, which {path.suffix} readers would reject; got {str(path)!r}."
        )
    if data is not None:
        check_type("data", data, DataSettings)
    pieces = model_pieces(model, motion, measurement, header, axis, data)
    first = next(pieces)  # the arguments are checked before any file is touched
    if path.exists() and not overwrite:
        raise FileExistsError(
            f"{path}: already exists; choose another path or pass overwrite=True."
        )
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8") as out:
        out.write(first)
        out.writelines(pieces)  # long element arrays in chunks: no whole text in memory
