"""Motion-equation fit: eq. 17 as a regression (the inverse model of section 4).

With the measured driving force u, displacement y, velocity ẏ and acceleration
ÿ, eq. 17 (with optional viscous and offset terms that real machines need) reads

    m·ÿ + c1·sign(ẏ) + Σ_j k_j (y − x_j(y, r_j)) [+ F_v·ẏ] [+ F_0] = u.

Every parameter but the thresholds r_j enters linearly: at fixed thresholds
this is linear least squares (the classical "inverse dynamic identification
model" when there are no elements); the thresholds follow by nonlinear least
squares from a start found on a threshold grid (`presliding.identification.problem._pi_regression`).

With ``asymmetric=True`` the symmetric fit (no offset) runs first, the
asymmetric one also starts from its thresholds (its residual is then never the
larger), and ``result.asymmetry`` tests the difference of the sides
(`presliding.identification.judge._asymmetry`).

When u = 0 throughout (a free response) the equation is homogeneous: the
mass and every force are determined only up to a common factor. Fix the mass
(``fixed={"mass": m}``) or use `fit_response`, which reports them per unit mass.
"""

from __future__ import annotations

from collections.abc import Mapping
from functools import partial
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._progress import Progress
from presliding._validation import as_nonnegative_scalar, fmt
from presliding.friction.pi_friction import PIFriction
from presliding.identification._fit_engine import FitPlan, FitRun, Found, run_fit
from presliding.identification.fit_presliding import (
    _with_note,
    check_enough,
    check_fit_options,
    check_varies,
    derived_quantities,
    element_count,
    pi_model,
)
from presliding.identification.fit_result import FitResult, Tie
from presliding.identification.judge._status import sign_hint
from presliding.identification.problem import _pi_regression as pr
from presliding.identification.problem._fit_problem import FitOptions
from presliding.identification.problem._parameters import check_flag, resolve_parameters
from presliding.identification.problem._separable_adequacy import separable_adequacy
from presliding.identification.problem._separable_problem import Separable, separable_problem
from presliding.identification.result._fit_progress import FitProgress, as_reporter, shows_progress
from presliding.measurement.measurement import Measurement

__all__ = ["fit_motion", "predict_motion_force"]

FloatArray = NDArray[np.float64]
_NONNEGATIVE = (0.0, np.inf)
_BOUNDED = ("mass", "coulomb", "viscous", "coulomb_negative", "viscous_negative")


def _design(
    m: Measurement, viscous: bool, offset: bool, asymmetric: bool = False
) -> tuple[FloatArray, tuple[str, ...]]:
    velocity, acceleration = m.require("velocity", "acceleration")
    if asymmetric:  # c1⁺ while ẏ > 0, −c1⁻ while ẏ < 0; σ⁺·ẏ and σ⁻·ẏ likewise
        pos, neg = velocity > 0, velocity < 0
        columns = [acceleration, pos * 1.0, -1.0 * neg]
        names = ["mass", "coulomb", "coulomb_negative"]
        if viscous:
            columns += [np.where(pos, velocity, 0.0), np.where(neg, velocity, 0.0)]
            names += ["viscous", "viscous_negative"]
        return np.column_stack(columns), tuple(names)
    columns = [acceleration, np.sign(velocity)]
    names = ["mass", "coulomb"]
    if viscous:
        columns.append(velocity)
        names.append("viscous")
    if offset:
        columns.append(np.ones(m.n_samples))
        names.append("offset")
    return np.column_stack(columns), tuple(names)


@shows_progress("fit_motion")
def fit_motion(
    measurement: Measurement,
    n_elements: int | None = None,
    thresholds: ArrayLike | None = None,
    *,
    viscous: bool = False,
    offset: bool = False,
    asymmetric: bool = False,
    min_speed: float = 0.0,
    refine_thresholds: bool = True,
    fixed: Mapping[str, float] | None = None,
    tied: Mapping[str, Tie] | None = None,
    initial: Mapping[str, float] | Any = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    level: float = 0.95,
    grid_size: int = pr.DEFAULT_GRID,
    max_evaluations: int | None = None,
    tolerance: float = 1e-8,
    progress: bool | Progress | FitProgress = False,
) -> FitResult:
    """Fit mass and friction parameters of eq. 17 by (separable) least squares.

    Parameters
    ----------
    measurement : Measurement
        Must hold `position`, `velocity`, `acceleration` and `applied_force`
        (estimate the derivatives with ``measurement.differentiate(cutoff)``).
    n_elements : int, optional
        Number N of elasto-plastic elements (default 0: mass, Coulomb and the
        optional terms only; or ``len(thresholds)``).
    thresholds : array_like, shape (N,), optional
        Start values r_j [m] instead of the grid search.
    viscous : bool
        Add F_v·ẏ (parameter ``viscous`` >= 0).
    offset : bool
        Add a constant force F_0 (parameter ``offset``).
    asymmetric : bool
        Asymmetric friction: separate Coulomb elements c1⁺ (``coulomb``, while
        ẏ > 0) and c1⁻ (``coulomb_negative``, while ẏ < 0), and with `viscous`
        separate σ⁺ (``viscous``) and σ⁻ (``viscous_negative``). The elements
        stay symmetric. Excludes `offset`: while the mass slides, a constant
        force is the same column as c1⁺ − c1⁻ (the offset is absorbed into
        (c1⁺ − c1⁻)/2). ``result.asymmetry`` tests the sides against the
        symmetric fit (module notes).
    min_speed : float
        Samples with |ẏ| <= min_speed are left out of the residual (at rest the
        Coulomb force is set-valued, and sign(ẏ) of a noisy estimate is
        unreliable); the play operators still run through them.
    refine_thresholds : bool
        False keeps the thresholds at their start (a purely linear fit).
    fixed, tied : mapping, optional
        Held or tied parameters: ``mass``, ``coulomb``, ``viscous``, ``offset``,
        ``stiffness_j``, ``threshold_j`` (``coulomb_negative`` and
        ``viscous_negative`` with `asymmetric`).
    initial : mapping or lmfit.Parameters, optional
        Start values by name (others from the linear start); an
        ``lmfit.Parameters`` gives values, bounds, fixed values and linear ties.
    bounds : mapping name -> (lower, upper), optional
        Bounds on any parameter, within its natural ones (stiffness >= 0, ...).
        Contradictory arguments (a fixed or start value outside them) are refused.
    level, grid_size, max_evaluations, tolerance : as in `fit_presliding`
        Confidence level in (0, 1), grid size >= 2, evaluation limit >= 1 (or
        None) and a positive tolerance.
    progress : bool or presliding._progress.Progress
        As in `fit_presliding`.

    Returns
    -------
    FitResult
        Fitted applied force against time; ``model`` is the PI friction model
        (Coulomb element c1, the elements and the viscous term σ = ``viscous``;
        the offset F_0 is in `parameters` only: the measured force is
        u = m·ÿ + F + F_0).
    """
    request = dict(locals())
    n = _check_request(measurement, n_elements, thresholds, asymmetric, offset)
    min_speed = as_nonnegative_scalar("min_speed", min_speed)
    initial, bounds, fixed, tied = resolve_parameters(initial, bounds, fixed, tied)
    fixed, tied, level, grid_size, max_evaluations, tolerance = check_fit_options(
        fixed, tied, level, grid_size, max_evaluations, tolerance
    )
    sep = _motion_model(measurement, n, viscous, offset, asymmetric, min_speed, fixed)
    names, position = sep.x_names, measurement.require("position")[0]
    problem = partial(
        separable_problem, sep, {k: _NONNEGATIVE for k in _BOUNDED if k in names},
        grid=pr.threshold_grid(position, grid_size), refine_thresholds=refine_thresholds,
        fixed=fixed, tied=tied, progress=as_reporter(progress), user_initial=initial,
        user_bounds=bounds,
    )  # fmt: skip
    options = FitOptions(level, max_evaluations, tolerance, progress=as_reporter(progress))
    result = partial(_result, sep, measurement, viscous or asymmetric)
    adequacy = partial(_adequacy, sep, measurement)
    if check_flag("asymmetric", asymmetric):
        return _fit_sided(request, problem, thresholds, result, options, viscous, adequacy)
    plan = FitPlan(search=lambda run: Found(run.problem.solve(run.options)), result=result,
                   adequacy=adequacy)  # fmt: skip
    return run_fit(problem(thresholds=thresholds), options, plan)


def _fit_sided(request: dict[str, Any], problem: Any, thresholds: Any, result: Any,
               options: FitOptions, viscous: bool, adequacy: Any) -> FitResult:  # fmt: skip
    """``asymmetric=True``: the symmetric fit, then the asymmetric one (module notes)."""
    from presliding.identification.plans._asymmetric_plan import fit_nested, split_negative

    symmetric = fit_motion(**{**split_negative(request), "asymmetric": False})
    rows = [{"coulomb_negative": 1.0, "coulomb": -1.0}]
    rows += [{"viscous_negative": 1.0, "viscous": -1.0}] if viscous else []
    return fit_nested(problem, thresholds, symmetric, result, rows, options, adequacy)


def _check_request(measurement: Any, n_elements: Any, thresholds: Any, asymmetric: Any,
                   offset: bool) -> int:  # fmt: skip
    """The measurement's signals and the model's options checked; the number of elements."""
    if not isinstance(measurement, Measurement):
        raise TypeError(f"`measurement` must be a Measurement; got {type(measurement).__name__}.")
    measurement.require(
        "position", "velocity", "acceleration", "applied_force", purpose="fit_motion"
    )
    n = element_count(n_elements, thresholds, 0)
    if not isinstance(asymmetric, (bool, np.bool_)):
        raise TypeError(f"`asymmetric` must be True or False; got {fmt(asymmetric)}.")
    if asymmetric and offset:
        raise ValueError(
            "`offset` must be False with `asymmetric`=True: while the mass slides a constant "
            "force is the same column as c1⁺ − c1⁻ (the fit absorbs it into the two Coulomb "
            "levels); got offset=True."
        )
    return n


def _motion_model(m: Measurement, n: int, viscous: bool, offset: bool, asymmetric: bool,
                  min_speed: float, fixed: Mapping[str, float]) -> Separable:  # fmt: skip
    """Eq. 17 on the measurement as a separable model, its data checked."""
    position, velocity, _, u = m.require("position", "velocity", "acceleration", "applied_force")
    if not np.any(u) and "mass" not in fixed:
        raise ValueError(
            "`applied_force` is zero throughout: mass and forces are then determined only up to "
            "a common factor; fix the mass (fixed={'mass': ...}) or use fit_response."
        )
    check_varies("position", position)
    check_varies("velocity", velocity)
    used = np.abs(velocity) > min_speed
    signs = np.sign(velocity[used])
    if (offset or asymmetric) and not (np.any(signs > 0) and np.any(signs < 0)):
        raise ValueError(
            "`velocity` must change sign (among the samples used) to separate the Coulomb force "
            "from the offset (or the two Coulomb levels of `asymmetric`); it keeps one sign."
        )
    if n and pr.reversal_indices(position, 0.0).shape[0] == 0:
        raise ValueError(
            "`position` must reverse at least once to identify presliding elements; got a "
            "monotone path."
        )
    design, names = _design(m, viscous, offset, asymmetric)
    check_enough(int(used.sum()), len(names) + 2 * n)
    return Separable(u, design, names, pr.stop_basis(position), n, used)


def _result(sep: Separable, m: Measurement, sided: bool, run: FitRun, sol: Any, boot: Any,
            found: Any) -> FitResult:  # fmt: skip
    """The public result: the model with σ and the sides; the force against time."""
    u, velocity, used = sep.target, m.require("velocity")[0], sep.used
    model, note = pi_model(sol.values, sep.n_elements, sol.values["coulomb"])
    if model is not None and sided:  # σ and the sides are part of the model
        v = sol.values
        model = PIFriction(model.coulomb, model.stiffness, model.breakaway,
                           viscous=max(v.get("viscous", 0.0), 0.0),
                           coulomb_negative=_side(v, "coulomb_negative"),
                           viscous_negative=_side(v, "viscous_negative"))  # fmt: skip
    rotary = m.axis == "rotary"
    return FitResult.from_solution(
        _with_note(sol, note), model, m.time[used], u[used], sep.fitted(sol.values)[used],
        kind="motion equation (eq. 17)", abscissa_label="time [s]",
        signal_label="applied force", signal_unit="N m" if rotary else "N",
        derived=_derived(model),
        hint=sign_hint(u, np.sign(velocity), "applied force"),
        rotary=rotary,
    )  # fmt: skip


def _adequacy(sep: Separable, m: Measurement, run: FitRun, sol: Any) -> Any:
    """The residual tests (`_separable_adequacy`): the equation error's own noise (it
    combines the force's with the acceleration's)."""
    position, velocity, _, u = m.require("position", "velocity", "acceleration", "applied_force")
    extra = {}
    if "coulomb_negative" not in sep.x_names:
        extra["asymmetry"] = (velocity < 0).astype(float)
    if "viscous" not in sep.x_names:
        extra["velocity"] = velocity
    regressors = {"the applied force": u, "the velocity": velocity,
                  "the direction of motion": np.sign(velocity)}  # fmt: skip
    return separable_adequacy(
        sep,
        sol,
        regressors,
        own_noise=True,
        extra=extra,
        signal="applied force",
        span=float(np.ptp(position)) if sep.n_elements else None,
    )


def _side(values: Mapping[str, float], name: str) -> float | None:
    return max(values[name], 0.0) if name in values else None


def _derived(model: PIFriction | None) -> dict[str, float]:
    """F_c (eq. 9), F_m and Σ k_j (eq. 7); F_c⁺ and F_c⁻ of an asymmetric model."""
    if model is None or model.is_symmetric:
        return derived_quantities(model)
    fp, fn = model.coulomb_levels
    return {"coulomb_level": fp, "coulomb_level_negative": fn,
            "initial_stiffness": model.initial_stiffness}  # fmt: skip


def predict_motion_force(result: FitResult, measurement: Measurement) -> FloatArray:
    """The force u that eq. 17 with the fitted parameters predicts along a measurement.

    m·ÿ + c1·sign(ẏ) + Σ k_j (y − x_j) [+ F_v·ẏ] [+ F_0], with the elements
    relaxed at the first sample: use it to validate a `fit_motion` result on
    another record.

    Parameters
    ----------
    result : FitResult
        A result of `fit_motion` (its parameters ``mass``, ``coulomb``, the
        elements' ``stiffness_j`` and ``threshold_j`` and the optional
        ``viscous`` and ``offset``; ``coulomb_negative`` and
        ``viscous_negative`` of an asymmetric fit).
    measurement : Measurement
        Must hold `position`, `velocity` and `acceleration`.

    Returns
    -------
    ndarray, shape (T,)
        The predicted applied force u [N] at every sample of `measurement`.
    """
    if not isinstance(result, FitResult) or "mass" not in result.parameters:
        what = "a FitResult without a mass" if isinstance(result, FitResult) else fmt(result)
        raise TypeError(f"`result` must be a FitResult of fit_motion; got {what}.")
    if not isinstance(measurement, Measurement):
        raise TypeError(f"`measurement` must be a Measurement; got {type(measurement).__name__}.")
    y, v, a = measurement.require("position", "velocity", "acceleration", purpose="the prediction")
    p = result.parameters
    if "coulomb_negative" in p:  # asymmetric: each direction with its own levels
        pos, neg = v > 0, v < 0
        force = p["mass"] * a + p["coulomb"] * pos - p["coulomb_negative"] * neg
        if "viscous" in p:
            force = force + np.where(pos, p["viscous"], p.get("viscous_negative", 0.0)) * v
    else:
        force = p["mass"] * a + p["coulomb"] * np.sign(v)
        force = force + p.get("viscous", 0.0) * v
    force = force + p.get("offset", 0.0)
    n = sum(1 for k in p if k.startswith("stiffness_"))
    if n:
        k_names, r_names = pr.element_names(n)
        k = np.array([p[x] for x in k_names])
        r = np.array([p[x] for x in r_names])
        force = force + pr.stop_basis(y)(r)[0] @ k
    return force
