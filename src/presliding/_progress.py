"""What a run shows and needs: numba's cache folder, compile notices and progress.

**numba's cache.** The kernels are compiled with ``cache=True``. numba keeps
the compiled code next to the source (``__pycache__``) or in the user's cache
folder (``$XDG_CACHE_HOME/numba``, ``~/.cache/numba``), and raises ``cannot cache
function ...: no locator available`` at import when neither can be written (a
read-only site-packages with no writable home: shared installs, containers, CI
images). This module is the first import of ``presliding/__init__.py``: it runs
`configure` before any kernel module loads, which keeps the first folder that
can be written: ``NUMBA_CACHE_DIR`` if set; the package's folders; numba's
platform cache folder; else a private folder of the temporary directory,
``presliding-numba-cache-<uid>`` (mode 0700, used only if this user owns it and
nobody else can write to it: numba's index files are pickles), which it puts in
``NUMBA_CACHE_DIR`` (the environment, so worker processes inherit it, and
``numba.config``). With no writable folder at all the kernels run uncached and
one line on stderr says so. `compiling` calls a function whenever numba compiles
one of presliding's kernels, through numba's event API (``"numba:compile"``,
sent only on cache misses).

**Progress.** `Progress` is what a command uses for work that can take more than
about two seconds (the demo, sweeps, fits): ``with Progress("presliding fit",
total=3, unit="stage", quiet=args.quiet) as bar:``, then ``bar.part(name)`` as a
named part begins, ``bar.note(text)`` and ``bar.update()`` per unit done. It
writes to stderr: on a terminal a tqdm bar named after the current part, with
the latest note after it; elsewhere (a log file, a pipe, CI) plain lines, one per
part, one per distinct note within a part and, for counted work without parts,
one per tenth of the total (``presliding demo: [2/6] free motion to a stop``);
nothing with ``quiet=True`` (``--quiet``). While it is open it says "compiling
(first run only)" whenever numba compiles a kernel (a cold cache).
`progress` and `progress_enabled` are the older bar-only helpers (a tqdm bar on
a terminal, nothing elsewhere) for short steps such as writing a CSV file.
"""

from __future__ import annotations

import contextlib
import os
import stat
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from types import TracebackType
from typing import IO, Any

# ---------------------------------------------------------------- numba's cache
#: Where the kernels are cached: "NUMBA_CACHE_DIR", "in-tree", "user", "temporary"
#: or "uncached"; set by `configure`.
LOCATION: str | None = None
#: The folder of the "NUMBA_CACHE_DIR" and "temporary" locations (None otherwise).
FOLDER: Path | None = None

_PACKAGE = Path(__file__).resolve().parent


def _writable(folder: Path) -> bool:
    """numba's own test: the folder can be made and a temporary file written in it."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        tempfile.TemporaryFile(dir=folder).close()
    except OSError:
        return False
    return True


def _user_cache_folder() -> Path | None:
    """The platform cache folder numba falls back to by itself (its `UserWideCacheLocator`)."""
    try:
        from numba.misc.appdirs import AppDirs
    except ImportError:  # a numba without it: numba's own fallback is unknown here
        return None
    return Path(AppDirs(appname="numba", appauthor=False).user_cache_dir)


def _private_temporary_folder() -> Path | None:
    """A per-user folder in the temporary directory that only this user can write to."""
    try:
        base = Path(tempfile.gettempdir())
    except OSError:  # no usable temporary directory at all
        return None
    uid = os.getuid() if hasattr(os, "getuid") else None
    folder = base / f"presliding-numba-cache-{uid if uid is not None else 'user'}"
    try:
        folder.mkdir(mode=0o700, exist_ok=True)
        info = folder.lstat()
    except OSError:
        return None
    if not stat.S_ISDIR(info.st_mode):  # a file or a symbolic link planted there
        return None
    if uid is not None and (info.st_uid != uid or info.st_mode & 0o022):
        return None  # owned by someone else, or writable by others: not safe to load
    return folder if _writable(folder) else None


def _set_cache_dir(folder: Path) -> None:
    os.environ["NUMBA_CACHE_DIR"] = str(folder)
    numba_config = sys.modules.get("numba.core.config")
    if numba_config is not None:  # numba already imported: its config was read
        setattr(numba_config, "CACHE_DIR", str(folder))  # noqa: B010 - a module of numba


def configure() -> str:
    """Choose where numba caches the kernels (see the module docstring); return the location.

    Call before any kernel module is imported. Safe to call again: a later call
    keeps the first choice.
    """
    global LOCATION, FOLDER
    if LOCATION is not None:
        return LOCATION
    given = os.environ.get("NUMBA_CACHE_DIR", "")
    if given and _writable(Path(given)):
        LOCATION, FOLDER = "NUMBA_CACHE_DIR", Path(given)
        return LOCATION
    # An unusable NUMBA_CACHE_DIR is skipped by numba itself, which then tries these two.
    layers = [p for p in _PACKAGE.iterdir() if (p / "__init__.py").is_file()]
    if all(_writable(p / "__pycache__") for p in [_PACKAGE, *layers]):
        LOCATION = "in-tree"
        return LOCATION
    user = _user_cache_folder()
    if user is not None and _writable(user):
        LOCATION = "user"
        return LOCATION
    folder = _private_temporary_folder()
    if folder is not None:
        _set_cache_dir(folder)
        LOCATION, FOLDER = "temporary", folder
        return LOCATION
    _run_uncached()
    LOCATION = "uncached"
    sys.stderr.write(
        "presliding: no writable folder for numba's cache (package, NUMBA_CACHE_DIR, user "
        "cache, temporary directory); kernels are compiled anew in every process.\n"
    )
    return LOCATION


def _run_uncached() -> None:
    """Let ``cache=True`` kernels of presliding compile without a cache instead of failing.

    numba raises at decoration when it finds no cache folder; this wraps
    ``Dispatcher.enable_caching`` to leave presliding's kernels with numba's
    null cache in that case (other packages' kernels are left as they are).
    """
    try:
        from numba.core.dispatcher import Dispatcher
    except ImportError:  # pragma: no cover - numba without this layout
        return
    original = Dispatcher.enable_caching
    if getattr(original, "_presliding_uncached", False):
        return

    def enable_caching(self: Dispatcher) -> None:
        try:
            original(self)
        except RuntimeError:
            module = getattr(self.py_func, "__module__", "") or ""
            if not module.startswith("presliding."):
                raise

    enable_caching._presliding_uncached = True  # type: ignore[attr-defined]
    Dispatcher.enable_caching = enable_caching  # type: ignore[method-assign]


@contextlib.contextmanager
def compiling(callback: Callable[[str], None]) -> Iterator[None]:
    """Call ``callback(name)`` each time numba compiles a kernel of presliding in the block.

    numba sends its ``"numba:compile"`` event only when a kernel is not found in
    the cache, so a warm cache calls nothing. ``name`` is the kernel's
    qualified name. Works as a no-op where numba's event API is missing.
    """
    try:
        from numba.core import event
    except ImportError:  # pragma: no cover - numba older than the event API
        yield
        return

    class _Listener(event.Listener):
        def on_start(self, ev: event.Event) -> None:
            dispatcher = (ev.data or {}).get("dispatcher")
            func = getattr(dispatcher, "py_func", None)
            module = getattr(func, "__module__", "") or ""
            if module.startswith("presliding."):
                callback(getattr(func, "__qualname__", "kernel"))

        def on_end(self, ev: event.Event) -> None:
            pass

    with event.install_listener("numba:compile", _Listener()):
        yield


# ---------------------------------------------------------------- progress
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
        total=total, desc=desc, unit=unit, disable=not progress_enabled(quiet), file=sys.stderr,
        leave=False, dynamic_ncols=True,
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
        `stream` is a terminal.
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
        self.interactive = _isatty(self.stream) if interactive is None else interactive
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
        if quiet:
            return
        if self.interactive:
            from tqdm import tqdm

            self._bar = tqdm(
                total=total, desc=desc, unit=unit, file=self.stream, leave=False,
                dynamic_ncols=True, mininterval=0.2, delay=self.delay,
            )  # fmt: skip
            if self.delay > 0:  # drawn when the delay ends, even if no update comes then
                self._timer = threading.Timer(self.delay, self._draw)
                self._timer.daemon = True
                self._timer.start()
        if compile_note:
            self._listening = compiling(self._on_compile)
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
        if self._bar is not None:
            n = self.n_compiled
            self.note(f"{COMPILING}: {n} kernel{'s' if n > 1 else ''}")
        else:
            self.note(COMPILING)

    def _line(self, text: str, *, part: bool = False) -> None:
        if self.delay and self.elapsed < self.delay:
            if part:  # said before the first line of the part that comes after the delay
                self._pending = text
            return
        pending, self._pending = self._pending, None
        lines = [text] if part or pending is None else [pending, text]
        # a closed stream: progress is never worth an error
        with contextlib.suppress(OSError, ValueError):
            for line in lines:
                print(f"{self.desc}: {line}", file=self.stream, flush=True)


configure()

__all__ = [
    "COMPILING",
    "FOLDER",
    "LOCATION",
    "Progress",
    "compiling",
    "configure",
    "progress",
    "progress_enabled",
]
