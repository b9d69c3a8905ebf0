"""compare_fits: model families fitted by the same engine to the same records, side by side."""

from __future__ import annotations

import functools

import numpy as np
import pytest

import presliding as ps
from presliding.identification.families import FAMILIES, register_family
from presliding.identification.fit_comparison import compare_fits
from tests.helpers import random_preload_stops

ASYMMETRIC = ps.PIFriction(0.3, [4000.0, 1000.0], breakaway=[0.35, 0.35], coulomb_negative=0.24,
                           breakaway_negative=[0.28, 0.28])  # fmt: skip
FAMILY_OPTIONS = {"pi": {"n_elements": 2}, "pi-asymmetric": {"n_elements": 2}, "coulomb": {}}


@functools.cache
def _records() -> tuple[list, list]:
    """Four stops to fit and two held out, of a model whose −y levels are 0.8 of the +y ones."""
    records = random_preload_stops(5, ASYMMETRIC, n_records=6, samples=500)
    return records[:4], records[4:]


@functools.cache
def _comparison() -> ps.FitComparison:
    fitted, held = _records()
    return compare_fits(fitted, FAMILY_OPTIONS, hold_out=held, initial_state="preload")


def test_the_asymmetric_family_wins_on_asymmetric_records():
    """Records of an asymmetric PI model: pi-asymmetric has the least AIC and BIC and predicts
    the held-out records best; the symmetric PI model beats Coulomb friction."""
    cmp = _comparison()
    assert cmp.best == "pi-asymmetric" and cmp.status == cmp.fits[1].status
    i = cmp.families.index("pi-asymmetric")
    assert np.argmin(cmp.bic) == i and np.argmin(cmp.aic) == i
    assert np.argmin(cmp.held_out_nrmse) == i and cmp.held_out_best == "pi-asymmetric"
    assert cmp.bic[0] < cmp.bic[2]  # elements beat Coulomb friction alone
    assert cmp.n_parameters.tolist() == [f.nvarys for f in cmp.fits]
    assert cmp.n_parameters[1] == cmp.n_parameters[0] + 1  # F_c⁻
    assert cmp.fits[i].asymmetry.verdict == "supported"
    assert len(cmp.predictions[i]) == 2 and cmp.held_out == ("held-out 1", "held-out 2")
    assert all(p.initial == "measured" for p in cmp.predictions[i])


def test_the_table_report_and_frame():
    cmp = _comparison()
    rows = cmp.table()
    assert len(rows) == 4 and rows[2][0] == "pi-asymmetric (supported)"
    assert rows[2][7] == "+0" and rows[1][7].startswith("+")
    assert "the data support pi-asymmetric" in cmp.message and "held out" in cmp.message
    assert "asymmetry supported" in cmp.report()
    frame = cmp.to_pandas()
    assert frame.loc["pi-asymmetric", "supported"] and frame.attrs["best"] == "pi-asymmetric"
    assert cmp.to_dict()["best"] == "pi-asymmetric"


def test_the_held_out_criterion_and_a_fitted_start():
    fitted, held = _records()
    cmp = compare_fits(fitted, {"coulomb": {}}, hold_out=held[0], labels=["stop 5"],
                       criterion="held_out", initial="fit")  # fmt: skip
    assert cmp.best == "coulomb" and cmp.held_out == ("stop 5",)
    assert cmp.held_out_best == "coulomb"
    assert cmp.predictions[0][0].initial == "fit"


def test_a_registered_family_plugs_in():
    """A fitter of the registry's contract (records, **options) -> FitResult is compared with
    the shipped ones; a name taken is refused unless replaced; a fitter returning something
    else is refused."""
    fitted, _ = _records()
    calls = []

    def quick(records, **options):
        calls.append(options)
        return _comparison().fits[0]

    register_family("test-quick", quick)
    try:
        with pytest.raises(ValueError, match="is a family already"):
            register_family("test-quick", quick)
        cmp = compare_fits(fitted, {"test-quick": {"n_elements": 2}}, signal="velocity")
        assert cmp.best == "test-quick" and calls == [{"signal": "velocity", "n_elements": 2}]
        register_family("test-quick", lambda records, **o: 3.0, replace=True)
        with pytest.raises(TypeError, match="must return a FitResult"):
            compare_fits(fitted, "test-quick")
    finally:
        FAMILIES.pop("test-quick", None)


@pytest.mark.parametrize(("kwargs", "error", "match"), [
    ({"candidates": ("pi", "lugre-x")}, ValueError, "must name families of"),
    ({"candidates": ("pi", "pi")}, ValueError, "each family once"),
    ({"candidates": ()}, ValueError, "at least one family"),
    ({"candidates": {"pi": 3}}, TypeError, "must be a mapping of options"),
    ({"criterion": "held_out"}, ValueError, "needs held-out records"),
    ({"criterion": "r2"}, ValueError, "criterion"),
    ({"hold_out": [1.0]}, TypeError, r"`hold_out\[0\]` must be a Measurement"),
])  # fmt: skip
def test_bad_requests_are_refused_before_any_fit(kwargs, error, match):
    fitted, _ = _records()
    with pytest.raises(error, match=match):
        compare_fits(fitted, **kwargs)


def test_register_family_checks_its_arguments():
    with pytest.raises(ValueError, match="letters, digits"):
        register_family("no spaces", lambda r: r)
    with pytest.raises(TypeError, match="callable"):
        register_family("ok-name", 3.0)  # type: ignore[arg-type]


def test_equal_held_out_errors_favour_the_simpler_family():
    """Held-out errors within 0.1 % of the least tie; the family with fewer free parameters
    wins (a PI fit whose elements carry nothing predicts as Coulomb friction does)."""
    from presliding.identification.fit_comparison import _ranked

    score = np.array([0.0771, 0.07712, 0.0770999])
    assert _ranked([0, 1, 2], score, [13, 14, 10], True) == [2, 0, 1]
    assert _ranked([0, 1, 2], score, [13, 14, 10], False) == [2, 0, 1]
    assert _ranked([0, 1], np.array([0.05, 0.0771]), [13, 10], True) == [0, 1]
