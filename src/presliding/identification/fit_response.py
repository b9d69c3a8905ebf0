"""Output-error fit of one or many records: simulated against measured motion (section 4).

The paper identifies m, F_c, c1 and k_2..k_5 of eq. 17 (four elements of equal
break-away force) by fitting the simulated velocity near a stop to the measured
one. A single stop rarely holds enough information for that; `fit_response`
therefore *pools* records: the physical parameters (mass, the friction model,
the force offset) are shared, and each record has its own nuisance parameters:
initial position, initial velocity and, with ``initial_state="preload"``, the
initial friction memory as an elastic force (`presliding.friction.preload`, the
branch family). Every evaluation simulates all records exactly (event method)
in one compiled call; the Jacobian exploits that a record's nuisance
parameters touch only its rows (`_pooled_problem`).

Scale. When no record has an applied force, eq. 17 is homogeneous: mass and
forces scale together and only F/m is identifiable. Unless `mass` or
`coulomb_level` is given, the mass is then held at 1 and the parameters are
reported per unit mass (said in the message and the report; not a failure).

Uncertainty. Output-error residuals are serially correlated, so the covariance
is the HAC sandwich of `presliding.identification.uncertainty` (one block per
record and signal); with three or more records each variance is the larger
of that and the record-level (cluster-robust) sandwich. With ``bootstrap``
resamples the records are also resampled with replacement and refitted, and
the reported interval is the union of the analytic and the bootstrap
percentile intervals.

Robustness (as before for one record): with equal break-away forces the
stiffest element can trade places with the Coulomb element (k_1 → ∞). The fit
tries the regression start and a spread start, then refits with that element
rigid; if the cost rises by no more than s²·t² the status is
``"not_identifiable"``. A model parameter on its bound 0 gives ``"at_bound"``.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from dataclasses import replace
from typing import Any

from presliding._progress import Progress
from presliding._validation import as_choice, as_count, as_positive_scalar, fmt
from presliding.identification import _pooled_problem as pp
from presliding.identification._fit_progress import FitProgress, as_reporter, shows_progress
from presliding.identification._least_squares import (
    LARGE_PROBLEM,
    check_constraints,
    check_options,
)
from presliding.identification._model_order import choose_order
from presliding.identification._model_spec import DENSITIES, ModelSpec
from presliding.identification._parameters import (
    check_flag,
    check_levels,
    kept_parameters,
    resolve_parameters,
)
from presliding.identification._response_box import start_and_box
from presliding.identification._response_checks import (
    bound_check,
    consistent_level,
    escape_corner,
    polish_initial_velocity,
    rigid_check,
    smallest_threshold_first,
    split_coalesced,
    spread_start,
    stiffest_first,
)
from presliding.identification._response_result import PER_UNIT_MASS, response_result
from presliding.identification._response_setup import (
    MAX_BOOTSTRAP,
    check_model_values,
    check_records,
    nuisance_only,
    prune_elements,
    record_bootstrap,
    signal_weights,
    with_penalty,
)
from presliding.identification._search import (
    SearchSummary,
    adaptive_search,
    floor_test,
    global_start,
)
from presliding.identification.fit_presliding import check_enough, element_count
from presliding.identification.fit_result import FitResult, Tie, solve_least_squares
from presliding.measurement.measurement import Measurement, common_axis

__all__ = ["fit_response"]

SIGNALS = ("velocity", "position", "both")
#: Units of the quantities the pooled fits add (the others: `_units.parameter_units`).
EXTRA_UNITS = {
    "height": "N/m^2",
    "max_threshold": "m",
    "length": "m",
    "preload": "N",
    "largest_swing": "m",
    "reachable_coulomb_level": "N",
    "effective_elements": "1",
}
#: evaluations of the rigid-limit refit of a large pooled problem (an upper bound of its
#: cost suffices to flag the rigid corner; the refit starts at the optimum)
RIGID_EVALUATIONS = 30
STATES = ("saturated", "preload", "relaxed")


@shows_progress("fit_response")
def fit_response(
    records: Measurement | Sequence[Measurement],
    n_elements: int | str = 4,
    equal_breakaway: bool = True,
    mass: float | None = None,
    *,
    density: str | None = None,
    density_cells: int = 32,
    coulomb_level: float | None = None,
    min_coulomb_level: float | None = None,
    viscous: bool = False,
    offset: bool = False,
    signal: str = "velocity",
    weights: Mapping[str, float] | None = None,
    initial_state: str = "saturated",
    initial: Mapping[str, float] | None = None,
    fit_initial: bool = True,
    fixed: Mapping[str, float] | None = None,
    tied: Mapping[str, Tie] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    prune: bool = False,
    bootstrap: int = 0,
    seed: int | None = None,
    level: float = 0.95,
    max_evaluations: int | None = None,
    tolerance: float = 1e-8,
    multistart: bool = True,
    progress: bool | Progress | FitProgress = False,
) -> FitResult:
    """Fit eq. 17 to one or many records by matching simulated to measured motion.

    Parameters
    ----------
    records : Measurement or sequence of Measurement
        Time and the measured `velocity` and/or `position`; `applied_force` u
        (held constant between samples; absent = 0: a free record). With one
        Measurement the per-record parameters have no suffix; with a sequence
        they are ``initial_position_i``, ``initial_velocity_i`` and
        ``preload_fraction_i`` (i from 1).
    n_elements : int or "auto"
        Number N of elasto-plastic elements (the paper: 4); with
        ``density="piecewise_constant"`` the number of cells of the density.
        ``"auto"``: N = 0..4 by the Bayesian information criterion, elements
        the data cannot reach dropped (`_model_order`; the table is in
        ``result.search.order_table`` and the report).
    equal_breakaway : bool
        ``coulomb_level`` F_c, ``coulomb`` c1, ``stiffness_j`` with
        c_j = (F_c − c1)/N (the paper's choice); False: ``coulomb``,
        ``stiffness_j``, ``breakaway_j``.
    mass : float, optional
        Known mass [kg] (held fixed).
    density : {"uniform", "exponential", "piecewise_constant"}, optional, keyword only
        A continuous density μ (eq. 10) instead of elements: parameters
        ``height``, ``max_threshold`` (uniform), ``height``, ``length``
        (exponential), ``max_threshold``, ``height_1..N`` (piecewise constant);
        simulated through its centroid discretisation with `density_cells`
        elements (`_model_spec`, error O(1/cells²) of F_m).
    density_cells : int, keyword only
        Elements of that discretisation (>= 4).
    coulomb_level : float, optional, keyword only
        Known F_c [N] (held fixed; needs ``equal_breakaway=True`` and elements).
    min_coulomb_level : float, optional, keyword only
        A lower bound on F_c [N] (a bound of ``coulomb_level``; for the other
        models a penalty that is zero above it).
    viscous : bool, keyword only
        Fit a viscous term σ·ẏ (parameter ``viscous`` σ >= 0 [N·s/m], shared; the
        model returned carries it, `PIFriction(..., viscous=σ)`).
    offset : bool, keyword only
        Fit a constant force offset (parameter ``offset``): the drive is u − offset.
    signal : {"velocity", "position", "both"}, keyword only
        What is compared; "both" weighs each signal by the inverse of its RMS.
    weights : mapping, optional, keyword only
        Factors on those weights, ``{"velocity": w_v, "position": w_y}``.
    initial_state : {"saturated", "preload", "relaxed"}, keyword only
        Friction memory at each record's first sample: steady sliding in the
        direction of the first motion; a fitted preload per record (the branch
        family of `preloaded_state`, ``preload_fraction`` in [−1, 1], 1 =
        saturated); or relaxed.
    initial : mapping or lmfit.Parameters, optional, keyword only
        Start values by parameter name (others from the pooled regression start).
        An ``lmfit.Parameters`` gives start values, bounds (min, max), fixed
        values (vary=False) and linear ties (expr ``a*name + b``) at once. An
        argument that contradicts another (``mass=1`` with ``fixed={"mass": 2}``,
        a start or fixed value outside `bounds`) is refused.
    fit_initial : bool, keyword only
        Estimate initial velocities and (when the position is compared)
        positions; False holds them at each record's first sample.
    fixed, tied : mapping, optional, keyword only
        Parameters held at a value or tied to another (name or (name, factor));
        a fixed or start mass, F_c, stiffness, break-away force or density
        parameter must be positive, c1 nonnegative.
    bounds : mapping name -> (lower, upper), optional, keyword only
        Bounds on any parameter, intersected with its natural ones.
    prune : bool, keyword only
        Drop elements that never slide in the data (their k_j → 0, or 2·r_j
        beyond the largest swing) and refit, with the `fixed`, `tied` and
        `bounds` given (those of dropped elements left out); the derived values
        ``effective_elements`` and ``reachable_coulomb_level`` are always given.
    bootstrap : int, keyword only
        Record-level bootstrap resamples (used with three or more records; 0: none).
    seed : int, optional, keyword only
        Seed of the bootstrap.
    level, max_evaluations, tolerance : as in `fit_presliding`
        `max_evaluations` defaults to 50 per parameter for each start and check.
    multistart : bool, keyword only
        Also try the spread start and test the rigid limit of the stiffest
        element (equal break-away forces; c1 and stiffnesses not fixed or tied).
    progress : bool or presliding._progress.Progress, keyword only
        Show the stages (starts, checks, bootstrap resamples) and the solver's
        evaluations with the cost: True draws a tqdm bar when stderr is a
        terminal (nothing otherwise); a given `Progress` is used as configured;
        default False. The result does not depend on it.

    Returns
    -------
    FitResult
        Against time (records one after the other; `records` gives their
        ranges), with the HAC `covariance`, `correlation`, `nfev`, the
        bootstrap when it ran, and `predict` for other records.
    """
    if isinstance(n_elements, str):
        if n_elements != "auto":
            raise ValueError(f"`n_elements` must be a count or 'auto'; got {n_elements!r}.")
        if density is not None:
            raise ValueError("`n_elements='auto'` chooses a number of elements; got a density.")
        return choose_order(fit_response, {
            "records": records, "equal_breakaway": equal_breakaway, "mass": mass,
            "coulomb_level": coulomb_level, "min_coulomb_level": min_coulomb_level,
            "viscous": viscous, "offset": offset, "signal": signal, "weights": weights,
            "initial_state": initial_state, "fit_initial": fit_initial, "bounds": bounds,
            "bootstrap": bootstrap, "seed": seed, "level": level,
            "max_evaluations": max_evaluations, "tolerance": tolerance,
            "multistart": multistart, "progress": progress,
            **{label: {x: v for x, v in dict(given or {}).items()  # element names vary with N
                       if not x.startswith(("stiffness_", "breakaway_"))}
               for label, given in (("initial", initial), ("fixed", fixed), ("tied", tied))},
        })  # fmt: skip
    single = isinstance(records, Measurement)
    shown = as_reporter(progress)
    recs = check_records(records, signal, SIGNALS)
    signal = as_choice("signal", signal, SIGNALS)
    initial_state = as_choice("initial_state", initial_state, STATES)
    if density is not None:
        density = as_choice("density", density, DENSITIES)
    cells = as_count("density_cells", density_cells, minimum=4)
    n = element_count(n_elements, None, 4)
    if density == "piecewise_constant" and n < 1:
        raise ValueError(f"`n_elements` (the cells of the density) must be >= 1; got {n}.")
    if n == 0 and density is None:  # Coulomb (+ viscous) friction: F_c = c1, one parameter
        equal_breakaway = False
        if coulomb_level is not None:
            fixed_level = as_positive_scalar("coulomb_level", coulomb_level)
            fixed = {**dict(fixed or {}), "coulomb": fixed_level}
            coulomb_level = None
    if coulomb_level is not None and (not equal_breakaway or density is not None):
        raise ValueError(
            "`coulomb_level` can be given only with equal_breakaway=True and elements; got "
            + ("a density." if density else "equal_breakaway=False.")
        )
    level, max_evaluations, tolerance = check_options(level, max_evaluations, tolerance)
    initial, bounds, fixed, tied = resolve_parameters(
        initial, bounds, fixed, tied, {"mass": mass, "coulomb_level": coulomb_level}
    )
    check_levels(coulomb_level, min_coulomb_level, fixed)
    prune = check_flag("prune", prune)
    fixed, tied = check_constraints(fixed, tied)
    given = {"fixed": dict(fixed), "tied": dict(tied), "bounds": bounds or {}}
    spec = ModelSpec(n, equal_breakaway, density, cells)
    check_model_values(spec, fixed, tied, initial)
    bootstrap = as_count("bootstrap", bootstrap, maximum=MAX_BOOTSTRAP)
    if mass is not None:
        fixed["mass"] = as_positive_scalar("mass", mass)
    if coulomb_level is not None:
        fixed["coulomb_level"] = as_positive_scalar("coulomb_level", coulomb_level)
    fmin = None if min_coulomb_level is None else as_positive_scalar(
        "min_coulomb_level", min_coulomb_level)  # fmt: skip
    fc = fixed.get("coulomb_level")
    if spec.has_level_parameter and n and fc is not None and fixed.get("coulomb", 0.0) >= fc:
        raise ValueError(
            f"`fixed['coulomb']` must be less than the Coulomb level {fmt(fc)} (else no force is "
            f"left for the elements); got {fmt(fixed['coulomb'])}."
        )
    forced = any(r.forced for r in recs)
    per_unit_mass = not forced and not ({"mass", "coulomb_level"} & set(fixed))
    if per_unit_mass:
        fixed["mass"] = 1.0
    wv, wy = signal_weights(signal, recs, weights)
    problem = pp.PooledProblem(
        recs,
        spec,
        (wv, wy),
        initial_state,
        offset=offset,
        suffix=not single,
        viscous=viscous,
    )
    names = problem.names
    for i, rec in enumerate(recs):
        if not fit_initial:
            fixed.setdefault(problem.nuisance("initial_velocity", i), float(rec.velocity[0]))
        if not fit_initial or signal == "velocity":
            fixed.setdefault(problem.nuisance("initial_position", i), float(rec.position[0]))
    check_enough(problem.n_res, len(names) - len(fixed))
    start, box = start_and_box(problem, spec, recs, fixed, forced, offset, viscous,
                               initial_state, initial, bounds, fmin)  # fmt: skip
    problem.set_typical(start)
    penalty = None if fmin is None or spec.has_level_parameter else fmin
    if max_evaluations is None:
        max_evaluations = 50 * len(names)
    options = {"bounds": box, "tied": tied, "level": level, "max_evaluations": max_evaluations,
               "tolerance": tolerance, "gradient_tolerance": max(tolerance**2, 1e-15),
               "progress": shown}  # fmt: skip
    evaluations = [0]
    free = len(names) - len(fixed)
    shown.stage(f"least squares: {problem.n_rec} record(s), {free} free parameters")

    def solve(begin, rigid=False, extra=None, **kw):
        fun, jac = with_penalty(problem, rigid, penalty)
        out = solve_least_squares(
            fun, begin, fixed={**fixed, **(extra or {})}, free_jacobian=jac,
            blocks=[rows for _, rows in problem.rows], residual_size=problem.n_res,
            clusters=[i for i, _ in problem.rows],
            step_limit=problem.step_limit, method="lm" if problem.n_rec > 1 else "auto",
            **{**options, **kw},
        )  # fmt: skip
        evaluations[0] += out.n_evaluations
        return out

    model_names = set(spec.names)
    shaped = model_names & (set(fixed) | set(tied))
    discrete_equal = density is None and equal_breakaway and n >= 1
    search = multistart and density is None and n >= 1 and not (
        {"coulomb", *spec.k_names, *spec.c_names} & shaped)  # fmt: skip
    large = problem.n_rec > 1 or problem.n_res * (len(names) - len(fixed)) ** 2 > LARGE_PROBLEM
    short = min(max_evaluations, 12 + 2 * len(problem.shared))

    def more_starts() -> Iterator[tuple[dict[str, float], int]]:
        """The further shared starts, made only when the search reaches them."""
        if search and discrete_equal:
            yield spread_start(start, spec.k_names), 0
        if multistart and not tied:
            shown.stage("search: the shared parameters' global start")
            extra, spent = global_start(problem, start, fixed, box)
            for j, e in enumerate(extra):
                yield {x: e[x] for x in names}, spent if j == 0 else 0

    shown.stage("search: the regression start, then the records that do not fit")
    sol, n_starts, at_best, count = adaptive_search(problem, solve, start, more_starts, fixed,
                                                    box, short)  # fmt: skip
    evaluations[0] += count
    if search and discrete_equal:
        shown.stage("checks: a rigid stiffest element, coalesced elements")
        sol = escape_corner(sol, solve, spec.k_names)
        sol = split_coalesced(sol, solve, spec.k_names)
    if single:
        sol = polish_initial_velocity(sol, solve, fixed, tied, recs[0].velocity)
    labelled = (set(spec.k_names) | set(spec.c_names)) & (set(fixed) | set(tied))
    if discrete_equal and not labelled:
        sol = stiffest_first(sol, spec.k_names)
    elif density is None and not equal_breakaway and not labelled and sol.status != "failed":
        sol = smallest_threshold_first(sol, spec.k_names, spec.c_names)
    if search and sol.status == "converged":
        shown.stage("check: the rigid limit of the smallest-threshold element")
        capped = (lambda *a, **k: solve(*a, max_evaluations=RIGID_EVALUATIONS, **k)) if large \
            else solve  # fmt: skip
        sol = rigid_check(sol, capped, problem, names, fixed, tied, level,
                          refine=solve if large else None)  # fmt: skip
    sol = bound_check(sol, start, names, fixed, tied, equal_breakaway and density is None)
    sol = consistent_level(nuisance_only(sol, problem, fixed), spec)
    notes = [PER_UNIT_MASS] if per_unit_mass else []
    pruned = prune_elements(problem, sol, spec)
    if prune and pruned.dead and density is None and spec.n - len(pruned.dead) >= 0:
        kw: dict[str, Any] = dict(
            n_elements=spec.n - len(pruned.dead), equal_breakaway=equal_breakaway, mass=mass,
            coulomb_level=coulomb_level, min_coulomb_level=min_coulomb_level, offset=offset,
            viscous=viscous, signal=signal, weights=weights, initial_state=initial_state,
            fit_initial=fit_initial, level=level, max_evaluations=max_evaluations,
            tolerance=tolerance, multistart=multistart, bootstrap=bootstrap, seed=seed,
            initial=pruned.start(sol.values, problem), progress=shown,
            **kept_parameters(given, spec.n - len(pruned.dead)),
        )  # fmt: skip
        shown.stage(f"refit without {len(pruned.dead)} element(s) that never slide")
        refit = fit_response(records, **kw)
        note = pruned.note(spec) + "; refitted without them"
        return replace(refit, notes=(*refit.notes, note), n_evaluations=refit.n_evaluations
                       + evaluations[0])  # fmt: skip
    if pruned.dead:
        notes.append(pruned.note(spec) + " (prune=True drops them)")
    boot = None
    if bootstrap and len(recs) >= 3 and sol.status != "failed":
        settings = {**options, "fixed": fixed}
        sol, boot, count = record_bootstrap(sol, problem, settings, bootstrap, seed)
        evaluations[0] += count
    sol, ratios, floor, over = floor_test(problem, sol, at_best == n_starts)
    sol = replace(sol, n_evaluations=evaluations[0])
    summary = SearchSummary(n_starts, at_best, floor, over, ratios, count)
    result = response_result(sol, problem, spec, pruned, notes, boot, per_unit_mass, signal)
    return replace(result, search=summary).on_axis(common_axis(records))
