"""Held-out predictions report both starts, the record's own parameters and the tolerance."""

from __future__ import annotations

import numpy as np
import pytest

import presliding as ps
from tests.helpers import stop_records

MODEL = ps.PIFriction(0.3, [4000.0, 1000.0], breakaway=[0.35, 0.35])


@pytest.fixture(scope="module")
def cv():
    records, _ = stop_records(11, 3, MODEL, quantum=1e-6)
    return ps.cross_validate(records, "response", n_elements=2, signal="both",
                             initial_state="preload")  # fmt: skip


def test_both_starts_are_predicted_and_tabled(cv):
    assert len(cv.alternatives) == len(cv.predictions) == 3
    assert {p.initial for p in cv.predictions} == {"fit"}
    assert {p.initial for p in cv.alternatives} == {"measured"}
    header, *rows = cv.table()
    assert "NRMSE % (measured start)" in header and "NRMSE % (fitted start)" in header
    for row, fitted, measured in zip(rows, cv.predictions, cv.alternatives, strict=True):
        assert row[2] == f"{100 * measured.nrmse:.3g}" and row[3] == f"{100 * fitted.nrmse:.3g}"
        # every parameter the fitted start took from the held-out record is named
        assert set(row[-1].split(", ")) == set(fitted.parameters)
        assert {"initial_position", "initial_velocity"} <= set(fitted.parameters)
    report = cv.report()
    assert "median NRMSE from the measured start" in report
    assert "encoder counts of 1e-06 m" in report


def test_the_reversal_tolerance_is_the_users():
    records, _ = stop_records(11, 2, MODEL, quantum=1e-6)
    wide = ps.cross_validate(records, "response", n_elements=2, reversal_tolerance=1.0)
    assert all(p.measured_reversals == 0 and p.predicted_reversals == 0
               for p in wide.predictions)  # fmt: skip
    assert all(p.reversal_tolerance == 1.0 for p in (*wide.predictions, *wide.alternatives))
    assert "tolerance of 1 m (1e+06 encoder counts" in wide.report()
    with pytest.raises(ValueError, match="`reversal_tolerance` must be"):
        ps.cross_validate(records, "response", n_elements=2, reversal_tolerance=-1.0)


def test_a_prediction_names_what_it_took_from_the_record():
    records, _ = stop_records(12, 2, MODEL, quantum=1e-6)
    fit = ps.fit_response(records[0], 2)
    pred = fit.predict(records[1], initial="measured", reversal_tolerance=3e-6)
    assert pred.initial == "measured" and pred.reversal_tolerance == 3e-6
    assert pred.quantum == pytest.approx(1e-6)
    assert set(pred.from_record.values()) <= {"its first samples"}
    text = pred.report()
    assert "start: measured (first samples)" in text
    assert "3 encoder counts" in text
    assert ps.reversal_tolerance(records[1].position) == pytest.approx(3e-6, rel=1e-6)
    assert np.isfinite(pred.nrmse)


def test_the_report_fits_a_page_and_says_why_a_left_out_fit_did_not_converge(cv):
    """The table was 254 columns wide and a fold's status came without its reason."""
    import dataclasses

    table = cv.report().split("  median NRMSE")[0].splitlines()
    assert max(len(line) for line in table) <= 100, table
    assert "fitted to each held-out record: initial_position" in cv.report()
    reason = "rule correlation: the data do not separate stiffness_1 ~ stiffness_2"
    odd = dataclasses.replace(cv.fits[1], status="not_identifiable", message=reason)
    fits = (cv.fits[0], odd, *cv.fits[2:])
    report = dataclasses.replace(cv, fits=fits).report()
    said = [ln for ln in report.splitlines() if f"{cv.labels[1]}: fit not_identifiable" in ln]
    assert len(said) == 1 and "rule correlation: the data do not separate" in said[0]
    assert len(said[0]) <= 100
