"""Bad input to every public entry point of the analysis layer (the review's table)."""

from __future__ import annotations

import pytest

from presliding import (
    CoulombFriction,
    DahlState,
    PIFriction,
    PIState,
    Uniform,
    dissipated_energy,
    elastic_energy,
    phi,
    stops_at_turning_point,
    total_energy,
    turning_point,
    turning_points,
    viscous_dissipation,
)
from tests.helpers import Entry, bad_input_cases, check_bad_input

MODEL = PIFriction(0.3, [100.0, 50.0], [0.2, 0.3])
DENSITY_MODEL = PIFriction(0.3, density=Uniform(2.0, 0.5))
STATE = MODEL.relaxed_state()
POINTS = turning_points(MODEL, 1.0, 0.1)
WRONG_STATE = [
    ("state-wrong-size", {"state": PIState(0.0, [0.0, 0.0, 0.0])}, "state", False),
    ("state-dahl", {"state": DahlState(0.0, 0.0)}, "state", False),
    ("state-str", {"state": "relaxed"}, "state", False),
]
MODELS = [("model-coulomb", {"model": CoulombFriction(0.5)}, "model", False)]
ENTRIES = {
    "turning_points": Entry(
        lambda **a: turning_points(**a),
        {"model": MODEL, "mass": 1.0, "initial_velocity": 0.1},
        {
            "model": "object",
            "mass": "positive",
            "initial_velocity": "real",
            "initial_state": "choice",
            "initial_position": "real",
            "max_reversals": "count0",
        },
        [
            *MODELS,
            (
                "density-huge-reversals",
                {"model": PIFriction(1e-9, density=Uniform(2.0, 0.5)), "max_reversals": 10**9},
                "max_reversals",
                False,
            ),
            ("v0-1e200", {"initial_velocity": 1e200}, "initial_velocity", True),
            ("state-wrong-size", {"initial_state": PIState(0.0, [0.0])}, "initial_state", False),
        ],
    ),
    "phi": Entry(
        lambda **a: phi(**a),
        {"model": MODEL, "displacement": [0.001, 0.01]},
        {"model": "object", "displacement": "real_array"},
        MODELS,
    ),
    "turning_point": Entry(lambda **a: turning_point(**a), {"model": MODEL}, {"model": "object"}),
    "stops_at_turning_point": Entry(
        lambda **a: stops_at_turning_point(**a), {"model": MODEL}, {"model": "object"}, MODELS
    ),
    "total_energy": Entry(
        lambda **a: total_energy(**a),
        {"model": MODEL, "mass": 1.0, "velocity": 0.1, "state": STATE},
        {"model": "object", "mass": "nonnegative", "velocity": "real", "state": "object"},
        [*WRONG_STATE, ("huge", {"mass": 1e200, "velocity": 1e200}, "mass|velocity", False)],
    ),
    "elastic_energy": Entry(
        lambda **a: elastic_energy(**a),
        {"model": MODEL, "state": STATE},
        {"model": "object", "state": "object"},
        WRONG_STATE,
    ),
    "dissipated_energy": Entry(
        lambda **a: dissipated_energy(**a),
        {"model": MODEL, "displacement": [0.0, 0.01, -0.01], "state": None},
        {"model": "object", "displacement": "signal", "state": "object?"},
        WRONG_STATE,
    ),
    "viscous_dissipation": Entry(
        lambda **a: viscous_dissipation(**a),
        {
            "model": PIFriction(0.3, [100.0], [0.2], viscous=1.0),
            "time": [0.0, 0.1, 0.2],
            "velocity": [0.1, 0.05, 0.0],
        },
        {"model": "object", "time": "signal", "velocity": "signal"},
        [
            ("mismatch", {"velocity": [0.1]}, "velocity", False),
            ("time-decreasing", {"time": [0.0, 0.2, 0.1]}, "time", False),
        ],
        needles={"time": "time|velocity", "velocity": "velocity|time"},
    ),
    "TurningPoints.plot": Entry(
        lambda **a: POINTS.plot(**a), {}, {"ax": "object?", "samples_per_swing": "count"}
    ),
}


@pytest.mark.parametrize(("entry", "overrides", "needle", "legal"), bad_input_cases(ENTRIES))
def test_bad_input_is_a_clear_error(entry, overrides, needle, legal, tmp_path):
    check_bad_input(entry, overrides, needle, legal, tmp_path)
