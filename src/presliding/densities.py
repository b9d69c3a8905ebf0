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
kernels of `_general_pi`, in closed form except for `Tabulated`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import integrate

from . import _general_pi as gk
from ._validation import (
    as_parameter_vector,
    as_positive_scalar,
    as_real_vector,
    fmt,
)

__all__ = ["Density", "Discrete", "Exponential", "PiecewiseConstant", "Tabulated", "Uniform"]

FloatArray = NDArray[np.float64]


class Density:
    """Base of the distributions μ on [0, R] (eq. 10).

    Subclasses are frozen dataclasses; they fill ``_kind``, ``_par`` and
    ``_tab`` (the compiled specification documented in `_general_pi`).
    """

    _kind: ClassVar[int]
    _par: FloatArray
    _tab: FloatArray

    # ------------------------------------------------------------ primitives
    def _eval(self, r: ArrayLike, which: int) -> Any:
        scalar = np.ndim(r) == 0
        rv = np.ascontiguousarray(np.atleast_1d(np.asarray(r, dtype=np.float64)))
        if rv.ndim != 1 or np.isnan(rv).any():
            raise ValueError(f"`r` must be a scalar or 1-D array without NaN; got {fmt(r)}.")
        out = np.empty(rv.shape[0])
        gk.evaluate(self._kind, self._par, self._tab, rv, which, out)
        return float(out[0]) if scalar else out

    def M1(self, r: ArrayLike) -> Any:
        """M1(r) = ∫_0^r s dμ(s): break-away force of the stops with threshold <= r."""
        return self._eval(r, 1)

    def M2(self, r: ArrayLike) -> Any:
        """M2(r) = ∫_0^r s² dμ(s)."""
        return self._eval(r, 2)

    def tail(self, r: ArrayLike) -> Any:
        """T(r) = μ((r, R]): stiffness of the stops with threshold > r."""
        return self._eval(r, 3)

    def M0(self, r: ArrayLike) -> Any:
        """M0(r) = μ([0, r]): stiffness of the stops with threshold <= r.

        Computed as μ([0, R]) − T(r), exact to a rounding unit of μ([0, R]).
        """
        return self.total_stiffness - self.tail(r)

    # ------------------------------------------------------------ summaries
    @property
    def _big_r(self) -> float:
        """R, the end of the support (inf for an untruncated exponential)."""
        return float(self._par[0])

    @property
    def total_stiffness(self) -> float:
        """μ([0, R]): the stiffness right after every reversal (eq. 7)."""
        return float(self.tail(0.0))

    @property
    def max_elastic_force(self) -> float:
        """F_m = ∫_0^R r dμ(r), the largest elastic force (section 3)."""
        return float(self.M1(self._big_r))

    @property
    def min_threshold(self) -> float:
        """inf{r : μ((0, r]) > 0}: below it no stop ever slides."""
        return 0.0

    def virgin_curve(self, displacement: ArrayLike) -> Any:
        """Elastic initial loading curve sign(y)·(M1(|y|) + |y|·T(|y|)) from the relaxed state."""
        y = np.asarray(displacement, dtype=np.float64)
        a = np.abs(y)
        out = np.sign(y) * (self.M1(a) + np.where(a < self._big_r, a, 0.0) * self.tail(a))
        return float(out) if np.ndim(out) == 0 else out

    def discretize(self, n: int, max_threshold: float | None = None) -> Discrete:
        """Midpoint discretisation: n equal cells on [0, R], k_j = μ(cell j) at its midpoint.

        Cells without mass are dropped. The exact operator differs from the
        discretised one by O(1/n²) (measured in the tests). An unbounded
        support needs `max_threshold` (the mass beyond it is dropped).
        """
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
            raise ValueError(f"`n` must be a positive integer; got {fmt(n)}.")
        big_r = self._big_r if max_threshold is None else max_threshold
        big_r = as_positive_scalar("max_threshold", big_r)
        edges = np.linspace(0.0, big_r, int(n) + 1)
        t = self.tail(edges)
        k = t[:-1] - t[1:]
        mid = 0.5 * (edges[:-1] + edges[1:])
        keep = k > 0
        return Discrete(k[keep], mid[keep])

    @staticmethod
    def from_function(
        function: Callable[[float], float], max_threshold: float, *, rtol: float = 1e-10
    ) -> Tabulated:
        """A density dμ/dr = function(r) on [0, R], tabulated once.

        The moments of every cell of a uniform grid are integrated by adaptive
        quadrature (`scipy.integrate.quad`); between the nodes M1, M2 and T are
        cubic Hermite interpolants with the exact derivatives r^k·f(r). The grid
        is refined (64 to 16384 cells) until the interpolant at every cell
        midpoint agrees with the quadrature to `rtol` times the totals; the
        error reached is kept in ``interpolation_error``. Use a smooth (or
        piecewise smooth) integrable, nonnegative, finite function.
        """
        return Tabulated.build(function, max_threshold, rtol)

    # ------------------------------------------------------------ helpers
    def _freeze(self, kind_par: FloatArray, tab: FloatArray) -> None:
        for arr in (kind_par, tab):
            arr.setflags(write=False)
        object.__setattr__(self, "_par", np.ascontiguousarray(kind_par))
        object.__setattr__(self, "_tab", np.ascontiguousarray(tab))

    def _same(self, other: object, *names: str) -> bool:
        if type(other) is not type(self):
            return False
        return all(np.array_equal(getattr(self, n), getattr(other, n)) for n in names)


_NO_TABLE = np.zeros((1, 1))


def _positive_or_inf(name: str, value: Any) -> float:
    if isinstance(value, (int, float, np.floating)) and value == math.inf:
        return math.inf
    return as_positive_scalar(name, value)


@dataclass(frozen=True, eq=False)
class Discrete(Density):
    """μ = Σ_j k_j·δ(r − r_j): the finite-element model of eq. 8 as a density.

    Parameters
    ----------
    stiffness : array_like, shape (N,)
        k_j > 0 [N/m].
    threshold : array_like, shape (N,)
        r_j > 0 [m]; the break-away forces are c_j = k_j·r_j (eq. 6).
    """

    stiffness: FloatArray
    threshold: FloatArray
    _kind: ClassVar[int] = gk.DISCRETE

    def __post_init__(self) -> None:
        k = as_parameter_vector("stiffness", self.stiffness, allow_empty=True)
        r = as_parameter_vector("threshold", self.threshold, allow_empty=True)
        if k.shape != r.shape:
            raise ValueError(
                f"`stiffness` and `threshold` must have the same length; "
                f"`stiffness` has {k.shape[0]}, `threshold` has {r.shape[0]}."
            )
        object.__setattr__(self, "stiffness", k)
        object.__setattr__(self, "threshold", r)
        order = np.argsort(r, kind="stable")
        rs, ks = r[order], k[order]
        tab = np.zeros((4, rs.shape[0] + 1))
        tab[0, :-1], tab[0, -1] = rs, np.inf
        tab[1, 1:] = np.cumsum(ks * rs)
        tab[2, 1:] = np.cumsum(ks * rs * rs)
        tab[3, :-1] = np.cumsum(ks[::-1])[::-1]
        big_r = float(rs[-1]) if rs.shape[0] else 0.0
        self._freeze(np.array([big_r]), tab)

    @property
    def max_threshold(self) -> float:
        """R, the largest threshold (end of the support)."""
        return self._big_r

    @property
    def min_threshold(self) -> float:
        return float(self.threshold.min()) if self.threshold.shape[0] else math.inf

    def __eq__(self, other: object) -> bool:
        return self._same(other, "stiffness", "threshold")

    __hash__ = None  # type: ignore[assignment]


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
    max_threshold: float  # type: ignore[misc]
    _kind: ClassVar[int] = gk.UNIFORM

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
    max_threshold: float = math.inf  # type: ignore[misc]
    _kind: ClassVar[int] = gk.EXPONENTIAL

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
    _kind: ClassVar[int] = gk.PIECEWISE

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
        return float(self.breaks[int(np.argmax(self.heights > 0))])

    def __eq__(self, other: object) -> bool:
        return self._same(other, "breaks", "heights")

    __hash__ = None  # type: ignore[assignment]


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
    _kind: ClassVar[int] = gk.TABULATED

    def __post_init__(self) -> None:
        g = as_real_vector("grid", self.grid)
        v = as_parameter_vector("values", self.values, positive=False)
        mom = np.asarray(self.moments, dtype=np.float64)
        n = g.shape[0] - 1
        if n < 1 or v.shape != g.shape or mom.shape != (3, n + 1):
            raise ValueError(
                f"`grid`, `values` and `moments` must have shapes (n+1,), (n+1,), (3, n+1); "
                f"got {g.shape}, {v.shape}, {mom.shape}."
            )
        h = g[-1] / n
        if g[0] != 0 or not np.allclose(g, h * np.arange(n + 1), rtol=1e-12, atol=0):
            raise ValueError("`grid` must be uniform and start at 0.")
        tab = np.vstack([g, v, mom])
        self._freeze(np.array([g[-1], h]), tab)

    @property
    def max_threshold(self) -> float:
        """R, the largest threshold (end of the support)."""
        return self._big_r

    @property
    def min_threshold(self) -> float:
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

        def f(r: float) -> float:
            val = float(function(r))
            if not (math.isfinite(val) and val >= 0):
                raise ValueError(
                    f"`function` must return finite nonnegative values; got {fmt(val)} at r={r!r}."
                )
            return val

        n = 64
        cells = _cell_moments(f, np.linspace(0.0, big_r, n + 1))
        while True:
            fine = _cell_moments(f, np.linspace(0.0, big_r, 2 * n + 1))
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
    grid = np.linspace(0.0, big_r, n + 1)
    values = np.array([f(r) for r in grid])
    mom = np.zeros((3, n + 1))
    mom[0, 1:] = np.cumsum(cells[1])
    mom[1, 1:] = np.cumsum(cells[2])
    mom[2, :-1] = np.cumsum(cells[0][::-1])[::-1]
    return Tabulated(grid, values, mom, float(err))
