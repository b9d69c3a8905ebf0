"""``presliding loop``: a PID position loop with PI friction, simulated exactly, and its
limit cycles predicted by the describing function."""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from presliding.cli.common import (
    UserError,
    check_folder,
    check_outputs,
    check_readable,
    new_figure,
    record_outputs,
    write_csv,
)

#: The specification file, printed by ``presliding loop --help``.
SCHEMA = """\
  [friction]                       # as in a model file (finite elements)
  coulomb = 0.002                  # c1 [N]
  stiffness = [2e4, 5e3, 1.5e3]    # k_j [N/m]
  breakaway = [0.2, 0.2, 0.2]      # c_j [N] (or threshold = [...] r_j [m])
  [plant]
  mass = 1.0                       # m [kg]
  initial_position = 0.0           # [m]   (optional)
  initial_velocity = 0.001         # [m/s] (optional)
  [controller]                     # a discrete PID, u held over each period
  kp = 400.0                       # [N/m]
  ki = 4e4                         # [N/(m s)]  (optional, default 0)
  kd = 0.0                         # [N s/m]    (optional, default 0)
  dt = 1e-4                        # sample time [s]
  filter_time = 0.0                # derivative filter T_f [s] (optional)
  limit = 5.0                      # saturation [N]: a bound, or [low, high] (optional)
  anti_windup = "clamping"         # or "back-calculation", "none" (optional)
  [reference]
  kind = "step"                    # "step", "sine" or "ramp"
  value = 1e-3                     # step height [m], sine amplitude [m] or ramp slope [m/s]
  start = 0.0                      # when it starts [s] (optional)
  frequency = 1.0                  # sine frequency [Hz] (sine only)
  t_end = 4.0                      # end of the run [s], a whole number of periods dt
"""

OUTPUTS = ("loop.csv", "loop.png", "nyquist.png", "report.md", "report.html")
HEADER = ("time [s]", "reference [m]", "position [m]", "velocity [m/s]", "control [N]",
          "friction_force [N]", "error [m]")  # fmt: skip
_TABLES = {
    "plant": {"mass", "initial_position", "initial_velocity"},
    "controller": {"kp", "ki", "kd", "dt", "filter_time", "limit", "anti_windup"},
    "reference": {"kind", "value", "start", "frequency", "t_end"},
}


@dataclass(frozen=True)
class LoopSpec:
    """A validated loop specification."""

    path: Path
    model: Any
    mass: float
    initial_position: float
    initial_velocity: float
    pid: Any
    kind: str
    value: float
    start: float
    frequency: float
    t_end: float

    def reference(self, t: np.ndarray) -> np.ndarray:
        """r at the times t."""
        on = t >= self.start
        if self.kind == "step":
            return np.where(on, self.value, 0.0)
        if self.kind == "ramp":
            return np.where(on, self.value * (t - self.start), 0.0)
        return np.where(on, self.value * np.sin(2 * np.pi * self.frequency * (t - self.start)),
                        0.0)  # fmt: skip


def _number(path: Path, table: dict, name: str, key: str, default: Any = None) -> Any:
    value = table.get(key, default)
    if value is None:
        raise UserError(f"{path}: missing `{name}.{key}`; see `presliding loop --help`.")
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise UserError(f"{path}: `{name}.{key}` must be a finite number; got {value!r}.")
    return float(value)


def load_spec(path: Path) -> LoopSpec:
    """Read and validate a loop specification; a `UserError` names the file and the field."""
    from presliding.control.controllers import PID
    from presliding.model_io import model_from_tables, read_tables

    check_readable(path, "loop specification")
    data = read_tables(path)
    unknown = sorted(set(data) - {"friction", *_TABLES})
    if unknown:
        raise UserError(f"{path}: unknown table `{unknown[0]}`; allowed: friction, "
                        f"{', '.join(_TABLES)}.")  # fmt: skip
    tables = {}
    for name, keys in _TABLES.items():
        table = data.get(name)
        if not isinstance(table, dict):
            raise UserError(f"{path}: missing table `{name}`; see `presliding loop --help`.")
        bad = sorted(set(table) - keys)
        if bad:
            raise UserError(f"{path}: unknown key `{name}.{bad[0]}`; allowed: "
                            f"{', '.join(sorted(keys))}.")  # fmt: skip
        tables[name] = table
    model = model_from_tables(path, {"friction": data.get("friction")} if "friction" in data
                              else {}).model  # fmt: skip
    if not model.is_discrete:
        raise UserError(f"{path}: `friction` must have finite elements for the exact loop; "
                        "discretise the density (stiffness, breakaway).")  # fmt: skip
    pl, co, rf = tables["plant"], tables["controller"], tables["reference"]
    mass = _number(path, pl, "plant", "mass")
    kind = rf.get("kind", "step")
    if kind not in ("step", "sine", "ramp"):
        raise UserError(f"{path}: `reference.kind` must be 'step', 'sine' or 'ramp'; got "
                        f"{kind!r}.")  # fmt: skip
    limit = co.get("limit")
    if limit is not None and not (isinstance(limit, (int, float, list)) and not isinstance(
            limit, bool)):  # fmt: skip
        raise UserError(f"{path}: `controller.limit` must be a number or [low, high]; got "
                        f"{limit!r}.")  # fmt: skip
    try:
        pid = PID(_number(path, co, "controller", "kp"), _number(path, co, "controller", "ki", 0),
                  _number(path, co, "controller", "kd", 0),
                  dt=_number(path, co, "controller", "dt"),
                  filter_time=_number(path, co, "controller", "filter_time", 0.0), limit=limit,
                  anti_windup=co.get("anti_windup", "clamping"))  # fmt: skip
        if not mass > 0:
            raise ValueError(f"`plant.mass` must be positive; got {mass!r}.")
    except (TypeError, ValueError) as exc:
        raise UserError(f"{path}: [controller] {exc}") from None
    if kind == "sine" and "frequency" not in rf:
        raise UserError(f"{path}: a sine reference needs `reference.frequency` [Hz]; see "
                        "`presliding loop --help`.")  # fmt: skip
    if kind != "sine" and "frequency" in rf:
        raise UserError(f"{path}: `reference.frequency` applies to kind = 'sine' only; got "
                        f"kind = {kind!r}.")  # fmt: skip
    freq = _number(path, rf, "reference", "frequency", 0.0)
    if kind == "sine" and not freq > 0:
        raise UserError(f"{path}: `reference.frequency` must be positive; got {freq!r}.")
    return LoopSpec(path, model, mass, _number(path, pl, "plant", "initial_position", 0.0),
                    _number(path, pl, "plant", "initial_velocity", 0.0), pid, kind,
                    _number(path, rf, "reference", "value"),
                    _number(path, rf, "reference", "start", 0.0), freq,
                    _number(path, rf, "reference", "t_end"))  # fmt: skip


def add_parser(sub: Any, parents: list) -> argparse.ArgumentParser:
    """The ``loop`` sub-parser (its handler is set by `presliding.cli.commands`)."""
    loop = sub.add_parser(
        "loop",
        help="a PID position loop with PI friction: exact response, predicted limit cycles",
        description="Simulate a sampled-data PID position loop around a mass with PI friction "
        "exactly (zero-order hold; eq. 17 solved in closed form between events) and predict "
        "its limit cycles (hunting) by harmonic balance with the exact describing function. "
        "Writes loop.csv (the controller's samples, units in the header), loop.png, "
        "nyquist.png (Nyquist curve of the loop with −1/N(A) and the predicted cycles) and "
        "report.md/report.html.",
        epilog="example:\n  presliding loop spec.toml -o loop/\n\n"
        "specification file (TOML, or JSON with the same tables; units in brackets):\n" + SCHEMA,
        formatter_class=argparse.RawDescriptionHelpFormatter,
        parents=parents,
    )
    loop.add_argument("spec", type=Path, help="loop specification (.toml, or .json)")
    loop.add_argument(
        "-o",
        "--output",
        type=Path,
        default=Path("presliding-loop"),
        help="output folder (default: ./presliding-loop)",
    )
    return loop


def run(args: argparse.Namespace) -> int:
    """Load, simulate, predict, write CSV, figures and report."""
    from presliding.control.limit_cycles import predict_limit_cycles
    from presliding.control.loop import simulate_loop

    spec = load_spec(args.spec)
    out = check_folder(args.output)
    paths = [out / name for name in OUTPUTS]
    check_outputs(paths, (args.spec,), overwrite=args.overwrite)
    try:
        res = simulate_loop(spec.model, spec.mass, spec.pid, spec.reference, t_end=spec.t_end,
                            initial_position=spec.initial_position,
                            initial_velocity=spec.initial_velocity)  # fmt: skip
        cycles = predict_limit_cycles(spec.mass, spec.model, spec.pid)
    except (TypeError, ValueError) as exc:
        raise UserError(f"{args.spec}: cannot simulate the loop: {exc}") from None
    record_outputs(paths)
    idx = np.arange(res.control_time.shape[0])
    write_csv(paths[0], HEADER, [res.control_time, res.reference, res.measured,
                                 res.velocity[idx], res.control, res.friction_force[idx],
                                 res.error], quiet=args.quiet)  # fmt: skip
    _figures(res, cycles, paths[1], paths[2], spec)
    _report(out, res, cycles, paths[1], paths[2], spec)
    if not args.quiet:
        print(res.report())
        print(cycles.report())
        for p in paths:
            print(f"wrote {p}")
    return 0 if res.success else 1


def _figures(res: Any, cycles: Any, loop_png: Path, nyquist_png: Path, spec: LoopSpec) -> None:
    from presliding.plotting import save_figure

    fig, axes = new_figure(1, 3, size=(7.5, 8.0))
    for ax, kind in zip(axes[:, 0], ("tracking", "error", "control"), strict=True):
        res.plot(ax=ax, kind=kind)
    axes[0, 0].set_title(f"{spec.path.name}: {spec.kind} reference, PID kp = {spec.pid.kp:g}, "
                         f"ki = {spec.pid.ki:g}, kd = {spec.pid.kd:g}")  # fmt: skip
    save_figure(fig, loop_png)
    fig, axes = new_figure(1, 1, size=(6.4, 5.6))
    cycles.plot(ax=axes[0, 0])
    save_figure(fig, nyquist_png)


def _report(out: Path, res: Any, cycles: Any, loop_png: Path, nyquist_png: Path,
            spec: LoopSpec) -> None:  # fmt: skip
    from presliding.cli.report import Section, write_report

    sim = res.limit_cycle()
    rows = [("", "amplitude [m]", "frequency [rad/s]", "stable")]
    found = zip(cycles.amplitude, cycles.frequency, cycles.stable, strict=True)
    rows += [("predicted", f"{a:.6g}", f"{w:.6g}", str(bool(s))) for a, w, s in found]
    rows.append(("simulated (second half)", f"{sim.amplitude:.6g}", f"{sim.frequency:.6g}",
                 "steady" if sim.steady else "not steady"))  # fmt: skip
    sections = [
        Section("Closed loop", "The sampled-data loop simulated exactly: the PID's output is "
                "held over each period and the motion of eq. 17 is solved in closed form "
                "between events, with exact stiction.", (loop_png,), code=res.report()),
        Section("Limit cycles", "Harmonic balance G(jω)·N(A) = −1 with the exact describing "
                "function of the friction, G the loop's linear part seen by the friction "
                "force; Loeb's criterion gives the stability. The describing function assumes "
                "near-sinusoidal motion: long rests (stick-slip) violate it.", (nyquist_png,),
                code=cycles.report(), table=rows),
    ]  # fmt: skip
    write_report(out, f"presliding loop: {spec.path.name}", sections)


__all__ = ["OUTPUTS", "SCHEMA", "add_parser", "load_spec", "run"]
