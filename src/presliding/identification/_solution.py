"""The outcome of one least-squares solve: `Solution` (values, errors, status), names listed."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

__all__ = ["Solution", "name_list"]

_LISTED = 6  # names listed in a message before "and N more"


@dataclass(frozen=True)
class Solution:
    """Outcome of `solve_least_squares` (values and errors of every parameter)."""

    values: dict[str, float]
    standard_error: dict[str, float]
    confidence_interval: dict[str, tuple[float, float]]
    level: float
    fixed: tuple[str, ...]
    tied: tuple[str, ...]
    residual: FloatArray
    status: str
    message: str
    n_evaluations: int
    covariance: FloatArray | None = None  # over every parameter, in the order of `values`
    bandwidths: tuple[int, ...] = ()  # HAC bandwidth of each block (empty: independent)
    at_bounds: tuple[str, ...] = ()
    free: tuple[str, ...] = ()
    bounds: dict[str, tuple[float, float]] = field(default_factory=dict)  # the finite ones
    #: how each free parameter's interval was formed ("profile" or "wald"; empty: not yet)
    interval_method: dict[str, str] = field(default_factory=dict)
    #: tied name -> (target, factor, offset)
    ties: dict[str, tuple[str, float, float]] = field(default_factory=dict)
    profiler: Any = field(default=None, repr=False, compare=False)  # `_profile.Profiler`
    #: other local optima the search reached, as (values, cost ‖r‖²) (`_alternatives`)
    others: tuple[tuple[dict[str, float], float], ...] = field(
        default=(), repr=False, compare=False
    )
    #: a solve whose errors were deferred (``errors=False``): returns the complete solution
    #: (`_least_squares.complete`); None when the errors are in
    pending: Any = field(default=None, repr=False, compare=False)


def name_list(names: Any, order: tuple[str, ...]) -> str:
    """Names in parameter order, at most a few, then "and N more"."""
    rank = {n: i for i, n in enumerate(order)}
    ordered = sorted(set(names), key=lambda n: (rank.get(n, len(rank)), n))
    shown = ", ".join(ordered[:_LISTED])
    return shown + (f" and {len(ordered) - _LISTED} more" if len(ordered) > _LISTED else "")
