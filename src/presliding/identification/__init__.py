"""Identification from measurements (section 4).

Files
-----
measurement.py      `Measurement`: checking, windowing, resampling and differentiating signals
_measurement_readers.py   `Measurement.from_csv`, `from_mat`, `from_dataframe`, `join`
_readers.py         delimited text: delimiters, headers or none, BOM, bad cells named
_mat.py             MATLAB files: variables checked, clear errors for other files
_frames.py          pandas DataFrames (pandas imported only when used)
_join.py            `Measurement.join`: per-signal records on one time base
_units.py           units in column headers → SI factors (pint), parameter units
_source.py          `Source`: the file, columns, units, factors and window of a measurement
_status.py          the poor-fit test: explained variance, parameters on bounds, likely causes
fit_presliding.py   `fit_presliding`, `fit_virgin_curve`: force against displacement (eqs. 4–9)
fit_motion.py       `fit_motion`: eq. 17 as a regression (the inverse model)
fit_response.py     `fit_response`: simulated against measured motion (output error)
fit_result.py       `FitResult`, the least-squares driver shared by the fits
_least_squares.py   the solver around scipy.optimize.least_squares (bounds, ties, statistics)
_pi_regression.py   separable least squares over the PI thresholds; the fused batch loss
_global_search.py   differential evolution over thresholds for `fit_presliding`
_response_tools.py, _response_checks.py   the compiled response simulator, starts and checks
_filters.py         zero-phase filters and derivative estimates

May import: `presliding.motion`, `presliding.analysis`, `presliding.friction`,
`presliding.hysteresis` and the root's shared modules.
"""

from presliding.identification.fit_motion import fit_motion, predict_motion_force
from presliding.identification.fit_presliding import fit_presliding, fit_virgin_curve
from presliding.identification.fit_response import fit_response
from presliding.identification.fit_result import FitResult
from presliding.identification.measurement import Measurement

__all__ = [
    "FitResult",
    "Measurement",
    "fit_motion",
    "fit_presliding",
    "fit_response",
    "fit_virgin_curve",
    "predict_motion_force",
]
