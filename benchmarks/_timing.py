"""Timing and input helpers shared by the benchmarks.

`seconds` is the median time of one call (each repeat calls until at least
`min_time` passed, so short calls are averaged over many); `accumulating` wraps a
function so that its calls add their seconds and count to a total; `through` samples a
path of turning points with every sample monotone to the next (the operators'
sampling assumption), `per_segment` samples per monotone piece.
"""

from __future__ import annotations

import itertools
import statistics
import time
from collections.abc import Callable

import numpy as np


def seconds(call: Callable[[], object], repeats: int, min_time: float = 0.1) -> float:
    """Median seconds per call of `call` over `repeats` repeats of at least `min_time` each."""
    out = []
    for _ in range(repeats):
        reps, start = 0, time.perf_counter()
        while True:
            call()
            reps += 1
            elapsed = time.perf_counter() - start
            if elapsed >= min_time:
                break
        out.append(elapsed / reps)
    return statistics.median(out)


def accumulating(original: Callable[..., object], total: list) -> Callable[..., object]:
    """`original`, adding each call's seconds to ``total[0]`` and, where `total` has a second
    entry, one to ``total[1]``."""

    def timed(*args, **kw):
        t0 = time.perf_counter()
        try:
            return original(*args, **kw)
        finally:
            total[0] += time.perf_counter() - t0
            if len(total) > 1:
                total[1] += 1

    return timed


def through(turns: np.ndarray, per_segment: int = 10) -> np.ndarray:
    """Samples along straight pieces between consecutive turning points, then the last one."""
    fine = [np.linspace(a, b, per_segment + 1)[:-1] for a, b in itertools.pairwise(turns)]
    return np.ascontiguousarray(np.concatenate([*fine, turns[-1:]]))
