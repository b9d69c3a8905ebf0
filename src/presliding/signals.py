"""Test inputs: piecewise-linear displacement paths through given turning points."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_positive_scalar,
    as_signal,
    check_finite_derived,
    check_size,
)

__all__ = ["FIGURE3_TURNING_POINTS", "piecewise_linear"]

#: Turning points of a displacement path chosen to reproduce the kind of loops
#: shown in the paper's Figure 3 (the paper does not give its input sequence):
#: relative to the thresholds r = c/k of that model, a major loop to ±0.3, then
#: nested minor loops that close on their reversal points.
FIGURE3_TURNING_POINTS = (0.0, 0.3, -0.3, 0.15, -0.05, 0.08, -0.3, 0.3)


def piecewise_linear(turning_points: ArrayLike, step: float) -> NDArray[np.float64]:
    """A path that moves linearly between consecutive turning points.

    Parameters
    ----------
    turning_points : array_like, shape (P,)
        Values visited in order (at least two).
    step : float
        Largest spacing between samples (> 0). Every turning point is a sample,
        so the path is monotone between consecutive samples, as the operators
        require for exactness.

    Returns
    -------
    ndarray
        The samples, starting at the first turning point.
    """
    tp = as_signal("turning_points", turning_points, min_length=2)
    h = as_positive_scalar("step", step)
    with np.errstate(over="ignore"):  # a count beyond the float range is reported as such
        span = np.abs(np.diff(tp))
        check_finite_derived("distance between consecutive turning points", span, "turning_points")
        counts = np.maximum(np.ceil(span / h), 1.0)
        total = 1.0 + float(np.sum(counts))
    check_size("step", h, total, what="samples", item_bytes=2 * 8)  # the pieces and the result
    pieces = [tp[:1]]
    for a, b, n in zip(tp[:-1], tp[1:], counts.astype(np.int64), strict=True):
        pieces.append(np.linspace(a, b, n + 1)[1:])
    return np.concatenate(pieces)
