"""`Tabulated`: a user-given density dμ/dr = f(r), behind `Density.from_function`.

The moments of every cell of a uniform grid are integrated by adaptive
quadrature; between the nodes M1, M2 and T are cubic Hermite interpolants
(evaluated by the compiled kernel of kind ``TABULATED``). The public home of
`Tabulated` is `densities`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray
from scipy import integrate

from presliding._validation import (
    as_nonnegative_scalar,
    as_parameter_vector,
    as_positive_scalar,
    as_real_array,
    as_real_vector,
    fmt,
)
from presliding.hysteresis._density_base import Density
from presliding.hysteresis._density_primitives import TABULATED

FloatArray = NDArray[np.float64]
#: R such that the finest grid (32768 cells) and the squares r² of the moments stay normal.
_R_RANGE = (32768 * np.finfo(np.float64).tiny, math.sqrt(np.finfo(np.float64).max))


@dataclass(frozen=True, eq=False)
class Tabulated(Density):
    """A user density dμ/dr = f(r) tabulated on a uniform grid (see `Density.from_function`).

    Parameters
    ----------
    grid : ndarray, shape (n + 1,)
        Nodes r_i = i·R/n.
    values : ndarray, shape (n + 1,)
        f(r_i) >= 0.
    moments : ndarray, shape (3, n + 1)
        M1, M2 and T at the nodes.
    interpolation_error : float
        Largest relative error of the interpolant found at the cell midpoints.
    """

    grid: FloatArray
    values: FloatArray
    moments: FloatArray
    interpolation_error: float = field(default=0.0)
    _kind: ClassVar[int] = TABULATED

    def __post_init__(self) -> None:
        g = as_real_vector("grid", self.grid)
        v = as_parameter_vector("values", self.values, positive=False)
        mom = as_real_array("moments", self.moments)
        n = g.shape[0] - 1
        if n < 1 or v.shape != g.shape or mom.shape != (3, n + 1):
            raise ValueError(
                f"`grid`, `values` and `moments` must have shapes (n+1,), (n+1,), (3, n+1); "
                f"got {g.shape}, {v.shape}, {mom.shape}."
            )
        h = g[-1] / n
        if g[0] != 0 or not np.allclose(g, h * np.arange(n + 1), rtol=1e-12, atol=0):
            raise ValueError(f"`grid` must be uniform and start at 0; got {fmt(g)}.")
        as_nonnegative_scalar("interpolation_error", self.interpolation_error)
        tab = np.vstack([g, v, mom])
        self._freeze(np.array([g[-1], h]), tab)

    @property
    def max_threshold(self) -> float:
        """R, the largest threshold (end of the support)."""
        return self._big_r

    @property
    def min_threshold(self) -> float:
        """The grid node below the first node with f > 0 (0 if that is r_0 or r_1).

        The interpolant may carry mass anywhere in the cell ending at that
        node, so this is the largest node below which μ has no mass for sure.
        """
        return float(self.grid[max(int(np.argmax(self.values > 0)) - 1, 0)])

    def __eq__(self, other: object) -> bool:
        return self._same(other, "grid", "values", "moments")

    __hash__ = None  # type: ignore[assignment]

    @classmethod
    def build(cls, function: Callable[[float], float], max_threshold: float, rtol: float) -> Any:
        """Tabulate `function` with adaptive quadrature and grid refinement (see from_function)."""
        if not callable(function):
            raise TypeError(f"`function` must be callable; got {fmt(function)}.")
        big_r = as_positive_scalar("max_threshold", max_threshold)
        rtol = as_positive_scalar("rtol", rtol)
        if not _R_RANGE[0] <= big_r <= _R_RANGE[1]:
            raise ValueError(
                f"`max_threshold` must lie in [{_R_RANGE[0]:.3g}, {_R_RANGE[1]:.3g}] (the grid and "
                f"the moments' r² stay normal floating-point numbers); got {fmt(big_r)}."
            )

        def f(r: float) -> float:
            try:
                val = float(function(r))
            except (ArithmeticError, TypeError, ValueError) as exc:
                raise ValueError(
                    f"`function` must return a real number on [0, max_threshold]; got "
                    f"{type(exc).__name__} ({exc}) at r={r!r}."
                ) from exc
            if not (math.isfinite(val) and val >= 0):
                raise ValueError(
                    f"`function` must return finite nonnegative values; got {fmt(val)} at r={r!r}."
                )
            return val

        n = 64
        cells = _cell_moments(f, np.linspace(0.0, big_r, n + 1, dtype=np.float64))
        while True:
            fine = _cell_moments(f, np.linspace(0.0, big_r, 2 * n + 1, dtype=np.float64))
            coarse = _tabulate(f, big_r, n, cells)
            exact = _tabulate(f, big_r, 2 * n, fine)
            mids = exact.grid[1::2]
            totals = np.array([exact.max_elastic_force, exact.M2(big_r), exact.total_stiffness])
            if not np.all(totals > 0):
                raise ValueError("`function` must not vanish on the whole of [0, max_threshold].")
            err = max(
                np.max(np.abs(coarse.M1(mids) - exact.moments[0, 1::2])) / totals[0],
                np.max(np.abs(coarse.M2(mids) - exact.moments[1, 1::2])) / totals[1],
                np.max(np.abs(coarse.tail(mids) - exact.moments[2, 1::2])) / totals[2],
            )
            n, cells = 2 * n, fine
            if err <= rtol or n >= 16384:
                break
        # The finer table is kept; its error is at most the coarser one's (O(h^4)).
        return _tabulate(f, big_r, n, cells, err)


def _cell_moments(f: Callable[[float], float], edges: FloatArray) -> FloatArray:
    """∫ r^k f(r) dr over every cell, k = 0, 1, 2 (adaptive Gauss–Kronrod)."""
    out = np.empty((3, edges.shape[0] - 1))
    for i in range(edges.shape[0] - 1):
        a, b = edges[i], edges[i + 1]
        for k in range(3):
            out[k, i] = integrate.quad(
                lambda r, k=k: r**k * f(r), a, b, epsabs=0.0, epsrel=1e-13, limit=200
            )[0]
    return out


def _tabulate(
    f: Callable[[float], float], big_r: float, n: int, cells: FloatArray, err: float = 0.0
) -> Tabulated:
    grid = np.linspace(0.0, big_r, n + 1, dtype=np.float64)
    values = np.array([f(r) for r in grid])
    mom = np.zeros((3, n + 1))
    mom[0, 1:] = np.cumsum(cells[1])
    mom[1, 1:] = np.cumsum(cells[2])
    mom[2, :-1] = np.cumsum(cells[0][::-1])[::-1]
    return Tabulated(grid, values, mom, float(err))
