"""Atomic, non-clobbering file output.

Every output is written to a temporary file next to it and renamed onto it, so a
reader never sees half a file. The temporary's name carries the writer's process
id and host, ``.<name>.<pid>@<host>.<random>.tmp``: a write that was killed
(SIGKILL, power loss) leaves one behind, and `remove_stale_temporaries` removes
those whose process is gone. Errors name the output file, never the temporary.
"""

from __future__ import annotations

import contextlib
import os
import re
import socket
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path

#: Called with the path of every output `atomic_path` has put in place.
_written_listeners: list[Callable[[Path], None]] = []


def _host() -> str:
    return re.sub(r"[^A-Za-z0-9-]", "-", socket.gethostname().split(".")[0]) or "host"


_TEMPORARY = re.compile(r"^\..+\.(?P<pid>\d+)@(?P<host>[A-Za-z0-9-]+)\.[^.]+\.tmp$")


def _naming(exc: OSError, target: Path, tmp: str | None) -> OSError:
    """The error `exc` reported for the output `target` (not its temporary file)."""
    if exc.filename not in (None, tmp, str(target.parent)) and tmp is not None:
        return exc
    return OSError(exc.errno, exc.strerror or str(exc), str(target))


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield a temporary path next to `path`; rename it onto `path` on success.

    The temporary file is removed if the block raises, so a failed write never
    leaves a partial output behind. An OSError (read-only folder, full disk)
    is raised naming `path`.
    """
    target = Path(path)
    tmp = None
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(
            prefix=f".{target.name}.{os.getpid()}@{_host()}.", suffix=".tmp", dir=target.parent
        )
        os.close(fd)
    except OSError as exc:
        raise _naming(exc, target, tmp) from None
    try:
        yield Path(tmp)
        # mkstemp creates the file private (0600); give it the mode a plain open() would
        os.chmod(tmp, _new_file_mode(target))
        _fsync(tmp)  # the data is on disk before the name points at it
        os.replace(tmp, target)
        _fsync(target.parent)  # and so is the rename (where folders can be synced)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        if isinstance(exc, OSError):
            raise _naming(exc, target, tmp) from None
        raise
    for listener in list(_written_listeners):
        listener(target)


def remove_stale_temporaries(folder: str | os.PathLike[str]) -> list[Path]:
    """Remove the temporaries of `atomic_path` in `folder` whose writer no longer runs.

    Only files named by this host are considered (a process id means nothing
    on another machine sharing the folder). Returns the files removed.
    """
    removed: list[Path] = []
    host = _host()
    try:
        names = os.listdir(folder)
    except OSError:
        return removed
    for name in names:
        match = _TEMPORARY.match(name)
        if match is None or match["host"] != host or _running(int(match["pid"])):
            continue
        with contextlib.suppress(FileNotFoundError):
            os.unlink(Path(folder) / name)
            removed.append(Path(folder) / name)
    return removed


def _running(pid: int) -> bool:
    """Whether a process with this id exists (a process of another user counts)."""
    if pid == os.getpid() or os.name == "nt":  # Windows' os.kill would end the process
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OSError, OverflowError):
        return True
    return True


def _new_file_mode(target: Path) -> int:
    """The mode of an existing `target`, else 0o666 less the process umask."""
    try:
        return target.stat().st_mode & 0o7777
    except FileNotFoundError:
        return 0o666 & ~_umask()


def _umask() -> int:
    """The process umask, read without changing it where the system allows."""
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)  # elsewhere: set and restore at once
    os.umask(mask)
    return mask


def _fsync(path: str | os.PathLike[str]) -> None:
    """Flush a file or folder to disk; a no-op where that is not supported."""
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def write_text(path: str | os.PathLike[str], text: str) -> None:
    """Write a text file atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
