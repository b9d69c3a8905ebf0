"""The compiled event loop, ready or not: on a cold cache it is compiled in a second process.

Compiling the event loop (`presliding.network.events._exact_kernel.run_events`) costs
about a minute of CPU (numba's front end over the piece construction, the contact
decision and the event search), against milliseconds for a typical run once it is
compiled. On a cold cache `simulate_network` does not wait for it: `ready` starts one
second process (running `presliding.network.events.exact.compile_main`, at low priority)
that compiles the kernel into numba's on-disk cache, and the run takes the general loop
(`presliding.network.events._exact_run`: the same event rules in numpy, the same events, the
same motion to rounding) meanwhile. Once the kernel is in the cache (loading it takes a
few tenths of a second), every run uses it. `presliding.network.events.exact.compile_now`
compiles it in this process (`presliding precompile`). In process, as before, when
``BACKGROUND`` is False (or the environment sets ``PRESLIDING_NETWORK_COMPILE=process``),
when numba cannot cache (a second process could not share its work) or when the JIT is
disabled.
"""

from __future__ import annotations

import os
import subprocess
import sys
from typing import Any

#: Compile the event loop in a second process on a cold cache (see the module notes).
BACKGROUND = os.environ.get("PRESLIDING_NETWORK_COMPILE", "background") != "process"

_process: dict[str, Any] = {}
#: The second process's program (the module as imported by the package, not ``__main__``).
_CHILD = "from presliding.network.events import exact; raise SystemExit(exact.compile_main())"


def _kernel() -> Any:
    from presliding.network.events._exact_kernel import run_events

    return run_events


def ready() -> bool:
    """Whether the compiled loop can run without compiling here: compiled in this process
    or cached on disk (or to be compiled in process: see the module notes). On a cold
    cache it starts the second process (once) and returns False."""
    kernel = _kernel()
    if kernel.overloads or not BACKGROUND:
        return True
    if os.environ.get("NUMBA_DISABLE_JIT", "0") not in ("", "0"):
        return True
    from presliding import _numba_cache

    if _numba_cache.LOCATION == "uncached":
        return True
    try:
        cached = bool(kernel._cache._cache_file._load_index())
    except Exception:  # any doubt: compile in process, as without a second process
        return True
    if cached:
        return True
    proc = _process.get("compile")
    if proc is None:
        _start()
    elif proc.poll() is not None:  # it ended without a cache entry: compile here
        return True
    return False


def _start() -> None:
    flags = ["-P"] if sys.version_info >= (3, 11) else []  # no current folder on sys.path
    try:
        _process["compile"] = subprocess.Popen(
            [sys.executable, *flags, "-c", _CHILD],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            env=dict(os.environ, PRESLIDING_NETWORK_COMPILE="process"),
        )  # fmt: skip
    except OSError:  # no second process: compile in process on the next call
        _process["compile"] = _Done()


class _Done:
    """A finished process (the start failed)."""

    def poll(self) -> int:
        return 1
