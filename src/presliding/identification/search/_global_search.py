"""A global search for the start thresholds of `fit_presliding` (section 4).

Differential evolution (`scipy.optimize.differential_evolution`) over the
parameters of eq. 8 fitted to a measured loop,

    F(t) ≈ c1·d(t) + o + Σ_j (c_j / r_j)·(y(t) − x_j(t)),

with d the direction of motion, o an optional offset, break-away forces c_j in
[0, ptp F] and log-thresholds log r_j in the range of the threshold grid. Each
generation is one call of the fused batch loss (`presliding.hysteresis._fused.batch_loss`,
both cores): the losses of all candidates are accumulated inside the time loop,
so no (T × candidates) output is formed. The best thresholds found start the
usual least-squares stage, which gives the final values and their errors.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding.identification.problem._pi_regression import batch_stop_loss

FloatArray = NDArray[np.float64]

#: candidates per generation, per searched parameter (scipy's ``popsize``)
POPULATION = 15


def search_thresholds(
    y: FloatArray,
    force: FloatArray,
    direction: FloatArray,
    n_elements: int,
    grid: FloatArray,
    *,
    coulomb: bool,
    offset: bool,
    skip: int,
    seed: int | None,
    max_generations: int,
    progress: Any = None,
) -> tuple[FloatArray, str]:
    """Thresholds (sorted) of the best model found, and a sentence saying how.

    `progress` (a `FitProgress`) is told each generation (it does not change the search).
    """
    from scipy.optimize import differential_evolution

    span = float(np.ptp(force))
    bounds = []
    if coulomb:
        bounds.append((0.0, span))
    if offset:
        bounds.append((-float(np.max(np.abs(force))), float(np.max(np.abs(force)))))
    bounds += [(0.0, span)] * n_elements
    bounds += [(float(np.log(grid[0])), float(np.log(grid[-1])))] * n_elements
    n_linear = int(coulomb) + int(offset)

    def objective(p: FloatArray) -> FloatArray:
        p = np.atleast_2d(p.T).T  # (parameters, candidates)
        m = p.shape[1]
        c1 = p[0] if coulomb else np.zeros(m)
        o = p[int(coulomb)] if offset else np.zeros(m)
        c = p[n_linear : n_linear + n_elements].T
        r = np.exp(p[n_linear + n_elements :].T)
        loss = batch_stop_loss(
            y, force, r, c / r, c1, design=direction, offset=o, skip=skip, parallel=True
        )
        lowest[0] = min(lowest[0], float(np.min(loss)))
        return loss

    generations, lowest = [0], [np.inf]

    def callback(xk: FloatArray, convergence: float = 0.0) -> None:
        generations[0] += 1
        if progress is not None:
            progress.generation(generations[0], max_generations, lowest[0])

    res = differential_evolution(
        objective, bounds, popsize=POPULATION, maxiter=max_generations, seed=seed,
        vectorized=True, updating="deferred", polish=False, tol=1e-10,
        callback=callback if progress is not None and progress.active else None,
    )  # fmt: skip
    r = np.sort(np.exp(res.x[n_linear + n_elements :]))
    how = (
        f"start thresholds from a global search (differential evolution: {res.nit} "
        f"generations of {POPULATION * len(bounds)} candidates, fused loss)"
    )
    return r, how
