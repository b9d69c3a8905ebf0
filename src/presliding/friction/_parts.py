"""The two forms of a `PIFriction`, typed: its finite elements, or its continuous density.

A model holds either elements (``stiffness``, ``threshold``, ``breakaway``) or a
continuous ``density``, so each of those fields may be None. Code that has
branched on `PIFriction.is_discrete` takes the form it needs from here, and a
type checker then knows it is present; a model of the other form raises.
`figures` are a model's key figures in either form (its notebook view).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from presliding.hysteresis.densities import Density

if TYPE_CHECKING:  # pragma: no cover
    from presliding.friction.pi_friction import PIFriction

__all__ = ["density_of", "elements", "figures"]

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


def figures(model: PIFriction) -> list[tuple[str, str, str]]:
    """(name, value, unit) of the levels and stiffness of `model` (eqs. 7, 9), in either form."""
    n = model.n_elements if model.is_discrete else 0
    form = (f"{n} element{'' if n == 1 else 's'}" if model.is_discrete
            else type(model.density).__name__ + " density")  # fmt: skip
    rows = [("form", form, "")]
    if model.is_symmetric:
        rows += [("Coulomb level F_c (eq. 9)", f"{model.coulomb_level:.6g}", "N"),
                 ("largest elastic force F_m", f"{model.max_elastic_force:.6g}", "N")]  # fmt: skip
    else:
        up, down = model.coulomb_levels
        rows.append(("Coulomb levels F_c⁺, F_c⁻ (eq. 9)", f"{up:.6g}, {down:.6g}", "N"))
    rows.append(("stiffness after a reversal Σk (eq. 7)", f"{model.initial_stiffness:.6g}", "N/m"))
    return rows
