"""Checks of a friction model that the layers above need before they use it.

`check_derived`: a bank's derived c_j and r_j (eq. 6) and totals (eqs. 7, 9) are finite;
`check_has_friction`: a model without stop elements needs a positive Coulomb element;
`check_finite_stiffness`: a motion needs a finite stiffness at reversals (eq. 7).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from presliding._validation import _first_bad, check_finite_derived

__all__ = ["check_derived", "check_finite_stiffness", "check_has_friction"]


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


def check_derived(
    k: np.ndarray,
    c: np.ndarray,
    r: np.ndarray,
    *,
    coulomb: Any = 0.0,
    given: str = "breakaway",
) -> None:
    """A bank's derived c and r = c/k (eq. 6) are finite and positive, and its totals over
    the last axis finite: Σ k_j (eq. 7), F_c (eq. 9), ½ Σ k_j r_j². `given`: "breakaway" or
    "threshold", the argument passed besides `stiffness`."""
    for name, arr in (("breakaway c_j = k_j r_j", c), ("threshold r_j = c_j/k_j", r)):
        bad = ~(np.isfinite(arr) & (arr > 0))  # the one not given is derived (eq. 6)
        if bad.any():
            raise ValueError(
                f"`stiffness` and `{given}` must give a finite, positive {name} (eq. 6); "
                f"{_first_bad(arr, bad)}."
            )
    if k.shape[-1] == 0:
        return
    with np.errstate(over="ignore", invalid="ignore"):
        totals = (
            ("initial stiffness Σ k_j (eq. 7)", np.sum(k, axis=-1), ("stiffness",)),
            (
                "Coulomb level F_c = c1 + Σ c_j (eq. 9)",
                np.sum(c, axis=-1) + coulomb,
                ("coulomb", given) if given == "breakaway" else ("coulomb", "stiffness", given),
            ),
            (
                "largest stored energy ½ Σ k_j r_j²",
                0.5 * np.sum(c * r, axis=-1),
                ("stiffness", given),
            ),
        )
    for what, value, names in totals:
        check_finite_derived(what, value, names)
