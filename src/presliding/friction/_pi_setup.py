"""Validation and set-up of a `PIFriction` on construction (its elements, density and sides)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._validation import (
    as_nonnegative_scalar,
    as_parameter_vector,
    check_finite_derived,
)
from presliding.friction import _sides
from presliding.friction._model_checks import check_derived, check_has_friction
from presliding.hysteresis.densities import Density, Discrete

__all__ = ["setup"]

FloatArray = NDArray[np.float64]


def setup(model: Any) -> None:
    """Validate a new `PIFriction` and set its derived fields (c_j or r_j, the density, the
    negative sides); raises TypeError/ValueError naming the argument."""
    c1 = as_nonnegative_scalar("coulomb", model.coulomb)
    object.__setattr__(model, "viscous", as_nonnegative_scalar("viscous", model.viscous))
    object.__setattr__(
        model,
        "coulomb_negative",
        _sides.negative_scalar("coulomb_negative", model.coulomb_negative, c1),
    )
    object.__setattr__(model, "viscous_negative", _sides.negative_scalar(
        "viscous_negative", model.viscous_negative, model.viscous))  # fmt: skip
    if model.density is not None and _take_density(model, c1):
        if model.threshold_negative is not None or not model.is_symmetric:
            raise ValueError(
                "asymmetric friction (a `*_negative` argument) needs finite elements; got a "
                f"continuous density {type(model.density).__name__}."
            )
        check_finite_derived(
            "Coulomb level F_c = c1 + F_m (eq. 9)",
            c1 + model.density.max_elastic_force,
            ("coulomb", "density"),
        )
        return
    k = as_parameter_vector("stiffness", model.stiffness, allow_empty=True)
    if (model.breakaway is None) == (model.threshold is None):
        if model.breakaway is None and k.shape[0] == 0:
            c = r = k
        else:
            raise TypeError(
                "`breakaway` or `threshold` must be given, not both; got "
                + ("both." if model.breakaway is not None else "neither.")
            )
    elif model.breakaway is not None:
        c = as_parameter_vector("breakaway", model.breakaway, allow_empty=True)
        _same_length(k, c, "breakaway")
        with np.errstate(over="ignore", under="ignore"):  # reported below
            r = c / k
    else:
        r = as_parameter_vector("threshold", model.threshold, allow_empty=True)
        _same_length(k, r, "threshold")
        with np.errstate(over="ignore", under="ignore"):  # reported below
            c = k * r
    given = "threshold" if model.threshold is not None else "breakaway"
    check_derived(k, c, r, coulomb=c1, given=given)
    check_has_friction(np.array([c1]), k.shape[0])
    for arr in (c, r):
        arr = np.asarray(arr)
        arr.setflags(write=False)
    object.__setattr__(model, "coulomb", c1)
    object.__setattr__(model, "stiffness", k)
    object.__setattr__(model, "breakaway", c)
    object.__setattr__(model, "threshold", r)
    if model.density is None:
        object.__setattr__(model, "density", Discrete(k, r))
    _sides.take_negative_elements(model, k, c, r)


def _take_density(model: Any, c1: float) -> bool:
    """Set up a model given by `density`; True when it is continuous (no elements)."""
    dens = model.density
    if not isinstance(dens, Density):
        raise TypeError(f"`density` must be a Density; got {type(dens).__name__}.")
    if np.size(model.stiffness) or model.breakaway is not None or model.threshold is not None:
        raise TypeError(
            "give either `density` or the elements (`stiffness` with `breakaway` or "
            "`threshold`), not both; got both."
        )
    if isinstance(dens, Discrete):
        object.__setattr__(model, "stiffness", dens.stiffness)
        object.__setattr__(model, "threshold", dens.threshold)
        return False
    object.__setattr__(model, "coulomb", c1)
    for name in ("stiffness", "breakaway", "threshold"):
        object.__setattr__(model, name, None)
    return True


def _same_length(k: FloatArray, other: FloatArray, name: str) -> None:
    if other.shape != k.shape:
        raise ValueError(
            f"`{name}` must have the same length as `stiffness` ({k.shape[0]}); "
            f"got {other.shape[0]}."
        )
