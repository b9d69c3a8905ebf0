"""Progress of long work on the command line: one helper for every command.

`Progress` is what a command uses for work that can take more than about two
seconds (the demo, sweeps, fits)::

    from presliding._progress import Progress

    with Progress("presliding fit", total=3, unit="stage", quiet=args.quiet) as bar:
        bar.part("start values")      # a named part begins
        ...
        bar.update()                  # one more unit done
        bar.part("least squares")
        ...
        bar.update()

What it shows, always on stderr:

- on a terminal, a tqdm bar (count, elapsed time, rate) named after the
  current part, with the latest note after it;
- elsewhere (a log file, a pipe, CI), plain lines: one per part, one per
  distinct note within a part and, for counted work without parts, one per tenth of the
  total, each prefixed with the description (``presliding demo: [2/5] free
  motion to a stop``);
- nothing at all with ``quiet=True`` (``--quiet``).

With ``compiling=True`` (the default) it says "compiling (first run only)"
whenever numba compiles one of presliding's kernels while the bar is open: that
happens only when the cache does not hold them yet (see `presliding._numba_cache`).

`progress` and `progress_enabled` are the older, bar-only helpers: a tqdm bar
on a terminal and nothing elsewhere (used for short steps such as writing a CSV
file).
"""

from __future__ import annotations

import contextlib
import sys
import time
from types import TracebackType
from typing import IO, Any

#: The note shown while numba compiles kernels (a cold cache).
COMPILING = "compiling (first run only)"


def progress_enabled(quiet: bool = False) -> bool:
    """True when a progress bar should be drawn: not quiet and stderr is a terminal."""
    if quiet:
        return False
    return _isatty(sys.stderr)


def _isatty(stream: Any) -> bool:
    isatty = getattr(stream, "isatty", None)
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


class Progress:
    """Progress of one command: a tqdm bar on a terminal, plain lines elsewhere, or nothing.

    Parameters
    ----------
    desc : str
        What runs, e.g. ``"presliding demo"``; it starts every plain line.
    total : int, optional
        Units of work (parts, chunks, iterations); None when unknown.
    unit : str
        Name of one unit on the bar (``"part"``, ``"chunk"``, ``"iteration"``).
    quiet : bool
        Show nothing (``--quiet``).
    stream : file, optional
        Where to write (default: ``sys.stderr`` at the time of the call).
    interactive : bool, optional
        Force the bar (True) or the plain lines (False); default: a bar when
        `stream` is a terminal.
    compiling : bool
        Say "compiling (first run only)" while numba compiles presliding's kernels.
    delay : float
        Show nothing before this many seconds have passed [s]: short work stays
        silent (the bar appears, or plain lines start, once it runs longer).

    Use it as a context manager (or call `close`). Every method is cheap and
    does nothing when quiet.
    """

    def __init__(
        self,
        desc: str,
        total: int | None = None,
        *,
        unit: str = "it",
        quiet: bool = False,
        stream: IO[str] | None = None,
        interactive: bool | None = None,
        compiling: bool = True,
        delay: float = 0.0,
    ) -> None:
        self.desc = desc
        self.total = total
        self.unit = unit
        self.quiet = quiet
        self.stream = sys.stderr if stream is None else stream
        self.interactive = _isatty(self.stream) if interactive is None else interactive
        self.delay = float(delay)
        self.n = 0
        self.n_compiled = 0
        self._part: str | None = None
        self._n_parts = 0
        self._note: str | None = None
        self._notes_said: set[str] = set()
        self._tenths_said = 0
        self._t0 = time.perf_counter()
        self._bar: Any = None
        self._listening: Any = None
        if quiet:
            return
        if self.interactive:
            from tqdm import tqdm

            self._bar = tqdm(
                total=total, desc=desc, unit=unit, file=self.stream, leave=False,
                dynamic_ncols=True, mininterval=0.2, delay=self.delay,
            )  # fmt: skip
        if compiling:
            from presliding._numba_cache import compiling as _compiling

            self._listening = _compiling(self._on_compile)
            self._listening.__enter__()

    # ---------------------------------------------------------------- public
    def part(self, name: str) -> None:
        """A named part of the work begins (one plain line, or the bar's text)."""
        if self.quiet:
            return
        self._part = name
        self._n_parts += 1
        self._note = None
        self._notes_said.clear()  # a note is said again in a later part
        if self._bar is not None:
            self._bar.set_description_str(f"{self.desc}: {name}", refresh=False)
            self._bar.set_postfix_str("", refresh=True)
        else:
            count = f"[{self._n_parts}/{self.total}] " if self.total else ""
            self._line(f"{count}{name}")

    def update(self, n: int = 1) -> None:
        """`n` more units of work are done."""
        if self.quiet:
            return
        self.n += n
        if self._bar is not None:
            self._bar.update(n)
        elif self.total and self._n_parts == 0:  # counted work without parts: every tenth
            tenths = min(10, int(10 * self.n / self.total))
            if tenths > self._tenths_said:
                self._tenths_said = tenths
                percent = 100 * self.n / self.total
                self._line(f"{self.n}/{self.total} {self.unit}s ({percent:.0f} %)")

    def note(self, text: str) -> None:
        """A remark on the current part (on the bar; a plain line the first time it is said)."""
        if self.quiet:
            return
        self._note = text
        if self._bar is not None:
            self._bar.set_postfix_str(text, refresh=True)
        elif text not in self._notes_said:
            self._notes_said.add(text)
            self._line(text)

    def close(self) -> None:
        """Remove the bar (terminal) and stop listening for compilation."""
        if self._listening is not None:
            listening, self._listening = self._listening, None
            listening.__exit__(None, None, None)
        if self._bar is not None:
            bar, self._bar = self._bar, None
            bar.close()

    @property
    def elapsed(self) -> float:
        """Seconds since the progress was created."""
        return time.perf_counter() - self._t0

    def __enter__(self) -> Progress:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    # ---------------------------------------------------------------- private
    def _on_compile(self, kernel: str) -> None:
        self.n_compiled += 1
        if self._bar is not None:
            n = self.n_compiled
            self.note(f"{COMPILING}: {n} kernel{'s' if n > 1 else ''}")
        else:
            self.note(COMPILING)

    def _line(self, text: str) -> None:
        if self.delay and self.elapsed < self.delay:
            return
        # a closed stream: progress is never worth an error
        with contextlib.suppress(OSError, ValueError):
            print(f"{self.desc}: {text}", file=self.stream, flush=True)


__all__ = ["COMPILING", "Progress", "progress", "progress_enabled"]
