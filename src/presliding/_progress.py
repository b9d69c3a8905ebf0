"""Progress bars for long work on the command line (tqdm).

A bar is shown only on an interactive terminal: it is quiet with ``--quiet``
and whenever stderr is redirected (a log file, a pipe, a test run).
"""

from __future__ import annotations

import sys
from typing import Any


def progress_enabled(quiet: bool = False) -> bool:
    """True when a progress bar should be drawn: not quiet and stderr is a terminal."""
    if quiet:
        return False
    isatty = getattr(sys.stderr, "isatty", None)
    try:
        return bool(isatty and isatty())
    except (OSError, ValueError):  # a closed or detached stream
        return False


def progress(total: float | None, desc: str, *, quiet: bool = False, unit: str = "it") -> Any:
    """A tqdm bar on stderr (a disabled one when `progress_enabled` is False).

    Use it as a context manager and call ``update(n)``; a disabled bar accepts
    the same calls and prints nothing.
    """
    from tqdm import tqdm

    return tqdm(
        total=total,
        desc=desc,
        unit=unit,
        disable=not progress_enabled(quiet),
        file=sys.stderr,
        leave=False,
        dynamic_ncols=True,
    )


__all__ = ["progress", "progress_enabled"]
