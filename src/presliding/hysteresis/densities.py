"""Distributions μ of the general Prandtl–Ishlinskii friction model (section 3, eq. 10).

A density is the measure dμ(r) of stiffness over the thresholds r in [0, R] of a
continuum of elasto-plastic stops. Everything the exact operator, the energy
and the stop analysis need is given by its primitives::

    M0(r) = μ([0, r])            stiffness of the stops with threshold <= r
    M1(r) = ∫_0^r s dμ(s)         their break-away force (M1(R) = F_m)
    M2(r) = ∫_0^r s² dμ(s)        (stored energy, eq. after 12)
    T(r)  = μ((r, R])            stiffness still sticking after a motion 2r

Provided: `Discrete` (the Heaviside sum of section 3, which turns eq. 10 into
eq. 8), `Uniform`, `Exponential` (truncated or not), `PiecewiseConstant`, and
`Density.from_function` for a user-given dμ/dr (`Tabulated`). All are frozen
and validated on construction; the primitives are evaluated by the compiled
kernels of `_density_primitives`, in closed form except for `Tabulated`.

This module holds the closed-form densities; the base class and `Discrete`
live in `_density_base`, `Tabulated` in `_tabulated`, and are re-exported here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from presliding._validation import as_parameter_vector, as_positive_scalar, as_real_vector, fmt
from presliding.hysteresis._density_base import Density, Discrete
from presliding.hysteresis._density_primitives import EXPONENTIAL, PIECEWISE, UNIFORM
from presliding.hysteresis._tabulated import Tabulated

__all__ = ["Density", "Discrete", "Exponential", "PiecewiseConstant", "Tabulated", "Uniform"]

FloatArray = NDArray[np.float64]

_NO_TABLE = np.zeros((1, 1))


def _positive_or_inf(name: str, value: Any) -> float:
    if isinstance(value, (int, float, np.floating)) and value == math.inf:
        return math.inf
    return as_positive_scalar(name, value)


@dataclass(frozen=True)
class Uniform(Density):
    """dμ/dr = height on [0, R]: F_m = height·R²/2, μ([0, R]) = height·R.

    Parameters
    ----------
    height : float
        Density of stiffness per unit threshold a > 0 [N/m²].
    max_threshold : float
        R > 0 [m].
    """

    height: float
    max_threshold: float
    _kind: ClassVar[int] = UNIFORM

    def __post_init__(self) -> None:
        a = as_positive_scalar("height", self.height)
        big_r = as_positive_scalar("max_threshold", self.max_threshold)
        object.__setattr__(self, "height", a)
        object.__setattr__(self, "max_threshold", big_r)
        self._freeze(np.array([big_r, a]), _NO_TABLE.copy())


@dataclass(frozen=True)
class Exponential(Density):
    """dμ/dr = height·exp(−r/length) on [0, R] (R = inf: untruncated).

    Untruncated: μ([0, ∞)) = a·b, F_m = a·b², and the virgin curve is
    a·b²·(1 − exp(−|y|/b))·sign(y), a Dahl-like exponential approach to F_m.

    Parameters
    ----------
    height : float
        a > 0 [N/m²], the density at r = 0.
    length : float
        b > 0 [m], the decay length of the thresholds.
    max_threshold : float, optional
        R > 0 [m] or inf (default).
    """

    height: float
    length: float
    max_threshold: float = math.inf
    _kind: ClassVar[int] = EXPONENTIAL

    def __post_init__(self) -> None:
        a = as_positive_scalar("height", self.height)
        b = as_positive_scalar("length", self.length)
        big_r = _positive_or_inf("max_threshold", self.max_threshold)
        for name, val in (("height", a), ("length", b), ("max_threshold", big_r)):
            object.__setattr__(self, name, val)
        self._freeze(np.array([big_r, a, b]), _NO_TABLE.copy())


@dataclass(frozen=True, eq=False)
class PiecewiseConstant(Density):
    """dμ/dr = heights[i] on [breaks[i], breaks[i+1]), zero below breaks[0].

    Parameters
    ----------
    breaks : array_like, shape (m + 1,)
        0 <= b_0 < b_1 < ... < b_m = R [m].
    heights : array_like, shape (m,)
        Nonnegative densities [N/m²], not all zero.
    """

    breaks: FloatArray
    heights: FloatArray
    _kind: ClassVar[int] = PIECEWISE

    def __post_init__(self) -> None:
        b = as_real_vector("breaks", self.breaks)
        h = as_parameter_vector("heights", self.heights, positive=False)
        if b.shape[0] != h.shape[0] + 1:
            raise ValueError(
                f"`breaks` must have one entry more than `heights`; "
                f"got {b.shape[0]} breaks and {h.shape[0]} heights."
            )
        if b[0] < 0 or np.any(np.diff(b) <= 0):
            raise ValueError(f"`breaks` must be nonnegative and strictly increasing; got {fmt(b)}.")
        if not np.any(h > 0):
            raise ValueError(f"`heights` must not all be zero; got {fmt(h)}.")
        object.__setattr__(self, "breaks", b)
        object.__setattr__(self, "heights", h)
        m = h.shape[0]
        tab = np.zeros((5, m + 1))
        tab[0], tab[1, :m] = b, h
        with np.errstate(over="ignore", invalid="ignore"):  # overflow reported by _freeze
            tab[2, 1:] = np.cumsum(h * (b[1:] ** 2 - b[:-1] ** 2) / 2)
            tab[3, 1:] = np.cumsum(h * (b[1:] ** 3 - b[:-1] ** 3) / 3)
            tab[4, :m] = np.cumsum((h * np.diff(b))[::-1])[::-1]
        self._freeze(np.array([b[-1]]), tab)

    @property
    def max_threshold(self) -> float:
        """R, the largest threshold (end of the support)."""
        return self._big_r

    @property
    def min_threshold(self) -> float:
        """The left break of the first cell with a positive height: no mass below it."""
        return float(self.breaks[int(np.argmax(self.heights > 0))])

    def __eq__(self, other: object) -> bool:
        return self._same(other, "breaks", "heights")

    __hash__ = None  # type: ignore[assignment]
