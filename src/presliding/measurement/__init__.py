"""Measured signals: reading, units, joining, windows, filters and derivatives.

A rig's record becomes a `Measurement` here, before any friction model is
involved: files and DataFrames are read, header units converted to SI, signals
on their own files joined onto one time base, windows cut, and velocity and
acceleration estimated with zero-phase filters.

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
segments.py         `Measurement.segments`, `Segments`: stops, loops and ramps cut from a record
_filters.py         zero-phase filters and derivative estimates
_summary.py         what a `Measurement` shows in a notebook (`_repr_html_`)

May import: the root's shared modules only (it needs no friction model).
"""

# the filters stay reachable where `presliding.measurement` (a module before) had them
from presliding.measurement.measurement import Measurement, estimate_derivatives, lowpass  # noqa: F401
from presliding.measurement.segments import Segments

__all__ = ["Measurement", "Segments"]
