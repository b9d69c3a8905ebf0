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
of that and the record-level (cluster-robust) sandwich. Where a record's
velocity is the difference quotient of its position (``velocity``) and both
signals are compared, the two carry one noise, the position's: each variance
is then also at least that of independent position noise at the level the
fit leaves (`_covariance`), which the records' initial velocities and
preloads, fixed by a few samples, need. With ``bootstrap``
resamples the records are also resampled with replacement and refitted, and
the reported interval is the union of the analytic and the bootstrap
percentile intervals.

Robustness (as before for one record): with equal break-away forces the
stiffest element can trade places with the Coulomb element (k_1 → ∞). The fit
tries the regression start and a spread start, then refits with that element
rigid; if the cost rises by no more than s²·t² the status is
``"not_identifiable"``. A model parameter on its bound 0 gives ``"at_bound"``.

Asymmetric friction (``asymmetric=True``): the level of sliding in −y, F_c⁻
(``coulomb_level_negative``; ``coulomb_negative`` c1⁻ without elements) and σ⁻
(``viscous_negative``) are fitted besides the positive side, every negative
level the share F_c⁻/F_c⁺ of its positive one (`_model_spec`: the records
determine the difference of the levels, not how it splits between c1 and the
elements). The symmetric fit runs first and the asymmetric one starts from it
(`_asymmetric_plan`); ``result.asymmetry`` tests whether the data support the
difference (`judge._asymmetry`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from presliding._progress import Progress
from presliding.identification._fit_engine import run_fit
from presliding.identification.fit_result import FitResult, Tie
from presliding.identification.plans._asymmetric_plan import fit_asymmetric
from presliding.identification.plans._response_plan import (
    asymmetric_parts,
    response_plan,
    response_problem,
)
from presliding.identification.plans._response_request import check_response, order_options
from presliding.identification.problem._parameters import check_flag
from presliding.identification.result._fit_progress import FitProgress, shows_progress
from presliding.identification.search._model_order import choose_order
from presliding.measurement.measurement import Measurement

__all__ = ["fit_response"]


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
    asymmetric: bool = False,
    signal: str = "velocity",
    velocity: str = "auto",
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
    family: str = "pi",
    substeps: int | None = None,
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
    asymmetric : bool, keyword only
        Separate levels for the two directions of sliding: ``coulomb_level_negative``
        F_c⁻ (``coulomb_negative`` without elements) and, with `viscous`,
        ``viscous_negative`` σ⁻; c1⁻ = ρ·c1 and c_j⁻ = ρ·c_j with ρ = F_c⁻/F_c⁺
        (the play band [y − r_j, y + ρ·r_j]). Elements only (no `density`);
        excludes `offset`, which is the same model: from any memory but the
        relaxed one, the asymmetric model moves exactly as the symmetric model
        of the mean levels under u − (F_c⁺ − F_c⁻)/2. The symmetric fit runs
        first; ``result.asymmetry`` says whether the data support the
        asymmetry (an F test of the nested fits, scaled for the residual's
        autocorrelation, with ΔAIC and ΔBIC) and holds the symmetric fit.
    signal : {"velocity", "position", "both"}, keyword only
        What is compared; "both" weighs each signal by the inverse of its RMS.
    velocity : {"auto", "difference", "measured"}, keyword only
        What a record's velocity is, and so what the model's velocity is
        compared with. ``"difference"``: the difference quotient of the
        position, ``numpy.gradient(position, time)`` (central differences,
        one-sided at the ends), as a drive or ``Measurement`` without a
        velocity gives it; the model's simulated position is passed through
        the same quotient before it is compared (and the Jacobian with it);
        every record needs its position.
        Compared with the exact velocity instead, the quotient's error
        O(a·Δt) where the acceleration a is large or jumps (the first sample,
        a stop, a change of u) biases the initial velocities (towards smaller
        speeds) and the forces. ``"measured"``: the velocity is measured
        (tachometer, laser vibrometer, a filtered estimate) and the model's
        exact velocity is compared. ``"auto"`` (default): ``"difference"``
        for a record without a velocity and for one whose velocity equals
        ``numpy.gradient(position, time)`` (edge order 1 or 2) to rounding,
        ``"measured"`` otherwise. With ``"difference"`` the fitted velocity
        in the result is the model's difference quotient.
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
        beyond the largest swing) and refit once, from the fit's optimum without
        them, with the `fixed`, `tied` and `bounds` given (those of dropped
        elements left out); the notes name the elements dropped, and any of the
        refit's own that never slide in turn (kept). The derived values
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
    family : {"pi", "gms", "lugre", "dahl"}, keyword only
        The model family fitted: the PI model of eq. 17 (default); the generalized
        Maxwell-slip model (`GMSFriction`: the PI elements with a Stribeck curve and a
        frictional lag, parameters ``stribeck_drop`` F_S − F_C, ``stribeck_velocity``,
        ``lag_time`` besides the PI model's; with the first and last 0 it is the PI
        model); LuGre (`LuGreFriction`: ``coulomb``, ``stribeck_drop``, ``stiffness``
        σ0, ``damping`` σ1, ``stribeck_velocity``; σ2 is ``viscous``) or Dahl
        (`DahlFriction`, α = 1: ``coulomb``, ``stiffness``). The rate families are
        simulated by the implicit step (`presliding.simulate`), `substeps` steps per
        sample interval, and fitted by the same engine (starts, statuses, intervals,
        `predict`); `density`, `prune`, `min_coulomb_level` (and, but for GMS,
        `n_elements`, `equal_breakaway`, `coulomb_level`) are the PI model's options
        and are refused with them (`_rate_plan`).
    substeps : int, optional, keyword only
        Implicit steps per sample interval of a rate family (default 4; the scheme
        is first order). Refused with ``family="pi"`` (exact events).
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
    request = dict(locals())
    if family != "pi" or substeps is not None:
        if check_flag("asymmetric", asymmetric):
            raise ValueError(
                "`asymmetric`=True fits the PI model's two directions (family 'pi'); the rate "
                f"families have one level; got asymmetric=True with family {family!r}."
            )
        return _fit_rate(request)
    if check_flag("asymmetric", asymmetric):
        return fit_asymmetric(fit_response, request, check_response, asymmetric_parts)
    if isinstance(n_elements, str):
        return choose_order(fit_response, order_options(request))
    checked = check_response(request)
    problem, options = response_problem(checked)
    plan = response_plan(checked, problem, options, refit_with=fit_response)
    return run_fit(problem, options, plan)


def _fit_rate(request: dict) -> FitResult:
    """`fit_response` of a rate family (`_rate_plan`); ``family="pi"`` refuses `substeps`."""
    from presliding.identification.plans._rate_plan import check_rate, rate_plan, rate_problem

    if request["family"] == "pi":
        raise ValueError(
            "`substeps` sets the implicit steps of a rate family (family 'gms', 'lugre' or "
            f"'dahl'); got {request['substeps']!r} with family 'pi' (exact events)."
        )
    checked, spec, substeps = check_rate(request)
    problem, options = rate_problem(checked, spec, substeps)
    return run_fit(problem, options, rate_plan(checked, spec, pi_fit=fit_response))
