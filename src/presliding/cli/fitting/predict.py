"""``presliding predict MODEL.toml FILE [FILE ...]``: a model predicting records it never saw.

Each file (or ``--join`` group) is read as for ``presliding fit`` and its motion
simulated from its applied force with the model file's friction, mass and
force offset (`presliding.identification.predict_record`), twice: from the
record's measured start (its first samples; nothing taken from the record) and
from a start fitted to it (the initial velocity, and with ``--signal position``
the initial position, taken from the record: the report names them). Writes,
atomically, ``predictions.csv`` (a row per record and start, naming its file
and segment: NRMSE, reversal counts measured and predicted at the stated
tolerance, rest error), a figure per record and ``report.md``/``report.html``.

The model file's ``[data]`` table says how the fitted records were read: the
column of each signal, the units and factors given, the sample rate, the text
options and the cut into segments. New records are read the same way unless an
option says otherwise (``--columns``, ``--units``, ``--scale``, ``--segments``
...; ``--segments none`` predicts whole files); the report says what was taken
from the model file, and which column each signal came from.

``presliding fit ... --hold-out FILE ...`` reports the same figures for files
the fit never saw, cut by ``--segments`` as the fitted ones (`held_out_section`).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from presliding.cli.common import (
    UserError,
    check_folder,
    check_outputs,
    check_readable,
    cli_words,
    new_figure,
    record_outputs,
)

__all__ = ["add_parser", "held_out_section", "run", "use_model_data"]

COLUMNS = ("file", "start", "NRMSE %", "reversals measured", "reversals predicted",
           "rest error", "taken from the record")  # fmt: skip


def add_parser(sub: Any, parents: list) -> argparse.ArgumentParser:
    """The ``predict`` sub-parser (its handler is set by `presliding.cli.commands`)."""
    from presliding.cli.common import checked
    from presliding.cli.fitting.records import add_data_options

    p = sub.add_parser(
        "predict",
        help="predict measured records with a model file: NRMSE, reversals, rest, figures",
        description=__doc__.split("\n\n", 1)[1].replace("``", "'"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
        parents=parents,
    )
    p.add_argument("model", type=Path, help="model file (.toml or .json) with a [motion] mass")
    p.add_argument("data", type=Path, nargs="*", help="data files, each one record")
    for option, help_text in (
        ("--columns", "columns by signal, e.g. time=0 position=1 applied_force=2"),
        ("--units", "unit of a signal's values, e.g. position=deg"),
        ("--scale", "factor applied after the unit conversion, e.g. applied_force=-1"),
    ):
        p.add_argument(option, nargs="+", default=(), metavar="SIGNAL=VALUE", help=help_text)
    p.add_argument("--window", default=None, metavar="START:STOP", help="time window [s]")
    p.add_argument("--sample-rate", type=checked("--sample-rate"), default=None, metavar="HZ",
                   help="sample rate [Hz] of files without a time column")  # fmt: skip
    p.add_argument("--signal", choices=("velocity", "position"), default=None,
                   help="the signal compared (default: velocity when measured)")  # fmt: skip
    p.add_argument(
        "--reversal-tolerance",
        type=checked("--reversal-tolerance", minimum=0.0),
        default=None,
        metavar="TRAVEL",
        help="travel [m or rad] by which reversals are counted (default: each record's own, "
        "three encoder counts or noise levels; the report states it)",
    )
    p.add_argument("-o", "--output", type=Path, default=Path("presliding-predict"),
                   help="output folder (default: ./presliding-predict)")  # fmt: skip
    add_data_options(p, fit=False)
    return p


def _model(path: Path) -> Any:
    """The model file (`ModelFile`); its [motion] mass must be given."""
    from presliding.model_io import load_model

    check_readable(path, "model file")
    spec = load_model(path)
    if "mass" not in spec.motion.given:
        raise UserError(f"{path}: has no [motion] mass; predicting a motion needs the mass "
                        "(add `mass = ...` under [motion]).")  # fmt: skip
    return spec


def _as_items(table: dict[str, Any]) -> list[str]:
    return [f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}" for k, v in table.items()]


def use_model_data(args: argparse.Namespace, data: Any) -> list[str]:
    """Read new records as the model file's ``[data]`` says, where no option overrides it;
    returns sentences saying what was taken from it."""
    from presliding.cli.common import check_options
    from presliding.cli.inputs.columns import SIGNALS

    if data.empty:
        return ["The model file has no [data] table (written by hand, or by an older "
                "presliding): the columns were found by their names and units."]  # fmt: skip
    args.model_data = data
    taken = []
    for option, table in (("units", data.units), ("scale", data.scale)):
        given = check_options(getattr(args, option), f"--{option}", SIGNALS)
        kept = {k: v for k, v in table.items() if k not in given}
        if kept:
            taken.append(f"--{option} {' '.join(_as_items(kept))}")
        setattr(args, option, _as_items({**table, **given}))
    if data.axis is not None and args.axis is None:
        args.axis = data.axis
        taken.append(f"--axis {data.axis}")
    if data.sample_rate is not None and args.sample_rate is None:
        taken.append(f"--sample-rate {data.sample_rate:g} for files without a time column")
    if data.decimal is not None and args.decimal is None:
        taken.append(f"--decimal {data.decimal} for text files")
    if data.header is not None and args.header is None:
        taken.append(f"--{'' if data.header else 'no-'}header for text files")
    if data.columns:
        taken.append("the columns " + ", ".join(f"{k} = {v!r}" for k, v in data.columns.items())
                     + " (where a file has them)")  # fmt: skip
    if data.segments and getattr(args, "segments", None) is None:
        options = {k: v for k, v in data.segments.items() if k != "kind"}
        args.segments = data.segments["kind"]
        for name, value in options.items():
            dest = "segment_tolerance" if name == "tolerance" else name
            if getattr(args, dest, None) is None:
                setattr(args, dest, value)
        from presliding.cli.inputs.cuts import OPTIONS

        taken.append(f"the cut --segments {args.segments}"
                     + "".join(f" {OPTIONS[k]} {v:g}" for k, v in options.items())
                     + " (--segments none predicts whole files)")  # fmt: skip
    return [f"Read as the model file's [data] table states: {'; '.join(taken)}."] if taken else []


def predict_both(model: Any, mass: float, meas: Any, args: argparse.Namespace,
                 offset: float = 0.0, result: Any = None) -> tuple[Any, Any]:  # fmt: skip
    """The predictions of a record from its measured start and from a start fitted to it."""
    from presliding.identification.model_prediction import predict_record

    tol = getattr(args, "reversal_tolerance", None)
    if result is not None and result.predictor is not None:  # a fit in memory: its predictor
        extra = {} if tol is None else {"reversal_tolerance": tol}
        return (result.predict(meas, initial="measured", **extra),
                result.predict(meas, initial="fit", **extra))  # fmt: skip
    signal = getattr(args, "signal", None)
    signal = signal if signal in ("velocity", "position") else None
    common: dict[str, Any] = {"signal": signal, "force_offset": offset,
                              "reversal_tolerance": tol}  # fmt: skip
    return (predict_record(model, mass, meas, initial="measured", **common),
            predict_record(model, mass, meas, initial="fit", **common))  # fmt: skip


def _rows(label: str, pair: tuple[Any, Any], unit: str) -> list[list[str]]:
    rows = []
    for p in pair:
        rest = "—" if p.rest_error is None else f"{p.rest_error:.3g} {unit}"
        own = ", ".join(f"{k} = {v:.4g}" for k, v in p.parameters.items()) or "nothing"
        rows.append([label, "measured" if p.initial == "measured" else "fitted",
                     f"{100 * p.nrmse:.3g}", str(p.measured_reversals),
                     str(p.predicted_reversals), rest, own])  # fmt: skip
    return rows


def _figure(label: str, pair: tuple[Any, Any], path: Path, unit: str) -> None:
    from presliding.plotting import save_figure

    fig, axes = new_figure(2, 1, size=(12.0, 4.4))
    for ax, p in zip(axes[0], pair, strict=True):
        ax.plot(p.abscissa, p.measured, color="0.3", lw=1.2, label="measured")
        ax.plot(p.abscissa, p.predicted, color="C1", lw=1.0, ls="--", label="predicted")
        start = "measured start" if p.initial == "measured" else "start fitted to the record"
        ax.set(xlabel=p.abscissa_label, ylabel=f"{p.signal_label} [{unit}]",
               title=f"{label}: {start}, NRMSE {100 * p.nrmse:.3g} %")  # fmt: skip
        ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize="small")
    save_figure(fig, path)


def _tolerance_note(pairs: list[tuple[Any, Any]], unit: str) -> str:
    from presliding.identification.prediction import tolerance_text

    texts = sorted({tolerance_text(p.reversal_tolerance, p.quantum, unit)
                    for pair in pairs for p in pair})  # fmt: skip
    return ("Reversals are counted alike on the measured and the predicted position, at a "
            f"tolerance of {'; '.join(texts)} (--reversal-tolerance sets it).")  # fmt: skip


def _predict_all(
    args: argparse.Namespace, folder: Path, records: list[Any], labels: list[str],
    model: Any, mass: float, offset: float, result: Any = None, stem: str = "prediction",
) -> tuple[list[list[str]], list[Path], list[tuple[Any, Any]]]:  # fmt: skip
    rows, figures, pairs = [], [], []
    for i, (meas, label) in enumerate(zip(records, labels, strict=True)):
        try:
            pair = predict_both(model, mass, meas, args, offset, result)
        except (TypeError, ValueError) as exc:
            raise UserError(cli_words(f"{label}: cannot predict: {exc}")) from None
        unit = meas.unit("velocity" if pair[0].signal_label == "velocity" else "position")
        rows += _rows(label, pair, meas.unit("position"))
        path = folder / f"{stem}_{i + 1}.png"
        _figure(label, pair, path, unit)
        figures.append(path)
        pairs.append(pair)
    return rows, figures, pairs


def _read_cut(args: argparse.Namespace, files: list[Path], joins: list) -> tuple:
    """The records of `files` and --join groups, cut by --segments: (pieces, labels, cuts,
    the files' names, the notes on their columns)."""
    from presliding.cli.fitting.records import read_file, read_join
    from presliding.cli.inputs.cuts import cut_records, segment_options

    options = segment_options(args)
    records = [read_file(args, p) for p in files] + [read_join(args, g) for g in joins]
    names = [p.name for p in files] + [" + ".join(Path(i.rpartition("=")[0] or i).name
                                                  for i in g) for g in joins]  # fmt: skip
    roles = [f"{n}: {line}" for n, m in zip(names, records, strict=True)
             for line in (m.source.roles if m.source is not None else ())]  # fmt: skip
    pieces, labels, cuts, _ = cut_records(records, names, getattr(args, "segments", None),
                                          options)  # fmt: skip
    return pieces, labels, cuts, roles


def held_out_section(args: argparse.Namespace, result: Any, folder: Path) -> tuple[Any, list]:
    """The report section of ``fit --hold-out``: each held-out file, cut by --segments as
    the fitted ones, predicted by the fit."""
    from presliding.cli.report import Section

    files = [Path(p) for p in args.hold_out]
    records, labels, cuts, roles = _read_cut(args, files, [])
    outputs = [folder / f"held_out_{i + 1}.png" for i in range(len(records))]
    check_outputs(outputs, files, overwrite=True)
    record_outputs(outputs)
    mass = float(result.parameters.get("mass", 1.0))
    offset = float(result.parameters.get("offset", 0.0))
    rows, figures, pairs = _predict_all(args, folder, records, labels, result.model, mass,
                                        offset, result, "held_out")  # fmt: skip
    unit = records[0].unit("position")
    cut = (f" Each file was cut by --segments {args.segments} as the fitted ones."
           if cuts else "")  # fmt: skip
    text = ("Files held out of the fit (--hold-out), predicted from their measured start "
            "(nothing taken from them) and from a start fitted to each (the parameters "
            f"named in the last column are taken from the held-out record).{cut} "
            + _tolerance_note(pairs, unit))  # fmt: skip
    code = "\n".join([*cuts, *roles])
    return (Section("Held-out files", text, tuple(figures), table=[list(COLUMNS), *rows],
                    code=code), figures)  # fmt: skip


def _write_table(path: Path, labels: list[str], pairs: list[tuple[Any, Any]]) -> None:
    """predictions.csv: a row per record and start, naming its file and segment."""
    import csv
    import io

    from presliding._io import write_text

    def number(x: Any) -> str:
        return "" if x is None else f"{float(x):.10g}"

    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["record", "file_name", "segment", "fitted_start", "nrmse",
                     "measured_reversals", "predicted_reversals", "rest_error",
                     "reversal_tolerance"])  # fmt: skip
    for i, (label, pair) in enumerate(zip(labels, pairs, strict=True)):
        name, _, piece = label.partition(" #")
        for p in pair:
            writer.writerow([i + 1, name, piece or 0, int(p.initial == "fit"), number(p.nrmse),
                             number(p.measured_reversals), number(p.predicted_reversals),
                             number(p.rest_error), number(p.reversal_tolerance)])  # fmt: skip
    write_text(path, out.getvalue())


def run(args: argparse.Namespace) -> int:
    """Load the model, read every record (as its [data] table says), predict, write the
    table, figures and report."""
    from presliding.cli.fitting.records import check_sources, input_files
    from presliding.cli.report import Section, write_report

    args.kind = "predict"  # the signals a motion prediction reads (those of --kind response)
    spec = _model(args.model)
    model, mass, offset = spec.model, spec.motion.mass, spec.measurement.force_offset
    if not args.data and not args.join:
        raise UserError("give at least one data file to predict, or per-signal files with --join.")
    check_sources(args)
    taken = use_model_data(args, spec.data)
    folder = check_folder(args.output)
    check_outputs([folder / "predictions.csv"], [args.model, *input_files(args)],
                  overwrite=args.overwrite)  # fmt: skip
    records, labels, cuts, roles = _read_cut(args, list(args.data), list(args.join or []))
    figures = [folder / f"prediction_{i + 1}.png" for i in range(len(labels))]
    table_path = folder / "predictions.csv"
    outputs = [*figures, table_path, folder / "report.md", folder / "report.html"]
    check_outputs(outputs, [args.model, *input_files(args)], overwrite=args.overwrite)
    record_outputs(outputs)
    rows, written, pairs = _predict_all(args, folder, records, labels, model, mass, offset)
    _write_table(table_path, labels, pairs)
    unit = records[0].unit("position")
    text = (f"{len(records)} record(s) predicted by {args.model.name} (mass {mass:.6g} "
            f"{records[0].unit('mass')}, force offset {offset:.6g} {records[0].unit('force')}), "
            "from each record's measured start (nothing taken from the record) and from a "
            "start fitted to it (the parameters named in the last column are taken from the "
            "record). " + _tolerance_note(pairs, unit))  # fmt: skip
    text = "\n\n".join([text, *taken])
    sources = "\n".join([*cuts, *roles])
    report = write_report(folder, f"presliding predict: {args.model.name}", [
        Section("Predictions", text, tuple(written), table=[list(COLUMNS), *rows], code=sources)
    ])  # fmt: skip
    if not args.quiet:
        for line in [*taken, *roles]:
            print(cli_words(line))
        widths = [max(len(r[i]) for r in [list(COLUMNS), *rows]) for i in range(len(COLUMNS))]
        for r in [list(COLUMNS), *rows]:
            print("  ".join(c.ljust(w) for c, w in zip(r, widths, strict=True)).rstrip())
        print(_tolerance_note(pairs, unit))
        for path in [*written, table_path, *report]:
            print(f"wrote {path}")
    return 0 if all(p.success for pair in pairs for p in pair) else 1
