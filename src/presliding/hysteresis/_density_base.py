"""The base class `Density` of the distributions μ (eq. 10), and `Discrete`.

`Density` gives every distribution its primitives M1, M2, T and M0, the
summaries (total stiffness μ([0, R]), F_m, the virgin curve) and the midpoint
discretisation into a `Discrete` density, the Heaviside sum of section 3 that
turns eq. 10 into eq. 8. The public home of all densities is `densities`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, fields, is_dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_count,
    as_parameter_vector,
    as_positive_scalar,
    as_real_array,
    check_finite_derived,
    check_same_length,
    check_size,
    fmt,
    renamed,
)
from presliding.hysteresis._density_primitives import DISCRETE, discrete_lookup, evaluate

FloatArray = NDArray[np.float64]


class Density:
    """Base of the distributions μ on [0, R] (eq. 10).

    Subclasses are frozen dataclasses; they fill ``_kind``, ``_par`` and
    ``_tab`` (the compiled specification documented in `_density_primitives`).
    """

    _kind: ClassVar[int]
    _par: FloatArray
    _tab: FloatArray
    #: The subclasses by name, filled as each is defined, so that the base can
    #: build a `Tabulated` (`from_function`) without importing its module.
    _registry: ClassVar[dict[str, type[Density]]] = {}

    if TYPE_CHECKING:  # every density has R: a field or a property of the subclass

        @property
        def max_threshold(self) -> float:
            """R, the end of the support (inf for an unbounded one)."""

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        Density._registry[cls.__name__] = cls

    # ------------------------------------------------------------ primitives
    def _eval(self, r: ArrayLike, which: int, name: str = "r") -> Any:
        rv = as_real_array(name, r, finite=False)  # r = inf: the moments over all thresholds
        scalar = rv.ndim == 0
        rv = np.ascontiguousarray(np.atleast_1d(rv))
        if rv.ndim != 1:
            raise ValueError(f"`{name}` must be a scalar or one-dimensional; got shape {rv.shape}.")
        if (rv < 0).any():
            i = int(np.argmax(rv < 0))
            raise ValueError(f"`{name}` must be nonnegative; got {fmt(rv[i])} at index {i}.")
        if self._kind == DISCRETE:  # a table lookup: nothing to compile
            out = discrete_lookup(self._tab, rv, which)
        else:
            out = np.empty(rv.shape[0])
            evaluate(self._kind, self._par, self._tab, rv, which, out)
        return float(out[0]) if scalar else out

    def M1(self, r: ArrayLike) -> Any:
        """M1(r) = ∫_0^r s dμ(s): break-away force of the stops with threshold <= r.

        A public primitive of μ (the first moment): the first integral of eq. 14
        is M1(y/2), and F_m = M1(R) is the largest elastic force (the continuous
        form of Σc_j, eq. 9 with c1 = 0). Exact for every density kind.

        Parameters
        ----------
        r : float or array_like, shape (n,)
            Thresholds r >= 0 [m] (no NaN; values beyond R give M1(R)).

        Returns
        -------
        float or ndarray
            M1(r) [N], nondecreasing in r; a float for a scalar `r`.
        """
        return self._eval(r, 1)

    def M2(self, r: ArrayLike) -> Any:
        """M2(r) = ∫_0^r s² dμ(s).

        A public primitive of μ (the second moment): the energy ½∫ f² dμ
        stored by sliding stops (f = ±r, the energy after eq. 12) is ½·M2.

        Parameters
        ----------
        r : float or array_like, shape (n,)
            Thresholds r >= 0 [m] (no NaN; values beyond R give M2(R)).

        Returns
        -------
        float or ndarray
            M2(r) [N·m], nondecreasing in r; a float for a scalar `r`.
        """
        return self._eval(r, 2)

    def tail(self, r: ArrayLike) -> Any:
        """T(r) = μ((r, R]): stiffness of the stops with threshold > r.

        A public primitive of μ: the second integral of eq. 14 is
        y·T(y/2) − (F_m − M1(y/2)), and T(0) = μ([0, R]) is the stiffness right
        after a reversal (eq. 7). Exact for every density kind.

        Parameters
        ----------
        r : float or array_like, shape (n,)
            Thresholds r >= 0 [m] (no NaN; 0 at and beyond R).

        Returns
        -------
        float or ndarray
            T(r) [N/m], nonincreasing in r; a float for a scalar `r`.
        """
        return self._eval(r, 3)

    def M0(self, r: ArrayLike) -> Any:
        """M0(r) = μ([0, r]): stiffness of the stops with threshold <= r.

        A public primitive of μ (the zeroth moment): the stiffness lost by the
        stops that slide, so that the slope of a branch whose front is ρ is
        μ([0, R]) − M0(ρ) (eq. 7 right after a reversal, where ρ = 0).
        Computed as μ([0, R]) − T(r), exact to a rounding unit of μ([0, R]).

        Parameters
        ----------
        r : float or array_like, shape (n,)
            Thresholds r >= 0 [m] (no NaN).

        Returns
        -------
        float or ndarray
            M0(r) [N/m], nondecreasing in r; a float for a scalar `r`.
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
        y = as_real_array("displacement", displacement)
        if y.ndim > 1 or y.size == 0:
            rule = "a scalar or a nonempty one-dimensional array"
            raise ValueError(f"`displacement` must be {rule}; got shape {y.shape}.")
        a = np.abs(y)
        t = np.where(a > 0, self.tail(a), 0.0)  # 0·T(0) = 0 also where T(0) = inf
        out = np.sign(y) * (self.M1(a) + np.where(a < self._big_r, a, 0.0) * t)
        return float(out) if np.ndim(out) == 0 else out

    def discretize(self, n: int, max_threshold: float | None = None) -> Discrete:
        """Midpoint discretisation: n equal cells on [0, R], k_j = μ(cell j) at its midpoint.

        Cells without mass are dropped. The exact operator differs from the
        discretised one by O(1/n²) (measured in the tests). An unbounded
        support needs `max_threshold` (the mass beyond it is dropped).

        Parameters
        ----------
        n : int
            Number of cells (>= 1).
        max_threshold : float, optional
            End of the discretised range [m] (> 0); default R.

        Returns
        -------
        Discrete
            k_j = μ(cell j) [N/m] at the cell midpoints r_j: the Heaviside sum
            that turns eq. 10 into eq. 8.
        """
        n = as_count("n", n, minimum=1)
        check_size("n", n, n + 1, what="cells", item_bytes=5 * 8)  # edges, T, k, midpoints, mask
        big_r = self._big_r if max_threshold is None else max_threshold
        big_r = as_positive_scalar("max_threshold", big_r)
        edges = np.linspace(0.0, big_r, int(n) + 1)
        t = self.tail(edges)
        k = t[:-1] - t[1:]
        mid = 0.5 * edges[:-1] + 0.5 * edges[1:]  # no overflow of the sum near the float range
        keep = k > 0
        with renamed(stiffness="n", threshold="max_threshold"):  # the cells they set
            return Discrete(k[keep], mid[keep])

    @staticmethod
    def from_function(
        function: Callable[[float], float], max_threshold: float, *, rtol: float = 1e-10
    ) -> Density:
        """A density dμ/dr = function(r) on [0, R], tabulated once.

        The moments of every cell of a uniform grid are integrated by adaptive
        quadrature (`scipy.integrate.quad`); between the nodes M1, M2 and T are
        cubic Hermite interpolants with the exact derivatives r^k·f(r). The grid
        is refined (64 to 16384 cells) until the interpolant at every cell
        midpoint agrees with the quadrature to `rtol` times the totals; the
        error reached is kept in ``interpolation_error``. Use a smooth (or
        piecewise smooth) integrable, nonnegative, finite function.

        Parameters
        ----------
        function : callable
            f(r) >= 0 [N/m²], the density dμ/dr, called with a float.
        max_threshold : float
            R > 0 [m], the end of the support, within about [7.3e-304, 1.3e154]
            (the grid and the squares r² of the moments stay normal numbers).
        rtol : float
            Relative accuracy asked of the interpolant (> 0).

        Returns
        -------
        Tabulated
        """
        tabulated: Any = Density._registry["Tabulated"]
        return tabulated.build(function, max_threshold, rtol)

    # ------------------------------------------------------------ helpers
    def _freeze(self, kind_par: FloatArray, tab: FloatArray) -> None:
        for arr in (kind_par, tab):
            arr.setflags(write=False)
        object.__setattr__(self, "_par", np.ascontiguousarray(kind_par))
        object.__setattr__(self, "_tab", np.ascontiguousarray(tab))
        self._check_totals()

    def _check_totals(self) -> None:
        """μ([0, R]), F_m = M1(R) and M2(R) are finite (no overflow of the parameters).

        They bound everything the operator computes: the slope, the force
        (|F| <= F_m) and the stored energy (<= ½·M2(R), as |f(r)| <= r).
        """
        names = tuple(f.name for f in fields(self)) if is_dataclass(self) else ("density",)
        with np.errstate(over="ignore", invalid="ignore"):
            totals = (
                ("total stiffness μ([0, R]) (eq. 7)", self.tail(0.0)),
                ("largest elastic force F_m = ∫ r dμ", self.M1(self._big_r)),
                ("largest stored energy ½ ∫ r² dμ", 0.5 * self.M2(self._big_r)),
            )
        for what, value in totals:
            check_finite_derived(what, value, names)

    def _same(self, other: object, *names: str) -> bool:
        if type(other) is not type(self):
            return False
        return all(np.array_equal(getattr(self, n), getattr(other, n)) for n in names)


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
    _kind: ClassVar[int] = DISCRETE

    def __post_init__(self) -> None:
        k = as_parameter_vector("stiffness", self.stiffness, allow_empty=True)
        r = as_parameter_vector("threshold", self.threshold, allow_empty=True)
        check_same_length(stiffness=k, threshold=r)
        object.__setattr__(self, "stiffness", k)
        object.__setattr__(self, "threshold", r)
        order = np.argsort(r, kind="stable")
        rs, ks = r[order], k[order]
        tab = np.zeros((4, rs.shape[0] + 1))
        tab[0, :-1], tab[0, -1] = rs, np.inf
        with np.errstate(over="ignore", invalid="ignore"):  # overflow reported by _freeze
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
        """The smallest threshold min r_j; inf without elements (no stop ever slides)."""
        return float(np.min(self.threshold)) if self.threshold.shape[0] else math.inf

    def __eq__(self, other: object) -> bool:
        return self._same(other, "stiffness", "threshold")

    __hash__ = None  # type: ignore[assignment]
