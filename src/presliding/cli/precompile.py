"""``presliding precompile``: fill numba's cache ahead of the first run (CI images, containers)."""

from __future__ import annotations

from typing import Any


def run(args: Any) -> int:
    """``presliding precompile``: run the demo's computations once in a temporary folder, and
    both network paths on a small chain, so that numba's cache holds the kernels (for CI
    images and containers); say where."""
    import tempfile
    from pathlib import Path

    from presliding import _numba_cache
    from presliding.cli.demo import run_demo

    compiled: list[str] = []
    with tempfile.TemporaryDirectory() as tmp, _numba_cache.compiling(compiled.append):
        run_demo(Path(tmp), quiet=args.quiet)
        network_kernels()
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


def network_kernels() -> None:
    """Run both network paths once on a small chain, so their kernels are cached too (the
    demo does not use them; compiling them takes about a minute of CPU)."""
    import numpy as np

    from presliding import PIFriction
    from presliding.network import chain_structure, exact, simulate_network_moreau

    exact.compile_now()  # in this process (a run on a cold cache leaves it to a second one)
    friction = PIFriction(0.2, [400.0, 150.0], [0.1, 0.15])
    for sparse in (False, True):
        chain = chain_structure(2, 1.0, 1000.0, friction, sparse=sparse)
        simulate_network_moreau(chain, 0.05, 1e-3, initial_velocity=np.array([0.3, -0.2]))


__all__ = ["network_kernels", "run"]
