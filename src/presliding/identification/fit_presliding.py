"""Presliding operator fits: friction force against displacement (eqs. 4–9, section 4).

`fit_presliding` fits the rate-independent model of eq. 8 along a measured
path,

    F(t) = c1·sign(ẏ) + Σ_j k_j (y − x_j(y, r_j))  [+ offset],

where sign(ẏ) is the direction of the last nonzero displacement increment and
the play operators start relaxed at the first sample (skip samples recorded
with an unknown earlier history with `burn_in`). All parameters but the
thresholds enter linearly: nonnegative least squares for the stiffnesses on a
geometric threshold grid gives a start, variable projection over the
thresholds on a grid of the path's turning-point amplitudes gives more
(`_threshold_search`), and nonlinear least squares over all parameters refines
each; the best is kept (see `presliding.identification.problem._pi_regression`).

Asymmetric friction (``asymmetric=True``): c1⁺·[ẏ > 0] − c1⁻·[ẏ < 0] in place of
c1·sign(ẏ), the elements shared, as in `fit_motion` (a constant offset is the
same column as c1⁺ − c1⁻ while the contact slides, so `offset` is excluded).
The symmetric fit runs first; the asymmetric one also starts from its
thresholds, and ``result.asymmetry`` tests the difference.

The virgin-curve fit (Madelung/Masing rules) lives in `fit_virgin`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import replace
from functools import partial
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._progress import Progress
from presliding._validation import (
    as_choice,
    as_count,
    as_signal,
    check_same_length,
)
from presliding.friction.pi_friction import PIFriction
from presliding.identification._fit_engine import FitPlan, FitRun, Found, run_fit
from presliding.identification.checks._response_checks import cost, relabelled
from presliding.identification.fit_result import FitResult, Tie
from presliding.identification.judge._status import sign_hint
from presliding.identification.problem import _pi_regression as pr
from presliding.identification.problem._fit_options import (
    check_budget,
    check_enough,
    check_fit_options,
    check_varies,
    element_count,
)
from presliding.identification.problem._fit_problem import FitOptions, FitProblem
from presliding.identification.problem._parameters import check_flag, resolve_parameters
from presliding.identification.problem._separable_adequacy import separable_adequacy
from presliding.identification.problem._separable_problem import Separable, separable_problem
from presliding.identification.result._fit_progress import reporting
from presliding.identification.search._global_search import search_thresholds
from presliding.identification.search._search import SAME_OPTIMUM
from presliding.identification.search._threshold_search import amplitude_grid, threshold_starts

__all__ = ["fit_presliding"]

FloatArray = NDArray[np.float64]


def pi_model(values: Mapping[str, float], n: int, coulomb: float,
             negative: float | None = None) -> tuple[PIFriction | None, str]:  # fmt: skip
    """The friction model from fitted values; elements of zero stiffness are left out;
    `negative` the Coulomb element c1⁻ of sliding in −y (None: symmetric)."""
    k_names, r_names = pr.element_names(n)
    k = np.array([values[x] for x in k_names])
    r = np.array([values[x] for x in r_names])
    keep = k > 0
    note = ""
    if not keep.all():
        dropped = ", ".join(str(j + 1) for j in np.flatnonzero(~keep))
        note = f"; element(s) {dropped} came out with zero stiffness and are left out of the model"
    try:
        below = None if negative is None else max(negative, 0.0)
        return PIFriction(max(coulomb, 0.0), k[keep], threshold=r[keep],
                          coulomb_negative=below), note  # fmt: skip
    except ValueError as exc:
        return None, f"; no valid model: {exc}"


def derived_quantities(model: PIFriction | None) -> dict[str, float]:
    """F_c (eq. 9), F_m and Σ k_j (eq. 7) of a model; F_c⁺ and F_c⁻ of an asymmetric one."""
    if model is None:
        return {}
    if not model.is_symmetric:
        fp, fn = model.coulomb_levels
        return {"coulomb_level": fp, "coulomb_level_negative": fn,
                "initial_stiffness": model.initial_stiffness}  # fmt: skip
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
    asymmetric: bool = False,
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
    asymmetric : bool
        Separate Coulomb elements c1⁺ (``coulomb``, while ẏ > 0) and c1⁻
        (``coulomb_negative``, while ẏ < 0); the elements stay symmetric.
        Excludes `offset` and needs `coulomb`. The symmetric fit runs first and
        ``result.asymmetry`` tests the difference (module notes).
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
        Parameters ``coulomb``, ``stiffness_j``, ``threshold_j`` (and ``offset``),
        the elements numbered by increasing threshold where the thresholds were
        searched; the model is ``PIFriction(coulomb, stiffness, threshold=...)``.
    """
    request = dict(locals())
    y, f = as_signal("displacement", displacement), as_signal("force", force)
    check_same_length(displacement=y, force=f)
    if check_flag("asymmetric", asymmetric) and (offset or not coulomb):
        raise ValueError(
            "`asymmetric`=True needs coulomb=True and offset=False: while the contact slides a "
            "constant force is the same column as c1⁺ − c1⁻ (the fit absorbs it into the two "
            f"Coulomb levels); got coulomb={coulomb!r}, offset={offset!r}."
        )
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
    sep = _path_model(y, f, n, thresholds, burn_in, coulomb, offset, asymmetric)
    grid = pr.threshold_grid(y, grid_size)
    top = pr.largest_threshold(y)
    with reporting(progress, "fit_presliding") as shown:
        problem = partial(
            separable_problem, sep, {**({"coulomb": (0.0, np.inf)} if coulomb else {}), **(
                {"coulomb_negative": (0.0, np.inf)} if asymmetric else {})}, grid=grid,
            refine_thresholds=refine_thresholds, fixed=fixed, tied=tied, progress=shown,
            user_initial=initial, user_bounds=bounds, largest_threshold=top,
        )  # fmt: skip
        if asymmetric:
            options = FitOptions(level, max_evaluations, tolerance, progress=shown)
            return _fit_sided(
                request,
                problem,
                thresholds,
                partial(_result, sep, y, f),
                options,
                partial(_adequacy, sep, y),
            )
        found = None if search == "grid" or n == 0 else partial(
            search_thresholds, y, f, _direction(y), n, grid, coulomb=coulomb, offset=offset,
            skip=burn_in, seed=seed, max_generations=max_generations, progress=shown,
        )  # fmt: skip
        shaped = bool({*pr.element_names(n)[0], *pr.element_names(n)[1]}
                      & ({*fixed, *tied, *(initial or {})}))  # fmt: skip
        starts = None if thresholds is not None or shaped or not refine_thresholds else partial(
            threshold_starts, sep, amplitude_grid(y, max(float(grid[0]), 1e-3 * top)),
            {"coulomb": (0.0, np.inf)}, fixed, seed=0 if seed is None else seed,
        )  # fmt: skip
        plan = FitPlan(search=partial(_search, problem, found, n, starts),
                       result=partial(_result, sep, y, f),
                       adequacy=partial(_adequacy, sep, y))  # fmt: skip
        options = FitOptions(level, max_evaluations, tolerance, progress=shown)
        return run_fit(problem(thresholds=thresholds), options, plan)


def _fit_sided(request: dict[str, Any], problem: Callable[..., FitProblem], thresholds: Any,
               result: Callable[..., FitResult], options: FitOptions,
               adequacy: Callable[..., Any]) -> FitResult:  # fmt: skip
    """``asymmetric=True``: the symmetric fit, then the asymmetric one (module notes)."""
    from presliding.identification.plans._asymmetric_plan import fit_nested, split_negative

    symmetric = fit_presliding(**{**split_negative(request), "asymmetric": False})
    rows = [{"coulomb_negative": 1.0, "coulomb": -1.0}]
    return fit_nested(problem, thresholds, symmetric, result, rows, options, adequacy)


def _path_model(y: FloatArray, f: FloatArray, n: int, thresholds: Any, burn_in: int,
                coulomb: bool, offset: bool, asymmetric: bool = False) -> Separable:  # fmt: skip
    """Eq. 8 along the path as a separable model, its data checked (budget, reversals)."""
    elements_from = "thresholds" if thresholds is not None else "n_elements"
    linear = int(bool(coulomb)) + int(bool(offset)) + int(bool(asymmetric))
    check_budget(y.shape[0], burn_in, n, linear, elements_from)
    check_varies("displacement", y)
    check_varies("force", f)
    if pr.reversal_indices(y, 0.0).shape[0] == 0:
        raise ValueError(
            "`displacement` must reverse at least once to identify presliding loops; got a "
            "monotone path (fit a virgin loading with fit_virgin_curve(..., loops=False))."
        )
    used = np.arange(y.shape[0]) >= burn_in
    columns, names = [], []
    if asymmetric:  # c1⁺ while ẏ > 0, −c1⁻ while ẏ < 0
        d = _direction(y)
        if not (np.any(d[used] > 0) and np.any(d[used] < 0)):
            raise ValueError(
                "`displacement` must move both ways (after `burn_in`) to separate the two "
                "Coulomb levels of `asymmetric`; it moves one way."
            )
        columns += [(d > 0) * 1.0, -1.0 * (d < 0)]
        names += ["coulomb", "coulomb_negative"]
    elif coulomb:
        columns.append(_direction(y))
        names.append("coulomb")
    if offset:
        columns.append(np.ones_like(y))
        names.append("offset")
    check_enough(int(used.sum()), len(names) + 2 * n)
    design = np.column_stack(columns) if columns else np.empty((y.shape[0], 0))
    return Separable(f, design, tuple(names), pr.stop_basis(y), n, used)


def _search(problem: Callable[..., FitProblem], found: Callable[[], tuple] | None, n: int,
            starts: Callable[..., list] | None, run: FitRun) -> Found:  # fmt: skip
    """The grid start solved; the best threshold sets of the variable-projection search
    (`_threshold_search`) too; with the global search, its thresholds as well. The best
    is kept, its elements labelled by increasing threshold (they are interchangeable), and
    how many starts reached it (cost within `SAME_OPTIMUM`) is said."""
    fit, how = run.problem.solve(run.options), ""
    fits = [fit]
    if starts is not None:
        run.stage(f"variable projection over the thresholds of {n} elements")
        r_names = pr.element_names(n)[1]
        merged = np.array([run.problem.initial[x] for x in r_names])
        for r0, _ in starts(merged=merged):
            fits.append(problem(thresholds=r0).solve(run.options))
    if found is not None:
        run.stage(f"global search over {n} elements (differential evolution)")
        start, how = found()
        run.stage("least squares from the global search's thresholds")
        other = problem(thresholds=start).solve(run.options)
        best = min(fits, key=cost)
        if cost(other) < cost(best):
            how += ": kept, it fits better than the other starts"
        else:
            how += ": another start fits at least as well and is kept"
        fits.append(other)
    best = min(fits, key=cost)
    at_best = sum(1 for f in fits if cost(f) <= cost(best) * (1.0 + SAME_OPTIMUM))
    if starts is not None and best.status != "failed":  # interchangeable: smallest r first
        k_names, r_names = pr.element_names(n)
        order = np.argsort([best.values[x] for x in r_names], kind="stable")
        rename = {}
        for i, j in enumerate(order):
            rename[k_names[int(j)]], rename[r_names[int(j)]] = k_names[i], r_names[i]
        best = relabelled(best, rename)
    return Found(best, len(fits), at_best, note=how)


def _result(sep: Separable, y: FloatArray, f: FloatArray, run: FitRun, sol: Any, boot: Any,
            found: Found) -> FitResult:  # fmt: skip
    """The public result: the model of the fitted values, F_c, F_m and Σ k_j."""
    used, fitted = sep.used, sep.fitted(sol.values)
    model, note = pi_model(sol.values, sep.n_elements, sol.values.get("coulomb", 0.0),
                           sol.values.get("coulomb_negative"))  # fmt: skip
    sol = _with_note(sol, note + (f"; {found.note}" if found.note else ""))
    return FitResult.from_solution(
        sol, model, y[used], f[used], fitted[used], kind="presliding operator",
        abscissa_label="displacement [m]", signal_label="friction force", signal_unit="N",
        derived=derived_quantities(model), hint=sign_hint(f, _direction(y), "friction force"),
        model_hint=lambda: _masing_note(model, y[used], f[used]),
    )  # fmt: skip


def _adequacy(sep: Separable, y: FloatArray, run: FitRun, sol: Any) -> Any:
    """The residual tests of the fit (`_separable_adequacy`): the force's own noise."""
    extra = {} if "offset" in sep.x_names else {"asymmetry": np.ones_like(y)}
    regressors = {"the displacement": y, "the motion": np.diff(y, prepend=y[0]),
                  "the direction of motion": _direction(y)}  # fmt: skip
    return separable_adequacy(sep, sol, regressors, extra=extra, span=float(np.ptp(y)))


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
