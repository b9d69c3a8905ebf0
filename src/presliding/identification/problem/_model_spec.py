"""The friction models the pooled fits identify, as named parameters (eqs. 8–10).

A `ModelSpec` turns named parameter values into the bank the compiled
simulators run (c1, k_j, r_j) and into the `PIFriction` a fit returns:

* ``n_elements=N, equal_breakaway=True``: ``coulomb_level`` F_c, ``coulomb`` c1,
  ``stiffness_j``; c_j = (F_c − c1)/N (the paper's choice, section 4).
* ``n_elements=N, equal_breakaway=False``: ``coulomb``, ``stiffness_j``, ``breakaway_j``.
* ``density="uniform"``: ``coulomb``, ``height`` a, ``max_threshold`` R.
* ``density="exponential"``: ``coulomb``, ``height`` a, ``length`` b (untruncated).
* ``density="piecewise_constant"``: ``coulomb``, ``max_threshold`` R and
  ``height_1..height_m`` on m equal cells of [0, R].

``asymmetric=True`` (elements only) adds the level of sliding in −y: ``coulomb_level_negative``
F_c⁻ (``coulomb_negative`` c1⁻ without elements), every level of that side the same share
ρ = F_c⁻/F_c⁺ of its positive one (c1⁻ = ρ·c1, c_j⁻ = ρ·c_j, r_j⁻ = ρ·r_j;
`presliding.friction._sides`). Motion data do not determine how a difference of the levels
splits between c1 and the elements: from any memory but the relaxed one, a model whose
elements share their stiffnesses moves exactly as the symmetric model of the mean levels
under the force u − (F_c⁺ − F_c⁻)/2 (the play band shifted by (r_j⁺ − r_j⁻)/2), so one
parameter carries the difference and the shared ratio is the convention that fixes the split.

A density is simulated through its *centroid discretisation* with about `cells`
elements: cells of about equal stiffness μ(cell) = k_j, each element at the centroid
r_j = ∫_cell r dμ / μ(cell) of its cell. Σ k_j = μ([0, R]) (eq. 7) and
Σ k_j r_j = F_m are exact, and the virgin curve differs from the density's by
O(1/cells²) (measured in the tests).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis.densities import Density, Exponential, PiecewiseConstant, Uniform

FloatArray = NDArray[np.float64]
DENSITIES = ("uniform", "exponential", "piecewise_constant")
TINY = np.finfo(float).tiny


def centroid_bank(density: Density, cells: int) -> tuple[FloatArray, FloatArray]:
    """Stiffnesses and thresholds of the centroid discretisation (module notes).

    The cell edges are quantiles of the stiffness μ([0, r]) (an exponential: of
    its mean with the force M1(r), which resolves the tail), and a piecewise
    constant density's breaks are always edges, so that no cell straddles a jump.
    """
    big_r = density.max_threshold
    total, fm = density.total_stiffness, density.max_elastic_force
    top = big_r if math.isfinite(big_r) else 40.0 * density.length  # type: ignore[attr-defined]
    grid = np.linspace(0.0, top, 64 * cells + 1)
    breaks = density.breaks if isinstance(density, PiecewiseConstant) else np.empty(0)
    grid = np.union1d(grid, breaks)
    share = (total - density.tail(grid)) / total
    if isinstance(density, Exponential):
        share = 0.5 * (share + density.M1(grid) / fm)
    share[-1] = 1.0
    edges = np.union1d(np.interp(np.arange(cells + 1) / cells, share, grid), breaks)
    edges[0], edges[-1] = 0.0, big_r
    finite = np.minimum(edges, np.finfo(float).max)
    tail, m1 = density.tail(finite), density.M1(finite)
    tail[-1], m1[-1] = 0.0, fm
    k = -np.diff(tail)
    keep = k > 0
    return k[keep], np.maximum(np.diff(m1)[keep] / k[keep], TINY)


def _spread(k: FloatArray, ratio: float = 1.5) -> FloatArray:
    """Stiffnesses (descending) at least `ratio` apart, around the same geometric mean.

    Equal elements are interchangeable: a start with two nearly equal ones sits
    next to the symmetric saddle where the data cannot tell them apart. A stiffness of 0
    (an element the start does not want) is taken 1e-12 of the largest: its logarithm
    made every start stiffness NaN, and the fit of a 50-sample record with four elements
    ran minutes without ending.
    """
    if k.shape[0] < 2:
        return k
    top = float(np.max(k)) if np.all(np.isfinite(k)) else 0.0
    if not top > 0:
        raise ValueError(f"the start stiffnesses must be finite and one positive; got {k}.")
    logk = np.log(np.maximum(np.sort(k)[::-1], 1e-12 * top))  # a zero one: far below the rest
    gaps = np.maximum(-np.diff(logk), np.log(ratio))
    spread = np.concatenate([[0.0], -np.cumsum(gaps)])
    return np.exp(spread - spread.mean() + logk.mean())


class ModelSpec:
    """Named parameters of a friction model and their bank (module notes)."""

    def __init__(self, n_elements: int, equal_breakaway: bool, density: str | None, cells: int,
                 asymmetric: bool = False):  # fmt: skip
        self.n, self.equal, self.density, self.cells = n_elements, equal_breakaway, density, cells
        self.asymmetric = asymmetric
        self.k_names: list[str] = []
        self.c_names: list[str] = []
        self.h_names: list[str] = []
        if density is None:
            self.k_names = [f"stiffness_{j + 1}" for j in range(n_elements)]
            self.c_names = (
                [] if equal_breakaway else [f"breakaway_{j + 1}" for j in range(n_elements)]
            )
            head = ["coulomb_level", "coulomb"] if equal_breakaway else ["coulomb"]
            self.names = head + self.k_names + self.c_names
        elif density == "uniform":
            self.names = ["coulomb", "height", "max_threshold"]
        elif density == "exponential":
            self.names = ["coulomb", "height", "length"]
        else:
            self.h_names = [f"height_{j + 1}" for j in range(n_elements)]
            self.names = ["coulomb", "max_threshold", *self.h_names]
        #: the parameter of the negative side's level (`asymmetric`), or None
        self.negative: str | None = None
        if asymmetric:
            if density is not None:
                raise ValueError(
                    f"`asymmetric` friction needs elements; got density={density!r} (a density "
                    "has one side)."
                )
            self.negative = "coulomb_level_negative" if n_elements else "coulomb_negative"
            self.names.append(self.negative)

    @property
    def has_level_parameter(self) -> bool:
        """True when F_c is a parameter (it can then be bounded below directly)."""
        return self.density is None and self.equal

    def positive(self, name: str) -> bool:
        """Whether a parameter must be positive (all but c1 and c1⁻, which may be 0)."""
        return name in self.names and name not in ("coulomb", "coulomb_negative")

    def bounds(self) -> dict[str, tuple[float, float]]:
        return dict.fromkeys(self.names, (0.0, np.inf))

    # ------------------------------------------------------------ values → model
    def friction_density(self, q: Mapping[str, float]) -> Density:
        """The density of a density model (heights and lengths kept positive)."""
        pos = {x: max(q[x], TINY) for x in self.names if x != "coulomb"}
        if self.density == "uniform":
            return Uniform(pos["height"], pos["max_threshold"])
        if self.density == "exponential":
            return Exponential(pos["height"], pos["length"])
        heights = np.array([max(q[x], 0.0) for x in self.h_names])
        if not np.any(heights > 0):
            heights[:] = TINY
        breaks = np.linspace(0.0, pos["max_threshold"], self.n + 1, dtype=np.float64)
        return PiecewiseConstant(breaks, heights)

    def bank(self, q: Mapping[str, float]) -> tuple[float, FloatArray, FloatArray]:
        """c1, k_j, r_j of the model (a density: its centroid discretisation)."""
        c1 = max(q["coulomb"], 0.0)
        if self.density is not None:
            k, r = centroid_bank(self.friction_density(q), self.cells)
            return c1, k, r
        k = np.maximum([q[x] for x in self.k_names], TINY)
        c: FloatArray
        if self.equal:
            c = np.full(self.n, max((q["coulomb_level"] - c1) / max(self.n, 1), TINY))
        else:
            c = np.maximum([q[x] for x in self.c_names], TINY)
        with np.errstate(over="ignore"):  # an element of zero stiffness never slides
            r = np.minimum(c / k, 1e300)
        return c1, k, r

    def ratio(self, q: Mapping[str, float]) -> float:
        """ρ = F_c⁻/F_c⁺, the share of every positive level the negative side has (1: one
        side; module notes)."""
        if self.negative is None:
            return 1.0
        if self.n == 0:
            c1 = max(q["coulomb"], 0.0)
            return max(q[self.negative], 0.0) / c1 if c1 > 0 else 1.0
        return max(q[self.negative], TINY) / max(self.coulomb_level(q), TINY)

    def sided(self, q: Mapping[str, float], ratio: float) -> dict[str, float]:
        """The values of an asymmetric model whose mean levels are those of `q` and whose
        negative side is `ratio` times its positive one: c1 and every c_j (F_c) scaled by
        2/(1 + ρ), F_c⁻ = ρ·F_c⁺ (ρ = 1: `q` itself, the symmetric model exactly)."""
        out = dict(q)
        scale = 2.0 / (1.0 + ratio)
        for x in ("coulomb", *self.c_names):
            out[x] = out[x] * scale
        if self.n and self.equal:
            out["coulomb_level"] = out["coulomb_level"] * scale
        out[str(self.negative)] = ratio * (self.coulomb_level(out) if self.n else out["coulomb"])
        return out

    def coulomb_level(self, q: Mapping[str, float]) -> float:
        """F_c = c1 + F_m (eq. 9); F_c⁺ of an asymmetric model."""
        if self.density is None and self.equal:
            return float(q["coulomb_level"])
        c1, k, r = self.bank(q)
        if self.density is not None:
            return c1 + self.friction_density(q).max_elastic_force
        return c1 + float(k @ r)

    def model(self, q: Mapping[str, float]) -> PIFriction:
        """The identified PIFriction (a density model keeps its density; σ from ``viscous``,
        σ⁻ from ``viscous_negative``; the negative side's levels ρ times the positive ones)."""
        sigma = max(q.get("viscous", 0.0), 0.0)
        if self.density is not None:
            dens = self.friction_density(q)
            return PIFriction(max(q["coulomb"], 0.0), density=dens, viscous=sigma)
        c1, k, r = self.bank(q)
        if self.negative is None:
            if self.n == 0:
                return PIFriction(c1, viscous=sigma)
            return PIFriction(c1, k, breakaway=k * r, viscous=sigma)
        rho = self.ratio(q)
        c1n = max(q[self.negative], 0.0) if self.n == 0 else rho * c1
        sigma_n = max(q.get("viscous_negative", sigma), 0.0)
        if self.n == 0:
            return PIFriction(c1, viscous=sigma, coulomb_negative=c1n, viscous_negative=sigma_n)
        return PIFriction(c1, k, breakaway=k * r, viscous=sigma, coulomb_negative=c1n,
                          breakaway_negative=rho * (k * r), viscous_negative=sigma_n)  # fmt: skip

    # ------------------------------------------------------------ start values
    def start(
        self, fc: float, c1: float, grid: FloatArray, weights: FloatArray
    ) -> dict[str, float]:
        """Start values whose elastic virgin curve is closest to G(s) = Σ_g w_g·min(s, r_g)."""
        from presliding.identification.problem import _pi_regression as pr
        from presliding.identification.records._response_tools import equal_breakaway_stiffness

        if self.density is None and self.n == 0 and not self.equal:
            return self._sided({"coulomb": float(fc)})  # Coulomb friction alone: c1 = F_c
        fm = max(fc - c1, TINY)
        out = {"coulomb": float(c1)}
        if self.density is None:
            if self.equal:
                out["coulomb_level"] = float(fc)
                k = _spread(equal_breakaway_stiffness(grid, weights, fm / max(self.n, 1), self.n))
            else:
                r, k = pr.merge_grid(grid, np.where(weights > 0, weights, 0.0), self.n)
                out.update({x: float(v) for x, v in zip(self.c_names, k * r, strict=True)})
            out.update({x: float(v) for x, v in zip(self.k_names, k, strict=True)})
            return self._sided(out)
        return {**out, **self._density_start(fm, grid, weights)}

    def _sided(self, start: dict[str, float]) -> dict[str, float]:
        """A start with its negative level equal to the positive one (one side)."""
        if self.negative is not None:
            start[self.negative] = self.coulomb_level(start) if self.n else start["coulomb"]
        return start

    def _density_start(self, fm: float, grid: FloatArray, weights: FloatArray) -> dict[str, float]:
        from scipy.optimize import least_squares

        s = np.geomspace(grid[0] / 4, grid[-1] * 2, 120)
        target = np.minimum(s[:, None], grid[None, :]) @ np.maximum(weights, 0.0)
        if not np.ptp(target) > 0:
            target = fm * np.minimum(s / grid[-1], 1.0)
        span = float(np.interp(0.9 * target[-1], target, s))  # travel to 90 % of F_m
        names = [x for x in self.names if x != "coulomb"]
        if self.density == "uniform":  # virgin curve saturates at R with F_m = a R²/2
            guess = {"height": 2 * fm / span**2, "max_threshold": span}
        elif self.density == "exponential":  # 1 − e^(−y/b) at 90 %: y = 2.3 b
            guess = {"height": fm / (span / 2.3) ** 2, "length": span / 2.3}
        else:
            h = 2 * fm / span**2
            guess = {"max_threshold": span, **dict.fromkeys(self.h_names, h)}

        def curve(logp: FloatArray) -> FloatArray:
            q = {"coulomb": 0.0, **dict(zip(names, np.exp(np.clip(logp, -700, 700)), strict=True))}
            return self.friction_density(q).virgin_curve(s) - target

        x0 = np.log([guess[x] for x in names])
        fit = least_squares(curve, x0, method="trf", xtol=1e-10, max_nfev=200 * len(x0))
        return dict(zip(names, np.exp(np.clip(fit.x, -700, 700)).tolist(), strict=True))
