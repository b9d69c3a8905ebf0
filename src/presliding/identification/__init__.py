"""Identification from measurements (section 4).

Files
-----
_status.py          the one status judge of every fit (its rules tabled), exit codes, hints
_profile.py         profile-likelihood intervals on the least-squares core
_profile_walk.py    the walk to one end of a profile interval (continuation, regula falsi)
_profile_inner.py   a profile point's inner optimisation (LM with per-record steps)
_profile_bound.py   a column vanishing on its bound: profiled inward, its partners' ranges
_normal_equations.py  JᵀJ and its scaled pseudo-inverse (profile, probes, alternatives)
_alternatives.py    other local optima within the profile's threshold: widened intervals
_parameters.py      initial, bounds, fixed, tied and lmfit.Parameters, checked together
_fit_names.py       lmfit's and scipy's names on `FitResult` (aic, bic, redchi, x, to_lmfit)
_fit_report.py      how a `FitResult` shows itself: report, notebook table, pandas, figure
fit_presliding.py   `fit_presliding`: force against displacement (eqs. 4–9)
fit_virgin.py       `fit_virgin_curve`: virgin curves from ramps or loops, pooled, quantised
masing.py           `masing_check`, `MasingCheck`: do measured loops follow a virgin curve?
fit_motion.py       `fit_motion`: eq. 17 as a regression (the inverse model)
fit_response.py     `fit_response`: simulated against measured motion, one or many records pooled
fit_quasi_static.py `fit_quasi_static`: position from a slow force (torque-driven presliding)
fit_result.py       `FitResult`, the public result of every fit
_fit_problem.py     `FitProblem`: what a fit minimises (parameters, residual, Jacobian structure)
_fit_engine.py      `run_fit`: the one pipeline (search, checks, judge, intervals, result)
prediction.py       `Prediction`, `count_reversals`: a fitted model on another record
cross_validation.py `cross_validate`, `CrossValidation`: leave-one-record-out tables
model_prediction.py `predict_record`: a given model (a model file's) predicting a record
uncertainty.py      HAC (Newey–West) covariance, correlations
_covariance.py      a fit's covariance: the HAC sandwich of leverage-adjusted residuals
_deferred.py        a solve whose covariance is deferred until the search keeps it
_least_squares.py   the solver around scipy.optimize.least_squares (bounds, ties, statistics)
_parameter_map.py   the free/fixed/tied split of named parameters
_solution.py        `Solution`: the outcome of one least-squares solve
_fit_options.py     the options every fit shares (level, evaluations, fixed, tied), checked
_fit_progress.py    what a fit shows while it runs (`progress=`): stages, evaluations, generations
_structured_lm.py   Levenberg–Marquardt on structured normal equations (large pooled fits)
_model_spec.py      the fitted models as named parameters (elements, densities)
_pooled_kernel.py   compiled batched responses of many records and parameter sets
_pooled_record.py   a measurement as a pooled record; its velocity as a difference quotient
_pooled_problem.py  the pooled residual and its structured Jacobian
_pooled_jacobian.py the finite differences of that Jacobian, records' columns together
_pooled_banks.py    the banks (c1, k_j, r_j) of many parameter sets as kernel arrays
_pooled_start.py    pooled start values (eq. 17 as a regression)
_quasi_static_problem.py   the pooled quasi-static residual
_quasi_static_start.py     quasi-static start values (eq. 8 as a regression)
_quasi_static_plan.py      `fit_quasi_static` as a problem and its search, checks, result
_quasi_static_kernel.py    compiled quasi-static positions of many records and parameter sets
_quasi_static_errors.py    the error floor of runs of equal quantised samples
_split_check.py     a split of neighbouring elements the records do not determine (a plateau)
_nuisance_search.py  each record's own parameters searched on a grid, the shared ones held
_block_lm.py        Levenberg–Marquardt on every record's own block at once (the grid's polish)
_search.py          the search step: starts, alternation, the noise-floor rule, its summary
_probes.py          probes of the valleys next to the best optimum (engage, corner, split)
_scale_probe.py     the probe along eq. 17's scale (mass and forces together, blocks re-searched)
_flat_probe.py      a far step along the least determined split of the k_j, solved short
_noise_floor.py     the noise floor of the data: quantum and high-frequency noise
_model_order.py     ``n_elements="auto"``: the number of elements by BIC
_response_setup.py, _response_result.py   pooled-fit checks, pruning, bootstrap, result
_response_request.py   `fit_response`'s arguments checked into one request
_response_plan.py   `fit_response` as a problem and its search, checks, refit, result
_predictors.py      how each fit predicts another record
_pi_regression.py   the PI bases and threshold grids of the separable fits; the fused batch loss
_separable_problem.py   the separable fits' problem: linear in all but the thresholds
_global_search.py   differential evolution over thresholds for `fit_presliding`
_response_tools.py, _response_checks.py   response start helpers and checks after a fit
_response_box.py    a pooled response fit's start values and bounds (regression, records, user)
_moved.py           old paths of the modules that moved to `presliding.measurement`

Measurements (`Measurement`, readers, units, filters) live one layer down, in
`presliding.measurement`; their old paths here (`presliding.identification.measurement`,
`presliding.identification._units`, ...) stay importable aliases.

May import: `presliding.measurement`, `presliding.motion`, `presliding.analysis`,
`presliding.friction`, `presliding.hysteresis` and the root's shared modules.
"""

# first: the old paths of the modules that moved to `presliding.measurement`
from presliding.identification import _moved  # noqa: F401  (registers the aliases)
from presliding.identification import fit_presliding as _fit_presliding
from presliding.identification.cross_validation import CrossValidation, cross_validate
from presliding.identification.fit_motion import fit_motion, predict_motion_force
from presliding.identification.fit_presliding import fit_presliding
from presliding.identification.fit_quasi_static import fit_quasi_static
from presliding.identification.fit_response import fit_response
from presliding.identification.fit_result import FitResult
from presliding.identification.fit_virgin import fit_virgin_curve, virgin_samples
from presliding.identification.masing import MasingCheck, masing_check
from presliding.identification.model_prediction import predict_record
from presliding.identification.prediction import Prediction, count_reversals, reversal_tolerance
from presliding.identification.uncertainty import correlation_matrix, hac_covariance
from presliding.measurement.measurement import Measurement

# the virgin-curve fit lived in fit_presliding before: its old names keep working
_fit_presliding.fit_virgin_curve = fit_virgin_curve  # type: ignore[attr-defined]
_fit_presliding.virgin_samples = virgin_samples  # type: ignore[attr-defined]

__all__ = [
    "CrossValidation",
    "FitResult",
    "MasingCheck",
    "Measurement",
    "Prediction",
    "correlation_matrix",
    "count_reversals",
    "cross_validate",
    "fit_motion",
    "fit_presliding",
    "fit_quasi_static",
    "fit_response",
    "fit_virgin_curve",
    "hac_covariance",
    "masing_check",
    "predict_motion_force",
    "predict_record",
    "reversal_tolerance",
]
