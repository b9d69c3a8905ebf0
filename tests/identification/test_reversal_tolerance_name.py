"""One name for the reversal tolerance everywhere, and cross-validation in the axis' units."""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np
import pytest

import presliding as ps
from presliding.identification import predict_record
from tests.helpers import stop_records

MODEL = ps.PIFriction(0.3, [4000.0], breakaway=[0.35])


@pytest.fixture(scope="module")
def records():
    recs, _ = stop_records(21, 3, MODEL, quantum=1e-6)
    return recs


def test_predict_record_takes_reversal_tolerance(records):
    """`predict_record(reversal_tolerance=...)` raised TypeError: it was called `tolerance`."""
    pred = predict_record(MODEL, 2.0, records[0], signal="position", reversal_tolerance=5e-6)
    assert pred.reversal_tolerance == 5e-6
    with pytest.warns(DeprecationWarning, match="`tolerance` is renamed `reversal_tolerance`"):
        old = predict_record(MODEL, 2.0, records[0], signal="position", tolerance=5e-6)
    assert old.reversal_tolerance == 5e-6 and old.nrmse == pred.nrmse
    with pytest.raises(TypeError, match="give `reversal_tolerance` only"):
        predict_record(MODEL, 2.0, records[0], tolerance=1e-6, reversal_tolerance=1e-6)
    with pytest.raises(TypeError, match="unexpected keyword argument 'tolerence'"):
        predict_record(MODEL, 2.0, records[0], tolerence=1e-6)
    with pytest.raises(ValueError, match="`reversal_tolerance` must be nonnegative"):
        predict_record(MODEL, 2.0, records[0], reversal_tolerance=-1.0)


def test_fit_predict_takes_reversal_tolerance(records):
    fit = ps.fit_response(records[:2], 1, signal="position")
    pred = fit.predict(records[2], initial="measured", reversal_tolerance=1.0)
    assert pred.reversal_tolerance == 1.0 and pred.measured_reversals == 0
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        fit.predict(records[2], initial="measured", reversal_tolerance=2e-6)  # no warning
    with pytest.warns(DeprecationWarning, match="renamed `reversal_tolerance`"):
        old = fit.predict(records[2], initial="measured", tolerance=1.0)
    assert old.reversal_tolerance == 1.0


def test_the_cross_validation_table_is_in_the_axis_units(records):
    """A rotary record's tolerance was printed as "0.00188 m"."""
    rotary = [replace(m, axis="rotary") for m in records[:2]]
    assert all(m.axis == "rotary" for m in rotary)
    cv = ps.cross_validate(rotary, "response", n_elements=1, signal="position",
                           reversal_tolerance=3e-6)  # fmt: skip
    text = cv.report()
    assert "tolerance of 3e-06 rad (3 encoder counts of 1e-06 rad)" in text, text
    assert "rest error [rad]" in cv.table()[0][6]
    assert " m " not in text.split("reversals counted")[1]
    frame = pytest.importorskip("pandas") and cv.to_pandas()
    assert frame.attrs["units"]["measured_rest"] == "rad"
    assert np.all(np.isfinite(cv.nrmse))
