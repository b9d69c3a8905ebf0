"""Helpers of the command line: user errors, input/output paths, CSV tables, figures."""

from __future__ import annotations

import argparse
import os
import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding import _io
from presliding._io import atomic_path, remove_stale_temporaries, write_text
from presliding._progress import progress
from presliding._validation import as_count, as_nonnegative_scalar, as_positive_scalar

FloatArray = NDArray[np.float64]

#: Rows written per block of a CSV file (the progress bar advances per block).
CSV_BLOCK = 50_000


class UserError(ValueError):
    """An error the user can fix: reported in one line, exit code 2."""


# ---------------------------------------------------------------------- paths
def _same_file(a: Path, b: Path) -> bool:
    if a.resolve() == b.resolve():
        return True
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


#: Names of the files presliding wrote into a folder, one per line: a later run
#: may replace these, and no other existing file (unless --overwrite is given).
#: A name is added once its file is in place; names of files that are gone are
#: dropped when the list is read.
MANIFEST = ".presliding-outputs"
#: Lock file of an output folder: one run at a time writes into a folder.
LOCK = ".presliding.lock"


def _listed(folder: Path) -> set[str]:
    """The names in the folder's `MANIFEST` as written (possibly of files now gone)."""
    try:
        lines = (folder / MANIFEST).read_text(encoding="utf-8").splitlines()
    except (FileNotFoundError, NotADirectoryError, UnicodeDecodeError, PermissionError):
        return set()
    return {ln.strip() for ln in lines if ln.strip() and not ln.startswith("#")}


def _written_before(folder: Path) -> set[str]:
    """The files an earlier run wrote into `folder` that are still there."""
    return {n for n in _listed(folder) if (folder / n).exists() or (folder / n).is_symlink()}


def _write_manifest(folder: Path, names: set[str]) -> None:
    header = "# written by presliding: a later run may replace these\n"
    write_text(folder / MANIFEST, header + "".join(f"{n}\n" for n in sorted(names)))


# ---------------------------------------------------------------------- folder locks
#: Folders this process holds (resolved path -> lock) and the outputs it will write
#: into them (resolved path -> folder as given).
_held: dict[Path, Any] = {}
_pending: dict[Path, Path] = {}


def claim_folder(folder: Path) -> None:
    """Lock an existing output folder for this run (until `release_folders`).

    A second run into the same folder fails at once with a one-line UserError
    naming it, so the outputs of two runs never mix. Under the lock, the
    temporaries of killed earlier writes are removed.
    """
    from filelock import FileLock, Timeout

    key = folder.resolve()
    if key in _held:
        return
    lock = FileLock(str(folder / LOCK), timeout=0)  # one attempt (filelock >= 3.12)
    try:
        lock.acquire()
    except Timeout:
        raise UserError(
            f"{folder}: another presliding run is writing into this folder; wait until it "
            "has finished or choose another folder with -o."
        ) from None
    except OSError as exc:
        raise UserError(f"{folder}: cannot lock the output folder ({exc.strerror}).") from None
    _held[key] = lock
    remove_stale_temporaries(folder)


def release_folders() -> None:
    """Release every folder this process claimed and forget its pending outputs."""
    for lock in _held.values():
        lock.release()
    _held.clear()
    _pending.clear()
    if _note_written in _io._written_listeners:
        _io._written_listeners.remove(_note_written)


def _note_written(path: Path) -> None:
    """Add an output to its folder's manifest once it is in place."""
    folder = _pending.get(Path(path).resolve())
    if folder is None:
        return
    names = _written_before(folder) | {Path(path).name}
    if names != _listed(folder):  # new, or listing files that are gone
        _write_manifest(folder, names)


def check_outputs(
    outputs: Iterable[Path], inputs: Iterable[Path | None], *, overwrite: bool = False
) -> None:
    """Refuse output paths that are inputs, or existing files presliding did not write.

    An output may never be an input file (also through links). An existing
    file may be replaced only if an earlier run wrote it (it is listed in the
    folder's `MANIFEST`) or `overwrite` is set. Nothing is created.
    """
    outs = [Path(p) for p in outputs]
    ins = [Path(p) for p in inputs if p is not None]
    for out in outs:
        for inp in ins:
            if _same_file(out, inp):
                raise UserError(
                    f"{out}: is the input file {inp}; choose another output with -o so that "
                    "the input is not overwritten."
                )
    known: dict[Path, set[str]] = {}
    for out in outs:
        if out.is_dir():
            raise UserError(
                f"{out}: is a folder; name an output file with -o, or give the folder itself "
                "to write the outputs into it."
            )
        exists = out.exists() or out.is_symlink()
        if exists and not overwrite:
            if out.parent not in known:
                known[out.parent] = _written_before(out.parent)
            if out.name in known[out.parent]:
                continue
            raise UserError(
                f"{out}: exists and was not written by presliding; choose another output "
                "with -o, or pass --overwrite to replace it."
            )
    for folder in dict.fromkeys(out.parent for out in outs):
        if folder.is_dir():  # a new folder is claimed when it is created (record_outputs)
            claim_folder(folder)


def record_outputs(outputs: Iterable[Path]) -> None:
    """Create and claim the output folders; each output enters its folder's `MANIFEST`
    as soon as it has been written (see `claim_folder`, `release_folders`)."""
    for out in outputs:
        folder = Path(out).parent
        make_folder(folder)
        claim_folder(folder)
        _pending[Path(out).resolve()] = folder
    if _note_written not in _io._written_listeners:
        _io._written_listeners.append(_note_written)


def check_folder(folder: Path) -> Path:
    """An output folder path: it must not be an existing file (it is created on claim)."""
    if folder.exists() and not folder.is_dir():
        raise UserError(f"{folder}: is a file, not a folder; pass a folder with -o.")
    return folder


def make_folder(folder: Path) -> Path:
    """Create the output folder (and parents)."""
    check_folder(folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UserError(f"{folder}: cannot create the output folder ({exc.strerror}).") from None
    return folder


def check_readable(path: Path, what: str) -> Path:
    """A clear error for a missing or unreadable input file."""
    if not path.exists():
        raise UserError(f"{path}: no such file; check the {what} path.")
    if path.is_dir():
        raise UserError(f"{path}: is a folder; the {what} must be a file.")
    return path


# ---------------------------------------------------------------------- CSV tables
_UNIT = re.compile(r"\s*[\[(][^\])]*[\])]\s*$")


def column_key(name: str) -> str:
    """Normalised column name: lower case, unit in brackets dropped, spaces as '_'.

    ``"Friction force [N]"`` -> ``"friction_force"``.
    """
    base = _UNIT.sub("", name.strip())
    return re.sub(r"[\s\-]+", "_", base.strip()).lower()


@dataclass(frozen=True)
class Table:
    """Columns of a CSV file: original header names and float columns."""

    path: Path
    names: list[str]
    columns: list[FloatArray]

    @property
    def n_rows(self) -> int:
        return int(self.columns[0].shape[0]) if self.columns else 0

    def find(self, aliases: Sequence[str]) -> int | None:
        """Index of the first column whose name (or normalised name) is in `aliases`."""
        keys = [column_key(n) for n in self.names]
        for alias in aliases:
            for i, (name, key) in enumerate(zip(self.names, keys, strict=True)):
                if alias in (name, key):
                    return i
        return None

    def column(self, signal: str, aliases: Sequence[str], option: str) -> FloatArray:
        """The column of `signal` (first match of `aliases`) or a one-line error."""
        i = self.find(aliases)
        if i is None:
            raise UserError(
                f"{self.path}: no column for `{signal}` (looked for "
                f"{', '.join(repr(a) for a in aliases)}); the columns are "
                f"{', '.join(repr(n) for n in self.names)}; name it with {option} "
                f"{signal}=COLUMN."
            )
        return self.columns[i]


def read_table(path: Path, what: str, example: str = "time,value") -> Table:
    """Read a delimited text file: one header line (after '#' comments), then numbers.

    The delimiter is a tab, a semicolon, a comma or whitespace; a byte-order
    mark is skipped; every row must be as long as the header and every value a
    finite number (see `presliding.measurement._readers`).
    """
    from presliding.measurement._readers import read_text

    check_readable(path, what)
    try:
        text = read_text(path)
        if text.names is None:
            raise UserError(
                f"{path}: the first line holds numbers, not column names; add a header line "
                f"(e.g. {example})."
            )
        values = text.values(list(range(text.n_columns)))
    except UserError:
        raise
    except (ValueError, OSError) as exc:
        raise UserError(str(exc)) from None
    names = list(text.names)
    return Table(path, names, [values[j] for j in range(len(names))])


def write_csv(
    path: Path, header: Sequence[str], columns: Sequence[FloatArray], *, quiet: bool = False
) -> None:
    """Write columns as CSV atomically (temporary file, then rename), with a progress bar."""
    data = np.column_stack([np.asarray(c, dtype=float) for c in columns])
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", newline="\n") as fh:
        fh.write(",".join(header) + "\n")
        with progress(data.shape[0], f"writing {path.name}", quiet=quiet, unit="row") as bar:
            for i in range(0, data.shape[0], CSV_BLOCK):
                block = data[i : i + CSV_BLOCK]
                np.savetxt(fh, block, fmt="%.15g", delimiter=",")
                bar.update(block.shape[0])


# ---------------------------------------------------------------------- figures
def new_figure(ncols: int = 1, nrows: int = 1, size: tuple[float, float] = (6.4, 4.4)) -> Any:
    """A matplotlib Figure (no pyplot state) with a constrained layout, and its axes."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=size, layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False)
    return fig, axes


def tidy_fit_axes(fig: Any, ax: Any, ylabel: str, unit: str) -> None:
    """Units on a `plot_fit` panel and its residual panel (the last axes of `fig`),
    with both y labels aligned clear of the tick labels."""
    residual = fig.axes[-1]
    ax.set_ylabel(f"{ylabel} [{unit}]")
    from matplotlib.ticker import FuncFormatter

    # a power of ten goes into the label, never as an offset text over the panel above
    top = float(np.max(np.abs(residual.dataLim.intervaly)))
    power = int(np.floor(np.log10(top))) if np.isfinite(top) and top > 0 else 0
    power = power if power < -2 or power > 3 else 0
    scale = f"$10^{{{power}}}$ " if power else ""
    residual.set_ylabel(f"residual [{scale}{unit}]")
    residual.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v / 10.0**power:g}"))
    fig.align_ylabels([ax, residual])


#: Words of the library's messages that name Python arguments, and the command line's words
#: for them (`cli_words`): a command-line user sets flags, not keywords.
_CLI_WORDS = (
    ("(prune=True drops them)", "(--prune drops them)"),
    ("give `mass` or `coulomb_level` to scale them", "give --mass to scale them"),
    (
        "`offset` must be False with `asymmetric`=True",
        "--offset cannot be combined with --asymmetric",
    ),
    ("levels); got offset=True.", "levels); drop --offset."),
    (
        "pass interpolate=True to interpolate onto the times of record 0",
        "pass --interpolate to interpolate onto the times of the group's first file",
    ),
    ("must be a loading ramp for loops=False", "must be a loading ramp for --ramps"),
    (": fit it with loops=True.", ": drop --ramps to fit it as loops."),
    (
        "(fit a virgin loading with fit_virgin_curve(..., loops=False))",
        "(fit a virgin loading with --kind virgin)",
    ),
    ("or give `axis` when reading", "or give --axis"),
    ("`units` names", "--units names"),
    ("`scale` names", "--scale names"),
    ("`reversal_tolerance`", "--reversal-tolerance"),
    ("`max_evaluations`", "--max-evaluations"),
    ("`n_elements`", "--elements"),
)


#: A Python argument followed by its flag in parentheses ("with `units` (--units)", "with
#: decimal=',' (--decimal ,)"): the command line says the flag alone.
_BOTH = re.compile(r"(?:`\w+`(?:(?: and |/)`\w+`)?|\b\w+='[^']*') \((--[^)]*)\)")


def cli_words(text: str) -> str:
    """A library message with the Python arguments it names put as command-line flags."""
    for python, flag in _CLI_WORDS:
        text = text.replace(python, flag)
    return _BOTH.sub(r"\1", text)


def check_options(pairs: Sequence[str] | None, option: str, allowed: Sequence[str]) -> dict:
    """Parse ``KEY=VALUE`` command-line items; keys must be in `allowed`."""
    out: dict[str, str] = {}
    for item in pairs or ():
        key, sep, value = item.partition("=")
        key, value = key.strip(), value.strip()
        if not sep or not key or not value:
            raise UserError(
                f"{option} {item!r}: expected KEY=COLUMN, e.g. {option} position='y [m]'."
            )
        if key not in allowed:
            raise UserError(
                f"{option} {item!r}: unknown signal {key!r}; use one of {', '.join(allowed)}."
            )
        out[key] = value
    return out


__all__ = [
    "LOCK",
    "MANIFEST",
    "Table",
    "UserError",
    "check_folder",
    "check_options",
    "check_outputs",
    "check_readable",
    "claim_folder",
    "cli_words",
    "column_key",
    "make_folder",
    "new_figure",
    "read_table",
    "record_outputs",
    "release_folders",
    "tidy_fit_axes",
    "write_csv",
]


def checked(option: str, *, integer: bool = False, **limits: Any) -> Callable[[str], Any]:
    """An argparse `type` for a numeric option, checked by the shared validation: a positive
    number (nonnegative with ``minimum=0.0``), or (`integer`) a count within `limits`
    (``minimum``, ``maximum``). A bad value is
    one line naming the option: "argument --cutoff: `--cutoff` must be positive; got -1.0."."""

    def convert(text: str) -> Any:
        try:
            value = int(text) if integer else float(text)
        except ValueError:
            kind = "a whole number" if integer else "a number"
            raise argparse.ArgumentTypeError(f"`{option}` must be {kind}; got {text!r}.") from None
        try:
            if integer:
                return as_count(option, value, **limits)
            if limits.get("minimum") == 0.0:
                return as_nonnegative_scalar(option, value)
            return as_positive_scalar(option, value)
        except (TypeError, ValueError) as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    return convert
