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
from typing import Any

import numpy as np

from presliding._progress import Progress, progress_enabled
from presliding.cli.common import (
    UserError,
    check_folder,
    check_outputs,
    cli_words,
    record_outputs,
)
from presliding.cli.inputs.columns import ALIASES
from presliding.cli.inputs.files import parse_window, read_measurement
from presliding.friction.pi_friction import PIFriction

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
            seed=args.seed, max_evaluations=args.max_evaluations,
            asymmetric=args.asymmetric, progress=bar,
        ).on_axis(meas.axis), meas  # fmt: skip
    fixed = None if args.mass is None else {"mass": args.mass}
    if args.kind == "motion":
        from presliding.identification.fit_motion import fit_motion

        if meas.velocity is None or meas.acceleration is None:
            meas = meas.resample(meas.sampling_step) if not meas.is_uniform else meas
            cutoff = 0.1 / meas.sampling_step if args.cutoff is None else args.cutoff
            meas = meas.differentiate(cutoff)
        elif args.cutoff is not None:
            raise UserError(f"--cutoff {args.cutoff:g}: {args.data} has velocity and "
                            "acceleration columns, so nothing is estimated; drop it.")  # fmt: skip
        return fit_motion(meas, n, viscous=args.viscous, offset=args.offset, fixed=fixed,
                          asymmetric=args.asymmetric, max_evaluations=args.max_evaluations,
                          progress=bar), meas  # fmt: skip
    from presliding.identification.fit_response import fit_response

    signal = "velocity" if meas.velocity is not None else "position"
    return fit_response(meas, n, mass=args.mass, signal=signal, asymmetric=args.asymmetric,
                        progress=bar), meas  # fmt: skip


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
    if not isinstance(result.model, PIFriction):  # what `save_model` writes (GMS, LuGre, ...)
        return (f"model files hold PI friction; the {type(result.model).__name__} fit's "
                "parameters, intervals and status are in the report")  # fmt: skip
    values = np.array(list(result.parameters.values()), dtype=float)
    if not np.all(np.isfinite(values)):
        return "some fitted parameters are not finite"
    threshold = result.model.threshold  # None for a density
    if threshold is not None and result.model.n_elements and meas.position is not None:
        travel = float(np.ptp(meas.position))
        big = float(np.max(threshold))
        if big > ABSURD_TRAVEL * travel:
            return (
                f"a threshold of {big:.3g} is {big / travel:.3g} times the measured travel "
                f"{travel:.3g} (the data do not determine it; try fewer --elements)"
            )
    return ""


def explained(result: Any, records: list[Any], labels: list[str]) -> Any:
    """The result with the column roles of its records among its notes (the result's
    metadata: `FitResult.notes`, its report and `to_dict`), and its message and notes in
    the command line's words (`cli_words`)."""
    from dataclasses import replace

    from presliding.cli.common import cli_words

    notes = tuple(cli_words(n) for n in (*column_roles(records, labels), *result.notes))
    return replace(result, notes=notes, message=cli_words(result.message))


def column_roles(records: list[Any], labels: list[str]) -> list[str]:
    """The column roles of the records (`Source.roles`): once when every file was read
    alike, else each file's own, named."""
    own = [meas.source.roles if meas.source is not None else () for meas in records]
    if not own or all(o == own[0] for o in own):
        return list(own[0]) if own else []
    roles, seen = [], set()
    for meas, label, lines in zip(records, labels, own, strict=True):
        path = meas.source.path if meas.source is not None else label
        if lines and path not in seen:  # the pieces of one file share its roles
            seen.add(path)
            roles += [f"{label.split(' #')[0]}: {line}" for line in lines]
    return roles


def data_settings(args: argparse.Namespace, records: list[Any]) -> Any:
    """The model file's ``[data]`` table: how these records were read (columns shared by
    every file, the units, factors, sample rate, text options, axis and cut given)."""
    from presliding._model_data import DataSettings
    from presliding.cli.common import check_options
    from presliding.cli.inputs.columns import SIGNALS

    columns: dict[str, Any] = {}
    for i, meas in enumerate(records):
        conversions = meas.source.all_conversions() if meas.source is not None else ()
        mine = {c.signal: c.column for c in conversions if c.column != "sample rate"}
        if meas.source is not None and meas.source.kind == "join":
            mine = {}  # --join files: each names its own columns
        columns = mine if i == 0 else {k: v for k, v in columns.items() if mine.get(k) == v}
    scale: dict[str, Any] = {}
    for key, text in check_options(args.scale, "--scale", SIGNALS).items():
        try:
            scale[key] = float(text)
        except ValueError:
            scale[key] = text  # a MATLAB variable
    cut = {}
    if getattr(args, "segments", None) not in (None, "none"):
        from presliding.cli.inputs.cuts import segment_options

        cut = {"kind": args.segments, **segment_options(args)}
    return DataSettings(
        columns=_as_given(columns), units=check_options(args.units, "--units", SIGNALS),
        scale=scale, sample_rate=args.sample_rate, decimal=getattr(args, "decimal", None),
        header=getattr(args, "header", None), axis=getattr(args, "axis", None), segments=cut,
    )  # fmt: skip


def _as_given(columns: dict[str, Any]) -> dict[str, Any]:
    """Column labels as --columns takes them: ``column 2`` of a headerless file is 2."""
    out: dict[str, Any] = {}
    for signal, label in columns.items():
        text = str(label)
        out[signal] = int(text[7:]) if text.startswith("column ") and text[7:].isdigit() else text
    return out


def _header(args: argparse.Namespace, meas: Any, result: Any) -> str:
    lines = [f"identified by `{args.command_line}`"]
    if result.status != "converged":
        lines.append(f"NOT CONVERGED: status {result.status}. Check the report before using it.")
    lines.append(f"status {result.status}, NRMSE {100 * result.nrmse:.3g} %")
    lines.append("data: " + meas.source.describe())
    if getattr(args, "cuts", None):
        lines += args.cuts
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    """Read, fit, write model.toml, fit.png and the report; print the fit report."""
    from presliding.cli.fitting.fit_figure import save_fit_figure
    from presliding.cli.report import Section, write_report
    from presliding.model_io import MeasurementTerms, save_model

    joined = bool(getattr(args, "join", None))
    if isinstance(args.data, list) and len(args.data) != 1 and not joined:
        raise UserError(f"--kind {args.kind} takes one data file; got {len(args.data)}.")
    # the files read, and a reader for a --join group:
    # `presliding.cli.fitting.records.prepare_single`
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
        except UserError:
            raise
        except (TypeError, ValueError) as exc:
            raise UserError(cli_words(f"{args.data}: cannot fit: {exc}")) from None
        result = explained(result, [meas], [args.data.name])
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
                axis=meas.axis, data=data_settings(args, [meas]),
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
        print("data: " + meas.source.describe(roles=False))  # the roles: the result's notes
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
