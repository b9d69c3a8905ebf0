"""The outcome of one least-squares solve: `Solution` (values, errors, status), names listed.

`solution_of` builds it from a solve's checked options and where the optimiser
stopped (`_least_squares`), with its errors or, deferred (`_deferred`), without.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding.identification.problem._parameter_map import tie_triples

FloatArray = NDArray[np.float64]

__all__ = ["Solution", "name_list", "solution_of"]

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
    #: the residual tests of the fit's optimum (`_adequacy.Adequacy`; None: not run)
    adequacy: Any = field(default=None, repr=False, compare=False)
    #: free parameters whose profile stopped unresolved (`_profile`: the inner optimisations
    #: disagree), their linearised intervals kept
    unresolved: tuple[str, ...] = ()


def name_list(names: Any, order: tuple[str, ...]) -> str:
    """Names in parameter order, at most a few, then "and N more"."""
    rank = {n: i for i, n in enumerate(order)}
    ordered = sorted(set(names), key=lambda n: (rank.get(n, len(rank)), n))
    shown = ", ".join(ordered[:_LISTED])
    return shown + (f" and {len(ordered) - _LISTED} more" if len(ordered) > _LISTED else "")


def solution_of(setup: Any, found: Any, status: str, message: str, **errors: Any) -> Solution:
    """The `Solution` of a solve: `setup` its checked options (`_least_squares._Setup`),
    `found` where the optimiser stopped (`_least_squares._Found`), the status and message
    judged, and `errors` the fields of the errors (standard errors and intervals at least;
    the covariance, bandwidths and profiler, or `pending`, where there are)."""
    pm, names = setup.pm, setup.names
    return Solution(
        values=dict(zip(names, pm.full(found.x).tolist(), strict=True)),
        level=setup.level, fixed=tuple(setup.fixed), tied=tuple(setup.tied), residual=found.r,
        status=status, message=message, n_evaluations=found.evaluations,
        at_bounds=found.on_bound, free=pm.free,
        bounds={
            n: (float(a), float(b))
            for n, a, b in zip(names, setup.lower, setup.upper, strict=True)
            if np.isfinite(a) or np.isfinite(b)
        },
        ties=tie_triples(setup.tied), **errors,
    )  # fmt: skip
