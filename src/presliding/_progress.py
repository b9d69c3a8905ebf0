"""What a run shows: compile notices and progress.

`Progress` is what a command uses for work that can take more than
about two seconds (the demo, sweeps, fits): ``with Progress("presliding fit",
total=3, unit="stage", quiet=args.quiet) as bar:``, then ``bar.part(name)`` as a
named part begins, ``bar.note(text)`` and ``bar.update()`` per unit done. It
writes to stderr: on a terminal a tqdm bar named after the current part, with
the latest note after it; in a Jupyter notebook tqdm's notebook bar (`tqdm.auto`: a
widget where ipywidgets is installed, else the text bar); elsewhere (a log file, a
pipe, CI) plain lines, one per part, one per distinct note within a part and, for
counted work without parts, one per tenth of the total (``presliding demo: [2/6]
free motion to a stop``);
nothing with ``quiet=True`` (``--quiet``). While it is open it says "compiling
(first run only)" whenever numba compiles a kernel (a cold cache).
`progress` and `progress_enabled` are the older bar-only helpers (a tqdm bar on
a terminal or in a notebook, nothing elsewhere) for short steps such as writing a
CSV file.
numba's cache folder is chosen in `presliding._numba_cache` (the package's first import).
"""

from __future__ import annotations

import contextlib
import os
import shutil
import sys
import threading
import time
from types import TracebackType
from typing import IO, Any

from presliding._numba_cache import FOLDER, LOCATION, compiling  # the last two: older home

# ---------------------------------------------------------------- progress
#: The note shown while numba compiles kernels (a cold cache).
COMPILING = "compiling (first run only)"


def progress_enabled(quiet: bool = False) -> bool:
    """True when a progress bar should be drawn: not quiet, and stderr is a terminal or the
    code runs in a Jupyter notebook."""
    if quiet:
        return False
    return _interactive(sys.stderr)


def in_notebook() -> bool:
    """True inside a Jupyter kernel (a notebook in Jupyter, JupyterLab, VS Code or Colab):
    IPython's shell there has a kernel; a terminal IPython has none."""
    ipython = sys.modules.get("IPython")  # never imported here: a kernel has imported it
    if ipython is None:
        return False
    try:
        shell = ipython.get_ipython()
    except Exception:  # an IPython without it, or in a broken state: not a notebook
        return False
    return shell is not None and hasattr(shell, "kernel")


def _interactive(stream: Any) -> bool:
    """A bar for `stream`: a terminal, or the notebook's own output (stderr or stdout)."""
    return _isatty(stream) or (in_notebook() and stream in (sys.stderr, sys.stdout))


def _tqdm(stream: Any) -> Any:
    """tqdm's bar class for `stream`: `tqdm.auto`'s in a notebook, the text bar elsewhere."""
    if not _isatty(stream) and in_notebook():
        from tqdm.auto import tqdm as bar
    else:
        from tqdm import tqdm as bar
    return bar


def _isatty(stream: Any) -> bool:
    isatty = getattr(stream, "isatty", None)
    try:
        return bool(isatty and isatty())
    except (OSError, ValueError):  # a closed or detached stream
        return False


def _shape(stream: Any) -> dict[str, Any]:
    """tqdm's size options for a terminal `stream`: its own size, followed as it changes;
    or, where the terminal reports no size (0 × 0: a pseudo-terminal nobody sized, as
    some consoles, containers and session recorders open), ``COLUMNS``/``LINES`` or
    80 × 24. tqdm draws nothing at all on a terminal of 0 rows."""
    try:
        size = os.get_terminal_size(stream.fileno())
    except (AttributeError, OSError, ValueError):  # not a real file: tqdm's own defaults
        return {"dynamic_ncols": True}
    if size.columns > 0 and size.lines > 0:
        return {"dynamic_ncols": True}
    fallback = shutil.get_terminal_size((80, 24))  # COLUMNS and LINES first
    columns = fallback.columns if fallback.columns > 0 else 80
    return {"ncols": columns, "nrows": fallback.lines if fallback.lines > 0 else 24}


def progress(total: float | None, desc: str, *, quiet: bool = False, unit: str = "it") -> Any:
    """A tqdm bar on stderr (a disabled one when `progress_enabled` is False).

    Use it as a context manager and call ``update(n)``; a disabled bar accepts
    the same calls and prints nothing.
    """
    return _tqdm(sys.stderr)(
        total=total, desc=desc, unit=unit, disable=not progress_enabled(quiet), file=sys.stderr,
        leave=False, **_shape(sys.stderr),
    )  # fmt: skip


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
        `stream` is a terminal or a Jupyter notebook's output.
    compile_note : bool
        Say "compiling (first run only)" while numba compiles presliding's kernels.
    delay : float
        Show nothing before this many seconds have passed [s]: short work stays
        silent (the bar appears, or plain lines start, once it runs longer; the
        line of the part in progress then comes first).

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
        compile_note: bool = True,
        delay: float = 0.0,
    ) -> None:
        self.desc = desc
        self.total = total
        self.unit = unit
        self.quiet = quiet
        self.stream = sys.stderr if stream is None else stream
        self.interactive = _interactive(self.stream) if interactive is None else interactive
        self.delay = float(delay)
        self.n = 0
        self.n_compiled = 0
        self._part: str | None = None
        self._n_parts = 0
        self._note: str | None = None
        self._notes_said: set[str] = set()
        self._tenths_said = 0
        self._pending: str | None = None  # a part's line held back by `delay`
        self._t0 = time.perf_counter()
        self._bar: Any = None
        self._timer: threading.Timer | None = None
        self._listening: Any = None
        self._compiling = 0  # kernels being compiled now (numba's events nest)
        self._last_line = time.perf_counter()
        self._stop = threading.Event()
        self._ticker: threading.Thread | None = None
        if quiet:
            return
        if self.interactive:
            self._bar = _tqdm(self.stream)(
                total=total, desc=desc, unit=unit, file=self.stream, leave=False,
                mininterval=0.2, delay=self.delay, **_shape(self.stream),
            )  # fmt: skip
            if self.delay > 0:  # drawn when the delay ends, even if no update comes then
                self._timer = threading.Timer(self.delay, self._draw)
                self._timer.daemon = True
                self._timer.start()
        if compile_note:
            self._listening = compiling(self._on_compile, self._on_compiled)
            self._listening.__enter__()
        # the bar's clock keeps ticking, and plain output says it is alive, while numba
        # compiles (a kernel can take 10 s, with no update from the work in between)
        self._ticker = threading.Thread(target=self._tick, name="presliding-progress", daemon=True)
        self._ticker.start()

    # ---------------------------------------------------------------- public
    def part(self, name: str) -> None:
        """A named part of the work begins (one plain line, or the bar's text)."""
        if self.quiet:
            return
        self._part = name
        self._n_parts += 1
        self._note = None
        self._notes_said.clear()  # a note is said again in a later part
        if self._bar is not None:  # drawn now only once `delay` has passed (as tqdm's updates)
            self._bar.set_description_str(f"{self.desc}: {name}", refresh=False)
            self._bar.set_postfix_str("", refresh=self._due())
        else:
            count = f"[{self._n_parts}/{self.total}] " if self.total else ""
            self._line(f"{count}{name}", part=True)

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
            self._bar.set_postfix_str(text, refresh=self._due())
        elif text not in self._notes_said:
            self._notes_said.add(text)
            self._line(text)

    def close(self) -> None:
        """Remove the bar (terminal) and stop listening for compilation."""
        if self._timer is not None:
            self._timer.cancel()
        self._stop.set()
        if self._ticker is not None and self._ticker is not threading.current_thread():
            self._ticker.join(timeout=2.0)
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
    def _draw(self) -> None:  # the timer's: a closed bar or stream is never worth an error
        with contextlib.suppress(OSError, ValueError, AttributeError):
            self._bar.refresh()

    def _due(self) -> bool:
        return not self.delay or self.elapsed >= self.delay

    def _on_compile(self, kernel: str) -> None:
        self.n_compiled += 1
        self._compiling += 1
        if self._bar is not None:
            # the note leads the line (tqdm cuts a long line at its right end: at 80 columns
            # the postfix is the first to go); the part and the count follow
            n = self.n_compiled
            self._bar.set_description_str(f"{self.desc}: {COMPILING}", refresh=False)
            part = f"{self._part}; " if self._part else ""
            self._bar.set_postfix_str(
                f"{part}{n} kernel{'s' if n > 1 else ''}", refresh=self._due()
            )
        else:
            self.note(COMPILING)

    def _on_compiled(self, kernel: str) -> None:
        self._compiling = max(self._compiling - 1, 0)
        if self._compiling == 0 and self._bar is not None:
            name = f"{self.desc}: {self._part}" if self._part else self.desc
            self._bar.set_description_str(name, refresh=False)
            self._bar.set_postfix_str(self._note or "", refresh=self._due())

    #: Seconds between two heartbeat lines (plain output) while kernels compile.
    HEARTBEAT = 5.0
    #: Seconds between two redraws of the bar by the ticker.
    TICK = 1.0

    def _tick(self) -> None:
        """Redraw the bar every `TICK` s; in plain output, a line at least every `HEARTBEAT` s
        while kernels compile."""
        period = self.TICK if self._bar is not None else min(self.TICK, self.HEARTBEAT / 5)
        while not self._stop.wait(period):
            if self._bar is not None:
                if self._due():
                    self._draw()
            elif self._compiling and time.perf_counter() - self._last_line >= self.HEARTBEAT:
                n = self.n_compiled
                self._line(
                    f"{COMPILING}: {n} kernel{'s' if n > 1 else ''} so far, {self.elapsed:.0f} s"
                )

    def _line(self, text: str, *, part: bool = False) -> None:
        if self.delay and self.elapsed < self.delay:
            if part:  # said before the first line of the part that comes after the delay
                self._pending = text
            return
        pending, self._pending = self._pending, None
        lines = [text] if part or pending is None else [pending, text]
        self._last_line = time.perf_counter()
        # a closed stream: progress is never worth an error
        with contextlib.suppress(OSError, ValueError):
            for line in lines:
                print(f"{self.desc}: {line}", file=self.stream, flush=True)


__all__ = [
    "COMPILING", "FOLDER", "LOCATION", "Progress", "compiling", "in_notebook", "progress",
    "progress_enabled",
]  # fmt: skip
