"""Checks of a friction model that the layers above need before they use it.

`check_has_friction`: a model without stop elements needs a positive Coulomb element;
`check_finite_stiffness`: a motion needs a finite stiffness at reversals (eq. 7).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["check_finite_stiffness", "check_has_friction"]


def check_has_friction(c1: np.ndarray, n_elements: int) -> None:
    """A model without elements needs a positive Coulomb element."""
    if n_elements == 0 and np.any(c1 == 0):
        i = int(np.argmax(c1 == 0))
        where = "" if c1.shape[0] == 1 else f" at index {i}"
        raise ValueError(
            "`coulomb` must be positive when `stiffness` is empty (a model without elements); "
            f"got 0.0{where}."
        )


def check_finite_stiffness(stiffness: float, where: str, density: Any) -> None:
    """A motion needs a finite stiffness μ([0, R]) at reversals (eq. 7)."""
    if not math.isfinite(stiffness):
        raise ValueError(
            f"{where} needs a finite stiffness μ([0, R]) at reversals (eq. 7); got the infinitely "
            f"stiff density {type(density).__name__} (a contact that sticks rigidly, such as the "
            f"microslip bar): use its force, branches and `amplitude_response`, or model it as a "
            f"`SliderNetwork` chain."
        )
