"""Quasi-static fit: position from a slowly applied force (torque-driven presliding).

A joint driven by a slow force (torque) below break-away moves through its
presliding hysteresis only: inertia and viscous friction are negligible, and
the position follows the force exactly through the inverse of the friction
model, y = Γ[u] with the Coulomb element c1 as a play on the force side
(`presliding.motion.quasi_static_response`). `fit_quasi_static` fits that
model to measured positions, pooling records like `fit_response`: the model
(c1 and the elements or a density) and a force offset are shared; each record
has its initial position and, with ``initial_state="preload"``, the elastic
force its memory starts with (the branch family of `preloaded_state`, on the
branch opposite to the record's first motion: the record starts with a
reversal at its preload; a branch the first motion continued could not be
told apart from a shift of the position).

F_c from below. A quasi-static response exists only while |u| < F_c, so the
Coulomb level is bounded below by the largest applied force (and by
`min_coulomb_level`): a model whose inverse would diverge is never returned.
Above that, loops that stay well below F_c hardly constrain it (the
intervals say so).

Start: eq. 8 as a regression, u = c1·sign(ẏ) + Σ_g w_g·stop_g(y) (+ offset) on
the samples where the position moves (there the balance holds with equality),
after each record's first reversal (an unknown earlier memory wiped out).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from presliding._progress import Progress
from presliding._validation import as_bounds, as_choice, as_count, as_positive_scalar, fmt
from presliding.identification import _pi_regression as pr
from presliding.identification._fit_progress import FitProgress, as_reporter, shows_progress
from presliding.identification._least_squares import check_constraints, check_options
from presliding.identification._model_spec import DENSITIES, ModelSpec
from presliding.identification._nuisance_search import search_nuisance
from presliding.identification._parameters import check_levels, resolve_parameters
from presliding.identification._quasi_static_problem import QuasiStaticProblem
from presliding.identification._response_checks import (
    bound_check,
    consistent_level,
    cost,
    split_coalesced,
    spread_start,
    stiffest_first,
)
from presliding.identification._response_setup import (
    MAX_BOOTSTRAP,
    check_model_values,
    check_quasi_static_records,
    nuisance_only,
    record_bootstrap,
    record_starts,
)
from presliding.identification._search import (
    SAME_OPTIMUM,
    SearchSummary,
    at_floor,
    floor_test,
    global_start,
    same_point,
)
from presliding.identification.fit_presliding import check_enough, element_count
from presliding.identification.fit_result import FitResult, Tie, solve_least_squares
from presliding.measurement.measurement import Measurement, common_axis

__all__ = ["fit_quasi_static"]

STATES = ("preload", "continuing", "relaxed")


def quasi_static_start(recs: list, spec: ModelSpec, offset: bool) -> dict[str, float]:
    """Start values from eq. 8 as a regression on the moving samples (module notes)."""
    from scipy.optimize import lsq_linear
    from threadpoolctl import threadpool_limits

    span = max(float(np.ptp(r.position)) for r in recs)
    steps = np.concatenate([np.abs(np.diff(r.position)) for r in recs])
    quantum = float(np.min(steps[steps > 0]))
    grid = pr.geometric_grid(max(2.0 * quantum, 1e-3 * span), 0.5 * span, span, 32)
    rows, rhs = [], []
    for r in recs:
        y, u = r.position, r.applied_force
        turns = pr.reversal_indices(np.ascontiguousarray(y), 2.0 * quantum)
        first_turn = int(turns[0]) if turns.size else 0
        dy = np.diff(y, prepend=y[0])
        moving = (np.abs(dy) > 0) & (np.arange(y.shape[0]) > first_turn)
        cols = [np.sign(dy), *pr.stop_basis(y)(grid)[0].T] + ([np.ones_like(y)] if offset else [])
        rows.append(np.column_stack(cols)[moving])
        rhs.append(u[moving])
    mat, b = np.vstack(rows), np.concatenate(rhs)
    lower = np.zeros(mat.shape[1])
    if offset:
        lower[-1] = -np.inf
    u_max = max(float(np.max(np.abs(r.applied_force))) for r in recs)
    if mat.shape[0] > mat.shape[1]:
        scale = np.linalg.norm(mat, axis=0)
        scale[scale == 0] = 1.0
        with threadpool_limits(limits=1, user_api="blas"):
            sol = lsq_linear(mat / scale, b, bounds=(lower, np.inf)).x / scale
        c1, weights = float(sol[0]), sol[1 : 1 + grid.shape[0]]
        off = float(sol[-1]) if offset else 0.0
    else:
        c1, weights, off = 0.1 * u_max, np.zeros_like(grid), 0.0
    fc = max(c1 + float(weights @ grid), 1.2 * u_max)
    c1 = min(max(c1, 0.02 * fc), 0.9 * fc)
    if not np.any(weights > 0):
        weights = np.zeros_like(grid)
        weights[len(grid) // 2] = (fc - c1) / grid[len(grid) // 2]
    start = spec.start(fc, c1, grid, weights)
    k_max = max([start[x] for x in spec.k_names], default=0.0)
    for x in spec.k_names:  # an element too soft to slide would blow the positions up
        start[x] = max(start[x], 0.02 * k_max)
    if offset:
        start["offset"] = off
    return start


def lift_density(spec: ModelSpec, start: dict[str, float], level: float,
                 fixed: Mapping[str, float]) -> dict[str, float]:  # fmt: skip
    """A density start whose F_c reaches `level`: its heights scaled (a start whose F_c
    is not above every |u| has no quasi-static response, and the solver could not begin)."""
    heights = [x for x in spec.names if x.startswith("height") and x not in fixed]
    fc = spec.coulomb_level(start)
    c1 = max(start.get("coulomb", 0.0), 0.0)
    if fc >= level or not heights or not fc > c1:
        return start
    if c1 >= 0.9 * level and "coulomb" not in fixed:
        c1 = start["coulomb"] = 0.5 * level
    factor = (level - c1) / (fc - c1)
    return {x: v * factor if x in heights else v for x, v in start.items()}


@shows_progress("fit_quasi_static")
def fit_quasi_static(
    records: Measurement | Sequence[Measurement],
    n_elements: int = 3,
    equal_breakaway: bool = True,
    *,
    density: str | None = None,
    density_cells: int = 32,
    min_coulomb_level: float | None = None,
    offset: bool = False,
    initial_state: str = "preload",
    initial: Mapping[str, float] | None = None,
    fixed: Mapping[str, float] | None = None,
    tied: Mapping[str, Tie] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    bootstrap: int = 0,
    seed: int | None = None,
    level: float = 0.95,
    max_evaluations: int | None = None,
    tolerance: float = 1e-8,
    progress: bool | Progress | FitProgress = False,
) -> FitResult:
    """Fit the quasi-static response y = Γ[u] (c1 included) to measured positions.

    Parameters
    ----------
    records : Measurement or sequence of Measurement
        Each with `position` y [m] and `applied_force` u [N] (a torque and an
        angle work alike), u slow enough for inertia to be negligible.
    n_elements, equal_breakaway, density, density_cells : as in `fit_response`
    min_coulomb_level : float, optional, keyword only
        A lower bound on F_c [N], besides the largest |u| (module notes).
    offset : bool, keyword only
        Fit a force offset (parameter ``offset``; the model sees u − offset).
    initial_state : {"preload", "continuing", "relaxed"}, keyword only
        The memory each record starts with: a fitted preload
        (``preload_fraction``; the record reverses at it), a branch its first
        motion continues (module notes), or relaxed.
    initial, fixed, tied, bounds, bootstrap, seed, level, max_evaluations, tolerance, progress
        As in `fit_response`.

    Returns
    -------
    FitResult
        Position against the applied force, records one after the other; the
        model is `PIFriction` (no mass: quasi-static), `predict` gives the
        response of another record.
    """
    from presliding.identification._predictors import QuasiStaticPredictor

    single = isinstance(records, Measurement)
    recs = check_quasi_static_records(records)
    initial_state = as_choice("initial_state", initial_state, STATES)
    if density is not None:
        density = as_choice("density", density, DENSITIES)
    n = element_count(n_elements, None, 3)
    if n < 1:
        raise ValueError(f"`n_elements` must be at least 1 (the position needs elements); got {n}.")
    cells = as_count("density_cells", density_cells, minimum=4)
    level, max_evaluations, tolerance = check_options(level, max_evaluations, tolerance)
    initial, bounds, fixed, tied = resolve_parameters(initial, bounds, fixed, tied)
    check_levels(None, min_coulomb_level, fixed)
    fixed, tied = check_constraints(fixed, tied)
    spec = ModelSpec(n, equal_breakaway, density, cells)
    check_model_values(spec, fixed, tied, initial)
    bootstrap = as_count("bootstrap", bootstrap, maximum=MAX_BOOTSTRAP)
    fmin = 0.0 if min_coulomb_level is None else as_positive_scalar(
        "min_coulomb_level", min_coulomb_level)  # fmt: skip
    problem = QuasiStaticProblem(recs, spec, initial_state, offset=offset, suffix=not single)
    names = problem.names
    check_enough(problem.n_res, len(names) - len(fixed))
    start = quasi_static_start(recs, spec, offset)
    floor = max(fmin, problem.u_max * (1 + 1e-9)) if not offset else fmin
    for i, rec in enumerate(recs):
        start[problem.nuisance("initial_position", i)] = float(rec.position[0])
        if initial_state == "preload":
            start[problem.nuisance("preload_fraction", i)] = 0.0
    for key, val in dict(initial or {}).items():
        if key not in names:
            raise ValueError(f"`initial` must name parameters of the fit; got {key!r}.")
        start[key] = float(val)
    start = {x: start[x] for x in names}
    box = {**spec.bounds(), "offset": (-np.inf, np.inf)}
    for i in range(problem.n_rec):
        box[problem.nuisance("initial_position", i)] = (-np.inf, np.inf)
        if initial_state == "preload":
            box[problem.nuisance("preload_fraction", i)] = (-1.0, 1.0)
    if spec.has_level_parameter and floor > 0:
        box["coulomb_level"] = (floor, np.inf)
        start["coulomb_level"] = max(start["coulomb_level"], floor * 1.01)
    elif floor > 0:  # a density: F_c = c1 + F_m is derived; F_m is linear in the heights
        start = lift_density(spec, start, 1.2 * floor, fixed)
    for key, (lo, hi) in as_bounds("bounds", bounds, names).items():  # the user's, within
        old = box.get(key, (-np.inf, np.inf))
        box[key] = (max(old[0], lo), min(old[1], hi))
    box = {x: box.get(x, (-np.inf, np.inf)) for x in names}
    problem.set_typical(start)
    if max_evaluations is None:
        max_evaluations = 50 * len(names)
    options: dict[str, Any] = {"bounds": box, "tied": tied, "level": level,
                               "max_evaluations": max_evaluations, "tolerance": tolerance,
                               "gradient_tolerance": max(tolerance**2, 1e-15),
                               "progress": as_reporter(progress)}  # fmt: skip
    evaluations = [0]

    def solve(begin: dict[str, float], max_evaluations: int | None = None) -> Any:
        opts = {**options, "max_evaluations": max_evaluations or options["max_evaluations"]}
        out = solve_least_squares(
            problem.residual(), begin, fixed=fixed, free_jacobian=problem.free_jacobian(),
            blocks=[rows for _, rows in problem.rows], residual_size=problem.n_res,
            clusters=[i for i, _ in problem.rows],
            step_limit=problem.step_limit, method="lm", **opts,
        )  # fmt: skip
        evaluations[0] += out.n_evaluations
        return out

    # the residual is far from convex in the records' preloads, in c1 against the
    # stiffest element and in the element split: the regression start, spread ones and
    # the best of a global search (`_search`), the records' own starts fitted one by one
    # for each, a few steps each; the best is refined, the records' own starts fitted
    # again, then searched on the grid of the fit engine (`_nuisance_search`)
    shaped = set(spec.k_names) & (set(fixed) | set(tied))
    own = initial_state == "preload" and not any(x in fixed or x in tied for x in names)
    # the cheapest route first: the regression start solved once; when it converged with
    # every record within the floor rule, no further start runs (`_search.at_floor`)
    first = solve(record_starts(problem, start) if own else dict(start))
    sol, n_starts, at_best, count = first, 1, 1, 0
    if not at_floor(problem, first):
        starts = [start]
        if density is None and equal_breakaway and spec.n > 1 and not shaped:
            spread = spread_start(start, spec.k_names)
            starts.append(spread)
            if "coulomb" not in fixed and "coulomb" not in tied:  # c1 against the stiffest element
                starts += [
                    {**spread, "coulomb": share * spread["coulomb_level"]} for share in (0.1, 0.4)
                ]
        if not tied:
            extra, count = global_start(problem, start, fixed, box, keep=1)
            evaluations[0] += count
            starts += [{x: e[x] for x in names} for e in extra]
        short = min(max_evaluations, 40)
        tries = [first] + [
            solve(record_starts(problem, s) if own else s, short) for s in starts[1:]
        ]
        best = min(tries, key=cost)
        begin = best.values if np.isfinite(cost(best)) else start
        sol = solve(record_starts(problem, begin) if own else begin)
        values, found, count = search_nuisance(problem, sol.values, fixed, box)  # then the grid
        if found < cost(sol) * (1.0 - SAME_OPTIMUM):
            again = solve(values)
            sol = again if cost(again) < cost(sol) else sol
        evaluations[0] += count
        n_starts = len(tries)
        at_best = sum(1 for t in tries if same_point(problem, t.values, sol.values)
                      or cost(t) <= cost(sol) * (1.0 + SAME_OPTIMUM))  # fmt: skip
    if density is None and equal_breakaway and not shaped:
        sol = split_coalesced(sol, solve, spec.k_names)
        sol = stiffest_first(sol, spec.k_names)
    sol = replace(sol, n_evaluations=evaluations[0])
    sol = bound_check(sol, {**start, "mass": 1.0}, names, fixed, tied,
                      equal_breakaway and density is None)  # fmt: skip
    sol = consistent_level(nuisance_only(sol, problem, fixed), spec)
    sol, ratios, noise, over = floor_test(problem, sol, at_best == n_starts)
    summary = SearchSummary(n_starts, at_best, noise, over, ratios, count)
    count, boot = sol.n_evaluations, None
    if bootstrap and len(recs) >= 3 and np.isfinite(cost(sol)):
        sol, boot, more = record_bootstrap(sol, problem, {**options, "fixed": fixed},
                                           bootstrap, seed)  # fmt: skip
        count += more
    values = sol.values
    full = np.array([values[x] for x in names])
    o_y, _, status, _ = problem.simulate(full)
    if np.any(status != 0) and sol.status == "converged":
        sol = replace(sol, status="failed", message="no quasi-static response at the optimum")
    derived = {"coulomb_level": spec.coulomb_level(values)} if not spec.has_level_parameter else {}
    fm = spec.coulomb_level(values) - max(values["coulomb"], 0.0)
    if initial_state == "preload":
        for i in range(problem.n_rec):
            x = problem.nuisance("preload_fraction", i)
            derived[x.replace("preload_fraction", "preload")] = values[x] * fm
    u_all = np.concatenate([r.applied_force for r in recs])
    units = {x: "1" for x in names if x.startswith("preload_fraction")}
    units.update({"height": "N/m^2", "max_threshold": "m", "length": "m", "preload": "N"})
    result = FitResult.from_solution(
        replace(sol, n_evaluations=count), spec.model(values), u_all,
        np.concatenate([r.position for r in recs]), o_y[0], kind="quasi-static",
        abscissa_label="applied force", signal_label="position", signal_unit="m",
        units=units, derived=derived, rotary=common_axis(records) == "rotary",
        model_hint=lambda: _masing_note(spec.model(values), recs),
    )  # fmt: skip
    spans = tuple(zip(problem.t_off[:-1].tolist(), problem.t_off[1:].tolist(), strict=True))
    if floor > 0 and spec.has_level_parameter and values["coulomb_level"] <= floor * (1 + 1e-6):
        note = (f"F_c sits on its lower bound {fmt(floor)} (the largest applied force or "
                "`min_coulomb_level`): the loops do not determine it")  # fmt: skip
        result = replace(result, notes=(note,))
    return replace(result, records=spans if problem.n_rec > 1 else (), bootstrap=boot,
                   predictor=QuasiStaticPredictor(problem, values), search=summary)  # fmt: skip


def _masing_note(model: Any, recs: list) -> str:
    """masing_check's verdict on the records' loops (position against applied force)."""
    from presliding.identification.masing import masing_verdict

    return masing_verdict(model, [(r.position, r.applied_force) for r in recs])
