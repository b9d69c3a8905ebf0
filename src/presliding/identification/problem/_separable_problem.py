"""The separable fits' problem: target ≈ X·θ + Σ_j k_j g(r_j), as a `FitProblem`.

`fit_presliding`, `fit_motion` and `fit_virgin_curve` fit models linear in all
but the PI thresholds (`_pi_regression`: the stop basis of a path or the
virgin-curve basis). `Separable` holds such a model on its data: the target,
the fixed regressors X (with their names), the basis g and the samples used,
with the residual and its exact Jacobian (∂g/∂r is ±1 or 0 for both bases).
`separable_problem` gives the start the paper suggests: bounded linear least
squares (NNLS for the stiffnesses) on a dense geometric grid of thresholds,
the grid elements carrying weight merged into the wanted number of elements
(or the caller's thresholds), and the natural and the user's bounds.
`solve_separable` solves one such problem (`FitProblem.solve`) and gives the
fitted target on every sample.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import as_bounds
from presliding.identification.problem._fit_problem import FitOptions, FitProblem
from presliding.identification.problem._pi_regression import Basis, element_names, merge_grid
from presliding.identification.solve._least_squares import Solution, Tie

FloatArray = NDArray[np.float64]

__all__ = ["Separable", "SeparableFit", "fit_separable", "separable_problem", "solve_separable"]


@dataclass(frozen=True)
class SeparableFit:
    """Solution of a separable fit, with the fitted target on every sample."""

    solution: Solution
    fitted: FloatArray
    x_names: tuple[str, ...]
    n_elements: int


@dataclass(frozen=True, eq=False)
class Separable:
    """target ≈ design·θ + basis(r)·k on the `used` samples (module notes)."""

    target: FloatArray
    design: FloatArray
    x_names: tuple[str, ...]
    basis: Basis
    n_elements: int
    used: NDArray[np.bool_]

    def unpack(self, q: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(θ, k, r) of the vector of every parameter."""
        p, n = len(self.x_names), self.n_elements
        return q[:p], q[p : p + n], q[p + n :]

    def residual(self, q: FloatArray) -> FloatArray:
        th, k, r = self.unpack(q)
        return self.design[self.used] @ th + self.basis(r)[0][self.used] @ k - self.target[
            self.used]  # fmt: skip

    def jacobian(self, q: FloatArray) -> FloatArray:
        _, k, r = self.unpack(q)
        g, dg = self.basis(r)
        return np.hstack([self.design[self.used], g[self.used], dg[self.used] * k])

    def fitted(self, values: Mapping[str, float]) -> FloatArray:
        """The fitted target on every sample (used or not)."""
        th, k, r = self.unpack(np.array(list(values.values())))
        return self.design @ th + (self.basis(r)[0] @ k if self.n_elements else 0.0)

    def linear_stage(self, r: FloatArray, x_bounds: Mapping[str, tuple[float, float]],
                     fixed: Mapping[str, float]) -> FloatArray:  # fmt: skip
        """Bounded linear least squares at thresholds r (fixed linear parameters honoured)."""
        from scipy.optimize import lsq_linear

        x_names, p, used = self.x_names, len(self.x_names), self.used
        lo_x = np.array([x_bounds.get(n, (-np.inf, np.inf))[0] for n in x_names])
        hi_x = np.array([x_bounds.get(n, (-np.inf, np.inf))[1] for n in x_names])
        a = np.hstack([self.design[used], self.basis(r)[0][used]])
        lo = np.concatenate([lo_x, np.zeros(r.shape[0])])
        hi = np.concatenate([hi_x, np.full(r.shape[0], np.inf)])
        held = np.array([x_names[i] in fixed for i in range(p)] + [False] * r.shape[0])
        out = np.zeros(a.shape[1])
        out[held] = [fixed[x_names[i]] for i in np.flatnonzero(held)]
        free = ~held
        scale = np.linalg.norm(a[:, free], axis=0)
        scale[scale == 0] = 1.0
        rhs = self.target[used] - a[:, held] @ out[held]
        bnd = (lo[free] * scale, hi[free] * scale)
        out[free] = lsq_linear(a[:, free] / scale, rhs, bounds=bnd, method="bvls").x / scale
        return out


def _linear_start(sep: Separable, x_bounds: Mapping, grid: FloatArray, thresholds: Any,
                  fixed: Mapping, progress: Any) -> dict[str, float]:  # fmt: skip
    """Start values: the grid stage merged into the elements, or the given thresholds."""
    p = len(sep.x_names)
    if sep.n_elements == 0:
        r0: FloatArray = np.empty(0)
    elif thresholds is not None:
        r0 = np.asarray(thresholds, dtype=float)
    else:
        if progress is not None:
            progress.stage(f"linear start on a grid of {grid.shape[0]} thresholds")
        coarse = sep.linear_stage(grid, x_bounds, fixed)
        r0, _ = merge_grid(grid, coarse[p:], sep.n_elements)
    theta = sep.linear_stage(r0, x_bounds, fixed)
    k_names, r_names = element_names(sep.n_elements)
    initial = dict(zip(sep.x_names, theta[:p], strict=True))
    initial.update(zip(k_names, theta[p:], strict=True))
    initial.update(zip(r_names, r0, strict=True))
    return initial


def separable_problem(
    sep: Separable,
    x_bounds: Mapping[str, tuple[float, float]],
    *,
    grid: FloatArray,
    thresholds: ArrayLike | None = None,
    refine_thresholds: bool = True,
    fixed: Mapping[str, float] | None = None,
    tied: Mapping[str, Tie] | None = None,
    smallest_threshold: float | None = None,
    largest_threshold: float | None = None,
    progress: Any = None,
    user_initial: Mapping[str, float] | None = None,
    user_bounds: Mapping[str, tuple[float, float]] | None = None,
) -> FitProblem:
    """The problem of `sep` with its linear start and bounds (module notes).

    Thresholds are kept >= `smallest_threshold` (default: a quarter of the
    smallest grid threshold): below the resolution of the data an element is
    indistinguishable from the Coulomb element; and <= `largest_threshold` when
    given: beyond it an element never slides along the path (a linear spring, the
    same for any larger threshold), and an optimum there sits on that bound.
    """
    fixed = dict(fixed or {})
    initial = _linear_start(sep, x_bounds, grid, thresholds, fixed, progress)
    k_names, r_names = element_names(sep.n_elements)
    if not refine_thresholds:
        fixed.update({n: initial[n] for n in r_names if n not in fixed})
    bounds = dict(x_bounds)
    bounds.update(dict.fromkeys(k_names, (0.0, np.inf)))
    r_min = float(grid[0]) / 4 if smallest_threshold is None else float(smallest_threshold)
    r_max = np.inf if largest_threshold is None else max(float(largest_threshold), r_min)
    bounds.update(dict.fromkeys(r_names, (r_min, r_max)))
    for key, (lo, hi) in as_bounds("bounds", user_bounds, tuple(initial)).items():
        old = bounds.get(key, (-np.inf, np.inf))  # the caller's, within the natural ones
        bounds[key] = (max(old[0], lo), min(old[1], hi))
    for key in user_initial or {}:
        if key not in initial:
            raise ValueError(f"`initial` must name parameters of the fit; got {key!r}.")
    initial.update(user_initial or {})
    return FitProblem(tuple(initial), initial, bounds, fixed, dict(tied or {}),
                      residual_function=sep.residual, jacobian_function=sep.jacobian)  # fmt: skip


def solve_separable(sep: Separable, problem: FitProblem, options: FitOptions) -> SeparableFit:
    """One solve of a separable problem from its start, with the fitted target."""
    sol = problem.solve(options)
    return SeparableFit(sol, sep.fitted(sol.values), sep.x_names, sep.n_elements)


def fit_separable(target: FloatArray, design: FloatArray, x_names: tuple[str, ...],
                  x_bounds: Mapping[str, tuple[float, float]], basis: Basis, n_elements: int,
                  *, used: NDArray[np.bool_] | None = None, level: float = 0.95,
                  max_evaluations: int | None = None, tolerance: float = 1e-8,
                  progress: Any = None, **start: Any) -> SeparableFit:  # fmt: skip
    """Two-stage fit of target ≈ design·θ + Σ k_j g(r_j) on the `used` samples (`start`:
    the keyword arguments of `separable_problem`)."""
    used = np.ones(target.shape[0], dtype=bool) if used is None else used
    sep = Separable(target, design, x_names, basis, n_elements, used)
    problem = separable_problem(sep, x_bounds, progress=progress, **start)
    return solve_separable(sep, problem, FitOptions(level, max_evaluations, tolerance,
                                                    progress=progress))  # fmt: skip
