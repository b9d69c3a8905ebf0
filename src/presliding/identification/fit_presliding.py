"""Presliding operator fits: friction force against displacement (eqs. 4–9, section 4).

`fit_presliding` fits the rate-independent model of eq. 8 along a measured
path,

    F(t) = c1·sign(ẏ) + Σ_j k_j (y − x_j(y, r_j))  [+ offset],

where sign(ẏ) is the direction of the last nonzero displacement increment and
the play operators start relaxed at the first sample (skip samples recorded
with an unknown earlier history with `burn_in`). All parameters but the
thresholds enter linearly: nonnegative least squares for the stiffnesses on a
geometric threshold grid gives the start, nonlinear least squares over all
parameters refines it (see `presliding.identification._pi_regression`).

The virgin-curve fit (Madelung/Masing rules) lives in `fit_virgin`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._progress import Progress
from presliding._validation import (
    as_choice,
    as_count,
    as_parameter_vector,
    as_signal,
    check_same_length,
    fmt,
)
from presliding.friction.pi_friction import PIFriction
from presliding.identification import _pi_regression as pr
from presliding.identification._fit_progress import FitProgress, reporting
from presliding.identification._global_search import search_thresholds
from presliding.identification._least_squares import (
    check_budget,
    check_constraints,
    check_options,
)
from presliding.identification._parameters import resolve_parameters
from presliding.identification._status import sign_hint
from presliding.identification.fit_result import FitResult, Tie

__all__ = ["fit_presliding"]

FloatArray = NDArray[np.float64]


def element_count(n_elements: int | None, thresholds: ArrayLike | None, default: int) -> int:
    """The number of elements from `n_elements` and/or `thresholds` (checked to agree)."""
    if thresholds is not None:
        n_thr = as_parameter_vector("thresholds", thresholds).shape[0]
        if n_elements is not None and n_elements != n_thr:
            raise ValueError(
                f"`n_elements` must equal the number of `thresholds` ({n_thr}); got {n_elements}."
            )
        return n_thr
    if n_elements is None:
        return default
    return as_count("n_elements", n_elements)


def check_varies(name: str, arr: FloatArray) -> None:
    """Reject a constant signal (nothing to fit)."""
    if not np.ptp(arr) > 0:
        raise ValueError(f"`{name}` must vary; got a constant signal ({fmt(float(arr[0]))}).")


def check_fit_options(
    fixed: Mapping[str, float] | None,
    tied: Mapping[str, Tie] | None,
    level: float,
    grid_size: int,
    max_evaluations: int | None,
    tolerance: float,
) -> tuple[dict[str, float], dict[str, Tie], float, int, int | None, float]:
    """The options shared by the separable fits, checked on entry (see `check_options`).

    `grid_size` must be at least 2: a geometric grid needs its two ends, and with
    one point the elements would all start at the same threshold.
    """
    fixed, tied = check_constraints(fixed, tied)
    level, max_evaluations, tolerance = check_options(level, max_evaluations, tolerance)
    grid_size = as_count("grid_size", grid_size, minimum=2)
    return fixed, tied, level, grid_size, max_evaluations, tolerance


def check_enough(n_used: int, n_parameters: int, what: str = "samples") -> None:
    """At least one more sample than parameters."""
    if n_used <= n_parameters:
        raise ValueError(
            f"the fit needs more {what} than parameters ({n_parameters}); got {n_used}."
        )


def pi_model(values: Mapping[str, float], n: int, coulomb: float) -> tuple[PIFriction | None, str]:
    """The friction model from fitted values; elements of zero stiffness are left out."""
    k_names, r_names = pr.element_names(n)
    k = np.array([values[x] for x in k_names])
    r = np.array([values[x] for x in r_names])
    keep = k > 0
    note = ""
    if not keep.all():
        dropped = ", ".join(str(j + 1) for j in np.flatnonzero(~keep))
        note = f"; element(s) {dropped} came out with zero stiffness and are left out of the model"
    try:
        return PIFriction(max(coulomb, 0.0), k[keep], threshold=r[keep]), note
    except ValueError as exc:
        return None, f"; no valid model: {exc}"


def derived_quantities(model: PIFriction | None) -> dict[str, float]:
    """F_c (eq. 9), F_m and Σ k_j (eq. 7) of a model."""
    if model is None:
        return {}
    return {
        "coulomb_level": model.coulomb_level,
        "max_elastic_force": model.max_elastic_force,
        "initial_stiffness": model.initial_stiffness,
    }


def fit_presliding(
    displacement: ArrayLike,
    force: ArrayLike,
    n_elements: int | None = None,
    thresholds: ArrayLike | None = None,
    *,
    coulomb: bool = True,
    offset: bool = False,
    refine_thresholds: bool = True,
    burn_in: int = 0,
    fixed: Mapping[str, float] | None = None,
    tied: Mapping[str, Tie] | None = None,
    initial: Mapping[str, float] | Any = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    level: float = 0.95,
    grid_size: int = pr.DEFAULT_GRID,
    max_evaluations: int | None = None,
    tolerance: float = 1e-8,
    search: str = "grid",
    seed: int | None = None,
    max_generations: int = 300,
    progress: bool | Progress = False,
) -> FitResult:
    """Fit the PI friction model of eq. 8 to force measured along a displacement path.

    Parameters
    ----------
    displacement : array_like, shape (T,)
        Displacement y [m], monotone between samples; the elements start relaxed
        at ``displacement[0]``.
    force : array_like, shape (T,)
        Friction force F [N] (positive when opposing positive motion).
    n_elements : int, optional
        Number N of elasto-plastic elements (default 3, or ``len(thresholds)``).
    thresholds : array_like, shape (N,), optional
        Start values of the thresholds r_j [m] instead of the grid search.
    coulomb : bool
        Include the Coulomb element c1·sign(ẏ) (parameter ``coulomb``, c1 >= 0).
    offset : bool
        Include a constant force offset (parameter ``offset``; the model returned
        does not contain it).
    refine_thresholds : bool
        Optimise the thresholds; False keeps them at the start (a linear fit).
    burn_in : int
        Number of samples (>= 0) at the start left out of the residual (while the unknown earlier
        memory is wiped out; the operators still run through them).
    fixed, tied : mapping, optional
        Parameters held at a value (a finite real), or tied to another: a
        parameter name or a (name, factor) pair (see `solve_least_squares`);
        names: ``coulomb``, ``offset``, ``stiffness_j``, ``threshold_j`` (j from 1).
    initial : mapping or lmfit.Parameters, optional
        Start values by name (others from the linear start); an
        ``lmfit.Parameters`` gives values, bounds, fixed values and linear ties.
    bounds : mapping name -> (lower, upper), optional
        Bounds on any parameter, within its natural ones (stiffness >= 0, ...).
        Contradictory arguments (a fixed or start value outside them) are refused.
    level : float
        Confidence level of the intervals, in (0, 1).
    grid_size : int
        Number of grid thresholds of the linear start (at least 2).
    max_evaluations : int, optional
        Most residual evaluations of the nonlinear stage (an integer >= 1);
        default: scipy's choice. Reaching it gives the status ``"max_evaluations"``.
    tolerance : float
        Relative tolerance on the cost, the step and the gradient of the
        nonlinear stage (positive).
    search : {"grid", "global"}
        How the start thresholds are found when `thresholds` is not given:
        "grid" (default) merges the elements of a nonnegative least-squares fit
        on the threshold grid; "global" also runs differential evolution over
        c1, the break-away forces and the thresholds (every generation one call
        of the fused batch loss), fits from its best thresholds too, and keeps
        the better of the two fits (never worse than "grid"; slower).
    seed : int, optional
        Seed of the global search (a nonnegative integer; reproducible results).
    max_generations : int
        Most generations of the global search (an integer >= 1).
    progress : bool or presliding._progress.Progress
        Show the stages, the global search's generations and the solver's
        evaluations: True draws a tqdm bar when stderr is a terminal (nothing
        otherwise); a given `Progress` is used as configured; default False.
        The result does not depend on it.

    Returns
    -------
    FitResult
        Parameters ``coulomb``, ``stiffness_j``, ``threshold_j`` (and ``offset``);
        the model is ``PIFriction(coulomb, stiffness, threshold=...)``.
    """
    y = as_signal("displacement", displacement)
    f = as_signal("force", force)
    check_same_length(displacement=y, force=f)
    n = element_count(n_elements, thresholds, 3)
    burn_in = as_count("burn_in", burn_in)
    initial, bounds, fixed, tied = resolve_parameters(initial, bounds, fixed, tied)
    fixed, tied, level, grid_size, max_evaluations, tolerance = check_fit_options(
        fixed, tied, level, grid_size, max_evaluations, tolerance
    )
    search = as_choice("search", search, ("grid", "global"))
    seed = None if seed is None else as_count("seed", seed)
    max_generations = as_count("max_generations", max_generations, minimum=1)
    if search == "global" and thresholds is not None:
        raise ValueError(
            "`search` must be 'grid' when `thresholds` are given (they are the start); "
            "got 'global'."
        )
    elements_from = "thresholds" if thresholds is not None else "n_elements"
    check_budget(y.shape[0], burn_in, n, int(bool(coulomb)) + int(bool(offset)), elements_from)
    check_varies("displacement", y)
    check_varies("force", f)
    if pr.reversal_indices(y, 0.0).shape[0] == 0:
        raise ValueError(
            "`displacement` must reverse at least once to identify presliding loops; got a "
            "monotone path (fit a virgin loading with fit_virgin_curve(..., loops=False))."
        )
    used = np.arange(y.shape[0]) >= burn_in
    columns, names = [], []
    if coulomb:
        columns.append(_direction(y))
        names.append("coulomb")
    if offset:
        columns.append(np.ones_like(y))
        names.append("offset")
    check_enough(int(used.sum()), len(names) + 2 * n)
    design = np.column_stack(columns) if columns else np.empty((y.shape[0], 0))
    grid = pr.threshold_grid(y, grid_size)

    def separable(start: ArrayLike | None, shown: FitProgress) -> pr.SeparableFit:
        return pr.fit_separable(
            f, design, tuple(names), {"coulomb": (0.0, np.inf)}, pr.stop_basis(y), n,
            grid=grid, thresholds=start, refine_thresholds=refine_thresholds, used=used,
            fixed=fixed, tied=tied, level=level, max_evaluations=max_evaluations,
            tolerance=tolerance, progress=shown,
            user_initial=initial, user_bounds=bounds,
    )  # fmt: skip

    with reporting(progress, "fit_presliding") as shown:
        fit, how = separable(thresholds, shown), ""
        if search == "global" and n > 0:
            shown.stage(f"global search over {n} elements (differential evolution)")
            found, how = search_thresholds(
                y, f, _direction(y), n, grid, coulomb=coulomb, offset=offset, skip=burn_in,
                seed=seed, max_generations=max_generations, progress=shown,
            )  # fmt: skip
            shown.stage("least squares from the global search's thresholds")
            other = separable(found, shown)
            if _cost(other) < _cost(fit):
                how += ": kept, it fits better than the grid start"
                fit = other
            else:
                how += ": the grid start fits at least as well and is kept"
    sol = fit.solution
    model, note = pi_model(sol.values, n, sol.values.get("coulomb", 0.0))
    sol = _with_note(sol, note + (f"; {how}" if how else ""))
    return FitResult.from_solution(
        sol, model, y[used], f[used], fit.fitted[used], kind="presliding operator",
        abscissa_label="displacement [m]", signal_label="friction force", signal_unit="N",
        derived=derived_quantities(model), hint=sign_hint(f, _direction(y), "friction force"),
        model_hint=lambda: _masing_note(model, y[used], f[used]),
    )  # fmt: skip


def _cost(fit: pr.SeparableFit) -> float:
    """Sum of squared residuals of a separable fit (inf if it failed)."""
    r = fit.solution.residual
    return float(r @ r) if fit.solution.status != "failed" else np.inf


def _direction(y: FloatArray) -> FloatArray:
    """Sign of the last nonzero increment (0 before any motion), as in PIFriction.force."""
    inc = np.sign(np.diff(y, prepend=y[0]))
    idx = np.where(inc != 0, np.arange(y.shape[0]), 0)
    np.maximum.accumulate(idx, out=idx)
    return inc[idx]


def _with_note(sol: Any, note: str) -> Any:
    return replace(sol, message=sol.message + note) if note else sol


def _masing_note(model: PIFriction | None, y: FloatArray, f: FloatArray) -> str:
    from presliding.identification.masing import masing_verdict

    return masing_verdict(model, (y, f))
