"""``presliding fit FILE [FILE ...] --kind response | quasi-static | virgin``: pooled fits.

Every file is read as one record with the same column, unit and scale options
(`presliding.cli.fitting.fit.read_measurement`). The records are fitted together:
shared physics, each record's own start (`fit_response`, `fit_quasi_static`),
or one virgin curve from all ramps or loops (`fit_virgin_curve`, loops when a
record reverses, else loading ramps). With two or more records of a response
or quasi-static fit, the report carries the leave-one-record-out table
(`cross_validate`) unless ``--no-cross-validation``. With ``--compare`` the named
model families are fitted to the same records instead (`compare_fits`): the
table goes to ``comparison.csv`` and the report, the family of least BIC is the
fit reported, and the ``--hold-out`` files are predicted by every family.

Outputs and exit codes as for the other kinds (`presliding.cli.fitting.fit`).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from presliding.cli.common import (
    UserError,
    check_folder,
    check_outputs,
    cli_words,
    record_outputs,
)

__all__ = ["fit_records", "run_pooled"]


def _read_all(args: argparse.Namespace) -> list[Any]:
    """Files, --join groups and --segments pieces (`presliding.cli.fitting.records`)."""
    from presliding.cli.fitting.records import read_records

    records, args.record_labels, args.cuts = read_records(args)
    return records


def _options(args: argparse.Namespace, records: list[Any]) -> dict[str, Any]:
    """Keyword options of the library fit, from the command line."""
    from presliding.cli.fitting.fit import DEFAULT_ELEMENTS

    n = DEFAULT_ELEMENTS[args.kind] if args.elements is None else args.elements
    if n == "auto" and args.kind != "response":
        raise UserError(f"--elements auto is for --kind response; got --kind {args.kind}.")
    if n != "auto" and n < 0:
        raise UserError(f"--elements must be 0 or more; got {n}.")
    if args.max_evaluations is not None and args.max_evaluations < 1:
        raise UserError(f"--max-evaluations must be 1 or more; got {args.max_evaluations}.")
    if args.bootstrap < 0:
        raise UserError(f"--bootstrap must be 0 or more; got {args.bootstrap}.")
    velocity = getattr(args, "velocity", None)
    if velocity is not None and args.kind != "response":
        raise UserError(f"--velocity {velocity} is for --kind response (the only kind that "
                        f"compares a velocity); drop it for --kind {args.kind}.")  # fmt: skip
    out: dict[str, Any] = {"n_elements": n, "max_evaluations": args.max_evaluations,
                           "asymmetric": args.asymmetric}  # fmt: skip
    if args.kind == "virgin":
        if args.density is not None:
            raise UserError(f"--density {args.density}: --kind virgin fits elastoplastic "
                            "elements only; drop --density, or fit a density with --kind "
                            "response or quasi-static.")  # fmt: skip
        return out
    if args.asymmetric and (args.offset or args.density is not None):
        raise UserError("--asymmetric: the two directions' levels need elements and no "
                        "offset (a constant force is their difference); drop --offset and "
                        "--density.")  # fmt: skip
    out.update(density=args.density, offset=args.offset, bootstrap=args.bootstrap)
    if args.seed is not None:
        out["seed"] = args.seed
    if args.kind == "response":
        signal = args.signal or (
            "velocity" if all(m.velocity is not None for m in records) else "position"
        )
        out.update(signal=signal, mass=args.mass, prune=args.prune, viscous=args.viscous,
                   velocity=velocity or "auto")  # fmt: skip
        out["initial_state"] = args.initial_state or "saturated"
    else:
        out["initial_state"] = args.initial_state or "preload"
        if out["initial_state"] == "saturated":
            raise UserError("--initial-state saturated is for --kind response; quasi-static "
                            "takes preload, continuing or relaxed.")  # fmt: skip
    return out


def fit_records(args: argparse.Namespace, records: list[Any], bar: Any = False) -> tuple[Any, Any]:
    """The pooled fit of `args.kind`, and its cross-validation (or None).

    `bar` (a `Progress`, or False) shows the fits' stages and evaluations.
    """
    from presliding.cli.inputs.virgin import virgin_inputs
    from presliding.identification import (
        cross_validate,
        fit_quasi_static,
        fit_response,
        fit_virgin_curve,
    )
    from presliding.measurement.measurement import common_axis

    options = {**_options(args, records), "progress": bar}
    if args.kind == "virgin":  # the whole records: their runs are read by virgin_inputs
        whole, labels = getattr(args, "whole", None) or (records, args.record_labels)
        ys = [np.asarray(m.position) for m in whole]
        fs = [np.asarray(m.friction_force if m.friction_force is not None else m.applied_force)
              for m in whole]  # fmt: skip
        told = {"ramps": True, "loops": False}.get(args.segments or "")
        told = True if getattr(args, "ramps", False) else told
        ys, fs, loops, notes = virgin_inputs(ys, fs, labels, told)
        if loops and args.asymmetric:
            raise UserError("--asymmetric with --kind virgin needs loading ramps from rest "
                            "in both directions (--ramps): the records reverse, and the "
                            "branches of loops follow the mean of the two sides.")  # fmt: skip
        n = options.pop("n_elements")
        fit = fit_virgin_curve(ys, fs, n, loops=loops, reversal_tolerance=None, **options)
        fit = replace(fit, notes=(*notes, *fit.notes))
        return fit.on_axis(common_axis(records)), None
    if getattr(args, "compare", None):
        args.comparison = _compare(args, records, options)
        best = args.comparison.fits[args.comparison.families.index(args.comparison.best)] \
            if args.comparison.best else args.comparison.fits[0]  # fmt: skip
        return best, None
    fitter: Callable[..., Any] = fit_response if args.kind == "response" else fit_quasi_static
    pooled: Any = records if len(records) > 1 else records[0]
    if len(records) < 2 or args.no_cross_validation:
        return fitter(pooled, **options), None
    labels = getattr(args, "record_labels", None) or [Path(p).name for p in args.data]
    tolerance = getattr(args, "reversal_tolerance", None)
    cv = cross_validate(records, fitter, labels=labels, reversal_tolerance=tolerance, **options)
    return cv.result, cv


def _compare(args: argparse.Namespace, records: list[Any], options: dict[str, Any]) -> Any:
    """``--compare``: the families named, fitted to the records (`compare_fits`);
    --elements goes to each family whose fitter takes ``n_elements``."""
    import inspect

    from presliding.cli.fitting.predict import _read_cut
    from presliding.identification.families import FAMILIES
    from presliding.identification.fit_comparison import compare_fits

    names = [x.strip() for x in str(args.compare).split(",") if x.strip()]
    unknown = [x for x in names if x not in FAMILIES]
    if not names or unknown:
        raise UserError(f"--compare {args.compare}: name families of "
                        f"{', '.join(sorted(FAMILIES))}, separated by commas.")  # fmt: skip
    if args.asymmetric:
        raise UserError("--asymmetric with --compare: name pi-asymmetric among the families "
                        "instead.")  # fmt: skip
    common = {k: v for k, v in options.items() if k not in ("n_elements", "asymmetric")}
    n = options["n_elements"]
    candidates = {x: ({"n_elements": n} if "n_elements" in inspect.signature(
        FAMILIES[x]).parameters else {}) for x in names}  # fmt: skip
    held, labels, _, _ = _read_cut(
        args, [Path(p) for p in getattr(args, "hold_out", ()) or ()], []
    )  # the --hold-out files, cut by --segments as the fitted
    return compare_fits(records, candidates, hold_out=held or None, labels=labels or None,
                        **common)  # fmt: skip


def _comparison_csv(path: Path, comparison: Any) -> None:
    """The comparison's table as CSV, written atomically."""
    import csv
    import io

    from presliding._io import write_text

    text = io.StringIO()
    csv.writer(text, lineterminator="\n").writerows(comparison.table())
    write_text(path, text.getvalue())


def run_pooled(args: argparse.Namespace) -> int:
    """Read every file, fit them together, write model.toml, fit.png and the report."""
    from presliding.cli.fitting.fit import explained, fit_progress, model_problem
    from presliding.cli.fitting.fit_options import check_record_count
    from presliding.cli.fitting.records import data_names, input_files

    folder = check_folder(args.output)
    paths = {"model": folder / "model.toml", "figure": folder / "fit.png",
             "md": folder / "report.md", "html": folder / "report.html"}  # fmt: skip
    if args.segments not in (None, "none"):
        paths["segments"] = folder / "segments.png"
    if getattr(args, "compare", None):
        paths["comparison"] = folder / "comparison.csv"
    check_outputs(paths.values(), input_files(args), overwrite=args.overwrite)
    names = ", ".join(data_names(args))
    with fit_progress(args.quiet) as bar:
        bar.part(f"reading {len(data_names(args))} file(s)")
        records = _read_all(args)
        check_record_count(args, len(records))
        bar.update()
        bar.part(f"fitting (--kind {args.kind}, {len(records)} record(s))")
        try:
            result, cv = fit_records(args, records, bar)
        except UserError:
            raise
        except (TypeError, ValueError) as exc:
            raise UserError(cli_words(f"{names}: cannot fit: {exc}")) from None
        result = explained(result, records, args.record_labels)
        bar.update()
        bar.part(f"writing {folder}")
        record_outputs(paths.values())
        problem = model_problem(result, records[0])
        written = _write_model(args, records, result, paths["model"], problem)
        sections, figures = _sections(args, records, result, cv, paths, problem, names)
        written += figures
        if getattr(args, "comparison", None) is not None:
            from presliding.cli.report import Section

            _comparison_csv(paths["comparison"], args.comparison)
            written.append(paths["comparison"])
            sections.insert(1, Section(
                "Model families", "Each family named by --compare fitted to the same records "
                "by the same engine: its status, free parameters, residual sum of squares, AIC "
                "and BIC (Gaussian least squares; ΔAIC and ΔBIC over the least), and the "
                "held-out files predicted from their measured starts. The fit above is the "
                "family the data support.", table=args.comparison.table(),
                code=args.comparison.report()))  # fmt: skip
        from presliding.cli.report import write_report

        written += write_report(folder, f"presliding fit: {names}", sections)
        bar.update()
    if not args.quiet:
        print(result.report())
        if problem:
            print(f"No model.toml written: {problem}.")
        for p in written:
            print(f"wrote {p}")
    from presliding.identification.judge._status import exit_code

    comparison = getattr(args, "comparison", None)
    return exit_code(result.status if comparison is None else comparison.status)


def _write_model(args: argparse.Namespace, records: list[Any], result: Any, path: Path,
                 problem: str) -> list[Path]:  # fmt: skip
    """model.toml (its header lists the command, the cut and every record); none for a fit
    that must not be used (an earlier run's is removed)."""
    from presliding.cli.fitting.fit import _header, _motion_settings, data_settings
    from presliding.cli.fitting.records import input_files, pooled_header
    from presliding.model_io import MeasurementTerms, MotionSettings, save_model

    if problem:  # an earlier run's model.toml would be taken for this fit's
        path.unlink(missing_ok=True)
        return []
    offset = result.parameters.get("offset")
    terms = None if offset is None else MeasurementTerms(float(offset))
    kind = "response" if args.kind == "response" else "other"
    motion = _motion_settings(argparse.Namespace(kind=kind), records[0], result)
    first = argparse.Namespace(**{**vars(args), "data": input_files(args)[0]})
    header = _header(first, records[0], result)
    if len(records) > 1:  # every record listed; no one record's start as [motion]
        motion = None if motion is None else MotionSettings(mass=motion.mass)
        header = pooled_header(args, records, args.record_labels, result)
    if getattr(args, "comparison", None) is not None:  # which family this model is
        header += (f"\nmodel family {args.comparison.best}: the least "
                   f"{args.comparison.criterion.upper()} of --compare {args.compare} "
                   "(comparison.csv)")  # fmt: skip
    save_model(path, result.model, motion, measurement=terms, header=header, overwrite=True,
               axis=result.axis, data=data_settings(args, records))  # fmt: skip
    return [path]


def _sections(args: argparse.Namespace, records: list[Any], result: Any, cv: Any,
              paths: dict[str, Path], problem: str, names: str) -> tuple[list, list]:  # fmt: skip
    """The report's sections (result, segments, held-out files, cross-validation) and the
    figures written for them."""
    from presliding.cli.fitting.fit_figure import save_fit_figure
    from presliding.cli.fitting.predict import held_out_section
    from presliding.cli.fitting.records import input_files
    from presliding.cli.inputs.cuts import save_segments_figure
    from presliding.cli.report import Section

    first = argparse.Namespace(**{**vars(args), "data": input_files(args)[0]})
    save_fit_figure(first, records[0], result, paths["figure"], labels=args.record_labels)
    figures = [paths["figure"]]
    note = f"No model.toml written: {problem}." if problem else ""
    text = (f"Pooled fit of {len(records)} record(s) ({names}; --kind {args.kind}): "
            f"{result.status}. NRMSE {100 * result.nrmse:.3g} %. {note}")  # fmt: skip
    data = "\n".join(f"Data: {m.source.describe(roles=False)}" for m in records)
    sections = [Section("Result", text, (paths["figure"],), code=f"{data}\n\n{result.report()}")]
    if getattr(args, "segmented", None):
        caption = save_segments_figure(args.segmented, data_labels(args), paths["segments"])
        figures.append(paths["segments"])
        sections.append(Section(
            "Segments", f"Each record was cut into {args.segments} (`--segments "
            f"{args.segments}`, with the values below: rerun with them to cut the same "
            "windows); every piece was fitted as a pooled record.", (paths["segments"],),
            code="\n".join(args.cuts), captions=(caption,)))  # fmt: skip
    if getattr(args, "hold_out", None):
        held, held_figures = held_out_section(args, result, paths["figure"].parent)
        sections.append(held)
        figures += held_figures
    if cv is not None:
        sections.append(Section(
            "Cross-validation",
            "Each record predicted by the fit of the others, from its measured start "
            "(nothing taken from it) and from a start fitted to it with the shared "
            "parameters held (the parameters in the last column are taken from the "
            "held-out record): NRMSE, reversal counts and rest errors.",
            table=cv.table(), code=cv.report(),
        ))  # fmt: skip
    return sections, figures


def data_labels(args: argparse.Namespace) -> list[str]:
    """The names of the files (or --join groups) read, before any cut."""
    from presliding.cli.fitting.records import data_names

    return data_names(args)
