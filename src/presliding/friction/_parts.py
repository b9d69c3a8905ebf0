"""The two forms of a `PIFriction`, typed: its finite elements, or its continuous density.

A model holds either elements (``stiffness``, ``threshold``, ``breakaway``) or a
continuous ``density``, so each of those fields may be None. Code that has
branched on `PIFriction.is_discrete` takes the form it needs from here, and a
type checker then knows it is present; a model of the other form raises.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from presliding.hysteresis.densities import Density

if TYPE_CHECKING:  # pragma: no cover
    from presliding.friction.pi_friction import PIFriction

__all__ = ["density_of", "elements"]

FloatArray = NDArray[np.float64]


def elements(model: PIFriction) -> tuple[FloatArray, FloatArray, FloatArray]:
    """(stiffness, threshold, breakaway) of a finite-element model (eq. 8).

    Raises
    ------
    TypeError
        For a model with a continuous density.
    """
    k, r, c = model.stiffness, model.threshold, model.breakaway
    if k is None or r is None or c is None:
        raise TypeError(f"a model with a continuous density has no elements; got {model!r}.")
    return k, r, c


def density_of(model: PIFriction) -> Density:
    """The continuous density μ of a model without elements (eq. 10).

    Raises
    ------
    TypeError
        For a finite-element model.
    """
    if model.is_discrete or not isinstance(model.density, Density):
        raise TypeError(f"a finite-element model has no continuous density; got {model!r}.")
    return model.density
