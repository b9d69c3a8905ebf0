"""Hardening of the analysis layer: energies that overflow, loop limits, reach of a free motion."""

from __future__ import annotations

import time

import pytest

from presliding import PIFriction, Uniform, total_energy, turning_points
from presliding.analysis.stops import MAX_REVERSALS
from tests.test_validation import assert_rejects

MODEL = PIFriction(0.5, [100.0, 10.0], [1.0, 1.0])
DENSITY_MODEL = PIFriction(0.0, density=Uniform(1.0, 1.0))


def test_total_energy_that_overflows_names_mass_and_velocity():
    state = MODEL.relaxed_state()
    message = assert_rejects(lambda: total_energy(MODEL, 1e200, 1e200, state), ValueError, "mass")
    assert "`velocity`" in message and "got inf" in message
    assert total_energy(MODEL, 2.0, 3.0, state) == 9.0


def test_turning_points_names_the_velocity_that_overflows():
    message = assert_rejects(lambda: turning_points(MODEL, 1, 1e200), ValueError, "mass")
    assert "`initial_velocity`" in message
    # a finite energy whose swing leaves the float range: the reach bound names it too
    tiny = PIFriction(1e-300, [1e-300], [1e-300])
    message = assert_rejects(
        lambda: turning_points(tiny, 1.0, 1e150), ValueError, "initial_velocity"
    )
    assert "reach" in message
    # large but representable motions still run
    res = turning_points(MODEL, 1.0, 1e100)
    assert res.success and abs(res.positions[0]) == pytest.approx(0.5e200 / 2.5, rel=1e-6)


def test_max_reversals_has_a_limit_instead_of_a_hang():
    start = time.perf_counter()
    message = assert_rejects(
        lambda: turning_points(DENSITY_MODEL, 1.0, 1.0, max_reversals=10**9),
        ValueError,
        "max_reversals",
    )
    assert time.perf_counter() - start < 1.0
    assert message == f"`max_reversals` must be at most {MAX_REVERSALS}; got 1000000000."
    res = turning_points(DENSITY_MODEL, 1.0, 1.0, max_reversals=50)
    assert res.status == "never_stops" and res.positions.shape == (50,)
