"""The fit engine: saturated starts in the first motion's direction, mirror symmetry."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import (
    Measurement,
    PIFriction,
    fit_quasi_static,
    fit_response,
    preloaded_state,
    simulate,
)
from tests.helpers import stop_records
from tests.identification.test_fit_quasi_static import _loops

MODEL2 = PIFriction(0.3, [4000.0, 1000.0], breakaway=[0.35, 0.35])
MODEL2_VALUES = {"mass": 2.0, "coulomb_level": 1.0, "coulomb": 0.3, "stiffness_1": 4000.0,
                 "stiffness_2": 1000.0}  # fmt: skip


def _mirror(m: Measurement) -> Measurement:
    neg = lambda a: None if a is None else -a  # noqa: E731
    return Measurement(m.time, position=neg(m.position), velocity=neg(m.velocity),
                       applied_force=neg(m.applied_force))  # fmt: skip


def _stop(d: float, fraction: float | None = None, samples: int = 500) -> Measurement:
    """A stop in direction d from steady sliding (or from a preload fraction·F_m)."""
    t = np.arange(samples) * 1e-3
    u = np.where(t < 0.05, -0.3 * d, 0.0)
    f0 = d * MODEL2.max_elastic_force if fraction is None else fraction * MODEL2.max_elastic_force
    state = preloaded_state(MODEL2, f0, direction=d, position=1e-4)
    res = simulate(MODEL2, 2.0, applied_force=(t, u), initial_position=1e-4,
                   initial_velocity=0.04 * d, initial_state=state, t_eval=t)  # fmt: skip
    return Measurement(t, position=res.position, velocity=res.velocity, applied_force=u)


def test_saturated_start_follows_a_negative_first_motion():
    """A stop moving in −y from steady sliding in −y is fitted exactly from a saturated start
    (the memory used to be saturated in +y for every record: mass 1.46 instead of 2)."""
    fit = fit_response(_stop(-1.0), 2, signal="both")
    for name in ("mass", "coulomb_level", "coulomb"):
        assert fit.parameters[name] == pytest.approx(MODEL2_VALUES[name], rel=1e-6), name
    # one stop from saturation determines the elements' sum, not their split
    total = fit.parameters["stiffness_1"] + fit.parameters["stiffness_2"]
    assert total == pytest.approx(5000.0, rel=1e-6)
    assert fit.status != "converged"


@pytest.mark.parametrize("state", ["saturated", "preload"])
def test_a_record_and_its_mirror_image_give_the_same_parameters(state):
    records, _ = stop_records(1, 3, MODEL2)
    a = fit_response(records, 2, signal="both", initial_state=state)
    b = fit_response([_mirror(r) for r in records], 2, signal="both", initial_state=state)
    assert a.status == b.status
    for name, value in a.parameters.items():
        mirrored = value if name in MODEL2_VALUES else -value
        assert b.parameters[name] == pytest.approx(mirrored, rel=1e-9, abs=1e-15), name
    if state == "preload":
        for name, value in MODEL2_VALUES.items():
            assert a.parameters[name] == pytest.approx(value, rel=1e-6), name


def test_mirror_image_of_torque_loops_gives_the_same_parameters():
    records, _ = _loops(0, 2)
    a = fit_quasi_static(records, 3)
    b = fit_quasi_static([_mirror(r) for r in records], 3)
    assert a.status == b.status == "converged"
    for name, value in a.parameters.items():
        mirrored = -value if name.startswith(("initial_", "preload_")) else value
        assert b.parameters[name] == pytest.approx(mirrored, rel=1e-9, abs=1e-15), name
