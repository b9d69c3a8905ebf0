"""Where the records of ``presliding fit`` and ``presliding predict`` come from.

A record is one data file (`presliding.cli.inputs.files.read_measurement`), or a group of
per-signal files joined on one time base (``--join pos.txt=position
tau.txt=applied_force``: one record per ``--join``), and ``--segments stops |
loops | ramps`` cuts each record into pieces that become pooled records of
their own (`presliding.cli.inputs.cuts`). Records come from data files or
from ``--join`` groups, never both; a ``--hold-out`` file is never a file to
fit. The options shared by the reading commands (``--header``, ``--decimal``,
``--axis``, ``--join``, ``--interpolate``, the cut) live here too, and so does
the header of a pooled model file, which lists every file.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from presliding.cli.common import UserError, check_options, check_readable

__all__ = [
    "add_data_options",
    "check_sources",
    "data_names",
    "input_files",
    "pooled_header",
    "prepare_single",
    "read_file",
    "read_records",
    "read_single",
]


def add_data_options(parser: argparse.ArgumentParser, *, fit: bool = True) -> None:
    """Add --header/--no-header, --decimal, --axis, --join, --interpolate and the cut into
    segments (and for fit: --ramps, --hold-out)."""
    parser.add_argument(
        "--header",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="whether the first line of a text file names the columns (default: detected; "
        "--no-header for a file whose first row is data)",
    )
    parser.add_argument(
        "--decimal",
        choices=(".", ","),
        default=None,
        help="the decimal mark of text files (',' for exports such as 0,5;1,25; default '.')",
    )
    parser.add_argument(
        "--axis",
        choices=("linear", "rotary"),
        default=None,
        help="linear (m, N, kg) or rotary (rad, N m, kg m^2) axis; default: from the units",
    )
    parser.add_argument(
        "--join",
        nargs="+",
        action="append",
        default=None,
        metavar="FILE[=SIGNAL]",
        help="per-signal files joined on one time base into one record (repeat --join for "
        "more records; not beside data files); FILE=SIGNAL names the signal a file holds "
        "besides its time",
    )
    parser.add_argument(
        "--interpolate",
        action="store_true",
        help="--join: interpolate files on other clocks onto the times of the group's first "
        "file (else such a group is an error)",
    )
    from presliding.cli.inputs.cuts import add_segment_options

    add_segment_options(parser)
    if not fit:
        return
    parser.add_argument(
        "--ramps",
        action="store_true",
        help="--kind virgin: every record starts at rest, its first run a virgin loading "
        "(default: detected; retreats of a few encoder counts are not reversals)",
    )
    parser.add_argument(
        "--hold-out",
        nargs="+",
        type=Path,
        default=(),
        metavar="FILE",
        help="files predicted by the fit and reported, never fitted (cut by --segments as "
        "the fitted ones)",
    )


def _signals() -> tuple[str, ...]:
    from presliding.cli.inputs.columns import SIGNALS

    return SIGNALS


def read_file(args: argparse.Namespace, path: Path | str) -> Any:
    """One data file read with the command's column, unit, scale and text options."""
    from presliding.cli.inputs.files import read_measurement

    return read_measurement(argparse.Namespace(**{**vars(args), "data": Path(path)}))


def _part(args: argparse.Namespace, item: str) -> Any:
    """One file of a --join group: its time and the signal(s) it holds."""
    from presliding.cli.inputs.columns import locate as _locate
    from presliding.cli.inputs.files import is_mat, text_options
    from presliding.measurement._mat import read_mat
    from presliding.measurement._readers import TextTable, read_text
    from presliding.measurement.measurement import Measurement

    text, _, signal = item.rpartition("=") if "=" in item else (item, "", "")
    path = check_readable(Path(text), "--join file")
    signals = _signals()
    if signal and signal not in signals[1:]:
        raise UserError(f"--join {item}: the signal must be one of {', '.join(signals[1:])}.")
    columns = check_options(args.columns, "--columns", signals)
    mat = is_mat(path)
    options = text_options(args, path, mat)
    table = read_mat(path) if mat else read_text(path, **options)
    names = list(table.names) if table.names else None
    time = _locate("time", columns, names)
    wanted = [signal] if signal else [s for s in signals[1:] if _locate(s, {}, names)]
    if not wanted:
        raise UserError(f"--join {item}: name the signal this file holds, e.g. {text}=position.")
    found: dict[str, Any] = {}
    for name in wanted:
        col = _locate(name, columns, names)
        if col is None and isinstance(table, TextTable) and table.n_columns == 2:
            col = _other_column(time, names)
        if col is None:
            raise UserError(f"--join {item}: no column for `{name}`; name it with --columns.")
        found[name] = col
    rate = args.sample_rate
    if time is None and rate is None:
        raise UserError(f"--join {item}: no time column; name it with --columns time=COLUMN "
                        "or give --sample-rate HZ.")  # fmt: skip
    keep = {"time", *found}
    units = {k: v for k, v in check_options(args.units, "--units", signals).items() if k in keep}
    given = check_options(args.scale, "--scale", signals).items()
    scale = {k: v if mat else float(v) for k, v in given if k in keep}
    reader: Any = Measurement.from_mat if mat else Measurement.from_csv
    return reader(path, time, sample_rate=rate, units=units or None, scale=scale or None,
                  axis=args.axis, **options, **found)  # fmt: skip


def _other_column(time: Any, names: list[str] | None) -> Any:
    """In a two-column file, the column that is not the time."""
    if time is None:
        return None
    if isinstance(time, int):
        return 1 - time
    return next((n for n in names or [] if n != time), None)


def read_join(args: argparse.Namespace, group: list[str]) -> Any:
    """The record of one --join group (per-signal files on one time base)."""
    from presliding.cli.common import cli_words
    from presliding.cli.inputs.files import parse_window
    from presliding.measurement.measurement import Measurement

    parts = [_part(args, item) for item in group]
    try:
        meas = Measurement.join(parts, interpolate=bool(getattr(args, "interpolate", False)))
    except ValueError as exc:
        raise UserError(cli_words(f"--join {' '.join(group)}: {exc}")) from None
    window = parse_window(args.window)
    if window is not None:
        meas = meas.window(*window)
    return meas


def data_names(args: argparse.Namespace) -> list[str]:
    """A name per record given: file names, and ``a + b`` for a --join group."""
    names = [Path(p).name for p in args.data]
    for group in getattr(args, "join", None) or []:
        names.append(" + ".join(Path(item.rpartition("=")[0] or item).name for item in group))
    return names


def input_files(args: argparse.Namespace, held_out: bool = True) -> list[Path]:
    """Every file the command reads (never to be overwritten by an output)."""
    data = args.data if isinstance(args.data, (list, tuple)) else [args.data]
    files = [Path(p) for p in data if p is not None]
    for group in getattr(args, "join", None) or []:
        files += [Path(item.rpartition("=")[0] or item) for item in group]
    return files + ([Path(p) for p in getattr(args, "hold_out", ()) or ()] if held_out else [])


def check_sources(args: argparse.Namespace) -> None:
    """Records come from data files or from --join groups, not both; --interpolate needs
    --join; a --hold-out file is never fitted too."""
    joins = getattr(args, "join", None) or []
    data = list(args.data) if isinstance(args.data, (list, tuple)) else [args.data]
    data = [p for p in data if p is not None]
    if joins and data:
        raise UserError(
            f"--join beside data files ({', '.join(Path(p).name for p in data)}): give every "
            "record the same way, as data files or as --join groups (a data file written "
            "after --join is read as one of its parts)."
        )
    if getattr(args, "interpolate", False) and not joins:
        raise UserError("--interpolate: an option of --join (files on other clocks); drop it.")
    fitted = {Path(p).resolve() for p in input_files(args, held_out=False)}
    for path in getattr(args, "hold_out", ()) or ():
        if Path(path).resolve() in fitted:
            raise UserError(
                f"--hold-out {path}: is also a file to fit; a held-out file is predicted by "
                "a fit that never saw it, so give it once, as data or as --hold-out."
            )


def read_records(args: argparse.Namespace) -> tuple[list[Any], list[str], list[str]]:
    """The records (files, or --join groups, each cut by --segments), their labels, the cuts.

    The `Segments` of the cut are kept in ``args.segmented`` (for segments.png).
    """
    from presliding.cli.inputs.cuts import cut_records, segment_options

    if not args.data and not getattr(args, "join", None):
        raise UserError("give at least one data file, or per-signal files with --join.")
    options = segment_options(args)
    records = [read_file(args, p) for p in args.data]
    records += [read_join(args, g) for g in getattr(args, "join", None) or []]
    args.whole = (records, data_names(args))  # before the cut (--kind virgin reads its runs)
    pieces, names, cuts, args.segmented = cut_records(records, data_names(args),
                                                      args.segments, options)  # fmt: skip
    return pieces, names, cuts


def prepare_single(args: argparse.Namespace) -> None:
    """Set up a single-record kind: the files it reads, and its reader (a file or one --join)."""
    args.inputs = input_files(args)
    args.read = read_single


def read_single(args: argparse.Namespace) -> Any:
    """The one record of a single-record kind (a file, or one --join group)."""
    joins = getattr(args, "join", None) or []
    if joins:
        if len(joins) != 1:
            raise UserError(f"--kind {args.kind} fits one record: give one file or one --join.")
        return read_join(args, joins[0])
    return read_file(args, args.data)


def pooled_header(args: argparse.Namespace, records: list[Any], labels: list[str],
                  result: Any) -> str:  # fmt: skip
    """Comment lines of a pooled model file: the command, the status and every record."""
    lines = [f"identified by `{args.command_line}`"]
    if result.status != "converged":
        lines.append(f"NOT CONVERGED: status {result.status}. Check the report before using it.")
    lines.append(f"status {result.status}, NRMSE {100 * result.nrmse:.3g} %")
    from presliding.cli.fitting.fit import column_roles

    lines.append(f"data: {len(records)} records pooled (each with its own start, not kept here)")
    lines += column_roles(records, labels)
    lines += getattr(args, "cuts", None) or []
    for label, meas in zip(labels, records, strict=True):
        source = meas.source.describe(roles=False) if meas.source is not None else "arrays"
        lines.append(f"record {label}: " + source.replace("\n", "\n  "))
    return "\n".join(lines)
