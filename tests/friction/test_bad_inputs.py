"""Bad input to every public entry point of the friction layer (the review's table)."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import (
    CoulombFriction,
    CreepingFriction,
    DahlFriction,
    DahlState,
    GMSFriction,
    GMSState,
    LuGreFriction,
    LuGreState,
    PIFriction,
    PIState,
    Uniform,
    compare,
    friction_batch,
    preloaded_state,
)
from tests.helpers import Entry, bad_input_cases, check_bad_input

MODEL = PIFriction(0.3, [100.0, 50.0], [0.2, 0.3])
DENSITY_MODEL = PIFriction(0.3, density=Uniform(2.0, 0.5))
COULOMB = CoulombFriction(0.5)
DAHL = DahlFriction(1.0, 100.0)
LUGRE = LuGreFriction(1.0, 1.5, 1e4, 100.0, 0.4, 0.01)
GMS = GMSFriction(0.3, [100.0, 50.0], [0.2, 0.3], static_level=0.8, stribeck_velocity=0.01,
                  lag_time=0.01)  # fmt: skip
Y = [0.0, 0.01, -0.005, 0.002]
T = [0.0, 0.1, 0.2, 0.3]
WRONG_STATE = [
    ("state-wrong-size", {"state": PIState(0.0, [0.0, 0.0, 0.0])}, "state", False),
    ("state-dahl", {"state": DahlState(0.0, 0.0)}, "state", False),
    ("state-str", {"state": "relaxed-ish"}, "state", False),
    ("state-float", {"state": 1.0}, "state", False),
]
ENTRIES = {
    "PIFriction": Entry(
        lambda **a: PIFriction(**a),
        {"coulomb": 0.3, "stiffness": [100.0, 50.0], "breakaway": [0.2, 0.3], "viscous": 0.0},
        {
            "coulomb": "nonnegative",
            "stiffness": "positive_vector*",
            "breakaway": "positive_vector",
            "viscous": "nonnegative",
        },
        [
            ("mismatch", {"breakaway": [0.2]}, "breakaway", False),
            ("threshold-and-breakaway", {"threshold": [0.1, 0.2]}, "threshold", False),
            ("threshold-mismatch", {"breakaway": None, "threshold": [0.1]}, "threshold", False),
            (
                "threshold-negative",
                {"breakaway": None, "threshold": [0.1, -0.2]},
                "threshold",
                False,
            ),
            (
                "density-object",
                {"stiffness": [], "breakaway": None, "density": "uniform"},
                "density",
                False,
            ),
            ("density-and-elements", {"density": Uniform(2.0, 0.5)}, "density", False),
            (
                "huge-levels",
                {"stiffness": [1e308, 1e308], "breakaway": [1e308, 1e308]},
                "stiffness|breakaway",
                False,
            ),
        ],
        needles={"stiffness": "stiffness|breakaway"},
    ),
    "PIFriction.viscous_force": Entry(
        lambda **a: MODEL.viscous_force(**a),
        {"velocity": [0.1, -0.2]},
        {"velocity": "real_array"},
    ),
    "PIFriction.steady_force": Entry(
        lambda **a: MODEL.steady_force(**a),
        {"velocity": [0.1, -0.2]},
        {"velocity": "real_array"},
    ),
    "PIFriction.relaxed_state": Entry(
        lambda **a: MODEL.relaxed_state(**a), {"position": 0.0}, {"position": "real"}
    ),
    "PIFriction.saturated_state": Entry(
        lambda **a: MODEL.saturated_state(**a),
        {"position": 0.0, "direction": 1.0},
        {"position": "real", "direction": "real"},
        [("direction-0.5", {"direction": 0.5}, "direction", False)],
    ),
    "PIFriction.virgin_curve": Entry(
        lambda **a: MODEL.virgin_curve(**a), {"displacement": Y}, {"displacement": "signal"}
    ),
    "PIFriction.elastic_force": Entry(
        lambda **a: MODEL.elastic_force(**a),
        {"displacement": Y, "state": None},
        {"displacement": "signal", "state": "object?"},
        WRONG_STATE,
    ),
    "PIFriction.force": Entry(
        lambda **a: MODEL.force(**a),
        {"displacement": Y, "state": None},
        {"displacement": "signal", "state": "object?"},
        [*WRONG_STATE, ("out-shape", {"out": np.zeros(2)}, "out", False)],
    ),
    "PIFriction(density).force": Entry(
        lambda **a: DENSITY_MODEL.force(**a),
        {"displacement": Y, "state": None},
        {"displacement": "signal", "state": "object?"},
        [("state-pi", {"state": PIState(0.0, [0.0])}, "state", False)],
    ),
    "CoulombFriction": Entry(
        lambda **a: CoulombFriction(**a), {"coulomb": 0.5}, {"coulomb": "positive"}
    ),
    "CoulombFriction.force": Entry(
        lambda **a: COULOMB.force(**a),
        {"displacement": Y, "state": None},
        {"displacement": "signal", "state": "object?"},
        WRONG_STATE[1:],
    ),
    "DahlFriction": Entry(
        lambda **a: DahlFriction(**a),
        {"coulomb": 1.0, "stiffness": 100.0, "exponent": 1.0},
        {"coulomb": "positive", "stiffness": "positive", "exponent": "positive"},
    ),
    "DahlFriction.relaxed_state": Entry(
        lambda **a: DAHL.relaxed_state(**a), {"position": 0.0}, {"position": "real"}
    ),
    "DahlFriction.force": Entry(
        lambda **a: DAHL.force(**a),
        {"displacement": Y, "state": None},
        {"displacement": "signal", "state": "object?"},
        [
            ("state-pi", {"state": PIState(0.0, [0.0])}, "state", False),
            ("state-too-large", {"state": DahlState(0.0, 5.0)}, "state", False),
        ],
    ),
    "DahlState": Entry(
        lambda **a: DahlState(**a),
        {"last_input": 0.0, "force": 0.0},
        {"last_input": "real", "force": "real"},
    ),
    "LuGreFriction": Entry(
        lambda **a: LuGreFriction(**a),
        {
            "coulomb": 1.0,
            "static": 1.5,
            "stiffness": 1e4,
            "damping": 100.0,
            "viscous": 0.4,
            "stribeck_velocity": 0.01,
        },
        {
            "coulomb": "positive",
            "static": "positive",
            "stiffness": "positive",
            "damping": "nonnegative",
            "viscous": "nonnegative",
            "stribeck_velocity": "positive",
        },
        [("static-below-coulomb", {"static": 0.5}, "static", False)],
        needles={"coulomb": "coulomb|static", "static": "static|coulomb"},
    ),
    "LuGreFriction.stribeck": Entry(
        lambda **a: LUGRE.stribeck(**a), {"velocity": [0.1, -0.2]}, {"velocity": "real_array"}
    ),
    "LuGreFriction.steady_state_force": Entry(
        lambda **a: LUGRE.steady_state_force(**a),
        {"velocity": [0.1]},
        {"velocity": "real_array"},
    ),
    "LuGreFriction.relaxed_state": Entry(
        lambda **a: LUGRE.relaxed_state(**a),
        {"position": 0.0, "time": 0.0},
        {"position": "real", "time": "real"},
    ),
    "LuGreFriction.force": Entry(
        lambda **a: LUGRE.force(**a),
        {"displacement": Y, "time": T, "state": None},
        {"displacement": "signal", "time": "signal", "state": "object?"},
        [
            ("time-mismatch", {"time": [0.0, 0.1]}, "time", False),
            ("time-decreasing", {"time": [0.0, 0.2, 0.1, 0.3]}, "time", False),
            ("time-tiny-steps", {"time": [0.0, 1e-300, 2e-300, 3e-300]}, "time", True),
            ("state-pi", {"state": PIState(0.0, [0.0])}, "state", False),
        ],
        needles={"displacement": "displacement|time", "time": "time|displacement"},
    ),
    "LuGreState": Entry(
        lambda **a: LuGreState(**a),
        {"last_input": 0.0, "last_time": 0.0, "bristle": 0.0, "velocity": 0.0},
        {"last_input": "real", "last_time": "real", "bristle": "real", "velocity": "real"},
    ),
    "GMSFriction": Entry(
        lambda **a: GMSFriction(**a),
        {
            "coulomb": 0.3,
            "stiffness": [100.0, 50.0],
            "breakaway": [0.2, 0.3],
            "static_level": 0.8,
            "stribeck_velocity": 0.01,
            "stribeck_exponent": 2.0,
            "lag_time": 0.01,
            "viscous": 0.0,
        },
        {
            "coulomb": "nonnegative",
            "stiffness": "positive_vector*",
            "breakaway": "positive_vector*",
            "static_level": "positive?",
            "stribeck_velocity": "positive?",
            "stribeck_exponent": "positive",
            "lag_time": "nonnegative",
            "viscous": "nonnegative",
        },
        [
            ("static-below-coulomb", {"static_level": 0.5}, "static_level", False),
            (
                "no-stribeck-velocity",
                {"stribeck_velocity": None, "static_level": 1.0},
                "stribeck_velocity",
                False,
            ),
            ("mismatch", {"breakaway": [0.2]}, "breakaway", False),
            (
                "no-friction",
                {"coulomb": 0.0, "stiffness": [], "breakaway": [], "static_level": None},
                "coulomb",
                False,
            ),
        ],
        needles={
            "coulomb": "coulomb|static_level",
            "stiffness": "stiffness|breakaway|static_level",
            "breakaway": "breakaway|static_level",
        },
    ),
    "GMSFriction.force": Entry(
        lambda **a: GMS.force(**a),
        {"displacement": Y, "time": T, "state": None},
        {"displacement": "signal", "time": "signal", "state": "object?"},
        [
            ("time-decreasing", {"time": [0.0, 0.2, 0.1, 0.3]}, "time", False),
            ("state-wrong-size", {"state": GMSState(0.0, -1.0, [0.0], [0.0])}, "state", False),
            (
                "state-beyond-static",
                {"state": GMSState(0.0, -1.0, [1.0, 0.0], [0.0, 0.0])},
                "state",
                False,
            ),
            ("state-lugre", {"state": LUGRE.relaxed_state()}, "state", False),
        ],
        needles={"displacement": "displacement|time", "time": "time|displacement"},
    ),
    "GMSState": Entry(
        lambda **a: GMSState(**a),
        {
            "last_input": 0.0,
            "last_time": 0.0,
            "forces": [0.1],
            "slipping": [1.0],
            "velocity": 0.0,
            "direction": 1.0,
        },
        {"last_input": "real", "last_time": "real", "velocity": "real"},
        [
            ("slipping-half", {"slipping": [0.5]}, "slipping", False),
            ("slipping-size", {"slipping": [0.0, 1.0]}, "slipping", False),
            ("direction-two", {"direction": 2.0}, "direction", False),
        ],
    ),
    "CreepingFriction": Entry(
        lambda **a: CreepingFriction(**a),
        {"friction": MODEL, "compliance": 1e-6, "creep_time": 0.1},
        {"friction": "object", "compliance": "nonnegative", "creep_time": "nonnegative"},
    ),
    "compare": Entry(
        lambda **a: compare(**a),
        {"models": {"pi": MODEL, "coulomb": COULOMB}, "displacement": Y, "time": None},
        {"models": "object", "displacement": "signal", "time": "signal?"},
        [
            ("models-empty", {"models": []}, "models", False),
            ("models-dahl-state", {"models": [DahlState(0.0, 0.0)]}, "models", False),
            ("models-str-item", {"models": {"a": "pi"}}, "models", False),
            ("lugre-without-time", {"models": [LUGRE]}, "time", False),
            ("time-mismatch", {"time": [0.0, 0.1]}, "time", False),
        ],
        needles={"displacement": "displacement|time", "time": "time|displacement"},
    ),
    "friction_batch": Entry(
        lambda **a: friction_batch(**a),
        {"models": [MODEL, MODEL]},
        {"models": "object"},
        [
            ("empty", {"models": []}, "models", False),
            ("mixed", {"models": [MODEL, COULOMB]}, "models", False),
            ("density", {"models": [DENSITY_MODEL]}, "models", False),
        ],
    ),
    "preloaded_state": Entry(
        lambda **a: preloaded_state(**a),
        {"model": MODEL, "elastic_force": 0.1, "direction": 1.0, "position": 0.0, "path": "branch"},
        {
            "model": "object",
            "elastic_force": "real",
            "direction": "real",
            "position": "real",
            "path": "choice",
        },
        [("beyond-saturation", {"elastic_force": 5.0}, "elastic_force", False)],
    ),
}


@pytest.mark.parametrize(("entry", "overrides", "needle", "legal"), bad_input_cases(ENTRIES))
def test_bad_input_is_a_clear_error(entry, overrides, needle, legal, tmp_path):
    check_bad_input(entry, overrides, needle, legal, tmp_path)
