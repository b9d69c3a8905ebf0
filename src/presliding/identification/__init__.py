"""Identification from measurements (section 4).

Where the fits end and the engine begins: the public modules at this level are the
fits (one verb function each) and what users do with a fit; the engine every fit runs
is `_fit_engine.run_fit`, whose steps live in the rooms below, named in the order a
fit passes through them (problem → search → solve → checks → judge → intervals →
result; `plans` holds each pooled fit's own parts of that pipeline).

Files
-----
fit_presliding.py   `fit_presliding`: force against displacement (eqs. 4–9)
fit_motion.py       `fit_motion`: eq. 17 as a regression (the inverse model)
fit_response.py     `fit_response`: simulated against measured motion, one or many records pooled
fit_quasi_static.py `fit_quasi_static`: position from a slow force (torque-driven presliding)
fit_virgin.py       `fit_virgin_curve`: virgin curves from ramps or loops, pooled, quantised
fit_result.py       `FitResult`, the public result of every fit
rate_families.py    `fit_gms`, `fit_lugre`, `fit_dahl`: the rate families as fitters of a registry
masing.py           `masing_check`, `MasingCheck`: do measured loops follow a virgin curve?
prediction.py       `Prediction`, `count_reversals`: a fitted model on another record
cross_validation.py `cross_validate`, `CrossValidation`: leave-one-record-out tables
fit_comparison.py   `compare_fits`, `FitComparison`: model families side by side
families.py         `FAMILIES`, `register_family`: the families compare_fits knows (registry)
model_prediction.py `predict_record`: a given model (a model file's) predicting a record
uncertainty.py      HAC (Newey–West) covariance, correlations
_fit_engine.py      `run_fit`: the one pipeline (search, checks, judge, intervals, result)
_moved.py           old paths of the modules that moved to `presliding.measurement`

Rooms (sub-packages, each opening with its own map)
---------------------------------------------------
problem/    what a fit minimises: named parameters, options, model spec, separable problems
records/    record-pooled residuals: records, compiled kernels, structured Jacobians, starts
search/     starts, multistart, nuisance grids, probes of neighbouring valleys, model order
solve/      one least-squares solve and its statistics (trust region, structured LM)
checks/     refinements of a found optimum (rigid corner, coalesced elements, splits)
judge/      the one status table of every fit, the noise floor
intervals/  HAC covariance, profile-likelihood intervals, other optima within the threshold
plans/      each pooled fit's own parts of the pipeline (request, box, setup, plan, result)
result/     how a fit shows itself: report, notebook table, lmfit's names, progress

Measurements (`Measurement`, readers, units, filters) live one layer down, in
`presliding.measurement`; their old paths here (`presliding.identification.measurement`,
`presliding.identification._units`, ...) stay importable aliases.

May import: `presliding.measurement`, `presliding.motion`, `presliding.analysis`,
`presliding.friction`, `presliding.hysteresis` and the root's shared modules.
"""

# first: the old paths of the modules that moved to `presliding.measurement`
from presliding.identification import _moved  # noqa: F401  (registers the aliases)
from presliding.identification import fit_presliding as _fit_presliding
from presliding.identification import rate_families as _rate_families  # noqa: F401  (registers)
from presliding.identification.cross_validation import CrossValidation, cross_validate
from presliding.identification.families import CARRIES, FAMILIES, register_family
from presliding.identification.fit_comparison import FitComparison, compare_fits
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
    "CARRIES",
    "FAMILIES",
    "CrossValidation",
    "FitComparison",
    "FitResult",
    "MasingCheck",
    "Measurement",
    "Prediction",
    "compare_fits",
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
    "register_family",
    "reversal_tolerance",
]
