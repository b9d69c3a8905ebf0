"""``presliding precompile``: fill numba's cache ahead of the first run (CI images, containers)."""

from __future__ import annotations

from typing import Any


def run(args: Any) -> int:
    """``presliding precompile``: run the demo's computations once in a temporary folder, so
    that numba's cache holds the kernels (for CI images and containers); say where."""
    import tempfile
    from pathlib import Path

    from presliding import _numba_cache
    from presliding.cli.demo import run_demo

    compiled: list[str] = []
    with tempfile.TemporaryDirectory() as tmp, _numba_cache.compiling(compiled.append):
        run_demo(Path(tmp), quiet=args.quiet)
    if not args.quiet:
        where = {
            "NUMBA_CACHE_DIR": f"in NUMBA_CACHE_DIR = {_numba_cache.FOLDER}",
            "in-tree": "next to the package's modules (__pycache__)",
            "user": "in numba's user cache folder",
            "temporary": f"in {_numba_cache.FOLDER}",
            "uncached": "nowhere: no folder can be written, so every process compiles them",
        }.get(str(_numba_cache.LOCATION), str(_numba_cache.LOCATION))
        print(
            f"presliding precompile: {len(compiled)} kernels compiled; the kernels are "
            f"cached {where}."
        )
    return 0


__all__ = ["run"]
