"""Delimited text files for `Measurement.from_csv` and the command line.

Delimited text (`read_text`):

- the delimiter is a tab, a semicolon, a comma or whitespace, detected from
  the first line that is not a comment (``#``) or blank (or given);
- a header line is detected when any cell of that first line is not a number
  (``header=None``); a file without one has its columns chosen by 0-based index;
- a delimiter at the end of every line (rig software that ends each value
  with a tab) is not a column: the cells before it are the row;
- a UTF-8 byte-order mark is skipped; UTF-16 and UTF-32 text (Excel's "Unicode
  text") is read, with its byte-order mark or without one (told by where its
  zero bytes fall); a file that is not UTF-8 is read as Windows-1252 (``µ``
  from older rig software);
- ``decimal=","`` reads decimal commas (European exports, ``1,5;2,25``), with
  a tab, semicolon or whitespace between the cells;
- rows are parsed by pandas' C parser when pandas is installed (else numpy);
  whenever a row does not parse cleanly, the rows are read one by one so that
  the error names the line and the column;
- every row must have as many cells as the header: a row with a missing cell
  is an error naming the file, line and column, never a shifted column, and so
  is an empty or non-numeric cell, or a non-finite value, in a column used;
- a binary file (or a MATLAB file) is an error naming the file.
"""

from __future__ import annotations

import io
import os
import re
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._validation import fmt
from presliding.measurement._units import parse_header

__all__ = ["TextTable", "check_path", "read_bytes", "read_text"]

FloatArray = NDArray[np.float64]
_SNIFF = 1 << 16  # bytes looked at for binary content
# a whitespace-separated header cell: a name, optionally followed by its unit in brackets
_WS_HEADER = re.compile(r"[^\s\[(]+(?:\s*\[[^\]]*\]|\s*\([^)]*\))?|\[[^\]]*\]|\([^)]*\)")
_DELIMITERS = {",": ",", ";": ";", "\t": "\t", " ": None, "whitespace": None}


def check_path(path: Any, what: str = "path") -> str:
    """A file path as str: TypeError for None or a non-path, clear errors for a folder."""
    if path is None or not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"`{what}` must be a file path (str or os.PathLike); got {fmt(path)}.")
    text = os.fspath(path)
    if not isinstance(text, str):
        text = os.fsdecode(text)
    if os.path.isdir(text):
        raise ValueError(f"{text}: is a folder; `{what}` must name a file.")
    if not os.path.exists(text):
        raise FileNotFoundError(f"{text}: no such file; check `{what}`.")
    return text


def read_bytes(path: str) -> bytes:
    try:
        with open(path, "rb") as fh:
            return fh.read()
    except OSError as exc:
        raise OSError(f"{path}: cannot be read ({exc.strerror}).") from None


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


@dataclass(frozen=True)
class TextTable:
    """The lines of a delimited text file, split on demand (see `read_text`)."""

    path: str
    names: tuple[str, ...] | None
    delimiter: str | None
    rows: list[str]
    first_line: int  # 1-based line number in the file of rows[0]
    decimal: str = "."

    def row_lines(self) -> NDArray[np.int64]:
        """1-based line numbers in the file of the data rows (blank and comment lines skipped)."""
        keep = [i for i, r in enumerate(self.rows) if _is_row(r)]
        return np.asarray(keep, dtype=np.int64) + self.first_line

    @property
    def n_columns(self) -> int:
        if self.names is not None:
            return len(self.names)
        return len(self._split(next(r for r in self.rows if _is_row(r))))

    def _split(self, row: str) -> list[str]:
        cells = row.split(self.delimiter) if self.delimiter else row.split()
        cells = [c.strip().strip('"').strip() for c in cells]
        if self.decimal != ".":
            cells = [c.replace(self.decimal, ".") for c in cells]
        return cells

    def label(self, j: int) -> str:
        """The header name of column j, or ``column j`` in a headerless file."""
        return self.names[j] if self.names is not None else f"column {j}"

    def index(self, signal: str, column: str | int) -> int:
        """0-based index of `column` (a header name, its name without unit, or an index)."""
        n = self.n_columns
        if isinstance(column, (int, np.integer)) and not isinstance(column, bool):
            if not 0 <= column < n:
                raise ValueError(
                    f"{self.path}: column of `{signal}` must be an index in 0..{n - 1}; "
                    f"got {column}."
                )
            return int(column)
        if not isinstance(column, str):
            raise TypeError(
                f"column of `{signal}` must be a header name (str) or a 0-based index (int); "
                f"got {fmt(column)}."
            )
        if self.names is None:
            raise ValueError(
                f"{self.path}: has no header line (its first row is numeric), so columns are "
                f"chosen by 0-based index (e.g. {signal}=1); got {column!r} for `{signal}`."
            )
        for candidates in (list(self.names), [parse_header(n)[0] for n in self.names]):
            hits = [j for j, name in enumerate(candidates) if name == column]
            if len(hits) == 1:
                return hits[0]
            if len(hits) > 1:
                raise ValueError(
                    f"{self.path}: {len(hits)} columns are named {column!r} (indices "
                    f"{', '.join(map(str, hits))}); choose `{signal}` by 0-based index."
                )
        raise ValueError(
            f"{self.path}: no column {column!r} for `{signal}`; the columns are "
            f"{', '.join(repr(n) for n in self.names)}."
        )

    def values(self, indices: list[int]) -> dict[int, FloatArray]:
        """The columns `indices` as finite float arrays; clear errors naming line and column."""
        n = self.n_columns
        data = self._fast_values()
        if data is None or data.ndim != 2 or data.shape[1] != n:
            return self._slow_values(indices)
        # a gap or a bad value in a column used is named below, line by line; a gap in an
        # unused column costs nothing, unless its row is short (cells would be shifted)
        if not np.all(np.isfinite(data[:, indices])) or not self._whole(np.isnan(data)):
            return self._slow_values(indices)
        return {j: np.ascontiguousarray(data[:, j]) for j in indices}

    def _whole(self, gaps: NDArray[np.bool_]) -> bool:
        """True when every row with a gap (NaN) has all its cells: an empty or NaN cell, not
        a short row that the parser padded at its end (its cells shifted left)."""
        rows_with_gaps = np.flatnonzero(gaps.any(axis=1))
        if rows_with_gaps.size == 0:
            return True
        rows = [r for r in self.rows if _is_row(r)]
        if len(rows) != gaps.shape[0]:
            return False
        n = self.n_columns
        if self.delimiter:  # the count of delimiters is the cells' (as `_split` sees them)
            return all(rows[i].count(self.delimiter) == n - 1 for i in rows_with_gaps)
        return all(len(self._split(rows[i])) == n for i in rows_with_gaps)

    def _fast_values(self) -> FloatArray | None:
        """Every row parsed at once (pandas' C parser, else numpy); None when a row fails."""
        rows = (
            self.rows if self.decimal == "." else [r.replace(self.decimal, ".") for r in self.rows]
        )
        try:
            import pandas as pd
        except ImportError:
            pd = None
        try:
            if pd is not None:
                # correctly rounded numbers: pandas' default before 3.0 may be 1 ulp off
                old = int(pd.__version__.split(".")[0]) < 3
                exact = {"float_precision": "round_trip"} if old else {}
                frame = pd.read_csv(
                    io.StringIO("\n".join(rows)), sep=self.delimiter or r"\s+", header=None,
                    comment="#", dtype=np.float64, engine="c", quotechar='"',
                    skip_blank_lines=True, skipinitialspace=True, **exact,
                )  # fmt: skip
                return np.asarray(frame.to_numpy(dtype=np.float64), dtype=np.float64)
            return np.loadtxt(rows, delimiter=self.delimiter, ndmin=2, dtype=np.float64,
                              comments="#", quotechar='"')  # fmt: skip
        except (ValueError, TypeError, IndexError):
            return None
        except Exception as exc:  # pandas' ParserError and EmptyDataError
            if pd is not None and isinstance(
                exc, (pd.errors.ParserError, pd.errors.EmptyDataError)
            ):
                return None
            raise

    def _slow_values(self, indices: list[int]) -> dict[int, FloatArray]:
        n = self.n_columns
        columns: dict[int, list[float]] = {j: [] for j in indices}
        for i, row in enumerate(self.rows):
            line = self.first_line + i
            if not _is_row(row):
                continue
            cells = self._split(row)
            if len(cells) != n:
                what = "the header names" if self.names is not None else "the first row has"
                raise ValueError(
                    f"{self.path}: line {line} has {len(cells)} cells but {what} {n} columns; "
                    "a missing or extra cell would shift the columns, so fix the row."
                )
            for j in indices:
                cell = cells[j]
                if not cell:
                    raise ValueError(
                        f"{self.path}: line {line}, column {self.label(j)!r}: empty cell; "
                        "every value used must be a number."
                    )
                try:
                    value = float(cell)
                except ValueError:
                    raise ValueError(
                        f"{self.path}: line {line}, column {self.label(j)!r}: {cell[:40]!r} is "
                        f"not a number{_comma_hint(cell, self.decimal)}."
                    ) from None
                if not np.isfinite(value):
                    raise ValueError(
                        f"{self.path}: line {line}, column {self.label(j)!r}: {cell!r} is not a "
                        "finite number; remove or fill the gap."
                    )
                columns[j].append(value)
        return {j: np.asarray(v, dtype=np.float64) for j, v in columns.items()}


_DECIMAL_COMMA = re.compile(r"^[+-]?(\d+,\d*|,\d+)([eE][+-]?\d+)?$")


def _comma_hint(cell: str, decimal: str) -> str:
    """``; it looks like a number with a decimal comma: ...`` for ``0,001`` read with '.'."""
    if decimal == "." and _DECIMAL_COMMA.match(cell.strip()):
        return (f"; it looks like a number with a decimal comma ({cell.replace(',', '.')!r}): "
                "read the file with decimal=',' (--decimal ,)")  # fmt: skip
    return ""


def _is_row(line: str) -> bool:
    """A data row: neither blank nor a comment."""
    return bool(line.strip()) and not line.lstrip().startswith("#")


def _decode(path: str, raw: bytes) -> str:
    head = raw[:_SNIFF]
    if head.startswith((b"MATLAB 5.0 MAT-file", b"MATLAB 7.3 MAT-file")):
        raise ValueError(
            f"{path}: is a MATLAB file, not delimited text; read it with Measurement.from_mat "
            "(the command line reads .mat files by their suffix)."
        )
    codec = _wide_codec(head)
    if codec is not None:  # UTF-16 or UTF-32, with a byte-order mark or without one
        try:
            text = raw.decode(codec)
        except UnicodeDecodeError:
            raise ValueError(
                f"{path}: is not valid {codec.upper()} text although it starts as such."
            ) from None
        if "\x00" in text:
            raise ValueError(f"{path}: holds NUL characters after decoding it as "
                             f"{codec.upper()}; save it as UTF-8 text.")  # fmt: skip
        return text.removeprefix("\ufeff")
    if b"\x00" in head:
        raise ValueError(
            f"{path}: is not a text file (it holds binary data); a data file must be delimited "
            "text (comma, tab, semicolon or whitespace separated) or a MATLAB .mat file."
        )
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        return raw.decode("cp1252", errors="replace")


#: Byte-order marks of the wide encodings (UTF-32 first: its little-endian mark starts
#: with UTF-16's).
_BOMS = ((b"\xff\xfe\x00\x00", "utf-32"), (b"\x00\x00\xfe\xff", "utf-32"),
         (b"\xff\xfe", "utf-16"), (b"\xfe\xff", "utf-16"))  # fmt: skip


def _wide_codec(head: bytes) -> str | None:
    """The codec of UTF-16 or UTF-32 text (Excel's "Unicode text", exports of rig software),
    from its byte-order mark, else from where its zero bytes fall (text in Latin letters and
    digits has a zero high byte in every code unit); None for anything else."""
    for bom, codec in _BOMS:
        if head.startswith(bom):
            return codec
    for width, codec in ((4, "utf-32"), (2, "utf-16")):
        n = (len(head) // width) * width
        if n < 4 * width or b"\x00" not in head:
            continue
        units = np.frombuffer(head[:n], dtype=np.uint8).reshape(-1, width)
        zero = units == 0
        for order, low in (("le", 0), ("be", width - 1)):
            high = [j for j in range(width) if j != low]
            if zero[:, high].mean() >= 0.99 and (~zero[:, low]).mean() >= 0.9:
                return f"{codec}-{order}"
    return None


def read_text(
    path: Any, *, delimiter: str | None = None, header: bool | None = None, decimal: str = "."
) -> TextTable:
    """Open a delimited text file (see the module notes); rows are parsed by `TextTable.values`.

    Parameters
    ----------
    path : path-like
    delimiter : {",", ";", "\\t", " ", "whitespace"}, optional
        Detected from the first line when None.
    header : bool, optional
        True: the first line names the columns; False: there is none; None:
        detected (a header when any cell of the first line is not a number).
    decimal : {".", ","}
        The decimal mark of the numbers; with ``","`` the cells must be
        separated by a tab, a semicolon or whitespace.
    """
    path = check_path(path)
    if delimiter is not None and (not isinstance(delimiter, str) or delimiter not in _DELIMITERS):
        raise ValueError(
            "`delimiter` must be one of ',', ';', '\\t', ' ' or 'whitespace'; got "
            f"{fmt(delimiter)}."
        )
    if header is not None and not isinstance(header, bool):
        raise TypeError(f"`header` must be True, False or None; got {fmt(header)}.")
    if decimal not in (".", ","):
        raise ValueError(f"`decimal` must be '.' or ','; got {fmt(decimal)}.")
    text = _decode(path, read_bytes(path))
    lines = text.splitlines()
    start = 0  # leading blank and comment lines
    while start < len(lines) and (not lines[start].strip() or lines[start].startswith("#")):
        start += 1
    if start == len(lines):
        raise ValueError(f"{path}: holds no data (it is empty or only comments).")
    first = lines[start]
    if delimiter is None:
        marks = ("\t", ";", ",") if decimal == "." else ("\t", ";")
        delim = next((d for d in marks if d in first), None)
    else:
        delim = _DELIMITERS[delimiter]
    if decimal == "," and delim == ",":
        raise ValueError(
            f"{path}: `decimal` ',' needs cells separated by a tab, a semicolon or whitespace; "
            "got the delimiter ','."
        )
    if delim is not None and first.rstrip("\r\n").endswith(delim):  # not a column
        first = first.rstrip("\r\n")[: -len(delim)]
        lines = [_drop_trailing(ln, delim) for ln in lines]
    cells = [c.strip().strip('"').strip() for c in (first.split(delim) if delim else first.split())]
    numbers = [c.replace(",", ".") for c in cells] if decimal == "," else cells
    has_header = (not all(_is_number(c) for c in numbers)) if header is None else header
    if has_header and delim is None:  # "Time [s] Position [mm]": units stay with their names
        cells = _WS_HEADER.findall(first)
    begin = start + 1 if has_header else start
    rows = lines[begin:]  # blank and comment lines stay: they keep the line numbers
    if not any(_is_row(r) for r in rows):
        raise ValueError(f"{path}: has a header line but no data rows.")
    names = tuple(cells) if has_header else None
    return TextTable(path, names, delim, rows, begin + 1, decimal)


def _drop_trailing(line: str, delim: str) -> str:
    text = line.rstrip("\r\n")
    return text[: -len(delim)] if text.endswith(delim) else text
