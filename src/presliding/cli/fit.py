"""``presliding fit``: identification from a data file (section 4) to a model file and report.

The data file is delimited text (a header line or none; comma, tab, semicolon
or whitespace) or a MATLAB file (by its ``.mat`` suffix). Units at the end of
column headers are converted to SI; ``--units`` gives or overrides them and
``--scale`` applies a factor on top (for a MATLAB file, a number or the name of
a scalar variable). ``--window START:STOP`` keeps the samples in that time span.

Exit codes, the same for every ``--kind`` (`identification._status.EXIT_CODES`):
0 when the fit converged; 1 when it did not (status ``local_minimum``,
``model_inadequate``, ``not_identifiable``, ``at_bound``, ``poor_fit``,
``max_evaluations`` or ``failed``: the report names the rule that fired); 2 for a
user error. ``model.toml`` is written for a converged fit, and marked as not
converged in its header for ``local_minimum``, ``model_inadequate``,
``not_identifiable``, ``at_bound`` and ``max_evaluations``; a ``poor_fit`` or
``failed`` fit, or one with non-finite or absurd parameters, writes none.
"""

from __future__ import annotations

import argparse
import textwrap
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from presliding._progress import Progress, progress_enabled
from presliding.cli.common import (
    UserError,
    check_folder,
    check_options,
    check_outputs,
    check_readable,
    column_key,
    record_outputs,
)

SIGNALS = ("time", "position", "velocity", "acceleration", "applied_force", "friction_force")
#: Column names tried for each signal (after `column_key` normalisation).
ALIASES = {
    "time": ("time", "t"),
    "position": ("position", "displacement", "y", "x"),
    "velocity": ("velocity", "v", "speed"),
    "acceleration": ("acceleration", "a"),
    "applied_force": ("applied_force", "u", "force_applied", "input"),
    "friction_force": ("friction_force", "friction", "force", "f"),
}
#: Signals each kind needs (one of a tuple), and those it uses when present.
NEEDS = {
    "presliding": (("position",), ("friction_force",)),
    "motion": (("time",), ("position",), ("applied_force",)),
    "response": (("time",), ("velocity", "position")),
    "quasi-static": (("position",), ("applied_force",)),
    "virgin": (("position",), ("friction_force", "applied_force")),
}
OPTIONAL = {
    "presliding": ("time",),
    "motion": ("velocity", "acceleration"),
    "response": ("applied_force",),
    "quasi-static": ("time",),
    "virgin": ("time",),
}
DEFAULT_ELEMENTS = {"presliding": 3, "motion": 0, "response": 4, "quasi-static": 3, "virgin": 3}
#: The help text of `presliding fit` (description and examples).
FIT_DESCRIPTION = (
    "Identify friction parameters (section 4) from a data file: delimited "
    "text (comma, tab, semicolon or whitespace; with a header line, or without one and "
    "columns chosen by 0-based index) or a MATLAB .mat file (columns are variables). "
    "--kind presliding: friction force against displacement (columns position, "
    "friction_force; time for --window); motion: eq. 17 as a regression (time, position, "
    "applied_force; velocity and acceleration are estimated when absent); response: "
    "simulated against measured motion (time, velocity and/or position, optional "
    "applied_force; several files pooled with shared physics and per-record starts); "
    "quasi-static: position from a slow force (position, applied_force; pooled); virgin: "
    "the virgin curve from loading ramps or loops (position, friction or applied force). "
    "With two or more files the report has a leave-one-record-out table. "
    "Columns are found by name ('Position [mm]' is position) unless "
    "--columns names them. A unit at the end of a header ('Position [mm]', 'x (um)', "
    "'Friction [uN]', 'torque [mN m]', 't [ms]', 'angle [deg]') is converted to SI (m, N, "
    "s; rad and N m for rotary axes); --units gives or overrides units, --scale applies "
    "a factor on top (a number, or for MAT files the name of a scalar variable). "
    "Exit status 0: converged; 1: the fit did not converge or is poor (see the report; "
    "model.toml is then marked as such, or not written for a poor or failed fit); "
    "2: a user error."
)
FIT_DESCRIPTION = "\n".join(textwrap.wrap(FIT_DESCRIPTION, 88))
FIT_EPILOG = (
    "examples:\n  presliding fit loops.csv --kind presliding --elements 4 -o fit/\n"
    "  presliding fit tribometer.txt --kind presliding --scale friction_force=-1 "
    "--window 8:210 -o fit/\n"
    "  presliding fit DATA_EMPS.mat --kind motion --columns time=t position=qm "
    "applied_force=vir --scale applied_force=gtau --viscous --offset -o fit/\n"
    "  presliding fit xf.txt --kind presliding --columns position=0 friction_force=1 -o fit/\n"
    "  presliding fit stop1.csv stop2.csv stop3.csv --kind response --signal both "
    "--initial-state preload -o fit/\n"
    "  presliding fit loop*.csv --kind quasi-static --elements 3 -o fit/"
)
#: Seconds before a fit shows progress: a quick fit (or a user error) prints nothing but its
#: results; a longer one shows its parts, stages and solver evaluations on stderr.
PROGRESS_DELAY = 1.0


def fit_progress(quiet: bool) -> Progress:
    """The fit command's progress: a bar on a terminal after `PROGRESS_DELAY`, silent when
    stderr is not a terminal (a log, a pipe) or with ``--quiet``."""
    return Progress("presliding fit", total=3, unit="stage", delay=PROGRESS_DELAY,
                    quiet=not progress_enabled(quiet))  # fmt: skip


#: A threshold beyond this many times the measured travel is not a model value.
ABSURD_TRAVEL = 100.0


def parse_window(text: str | None) -> tuple[float | None, float | None] | None:
    """``"8:210"`` → (8.0, 210.0); either side may be empty (``"8:"``, ``":210"``)."""
    if text is None:
        return None
    start, sep, stop = text.partition(":")
    try:
        if not sep:
            raise ValueError
        bounds = tuple(float(x) if x.strip() else None for x in (start, stop))
    except ValueError:
        raise UserError(
            f"--window {text}: expected START:STOP in seconds, e.g. --window 8:210 (either "
            "side may be left empty)."
        ) from None
    if any(b is not None and not np.isfinite(b) for b in bounds):
        raise UserError(f"--window {text}: the bounds must be finite numbers of seconds.")
    return bounds  # type: ignore[return-value]


def _is_mat(path: Path) -> bool:
    with open(path, "rb") as fh:
        return path.suffix.lower() == ".mat" or fh.read(19) == b"MATLAB 5.0 MAT-file"


def _locate(signal: str, columns: dict[str, str], names: Sequence[str] | None) -> str | int | None:
    """The column (name or index) of `signal`: from --columns, else by alias; None if absent."""
    if signal in columns:
        spec = columns[signal]
        if names is not None and spec in names:
            return spec
        return int(spec) if spec.lstrip("-").isdigit() else spec
    if names is None:
        return None
    keys = [column_key(n) for n in names]
    for alias in ALIASES[signal]:
        for name, key in zip(names, keys, strict=True):
            if alias in (name, key):
                return name
    return None


def read_measurement(args: argparse.Namespace) -> Any:
    """The Measurement of the columns `args.kind` needs, in SI, windowed; clear errors."""
    from presliding.measurement._mat import read_mat
    from presliding.measurement._readers import read_text
    from presliding.measurement.measurement import Measurement

    check_readable(args.data, "data file")
    columns = check_options(args.columns, "--columns", SIGNALS)
    units = check_options(args.units, "--units", SIGNALS)
    window = parse_window(args.window)
    mat = _is_mat(args.data)
    scales: dict[str, Any] = {}
    for key, text in check_options(args.scale, "--scale", SIGNALS).items():
        try:
            scales[key] = float(text)
        except ValueError:
            if not mat:
                raise UserError(
                    f"--scale {key}={text}: the factor must be a number (names of scalar "
                    "variables work for MATLAB files only)."
                ) from None
            scales[key] = text
        if isinstance(scales[key], float) and not (np.isfinite(scales[key]) and scales[key]):
            raise UserError(f"--scale {key}={text}: the factor must be finite and nonzero.")
    text_options: dict[str, Any] = {"header": getattr(args, "header", None),
                    "decimal": getattr(args, "decimal", None) or "."}  # fmt: skip
    source = read_mat(args.data) if mat else read_text(args.data, **text_options)
    names = source.names if mat else (list(source.names) if source.names else None)
    found = {}
    for signal in (*[s for group in NEEDS[args.kind] for s in group], *OPTIONAL[args.kind]):
        col = _locate(signal, columns, names)
        if col is not None:
            found[signal] = col
    rate = args.sample_rate
    numbered = ("presliding", "virgin")  # fits that use no time
    if "time" not in found and rate is None and args.kind in numbered and window is None:
        rate = 1.0  # numbered samples: the presliding fit needs no time
    for group in NEEDS[args.kind]:
        if not any(s in found for s in group) and not (group == ("time",) and rate):
            raise UserError(_missing(args, group, names, mat))
    time = found.pop("time", None)
    if time is None and rate is None:
        raise UserError(_missing(args, ("time",), names, mat))
    if time is not None and rate is not None:
        raise UserError(f"--sample-rate: {args.data} has a time column ({time!r}); drop one.")
    reader: Callable[..., Measurement] = Measurement.from_mat if mat else Measurement.from_csv
    extra = {} if mat else text_options
    meas = reader(args.data, time, sample_rate=rate, units=units or None, scale=scales,
                  axis=getattr(args, "axis", None), **extra, **found)  # fmt: skip
    if time is None and args.sample_rate is None:
        note = "no time column: samples numbered 0, 1, 2, ..."
        assert meas.source is not None  # a record read from a file knows its source
        meas = replace(meas, source=replace(meas.source, sample_rate=None, notes=(note,)))
    if window is not None:
        try:
            meas = meas.window(*window)
        except ValueError as exc:
            raise UserError(f"--window {args.window}: {exc}") from None
    return meas


def _missing(args: argparse.Namespace, group: tuple[str, ...], names: Any, mat: bool) -> str:
    what = " or ".join(f"`{s}`" for s in group)
    if names is None:
        return (
            f"{args.data}: has no header line, so columns are chosen by 0-based index; name "
            f"{what} with --columns, e.g. --columns time=0 position=1."
        )
    kinds = "variables" if mat else "columns"
    hint = " (or give --sample-rate HZ)" if group == ("time",) else ""
    return (
        f"{args.data}: no {kinds[:-1]} for {what} (needed by --kind {args.kind}); the {kinds} "
        f"are {', '.join(repr(n) for n in names)}; name it with --columns "
        f"{group[0]}=COLUMN{hint}."
    )


def fit(args: argparse.Namespace, meas: Any, bar: Any = False) -> tuple[Any, Any]:
    """Run the fit of `args.kind`; returns the FitResult and the measurement it used.

    `bar` (a `Progress`, or False) shows the fit's stages and evaluations.
    """
    n = DEFAULT_ELEMENTS[args.kind] if args.elements is None else args.elements
    if n == "auto" and args.kind != "response":
        raise UserError(f"--elements auto is for --kind response; got --kind {args.kind}.")
    if n != "auto" and n < 0:
        raise UserError(f"--elements must be 0 or more; got {n}.")
    if args.kind == "presliding":
        from presliding.identification.fit_presliding import fit_presliding

        return fit_presliding(
            meas.position, meas.friction_force, n, offset=args.offset, search=args.search,
            seed=args.seed, progress=bar,
        ).on_axis(meas.axis), meas  # fmt: skip
    fixed = None if args.mass is None else {"mass": args.mass}
    if args.kind == "motion":
        from presliding.identification.fit_motion import fit_motion

        if meas.velocity is None or meas.acceleration is None:
            meas = meas.resample(meas.sampling_step) if not meas.is_uniform else meas
            cutoff = 0.1 / meas.sampling_step if args.cutoff is None else args.cutoff
            meas = meas.differentiate(cutoff)
        return fit_motion(meas, n, viscous=args.viscous, offset=args.offset, fixed=fixed,
                          asymmetric=args.asymmetric, progress=bar), meas  # fmt: skip
    from presliding.identification.fit_response import fit_response

    signal = "velocity" if meas.velocity is not None else "position"
    return fit_response(meas, n, mass=args.mass, signal=signal, progress=bar), meas


def _motion_settings(args: argparse.Namespace, meas: Any, result: Any) -> Any:
    """[motion] table reproducing the fitted response (response and motion kinds)."""
    from presliding.model_io import MotionSettings

    mass = result.parameters.get("mass")
    if mass is None or args.kind != "response":
        return None if mass is None else MotionSettings(mass=float(mass))
    t = meas.time
    v = meas.velocity if meas.velocity is not None else np.gradient(meas.position, t)
    u = meas.applied_force
    y0 = meas.position[0] if meas.position is not None else 0.0
    return MotionSettings(
        mass=float(mass),
        initial_velocity=float(result.parameters.get("initial_velocity", v[0])),
        initial_position=float(result.parameters.get("initial_position", y0)),
        initial_state="saturated",
        applied_force=float(u[0]) if u is not None and np.all(u == u[0]) else 0.0,
        t_end=float(t[-1] - t[0]),
        samples=int(t.shape[0]),
    )


def model_problem(result: Any, meas: Any) -> str:
    """Why the fitted model must not be written ("" when it may be)."""
    if result.status in ("poor_fit", "failed"):
        return f"the fit's status is {result.status}"
    if result.model is None:
        return "the fitted parameters do not form a valid model"
    values = np.array(list(result.parameters.values()), dtype=float)
    if not np.all(np.isfinite(values)):
        return "some fitted parameters are not finite"
    if result.model.is_discrete and result.model.n_elements and meas.position is not None:
        travel = float(np.ptp(meas.position))
        big = float(np.max(result.model.threshold))
        if big > ABSURD_TRAVEL * travel:
            return (
                f"a threshold of {big:.3g} is {big / travel:.3g} times the measured travel "
                f"{travel:.3g} (the data do not determine it; try fewer --elements)"
            )
    return ""


def _command_line(args: argparse.Namespace) -> str:
    """The fit's command line, rebuilt from its options (paths shortened to file names)."""
    parts = ["presliding fit", args.data.name, "--kind", args.kind]
    for option in ("columns", "units", "scale"):
        items = getattr(args, option)
        if items:
            parts += [f"--{option}", *items]
    for option, value in (("--window", args.window), ("--sample-rate", args.sample_rate),
                          ("--elements", args.elements), ("--cutoff", args.cutoff),
                          ("--mass", args.mass)):  # fmt: skip
        if value is not None:
            parts += [option, str(value)]
    parts += [flag for flag in ("--viscous", "--offset", "--asymmetric") if getattr(args, flag[2:])]
    return " ".join(parts)


def _header(args: argparse.Namespace, meas: Any, result: Any) -> str:
    lines = [f"identified by `{_command_line(args)}`"]
    if result.status != "converged":
        lines.append(f"NOT CONVERGED: status {result.status}. Check the report before using it.")
    lines.append(f"status {result.status}, NRMSE {100 * result.nrmse:.3g} %")
    lines.append("data: " + meas.source.describe())
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    """Read, fit, write model.toml, fit.png and the report; print the fit report."""
    from presliding.cli.fit_figure import save_fit_figure
    from presliding.cli.report import Section, write_report
    from presliding.model_io import MeasurementTerms, save_model

    joined = bool(getattr(args, "join", None))
    if isinstance(args.data, list) and len(args.data) != 1 and not joined:
        raise UserError(f"--kind {args.kind} takes one data file; got {len(args.data)}.")
    # the files read, and a reader for a --join group: `presliding.cli.records.prepare_single`
    first = args.data[0] if isinstance(args.data, list) and args.data else args.data
    inputs = list(getattr(args, "inputs", None) or [first])
    if isinstance(args.data, list):
        args.data = args.data[0] if args.data else None
    folder = check_folder(args.output)
    paths = {
        "model": folder / "model.toml",
        "figure": folder / "fit.png",
        "md": folder / "report.md",
        "html": folder / "report.html",
    }
    check_outputs(paths.values(), inputs, overwrite=args.overwrite)
    with fit_progress(args.quiet) as bar:
        bar.part(f"reading {inputs[0].name}")
        meas = args.read(args) if getattr(args, "read", None) else read_measurement(args)
        if args.data is None:  # one --join group: named by its first file
            args.data, args.join = inputs[0], None
        bar.update()
        bar.part(f"fitting (--kind {args.kind}, {meas.time.shape[0]} samples)")
        try:
            result, meas = fit(args, meas, bar)
        except (TypeError, ValueError) as exc:
            raise UserError(f"{args.data}: cannot fit: {exc}") from None
        bar.update()
        bar.part(f"writing {folder}")
        record_outputs(paths.values())
        save_fit_figure(args, meas, result, paths["figure"])
        written = [paths["figure"]]
        problem = model_problem(result, meas)
        if not problem:
            offset = result.parameters.get("offset")
            terms = None if offset is None else MeasurementTerms(float(offset))
            save_model(
                paths["model"], result.model, _motion_settings(args, meas, result),
                measurement=terms, header=_header(args, meas, result), overwrite=True,
                axis=meas.axis,
            )  # fmt: skip
            written.insert(0, paths["model"])
        else:  # an earlier run's model.toml would be taken for this fit's
            paths["model"].unlink(missing_ok=True)
        note = f"No model.toml written: {problem}." if problem else ""
        text = (
            f"Fit of {args.data.name} (--kind {args.kind}): {result.status}. "
            f"NRMSE {100 * result.nrmse:.3g} %. {note}"
        )
        data = "Data: " + meas.source.describe()
        written += write_report(
            folder,
            f"presliding fit: {args.data.name}",
            [Section("Result", text, (paths["figure"],), code=f"{data}\n\n{result.report()}")],
        )
        bar.update()
    if not args.quiet:
        print("data: " + meas.source.describe())
        print(result.report())
        if note:
            print(note)
        for p in written:
            print(f"wrote {p}")
    from presliding.identification.judge._status import exit_code

    return exit_code(result.status)


__all__ = [
    "ALIASES",
    "FIT_DESCRIPTION",
    "FIT_EPILOG",
    "PROGRESS_DELAY",
    "fit",
    "fit_progress",
    "model_problem",
    "parse_window",
    "read_measurement",
    "run",
]
