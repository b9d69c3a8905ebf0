"""Sweep specifications for ``presliding sweep``: reading and validation.

A specification file (TOML, or JSON with the same tables) holds a base model,
its free motion and the grid to sweep. Each grid point is the free motion
m·ÿ + c1·Sign(ẏ) + F_el(y) = u (eqs. 12, 17; u constant, 0 by default) of the
base model with the swept parameters replaced. The per-chunk work (`SweepTask`,
`evaluate_chunk`) lives in `_sweep_chunk`. Schema (units
in brackets)::

    [friction]                      # the base model, exactly as in a model file
    coulomb = 0.3                   # c1 [N] (replaced by a coulomb or coulomb_ratio axis)
    stiffness = [2e4, 5e3, 1.5e3]   # k_j [N/m]
    breakaway = [0.2, 0.2, 0.3]     # c_j [N] (or threshold = [...] r_j [m], eq. 6,
                                    #  or a [friction.density] table, eq. 10)
    [motion]                        # optional
    mass = 1.0                      # m [kg]
    initial_velocity = 1.0          # v0 [m/s]
    initial_position = 0.0          # y0 [m]
    initial_state = "relaxed"       # default; or "saturated": a long slide before, in the
                                    #  direction of v0 (the paper's start for eqs. 13-16)
    applied_force = 0.0             # u [N], constant ("simulate" only)
    t_end = 1.0                     # [s] horizon of "simulate": later stops are missed

    [sweep]
    quantity = "reversals"          # "reversals" [-]: turning points before the stop;
                                    # "rest_position" [m]; "stop_time" [s] ("simulate")
    method = "simulate"             # "simulate": the exact event batch (finite elements);
                                    # "analysis": turning points by the work-energy
                                    # balance (eqs. 13-16; any model, u = 0).
                                    # Default: simulate for elements, analysis for a density
    chunk_size = 5000               # optional: grid points per call (default: about 64
                                    #  chunks, at least 4 per worker, >= 500 points)

    [sweep.axes]                    # one or two axes; the first is x of the map
    coulomb_ratio = {start = 0.05, stop = 1.2, num = 60}   # c1/F_m [-], the base F_m kept
    initial_velocity = {start = 0.05, stop = 2.0, num = 60, scale = "log"}   # v0 [m/s]
    # any axis also as explicit values: mass = {values = [0.5, 1.0, 2.0]}

Axes: coulomb_ratio c1/F_m [-], coulomb c1 [N], initial_velocity v0 [m/s],
mass m [kg]; an axis replaces the base value of its parameter. `num` >= 1
points from `start` to `stop` (increasing), `scale` "linear" (default) or
"log"; or `values`, increasing. A point whose motion has not stopped (still
moving at `t_end`, or c1 = 0 with no stop) gets NaN and `stopped` = 0.
Unknown keys are errors, so a misspelt field is never ignored.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from presliding.cli.common import UserError
from presliding.friction.pi_friction import PIFriction
from presliding.model_io import MotionSettings, model_from_tables, read_tables
from presliding.sweep._tasks import SweepTask

_DOC = __doc__ or ""
#: The schema shown by ``presliding sweep --help``.
SCHEMA = _DOC[_DOC.find("    [friction]") :].rstrip() + "\n"

#: Axis name: (unit, description).
AXES: dict[str, tuple[str, str]] = {
    "coulomb_ratio": ("-", "c1 / F_m"),
    "coulomb": ("N", "Coulomb element c1"),
    "initial_velocity": ("m/s", "initial velocity v0"),
    "mass": ("kg", "mass m"),
}
#: Quantity name: (unit, description).
QUANTITIES: dict[str, tuple[str, str]] = {
    "reversals": ("-", "reversals before the stop"),
    "rest_position": ("m", "rest position"),
    "stop_time": ("s", "stop time"),
}
METHODS = ("simulate", "analysis")
MAX_POINTS = 10_000_000
_SWEEP_KEYS = ("quantity", "method", "chunk_size", "axes")
_AXIS_KEYS = ("start", "stop", "num", "scale", "values")


@dataclass(frozen=True)
class Axis:
    """One swept parameter: its name, its values (increasing) and the scale they were made on."""

    name: str
    values: np.ndarray
    scale: str = "linear"

    @property
    def unit(self) -> str:
        return AXES[self.name][0]

    @property
    def label(self) -> str:
        return f"{self.name} [{self.unit}]"


@dataclass(frozen=True)
class SweepSpec:
    """A validated specification file."""

    path: Path
    model: PIFriction
    motion: MotionSettings
    quantity: str
    method: str
    axes: tuple[Axis, ...]
    chunk_size: int | None

    @property
    def n_points(self) -> int:
        return math.prod(a.values.size for a in self.axes)

    @property
    def grid(self) -> dict[str, np.ndarray]:
        return {a.name: a.values for a in self.axes}

    def task(self, single_thread: bool = False) -> SweepTask:
        return SweepTask(self.model, self.motion, self.quantity, self.method, single_thread)


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _fail(path: Path, text: str) -> UserError:
    return UserError(f"{path}: {text}")


def load_spec(path: Path) -> SweepSpec:
    """Read and validate a sweep specification; a `UserError` names the file and the field.

    Order: the tables, then `[sweep]` and its axes, then the model, then what
    depends on both (method, quantity, ranges).
    """
    data = read_tables(path)
    unknown = sorted(set(data) - {"friction", "motion", "sweep"})
    if unknown:
        raise _fail(path, f"unknown table `{unknown[0]}`; allowed: friction, motion, sweep.")
    sw = data.get("sweep")
    if not isinstance(sw, dict):
        raise _fail(path, "missing table `sweep`; see `presliding sweep --help`.")
    bad = sorted(set(sw) - set(_SWEEP_KEYS))
    if bad:
        raise _fail(path, f"unknown key `sweep.{bad[0]}`; allowed: {', '.join(_SWEEP_KEYS)}.")
    quantity = sw.get("quantity")
    if quantity not in QUANTITIES:
        names = ", ".join(map(repr, QUANTITIES))
        raise _fail(path, f"`sweep.quantity` must be one of {names}; got {quantity!r}.")
    chunk = sw.get("chunk_size")
    if chunk is not None and (not isinstance(chunk, int) or isinstance(chunk, bool) or chunk < 1):
        raise _fail(path, f"`sweep.chunk_size` must be a whole number >= 1; got {chunk!r}.")
    axes = _axes(path, sw.get("axes"))
    motion = data.get("motion", {})
    if isinstance(motion, dict) and "samples" in motion:
        raise _fail(path, "`motion.samples` has no use in a sweep (only the stop counts).")
    fr = data.get("friction")
    if (
        isinstance(fr, dict)
        and "coulomb" not in fr
        and {"coulomb", "coulomb_ratio"} & {a.name for a in axes}
    ):
        fr = {**fr, "coulomb": 1.0}  # a placeholder: the axis sets c1
    base = model_from_tables(path, {**data, "friction": fr} if fr is not None else data)
    model, motion = base.model, base.motion
    method = sw.get("method", "simulate" if model.is_discrete else "analysis")
    if method not in METHODS:
        raise _fail(path, f"`sweep.method` must be 'simulate' or 'analysis'; got {method!r}.")
    if method == "simulate" and not model.is_discrete:
        raise _fail(path, "`sweep.method` 'simulate' needs finite elements; use 'analysis'.")
    if method == "analysis" and quantity == "stop_time":
        raise _fail(
            path, "`sweep.quantity` 'stop_time' needs method = 'simulate' (analysis has no times)."
        )
    if method == "analysis" and model.viscous != 0.0:
        raise _fail(
            path,
            "`friction.viscous` must be 0 with method 'analysis' (eqs. 13-16 assume no viscous "
            f"friction, the paper's assumption (i)); got {model.viscous!r}: use method = "
            "'simulate' (finite elements).",
        )
    if method == "analysis" and motion.applied_force != 0.0:
        raise _fail(
            path,
            "`motion.applied_force` must be 0 with method 'analysis' (free motion, eq. 12); "
            f"got {motion.applied_force!r}.",
        )
    spec = SweepSpec(path, model, motion, quantity, method, axes, chunk)
    _check_domain(spec)
    return spec


def _axes(path: Path, table: Any) -> tuple[Axis, ...]:
    example = "e.g. [sweep.axes] initial_velocity = {start = 0.1, stop = 2.0, num = 40}"
    if table is None:
        raise _fail(path, f"missing table `sweep.axes` ({example}).")
    if not isinstance(table, dict) or not 1 <= len(table) <= 2:
        got = f"{len(table)} axes" if isinstance(table, dict) else repr(table)
        raise _fail(
            path, f"`sweep.axes` must be a table of one or two axes ({example}); got {got}."
        )
    axes = []
    for name, entry in table.items():
        field = f"sweep.axes.{name}"
        if name not in AXES:
            allowed = ", ".join(f"{k} [{u}]" for k, (u, _) in AXES.items())
            raise _fail(path, f"unknown axis `{field}`; allowed axes are {allowed}.")
        axes.append(_axis(path, field, name, entry))
    if {"coulomb", "coulomb_ratio"} <= set(table):
        raise _fail(
            path, "`sweep.axes.coulomb` and `sweep.axes.coulomb_ratio` both set c1; keep one."
        )
    n = math.prod(a.values.size for a in axes)
    if n > MAX_POINTS:
        raise _fail(
            path,
            f"`sweep.axes` give {n} points; at most {MAX_POINTS} per run (split "
            "the sweep, or lower num).",
        )
    return tuple(axes)


def _axis(path: Path, field: str, name: str, entry: Any) -> Axis:
    form = "{start = ..., stop = ..., num = ...} or {values = [...]}"
    if not isinstance(entry, dict):
        raise _fail(path, f"`{field}` must be a table {form}; got {entry!r}.")
    bad = sorted(set(entry) - set(_AXIS_KEYS))
    if bad:
        raise _fail(
            path, f"unknown key `{field}.{bad[0]}`; allowed keys are {', '.join(_AXIS_KEYS)}."
        )
    if "values" in entry:
        others = sorted(set(entry) - {"values"})
        if others:
            raise _fail(
                path,
                f"`{field}.values` excludes `{field}.{others[0]}`; give values "
                "or start, stop, num.",
            )
        values = entry["values"]
        if not isinstance(values, list) or not values or not all(map(_is_number, values)):
            raise _fail(
                path, f"`{field}.values` must be a non-empty list of numbers; got {values!r}."
            )
        arr = np.array(values, dtype=np.float64)
        if not np.all(np.isfinite(arr)):
            raise _fail(path, f"`{field}.values` must be finite; got {values!r}.")
        if np.any(np.diff(arr) <= 0):
            raise _fail(path, f"`{field}.values` must increase strictly; got {values!r}.")
        return Axis(name, arr)
    missing = [k for k in ("start", "stop", "num") if k not in entry]
    if missing:
        raise _fail(path, f"missing `{field}.{missing[0]}`; an axis is {form}.")
    num = entry["num"]
    if not isinstance(num, int) or isinstance(num, bool) or num < 1:
        raise _fail(path, f"`{field}.num` must be a whole number >= 1; got {num!r}.")
    if num > MAX_POINTS:  # before the axis is allocated
        raise _fail(path, f"`{field}.num` must be at most {MAX_POINTS} per run; got {num!r}.")
    for key in ("start", "stop"):
        if not _is_number(entry[key]) or not math.isfinite(entry[key]):
            raise _fail(path, f"`{field}.{key}` must be a finite number; got {entry[key]!r}.")
    start, stop = float(entry["start"]), float(entry["stop"])
    if num > 1 and not start < stop:
        raise _fail(
            path, f"`{field}.start` must be less than `{field}.stop`; got {start!r} and {stop!r}."
        )
    scale = entry.get("scale", "linear")
    if scale not in ("linear", "log"):
        raise _fail(path, f"`{field}.scale` must be 'linear' or 'log'; got {scale!r}.")
    if scale == "log":
        if not start > 0:
            raise _fail(path, f"`{field}.start` must be positive with scale 'log'; got {start!r}.")
        return Axis(name, np.geomspace(start, stop, num), scale)
    return Axis(name, np.linspace(start, stop, num), scale)


def _check_domain(spec: SweepSpec) -> None:
    """Physical ranges: c1 >= 0 (> 0 without elements), m > 0, a direction to saturate in."""
    path, model = spec.path, spec.model
    fm = model.max_elastic_force
    for axis in spec.axes:
        field, low = f"sweep.axes.{axis.name}", float(axis.values.min())
        if axis.name == "coulomb_ratio" and not fm > 0:
            raise _fail(
                path,
                f"`{field}` needs elasto-plastic elements (F_m > 0); the base "
                "model is pure Coulomb: sweep `coulomb` instead.",
            )
        if axis.name in ("coulomb", "coulomb_ratio") and low < 0:
            raise _fail(path, f"`{field}` must be nonnegative (c1 >= 0); got {low!r}.")
        if axis.name in ("coulomb", "coulomb_ratio") and low == 0 and not fm > 0:
            raise _fail(path, f"`{field}` must be positive for a pure Coulomb model; got 0.0.")
        if axis.name == "mass" and not low > 0:
            raise _fail(path, f"`{field}` must be positive (m > 0); got {low!r}.")
    mo = spec.motion
    v0 = spec.grid.get("initial_velocity", np.array([mo.initial_velocity]))
    if mo.initial_state == "saturated" and mo.applied_force == 0.0 and np.any(v0 == 0):
        field = "sweep.axes" if "initial_velocity" in spec.grid else "motion"
        raise _fail(path, f"`{field}.initial_velocity` holds 0; `motion.initial_state` "
                          "'saturated' needs a nonzero velocity (its direction).")  # fmt: skip


__all__ = [
    "AXES",
    "QUANTITIES",
    "SCHEMA",
    "Axis",
    "SweepSpec",
    "load_spec",
]
