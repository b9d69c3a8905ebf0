"""Compile the kernels of a later part of a command in a second process, on a cold cache.

On the first run the numba kernels are compiled, which takes most of the time
of ``presliding demo`` (20–40 s on a 2-core machine, against a few seconds
once they are cached). Compilation holds numba's global compiler lock, so
threads cannot compile two kernels at once; a second process can. When the
cache is cold, `start` launches ``python -m presliding.cli._precompile TASK``,
which runs the named part of the command once (with the same argument types,
so it compiles exactly the kernels that part uses) and discards its results;
numba writes each compiled kernel to the shared on-disk cache (atomically:
a temporary file, then a rename). The command meanwhile does its other parts,
and `wait` blocks before the part that needs those kernels, which then loads
them from the cache instead of compiling them again. Nothing changes in what
the command computes: the second process only fills the cache.

A task is a list of steps, each a part to run once the kernels it shares with
the command are in the cache (``needs``): the second process waits for them
(polling the cache's index, at most `NEEDS_LIMIT` seconds) rather than compile
them a second time while the command compiles them too. One process runs all
the steps of a task: every process pays for importing the package and for
numba's own helpers again, so one second process costs less CPU time than two.

With a warm cache, a single core, ``NUMBA_DISABLE_JIT`` or a cache that cannot
be read, nothing is started and `wait` returns at once. A second process that
fails or overruns is stopped, and the command compiles what it needs itself.
"""

from __future__ import annotations

import atexit
import importlib
import os
import subprocess
import sys
import time

__all__ = ["start", "stop_all", "wait"]

#: task name -> steps (kernel the step needs in the cache first or None, "module:function"
#: run once in the second process)
TASKS: dict[str, tuple[tuple[str | None, str], ...]] = {
    # the demo's continuous densities, then its identification round trip, while the
    # demo runs its first parts and compiles its closed loop's kernels itself: the
    # densities need the primitives that the demo's first model compiles (and the
    # event kernel that the free stop compiles, last, by when the command has cached
    # it), the fit the stop kernels that the Figure 3 loops compile
    "demo-later": (
        ("presliding.hysteresis._density_primitives:evaluate",
         "presliding.cli.demo_sections:density_part"),
        ("presliding.hysteresis._fused:stop_sum_blocked",
         "presliding.cli.demo_sections:identification"),
    ),
}  # fmt: skip
#: kernel whose cache entry tells whether a task's kernels are compiled already
_SENTINELS = {
    "demo-later": "presliding.motion._density_loop:run_fused",
}
#: seconds `wait` gives a second process before stopping it
WAIT_LIMIT = 600.0
#: seconds a step waits for the kernels it needs before it compiles them itself
NEEDS_LIMIT = 120.0
#: seconds between two looks at the cache's index
_POLL = 0.1

_running: dict[str, subprocess.Popen] = {}


def _is_cached(kernel: str) -> bool | None:
    """Whether ``"module:name"`` has an entry in numba's cache (None: cannot tell)."""
    try:
        module, name = kernel.split(":")
        dispatcher = getattr(importlib.import_module(module), name)
        cache = dispatcher._cache  # numba's FunctionCache (cache=True)
        return bool(cache._cache_file._load_index())
    except Exception:  # any doubt: the caller behaves as without a second process
        return None


def _cache_is_cold(task: str) -> bool:
    """True when the task's sentinel kernel has no usable entry in numba's cache."""
    if os.environ.get("NUMBA_DISABLE_JIT", "0") not in ("", "0"):
        return False
    return _is_cached(_SENTINELS.get(task, "")) is False


def _await_cached(kernel: str, limit: float = NEEDS_LIMIT) -> bool:
    """Wait until `kernel` is in the cache (True), or `limit` seconds (False)."""
    end = time.monotonic() + limit
    while True:
        cached = _is_cached(kernel)
        if cached is None or cached:
            return bool(cached)
        if time.monotonic() >= end:
            return False
        time.sleep(_POLL)


def _cores() -> int:
    """Cores this process may run on (its affinity mask where the platform has one)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on every platform
        return os.cpu_count() or 1


def start(task: str) -> bool:
    """Start compiling `task`'s kernels in a second process if that can help; True if started."""
    if task in _running or _cores() < 2 or not _cache_is_cold(task):
        return False
    flags = ["-P"] if sys.version_info >= (3, 11) else []  # no current folder on sys.path
    try:
        proc = subprocess.Popen(
            [sys.executable, *flags, "-m", "presliding.cli._precompile", task],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
    except OSError:
        return False
    if not _running:
        atexit.register(stop_all)
    _running[task] = proc
    return True


def wait(task: str) -> None:
    """Block until `task`'s second process (if any) has finished; stop it past `WAIT_LIMIT`."""
    proc = _running.pop(task, None)
    if proc is None:
        return
    try:
        proc.wait(timeout=WAIT_LIMIT)
    except subprocess.TimeoutExpired:
        _stop(proc)


def stop_all() -> None:
    """Stop every second process still running (the command ended or failed early)."""
    while _running:
        _stop(_running.popitem()[1])


def _stop(proc: subprocess.Popen) -> None:
    if proc.poll() is None:
        proc.terminate()
    try:
        proc.wait(timeout=10.0)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()


def main(argv: list[str]) -> int:
    """Run each named task's steps once, discarding their results (the kernels land in
    the cache)."""
    for task in argv:
        for needs, target in TASKS[task]:
            if needs is not None:
                _await_cached(needs)
            module, name = target.split(":")
            getattr(importlib.import_module(module), name)()
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
