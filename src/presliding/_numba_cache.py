"""numba's cache folder, chosen before any kernel module loads; compile notices.

The kernels are compiled with ``cache=True``. numba keeps
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

This module is shared ground (it imports no layer); `presliding._progress` uses
`compiling` for its "compiling (first run only)" note.
"""

from __future__ import annotations

import contextlib
import os
import stat
import sys
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path

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
def compiling(
    callback: Callable[[str], None], done: Callable[[str], None] | None = None
) -> Iterator[None]:
    """Call ``callback(name)`` each time numba starts compiling a kernel of presliding in the
    block (and ``done(name)`` when it has finished).

    numba sends its ``"numba:compile"`` event only when a kernel is not found in
    the cache, so a warm cache calls nothing. ``name`` is the kernel's
    qualified name. Works as a no-op where numba's event API is missing.
    """
    try:
        from numba.core import event
    except ImportError:  # pragma: no cover - numba older than the event API
        yield
        return

    def ours(ev: event.Event) -> str | None:
        func = getattr((ev.data or {}).get("dispatcher"), "py_func", None)
        module = getattr(func, "__module__", "") or ""
        return getattr(func, "__qualname__", "kernel") if module.startswith("presliding.") else None

    class _Listener(event.Listener):
        def on_start(self, ev: event.Event) -> None:
            name = ours(ev)
            if name is not None:
                callback(name)

        def on_end(self, ev: event.Event) -> None:
            name = ours(ev)
            if name is not None and done is not None:
                done(name)

    with event.install_listener("numba:compile", _Listener()):
        yield


configure()

__all__ = ["FOLDER", "LOCATION", "compiling", "configure"]
