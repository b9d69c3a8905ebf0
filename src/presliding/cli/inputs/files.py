"""One data file read as a record of ``presliding fit`` or ``presliding predict``.

The file is delimited text (a header line or none; comma, tab, semicolon or
whitespace) or a MATLAB file (by its ``.mat`` suffix or its header). The
columns are found by `presliding.cli.inputs.columns` (the reasons go into the
record's `Source.roles`), units at the end of headers are converted to SI,
``--units`` gives or overrides them and ``--scale`` applies a factor on top
(for a MATLAB file, a number or the name of a scalar variable); ``--window
START:STOP`` keeps the samples in that time span. An option that cannot apply
to the file (``--decimal`` or ``--header`` for a MATLAB file) is refused.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from presliding.cli.common import UserError, check_options, check_readable
from presliding.cli.inputs.columns import NEEDS, SIGNALS, assign_columns, who

__all__ = ["is_mat", "parse_window", "read_measurement", "text_options"]


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


def is_mat(path: Path) -> bool:
    """A MATLAB file: by its suffix, or by the header of a version 5 file."""
    with open(path, "rb") as fh:
        return path.suffix.lower() == ".mat" or fh.read(19) == b"MATLAB 5.0 MAT-file"


def text_options(args: argparse.Namespace, path: Path, mat: bool) -> dict[str, Any]:
    """``header`` and ``decimal`` for a text file (given, else a model file's ``[data]``);
    given for a MATLAB file, they are refused (not ignored)."""
    header, decimal = getattr(args, "header", None), getattr(args, "decimal", None)
    if mat:
        for flag, value in (("--decimal", decimal), ("--header", header)):
            if value is not None:
                shown = flag if flag != "--header" or value else "--no-header"
                raise UserError(f"{shown}: {path} is a MATLAB file, whose variables carry no "
                                "header or decimal mark; drop the option.")  # fmt: skip
        return {}
    model = getattr(args, "model_data", None)
    if header is None and model is not None:
        header = model.header
    if decimal is None and model is not None:
        decimal = model.decimal
    return {"header": header, "decimal": decimal or "."}


def _scales(args: argparse.Namespace, mat: bool) -> dict[str, Any]:
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
    return scales


def _vector_names(mat: Any) -> list[str]:
    """The variables of a MATLAB file that can be signals (numeric vectors)."""
    out = []
    for name in mat.names:
        arr = np.asarray(mat.contents[name])
        if arr.dtype.kind in "iuf" and arr.squeeze().ndim == 1 and arr.size > 1:
            out.append(name)
    return out


def read_measurement(args: argparse.Namespace) -> Any:
    """The Measurement of the columns `args.kind` reads, in SI, windowed; clear errors.

    `args` may carry ``model_data`` (a model file's `DataSettings`: its columns, and its
    sample rate and text options where none are given).
    """
    from presliding.measurement._mat import read_mat
    from presliding.measurement._readers import read_text
    from presliding.measurement.measurement import Measurement

    check_readable(args.data, "data file")
    given = check_options(args.columns, "--columns", SIGNALS)
    units = check_options(args.units, "--units", SIGNALS)
    window = parse_window(args.window)
    mat = is_mat(args.data)
    options = text_options(args, args.data, mat)
    scales = _scales(args, mat)
    source = read_mat(args.data) if mat else read_text(args.data, **options)
    names = source.names if mat else (list(source.names) if source.names else None)
    mapping = getattr(getattr(args, "model_data", None), "columns", None)
    roles = assign_columns(args.kind, _vector_names(source) if mat else names, given, mapping,
                           args.data.name)  # fmt: skip
    found = roles.columns()
    rate = args.sample_rate
    model = getattr(args, "model_data", None)
    if "time" not in found and rate is None and model is not None:
        rate = model.sample_rate  # a model file's records had no time column either
    numbered = "time" not in found and rate is None and args.kind in ("presliding", "virgin")
    if numbered and window is None:
        rate = 1.0  # numbered samples: the presliding and virgin fits need no time
    for group in NEEDS[args.kind]:
        if not any(s in found for s in group) and not (group == ("time",) and rate):
            raise UserError(_missing(args, group, names, mat, roles))
    time = found.pop("time", None)
    if time is None and rate is None:
        raise UserError(_missing(args, ("time",), names, mat, roles))
    if time is not None and args.sample_rate is not None:
        raise UserError(f"--sample-rate: {args.data} has a time column ({time!r}); drop one.")
    reader: Callable[..., Measurement] = Measurement.from_mat if mat else Measurement.from_csv
    meas = reader(args.data, time, sample_rate=rate, units=units or None, scale=scales,
                  axis=getattr(args, "axis", None), **options, **found)  # fmt: skip
    read = meas.source
    assert read is not None  # a record read from a file knows its source
    read = replace(read, roles=roles.notes())
    if numbered and window is None:
        note = "no time column: samples numbered 0, 1, 2, ..."
        read = replace(read, sample_rate=None, notes=(note,))
    meas = replace(meas, source=read)
    if window is not None:
        try:
            meas = meas.window(*window)
        except ValueError as exc:
            raise UserError(f"--window {args.window}: {exc}") from None
    return meas


def _missing(args: argparse.Namespace, group: tuple[str, ...], names: Any, mat: bool,
             roles: Any) -> str:  # fmt: skip
    what = " or ".join(f"`{s}`" for s in group)
    rate = " (or give --sample-rate HZ)" if group == ("time",) else ""
    if names is None:
        wanted = ["time", *["position" if "position" in g else g[0]
                            for g in NEEDS[args.kind] if g != ("time",)]]  # fmt: skip
        example = " ".join(f"{s}={i}" for i, s in enumerate(wanted))
        return (
            f"{args.data}: has no header line, so columns are chosen by 0-based index; name "
            f"{what} with --columns, e.g. --columns {example}{rate}."
        )
    kinds = "variables" if mat else "columns"
    why = "; ".join(w for s, w in roles.missing.items() if s in group)
    return (
        f"{args.data}: no {kinds[:-1]} for {what} (needed by {who(args.kind)}"
        f"{'; ' + why if why else ''}); the {kinds} are {', '.join(repr(n) for n in names)}; "
        f"name it with --columns {group[0]}=COLUMN{rate}."
    )
