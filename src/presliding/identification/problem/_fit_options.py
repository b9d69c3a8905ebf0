"""The options every least-squares fit shares, checked on entry (counts, budgets, ties)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_count,
    as_parameter_vector,
    as_positive_scalar,
    as_real_scalar,
    fmt,
)

Tie = str | tuple[str, float] | tuple[str, float, float]
FloatArray = NDArray[np.float64]


def check_options(
    level: Any, max_evaluations: Any, tolerance: Any
) -> tuple[float, int | None, float]:
    """The options every fit shares, checked on entry.

    `level` must be a real number in (0, 1), `max_evaluations` None or an
    integer >= 1, `tolerance` a positive finite real; returned as float,
    int (or None) and float.
    """
    level = as_real_scalar("level", level)
    if not 0 < level < 1:
        raise ValueError(f"`level` must be between 0 and 1 (exclusive); got {fmt(level)}.")
    if max_evaluations is not None:
        max_evaluations = as_count("max_evaluations", max_evaluations, minimum=1)
    return level, max_evaluations, as_positive_scalar("tolerance", tolerance)


def check_budget(n_samples: int, burn_in: int, n_elements: int, n_other: int, source: str) -> None:
    """On entry: `burn_in` and the element count (two parameters each, besides `n_other`)
    leave more used samples than parameters; `source` names the argument of the count."""
    n_params = n_other + 2 * n_elements
    if n_samples - burn_in > n_params:
        return
    if burn_in > 0 and n_samples > n_params:
        raise ValueError(
            f"`burn_in` must leave more samples than parameters ({n_params}), i.e. be at "
            f"most {n_samples - n_params - 1} for {n_samples} samples; got {burn_in}."
        )
    if burn_in >= n_samples:
        raise ValueError(
            f"`burn_in` must be below the number of samples ({n_samples}); got {burn_in}."
        )
    most, used = max((n_samples - burn_in - 1 - n_other) // 2, 0), n_samples - burn_in
    raise ValueError(
        f"`{source}` must give at most {most} elements for {used} used samples "
        f"(two parameters each, and more samples than parameters); got {n_elements}."
    )


def check_constraints(
    fixed: Mapping[str, Any] | None, tied: Mapping[str, Any] | None
) -> tuple[dict[str, float], dict[str, Tie]]:
    """`fixed` and `tied` checked entry by entry, as new dicts.

    Every fixed value must be a finite real number (returned as float); every
    tie a parameter name, a (name, factor) pair or a (name, factor, offset)
    triple (p = factor·name + offset) of finite reals. The names themselves are
    checked against the parameters by `solve_least_squares`.
    """
    out_fixed: dict[str, float] = {}
    out_tied: dict[str, Tie] = {}
    for label, spec, what in (("fixed", fixed, "values"), ("tied", tied, "ties")):
        if spec is not None and not isinstance(spec, Mapping):
            raise TypeError(
                f"`{label}` must be a mapping of parameter names to {what}; "
                f"got {type(spec).__name__}."
            )
    for n, v in (fixed or {}).items():
        out_fixed[n] = as_real_scalar(f"fixed[{n!r}]", v)
    for n, v in (tied or {}).items():
        if isinstance(v, str):
            out_tied[n] = v
            continue
        if not (isinstance(v, (tuple, list)) and len(v) in (2, 3) and isinstance(v[0], str)):
            raise TypeError(
                f"`tied[{n!r}]` must be a parameter name, a (name, factor) pair or a "
                f"(name, factor, offset) triple; got {fmt(v)}."
            )
        factor = as_real_scalar(f"tied[{n!r}][1]", v[1])
        out_tied[n] = (
            (v[0], factor, as_real_scalar(f"tied[{n!r}][2]", v[2]))
            if len(v) == 3 and v[2] != 0
            else (v[0], factor)
        )
    return out_fixed, out_tied


def element_count(n_elements: int | None, thresholds: ArrayLike | None, default: int) -> int:
    """The number of elements from `n_elements` and/or `thresholds` (checked to agree)."""
    if thresholds is not None:
        n_thr = as_parameter_vector("thresholds", thresholds).shape[0]
        if n_elements is not None and n_elements != n_thr:
            raise ValueError(
                f"`n_elements` must equal the number of `thresholds` ({n_thr}); got {n_elements}."
            )
        return n_thr
    if n_elements is None:
        return default
    return as_count("n_elements", n_elements)


def check_varies(name: str, arr: FloatArray) -> None:
    """Reject a constant signal (nothing to fit)."""
    if not np.ptp(arr) > 0:
        raise ValueError(f"`{name}` must vary; got a constant signal ({fmt(float(arr[0]))}).")


def check_fit_options(
    fixed: Mapping[str, float] | None,
    tied: Mapping[str, Tie] | None,
    level: float,
    grid_size: int,
    max_evaluations: int | None,
    tolerance: float,
) -> tuple[dict[str, float], dict[str, Tie], float, int, int | None, float]:
    """The options shared by the separable fits, checked on entry (see `check_options`).

    `grid_size` must be at least 2: a geometric grid needs its two ends, and with
    one point the elements would all start at the same threshold.
    """
    fixed, tied = check_constraints(fixed, tied)
    level, max_evaluations, tolerance = check_options(level, max_evaluations, tolerance)
    grid_size = as_count("grid_size", grid_size, minimum=2)
    return fixed, tied, level, grid_size, max_evaluations, tolerance


def check_enough(n_used: int, n_parameters: int, what: str = "samples") -> None:
    """At least one more sample than parameters."""
    if n_used <= n_parameters:
        raise ValueError(
            f"the fit needs more {what} than parameters ({n_parameters}); got {n_used}."
        )
