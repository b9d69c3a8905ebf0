"""``presliding predict MODEL.toml FILE [FILE ...]``: a model predicting records it never saw.

Each file (or ``--join`` group) is read as for ``presliding fit`` and its motion
simulated from its applied force with the model file's friction, mass and
force offset (`presliding.identification.predict_record`), twice: from the
record's measured start (its first samples; nothing taken from the record) and
from a start fitted to it (the initial velocity, and with ``--signal position``
the initial position, taken from the record: the report names them). Writes,
atomically, ``predictions.csv`` (a row per file: NRMSE, reversal counts measured
and predicted at the stated tolerance, rest error, for both starts), a figure
per file and ``report.md``/``report.html``.

``presliding fit ... --hold-out FILE ...`` reports the same figures for files
the fit never saw (`held_out_section`).
"""

from __future__ import annotations

import argparse
import sys
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
)

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = ["add_parser", "held_out_section", "run"]

COLUMNS = ("file", "start", "NRMSE %", "reversals measured", "reversals predicted",
           "rest error", "taken from the record")  # fmt: skip


def add_parser(sub: Any, parents: list) -> argparse.ArgumentParser:
    """The ``predict`` sub-parser (its handler is set by `presliding.cli.commands`)."""
    from presliding.cli.common import checked
    from presliding.cli.records import add_data_options

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


def _model(path: Path) -> tuple[Any, float, float]:
    """Friction model, mass and force offset of a model file (the mass must be given)."""
    from presliding.model_io import load_model

    check_readable(path, "model file")
    spec = load_model(path)
    try:
        raw = tomllib.loads(path.read_text(encoding="utf-8")) if path.suffix != ".json" else None
    except (OSError, ValueError):
        raw = None
    if raw is not None and "mass" not in raw.get("motion", {}):
        raise UserError(f"{path}: has no [motion] mass; predicting a motion needs the mass "
                        "(add `mass = ...` under [motion]).")  # fmt: skip
    return spec.model, spec.motion.mass, spec.measurement.force_offset


def predict_both(model: Any, mass: float, meas: Any, args: argparse.Namespace,
                 offset: float = 0.0, result: Any = None) -> tuple[Any, Any]:  # fmt: skip
    """The predictions of a record from its measured start and from a start fitted to it."""
    from presliding.identification.model_prediction import predict_record

    tol = getattr(args, "reversal_tolerance", None)
    if result is not None and result.predictor is not None:  # a fit in memory: its predictor
        extra = {} if tol is None else {"tolerance": tol}
        return (result.predict(meas, initial="measured", **extra),
                result.predict(meas, initial="fit", **extra))  # fmt: skip
    signal = getattr(args, "signal", None)
    signal = signal if signal in ("velocity", "position") else None
    common: dict[str, Any] = {"signal": signal, "force_offset": offset, "tolerance": tol}
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
               title=f"{label}: {start}, NRMSE {100 * p.nrmse:.2g} %")  # fmt: skip
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
            raise UserError(f"{label}: cannot predict: {exc}") from None
        unit = meas.unit("velocity" if pair[0].signal_label == "velocity" else "position")
        rows += _rows(label, pair, meas.unit("position"))
        path = folder / f"{stem}_{i + 1}.png"
        _figure(label, pair, path, unit)
        figures.append(path)
        pairs.append(pair)
    return rows, figures, pairs


def held_out_section(args: argparse.Namespace, result: Any, folder: Path) -> tuple[Any, list]:
    """The report section of ``fit --hold-out``: each held-out file predicted by the fit."""
    from presliding.cli.records import read_file
    from presliding.cli.report import Section

    files = [Path(p) for p in args.hold_out]
    outputs = [folder / f"held_out_{i + 1}.png" for i in range(len(files))]
    check_outputs(outputs, files, overwrite=True)
    record_outputs(outputs)
    records = [read_file(args, p) for p in files]
    mass = float(result.parameters.get("mass", 1.0))
    offset = float(result.parameters.get("offset", 0.0))
    rows, figures, pairs = _predict_all(args, folder, records, [p.name for p in files],
                                        result.model, mass, offset, result, "held_out")  # fmt: skip
    unit = records[0].unit("position")
    text = ("Files held out of the fit (--hold-out), predicted from their measured start "
            "(nothing taken from them) and from a start fitted to each (the parameters "
            "named in the last column are taken from the held-out record). "
            + _tolerance_note(pairs, unit))  # fmt: skip
    return Section("Held-out files", text, tuple(figures), table=[list(COLUMNS), *rows]), figures


def run(args: argparse.Namespace) -> int:
    """Load the model, read every record, predict, write the table, figures and report."""
    from presliding.cli.common import write_csv
    from presliding.cli.records import data_names, input_files, read_file, read_join
    from presliding.cli.report import Section, write_report

    args.kind = "response"  # the signals a motion prediction needs
    model, mass, offset = _model(args.model)
    if not args.data and not args.join:
        raise UserError("give at least one data file to predict, or per-signal files with --join.")
    folder = check_folder(args.output)
    labels = data_names(args)
    figures = [folder / f"prediction_{i + 1}.png" for i in range(len(labels))]
    table_path = folder / "predictions.csv"
    outputs = [*figures, table_path, folder / "report.md", folder / "report.html"]
    check_outputs(outputs, [args.model, *input_files(args)], overwrite=args.overwrite)
    records = [read_file(args, p) for p in args.data]
    records += [read_join(args, g) for g in args.join or []]
    record_outputs(outputs)
    rows, written, pairs = _predict_all(args, folder, records, labels, model, mass, offset)
    flat = [p for pair in pairs for p in pair]

    def column(get: Any) -> np.ndarray:
        return np.array([np.nan if get(p) is None else float(get(p)) for p in flat])

    columns = [np.repeat(np.arange(1, len(pairs) + 1), 2).astype(float),
               column(lambda p: p.initial == "fit"), column(lambda p: p.nrmse),
               column(lambda p: p.measured_reversals), column(lambda p: p.predicted_reversals),
               column(lambda p: p.rest_error), column(lambda p: p.reversal_tolerance)]  # fmt: skip
    write_csv(table_path, ["record", "fitted_start", "nrmse", "measured_reversals",
                           "predicted_reversals", "rest_error", "reversal_tolerance"], columns,
              quiet=True)  # fmt: skip
    unit = records[0].unit("position")
    text = (f"{len(records)} record(s) predicted by {args.model.name} (mass {mass:.6g} "
            f"{records[0].unit('mass')}, force offset {offset:.6g} {records[0].unit('force')}), "
            "from each record's measured start (nothing taken from the record) and from a "
            "start fitted to it (the parameters named in the last column are taken from the "
            "record). " + _tolerance_note(pairs, unit))  # fmt: skip
    sources = "\n".join(f"{label}: {m.source.describe()}" for label, m in
                        zip(labels, records, strict=True) if m.source is not None)  # fmt: skip
    report = write_report(folder, f"presliding predict: {args.model.name}", [
        Section("Predictions", text, tuple(written), table=[list(COLUMNS), *rows], code=sources)
    ])  # fmt: skip
    if not args.quiet:
        widths = [max(len(r[i]) for r in [list(COLUMNS), *rows]) for i in range(len(COLUMNS))]
        for r in [list(COLUMNS), *rows]:
            print("  ".join(c.ljust(w) for c, w in zip(r, widths, strict=True)).rstrip())
        print(_tolerance_note(pairs, unit))
        for path in [*written, table_path, *report]:
            print(f"wrote {path}")
    return 0 if all(p.success for p in flat) else 1
