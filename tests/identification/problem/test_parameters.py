"""Parameters the way users know them: initial, bounds, fixed, tied and lmfit.Parameters,
one checker for every fit, contradictions refused with one sentence naming both."""

from __future__ import annotations

import numpy as np
import pytest
from presliding.identification.measurement import Measurement

import presliding as ps
from presliding.identification.problem._parameters import (
    from_lmfit,
    kept_parameters,
    resolve_parameters,
    to_lmfit,
)
from presliding.signals import piecewise_linear

lmfit = pytest.importorskip("lmfit")

T = np.arange(400) * 1e-3
MEAS = Measurement(T, velocity=np.sin(20 * T) * np.exp(-3 * T), applied_force=np.cos(5 * T))


def _loops():
    y = piecewise_linear([0.0, 0.8, -0.8, 0.4, -0.2, 0.6, -0.6], 1e-3)
    model = ps.PIFriction(0.2, [500.0, 50.0], [1.0, 1.0])
    f = model.force(y)[0] + np.random.default_rng(3).normal(0.0, 0.01, y.shape)
    return y, f


@pytest.mark.parametrize(
    ("kwargs", "first", "second"),
    [
        ({"mass": 1.0, "fixed": {"mass": 2.0}}, "`mass`", "`fixed['mass']`"),
        (
            {"coulomb_level": 1.0, "fixed": {"coulomb_level": 2.0}},
            "`coulomb_level`",
            "`fixed['coulomb_level']`",
        ),
        ({"coulomb_level": 1.0, "min_coulomb_level": 2.0}, "`coulomb_level`", "min_coulomb"),
        ({"initial": {"mass": 1.0}, "fixed": {"mass": 2.0}}, "`initial['mass']`", "`fixed"),
        ({"fixed": {"mass": 5.0}, "bounds": {"mass": (0.0, 2.0)}}, "`fixed['mass']`", "`bounds"),
        ({"initial": {"mass": 5.0}, "bounds": {"mass": (0.0, 2.0)}}, "`initial", "`bounds"),
        ({"fixed": {"mass": 1.0}, "tied": {"mass": "coulomb"}}, "`fixed['mass']`", "`tied"),
    ],
)
def test_every_contradictory_pair_is_refused_naming_both(kwargs, first, second):
    with pytest.raises(ValueError, match="contradict each other") as err:
        ps.fit_response(MEAS, 2, **kwargs)
    text = str(err.value)
    assert first in text and second in text and text.count(".") >= 1


def test_equal_values_are_not_a_contradiction():
    fix = resolve_parameters(None, None, {"mass": 2.0}, None, {"mass": 2.0})[2]
    assert fix == {"mass": 2.0}


def test_prune_must_be_a_bool():
    with pytest.raises(TypeError, match="`prune` must be True or False; got str"):
        ps.fit_response(MEAS, 2, prune="no")


def test_quasi_static_contradiction_and_separable_fits_too():
    y, f = _loops()
    with pytest.raises(ValueError, match="contradict each other"):
        ps.fit_presliding(y, f, 2, fixed={"coulomb": 5.0}, bounds={"coulomb": (0.0, 1.0)})
    with pytest.raises(ValueError, match="`initial` must name parameters"):
        ps.fit_presliding(y, f, 2, initial={"mass": 1.0})


def test_lmfit_parameters_round_trip_values_bounds_vary_and_linear_ties():
    params = lmfit.Parameters()
    params.add("coulomb", value=0.1, min=0.0, max=0.5)
    params.add("stiffness_1", value=400.0, min=0.0)
    params.add("stiffness_2", value=60.0, vary=True)
    params.add("threshold_1", value=0.002, vary=False)
    params.add("threshold_2", expr="1.0*threshold_1 + 0.0")
    initial, bounds, fixed, tied = from_lmfit(params)
    assert initial == {"coulomb": 0.1, "stiffness_1": 400.0, "stiffness_2": 60.0}
    assert bounds["coulomb"] == (0.0, 0.5) and bounds["stiffness_1"] == (0.0, np.inf)
    assert fixed == {"threshold_1": 0.002} and tied == {"threshold_2": ("threshold_1", 1.0, 0.0)}
    y, f = _loops()
    res = ps.fit_presliding(y, f, 2, initial=params)
    assert res.parameters["threshold_1"] == 0.002 == res.parameters["threshold_2"]
    assert "threshold_1" in res.fixed and "threshold_2" in res.tied
    assert res.bounds["coulomb"] == (0.0, 0.5)
    back = res.to_lmfit()
    assert isinstance(back, lmfit.Parameters)
    assert back["threshold_1"].vary is False and back["coulomb"].max == 0.5
    assert back["stiffness_1"].value == res.parameters["stiffness_1"]
    assert back["threshold_2"].expr is not None
    again = from_lmfit(back)
    assert again[2] == {"threshold_1": 0.002}


@pytest.mark.parametrize("expr", ["2*a + 1", "a*2 - 1", "a + 3", "a", "-0.5 * a"])
def test_linear_ties_are_read(expr):
    params = lmfit.Parameters()
    params.add("a", value=1.0)
    params.add("b", expr=expr)
    assert from_lmfit(params)[3]["b"][0] == "a"


def test_a_tie_that_is_not_linear_is_refused():
    params = lmfit.Parameters()
    params.add("a", value=1.0)
    params.add("b", expr="a**2")
    with pytest.raises(ValueError, match="linear tie"):
        from_lmfit(params)


def test_a_linear_tie_with_offset_holds_in_the_fit():
    y, f = _loops()
    res = ps.fit_presliding(y, f, 2, tied={"stiffness_2": ("stiffness_1", 0.1, 5.0)})
    assert res.parameters["stiffness_2"] == pytest.approx(0.1 * res.parameters["stiffness_1"] + 5)


def test_prune_keeps_the_users_entries_of_the_elements_left():
    given = {
        "fixed": {"mass": 2.0, "stiffness_3": 10.0},
        "tied": {"breakaway_2": "breakaway_1"},
        "bounds": {"coulomb": (0.0, 1.0), "stiffness_4": (0.0, 5.0)},
    }
    kept = kept_parameters(given, 2)
    assert kept["fixed"] == {"mass": 2.0}
    assert kept["tied"] == {"breakaway_2": "breakaway_1"}
    assert kept["bounds"] == {"coulomb": (0.0, 1.0)}


def test_to_lmfit_names_the_extra_when_lmfit_is_missing(monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "lmfit", None)  # an import of lmfit now fails
    with pytest.raises(ImportError, match=r'pip install "presliding\[lmfit\]"'):
        to_lmfit({"a": 1.0}, {}, (), {})


def test_min_coulomb_level_far_above_the_data_is_a_poor_fit_naming_the_bound():
    dt, n = 2.5e-4, 3000
    t = np.arange(n) * dt
    u = np.select([t < 0.15, t < 0.35, t < 0.5], [2.0, -2.0, 2.0], 0.0)
    model = ps.PIFriction(0.3, [4000.0, 2000.0], breakaway=[0.35, 0.35])
    res = ps.simulate(model, 2.0, applied_force=(t, u), initial_velocity=0.05,
                      initial_state="saturated", t_eval=t)  # fmt: skip
    noise = 1e-4 * np.random.default_rng(0).standard_normal(n)
    fit = ps.fit_response(Measurement(t, velocity=res.velocity + noise, applied_force=u), 2,
                          min_coulomb_level=1000.0)  # fmt: skip
    # the level is held far above the data: never converged. The mass scales with it (eq.
    # 17's scale: mass and forces up together): a ridge the judge reports as not
    # identifiable naming the level, the bound, or an optimum far up that scale whose
    # residual the search finds hundreds of times the noise floor (a local minimum)
    assert fit.status in ("poor_fit", "failed", "not_identifiable", "at_bound", "local_minimum")
    assert not fit.success
    if fit.status == "local_minimum":
        assert fit.search is not None and fit.search.residual_over_floor > 10
        assert fit.parameters["mass"] > 100 * 2.0  # far up the scale, not a rescaled truth
    else:
        assert "coulomb_level" in fit.message
    assert all(np.isfinite(v) for v in fit.parameters.values())
    assert np.isfinite(fit.residual_rms) and np.isfinite(fit.nrmse)
