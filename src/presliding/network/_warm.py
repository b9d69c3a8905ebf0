"""The compiled event loop, ready or not: on a cold cache it is compiled in a second process.

Compiling the event loop (`presliding.network._exact_kernel.run_events`) costs
about a minute of CPU (numba's front end over the piece construction, the contact
decision and the event search), against milliseconds for a typical run once it is
compiled. On a cold cache `simulate_network` does not wait for it: `ready` starts one
second process (running `main`, at low priority) that compiles
the kernel into numba's on-disk cache, and the run takes the general loop
(`presliding.network._exact_run`: the same event rules in numpy, the same events, the
same motion to rounding) meanwhile. Once the kernel is in the cache (loading it takes a
few tenths of a second), every run uses it. `compile_now` compiles it in this process
(`presliding precompile`). In process, as before, when ``BACKGROUND`` is False (or the
environment sets ``PRESLIDING_NETWORK_COMPILE=process``), when numba cannot cache (a
second process could not share its work) or when the JIT is disabled.
"""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
from typing import Any

#: Compile the event loop in a second process on a cold cache (see the module notes).
BACKGROUND = os.environ.get("PRESLIDING_NETWORK_COMPILE", "background") != "process"

_process: dict[str, Any] = {}
#: The second process's program (the module as imported by the package, not ``__main__``).
_CHILD = "from presliding.network import _warm; raise SystemExit(_warm.main())"


def _kernel() -> Any:
    from presliding.network._exact_kernel import run_events

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


def compile_now() -> None:
    """Compile the event loop in this process (with the argument types of every
    call), so that it is cached."""
    import numpy as np

    from presliding.friction import PIFriction
    from presliding.network.exact import simulate_network
    from presliding.network.structure import chain_structure

    global BACKGROUND
    before, BACKGROUND = BACKGROUND, False
    try:
        friction = PIFriction(0.2, [400.0, 150.0], [0.1, 0.15])
        chain = chain_structure(2, 1.0, 1000.0, friction, forcing=([0.0, 0.02], [[0, 0], [0, 1]]))
        simulate_network(chain, 0.05, initial_velocity=np.array([0.3, -0.2]))
    finally:
        BACKGROUND = before


def main() -> int:
    """The second process: compile at low priority, discard the result."""
    with contextlib.suppress(AttributeError, OSError):  # not on every platform
        os.nice(10)
    global BACKGROUND
    BACKGROUND = False  # never a third process
    compile_now()
    return 0
