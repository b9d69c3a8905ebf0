"""Inputs as users bring them (issue 34, item 3): rounded decimals, records that start at rest,
too short or never moving, starts that are not finite, lmfit values of NaN."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import Measurement, PIFriction, fit_response
from presliding.identification.judge._noise_floor import noise_variance, record_floors
from presliding.identification.problem._fit_problem import FitProblem
from presliding.identification.problem._model_spec import ModelSpec, _spread
from presliding.identification.records import _pooled_problem as pp
from presliding.identification.records._pooled_record import as_record
from presliding.identification.records._response_tools import equal_breakaway_stiffness
from tests.helpers import sine_records

MODEL = PIFriction(0.2, [6000.0, 2000.0, 700.0], breakaway=[0.2, 0.2, 0.2])


def test_positions_printed_with_four_decimals_have_that_quantum_even_where_a_record_rests():
    """Positions in mm printed with 4 decimals (a quantum of 1e-7 m): a record that hardly
    moves shows too few steps for a quantum of its own, and its floor came out at the
    round-off level (the noise-floor rule said "record 6 (1.44e+08×)")."""
    records = sine_records(0, MODEL, n_records=3, samples=200)
    t = records[0].time
    still = np.where(t < 0.1, 0.0, 1e-7) + 0.01234  # one step of one printed digit
    printed = [Measurement(m.time, position=np.round(m.position * 1e3, 4) / 1e3,
                           applied_force=m.applied_force) for m in records]  # fmt: skip
    printed.append(Measurement(t, position=np.round(still * 1e3, 4) / 1e3,
                               applied_force=records[0].applied_force))  # fmt: skip
    problem = pp.PooledProblem([as_record(m) for m in printed], ModelSpec(3, True, None, 32),
                               (0.0, 1.0), "preload", offset=False, suffix=True)  # fmt: skip
    floors = record_floors(problem)
    assert floors[-1] >= (1e-7) ** 2 / 12 * 0.99  # the printed digit's rounding, q²/12
    assert noise_variance(np.round(still * 1e3, 4) / 1e3) >= (1e-7) ** 2 / 12 * 0.99


def test_a_record_starting_at_rest_takes_its_direction_from_its_first_motion():
    """At rest, the first difference quotient is noise: its sign gave the preload's direction
    (two rotary records got −1 while moving positive, their preload intervals off by z −237).
    The first displacement beyond the noise and quantum gives it now."""
    t = np.arange(300) * 1e-3
    rng = np.random.default_rng(3)
    true = np.where(t < 0.05, 0.0, 0.02 * (t - 0.05) ** 2)
    y = 1e-7 * np.round((true + 5e-8 * rng.standard_normal(300)) / 1e-7)
    y[1] = y[0] - 1e-7  # the noise's first step is negative
    m = Measurement(t, position=y, applied_force=np.where(t < 0.05, 0.0, 0.1))
    rec = as_record(m)
    assert rec.velocity[0] < 0  # the first sample of the quotient points the wrong way
    assert rec.direction == 1.0


def test_start_stiffnesses_are_finite_where_the_curve_wants_an_element_less():
    """The equal-break-away solve drove an unwanted element's log-stiffness to −inf: its
    stiffness came out 0, `_spread` took its logarithm and every start stiffness was NaN (a
    50-sample record with N = 4 ran 3.5 min without ending)."""
    grid = np.geomspace(1e-6, 1e-3, 32)
    weight = np.zeros(32)
    weight[0] = 7130.22331575
    k = equal_breakaway_stiffness(grid, weight, 0.0020174537003809423, 4)
    assert np.all(np.isfinite(k)) and np.all(k > 0)
    assert np.all(np.isfinite(_spread(np.array([1000.0, 0.0, 10.0]))))


def test_a_start_value_that_is_not_finite_is_an_error_naming_it():
    with pytest.raises(ValueError, match="start value of `stiffness_2` came out nan"):
        FitProblem(("stiffness_1", "stiffness_2"), {"stiffness_1": 1.0, "stiffness_2": np.nan},
                   {}, {}, {})  # fmt: skip


def test_a_record_too_short_or_never_moving_is_refused_naming_it():
    """A 3-sample record among others ended ``max_evaluations``; a record that never moves
    was refused without saying which."""
    records = sine_records(0, MODEL, n_records=2, samples=200)
    m = records[0]
    short = Measurement(m.time[:3], position=m.position[:3], applied_force=m.applied_force[:3])
    with pytest.raises(ValueError, match=r"`records\[1\]` must have at least 8 samples.*got 3"):
        fit_response([records[1], short], 3, signal="position")
    still = Measurement(m.time, position=np.full(200, 1e-3), applied_force=m.applied_force)
    with pytest.raises(ValueError, match=r"`records\[1\]` must move"):
        fit_response([records[1], still], 3, signal="position")


def test_an_lmfit_value_or_bound_of_nan_is_refused_not_ignored():
    """A NaN value of a varied parameter was taken for "no start" and a NaN bound for none
    (issue 37: a NaN in lmfit.Parameters went through); a fixed NaN is refused as before."""
    lmfit = pytest.importorskip("lmfit")
    from presliding.identification.problem._parameters import from_lmfit

    for kw in ({"value": np.nan}, {"value": 0.1, "min": np.nan}, {"value": np.nan, "vary": False}):
        params = lmfit.Parameters()
        params.add("coulomb", **kw)
        with pytest.raises(ValueError, match=r"`initial\['coulomb'\]"):
            from_lmfit(params)
    params = lmfit.Parameters()
    params.add("coulomb")  # lmfit's default value −inf of a varied parameter: no start
    assert from_lmfit(params)[0] == {}
