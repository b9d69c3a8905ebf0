"""Bad input to every public entry point of the motion layer (the review's table)."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import (
    DahlState,
    GMSFriction,
    LuGreFriction,
    MemoryState,
    PIFriction,
    PIState,
    Uniform,
    free_response,
    friction_inverse,
    quasi_static_response,
    simulate,
    simulate_batch,
)
from tests.helpers import Entry, bad_input_cases, check_bad_input

MODEL = PIFriction(0.3, [100.0, 50.0], [0.2, 0.3])
DENSITY_MODEL = PIFriction(0.3, density=Uniform(2.0, 0.5))
RESULT = simulate(MODEL, 1.0, initial_velocity=0.1, t_end=0.5)
BATCH = simulate_batch([MODEL], 1.0, 0.1, t_end=0.5)
STATES = [
    ("state-wrong-size", {"initial_state": PIState(0.0, [0.0, 0.0, 0.0])}, "initial_state",
     False),
    ("state-dahl", {"initial_state": DahlState(0.0, 0.0)}, "initial_state", False),
    ("state-memory", {"initial_state": MemoryState.relaxed()}, "initial_state", False),
    ("state-unknown", {"initial_state": "nope"}, "initial_state", False),
    ("state-float", {"initial_state": 1.0}, "initial_state", False),
]  # fmt: skip
SIMULATE = {"model": MODEL, "mass": 1.0, "initial_velocity": 0.1, "t_end": 0.5}
GMS = GMSFriction(0.3, [100.0, 50.0], [0.2, 0.3], static_level=0.8, stribeck_velocity=0.01,
                  lag_time=0.01)  # fmt: skip
ENTRIES = {
    "simulate-gms": Entry(
        lambda **a: simulate(**a),
        {**SIMULATE, "model": GMS, "step": 1e-3},
        {
            "mass": "positive",
            "applied_force": "real",
            "initial_position": "real",
            "initial_velocity": "real",
            "t_end": "positive?",
            "t_eval": "signal?",
            "method": "choice",
            "hold": "choice",
            "step": "positive?",
            "t_start": "real",
            "rtol": "positive?",
            "atol": "nonnegative",
        },
        [
            *STATES[1:],
            (
                "state-lugre",
                {"initial_state": LuGreFriction(1.0, 1.5, 1e4, 0.0, 0.0, 0.01).relaxed_state()},
                "initial_state",
                False,
            ),
            ("state-elsewhere", {"initial_state": GMS.relaxed_state(1.0)}, "initial_state", False),
            ("event", {"method": "event"}, "method", False),
            ("t_end-before-start", {"t_start": 1.0}, "t_end", False),
            ("v0-1e200", {"initial_velocity": 1e200}, "initial_velocity", True),
        ],
        needles={"t_end": "t_end|step", "t_start": "t_start|t_end|step"},
    ),
    "simulate": Entry(
        lambda **a: simulate(**a),
        SIMULATE,
        {
            "model": "object",
            "mass": "positive",
            "applied_force": "real",
            "initial_position": "real",
            "initial_velocity": "real",
            "t_end": "positive?",
            "t_eval": "signal?",
            "method": "choice",
            "hold": "choice",
            "step": "positive?",
            "t_start": "real",
            "max_events": "count",
            "rtol": "positive?",
            "atol": "nonnegative",
        },
        [
            *STATES,
            ("t_eval-decreasing", {"t_eval": [0.0, 0.2, 0.1]}, "t_eval", False),
            ("t_eval-beyond", {"t_eval": [0.0, 0.2, 0.9]}, "t_eval", False),
            ("t_end-before-start", {"t_start": 1.0}, "t_end", False),
            ("no-horizon", {"t_end": None}, "t_end", False),
            ("implicit-tiny-step", {"method": "implicit", "step": 1e-12}, "step", False),
            ("implicit-tiny-step-300", {"method": "implicit", "step": 1e-300}, "step", False),
            ("t_end-1e308", {"t_end": 1e308}, "t_end", True),
            ("v0-1e200", {"initial_velocity": 1e200}, "initial_velocity", True),
            (
                "force-samples-ragged",
                {"applied_force": ([0.0, 1.0], [0.0])},
                "applied_force",
                False,
            ),
            (
                "force-samples-decreasing",
                {"applied_force": ([0.0, 1.0, 0.5], [0.0, 1.0, 2.0])},
                "applied_force",
                False,
            ),
            (
                "force-callable-nan",
                {"applied_force": lambda t: np.full_like(t, np.nan)},
                "applied_force",
                False,
            ),
            ("force-callable-str", {"applied_force": lambda t: "x"}, "applied_force", False),
            (
                "density-state-pi",
                {"model": DENSITY_MODEL, "initial_state": PIState(0.0, [0.0])},
                "initial_state",
                False,
            ),
        ],
        needles={
            "t_end": "t_end|t_start",
            "t_start": "t_start|t_end",
            "t_eval": "t_eval|t_end",
            "step": "step|method",
        },
    ),
    "simulate_batch": Entry(
        lambda **a: simulate_batch(**a),
        {"models": [MODEL, MODEL], "mass": 1.0, "initial_velocity": 0.1, "t_end": 0.5},
        {
            "models": "object?",
            "mass": "positive_vector",
            "initial_velocity": "real_vector",
            "initial_position": "real_vector",
            "initial_state": "choice",
            "t_end": "positive?",
            "t_eval": "signal?",
            "t_start": "real",
            "max_events": "count",
        },
        [
            ("models-empty", {"models": []}, "models", False),
            ("models-mixed", {"models": [MODEL, "x"]}, "models", False),
            ("mass-mismatch", {"mass": [1.0, 2.0, 3.0]}, "mass", False),
            ("arrays-and-models", {"stiffness": [[1.0, 2.0]]}, "stiffness", False),
            (
                "arrays-mismatch",
                {
                    "models": None,
                    "coulomb": [0.1, 0.2],
                    "stiffness": [[1.0]],
                    "breakaway": [[0.1, 0.2]],
                },
                "breakaway",
                False,
            ),
        ],
        needles={
            "mass": "mass|models",
            "initial_velocity": "initial_velocity|models",
            "initial_position": "initial_position|models",
        },
    ),
    "free_response": Entry(
        lambda **a: free_response(**a),
        {
            "mass": 1.0,
            "coulomb": 0.3,
            "stiffness": [100.0, 50.0],
            "threshold": [0.002, 0.006],
            "initial_velocity": 0.1,
            "time_step": 1e-3,
            "n_samples": 100,
        },
        {
            "mass": "positive",
            "coulomb": "nonnegative",
            "stiffness": "positive_vector",
            "threshold": "positive_vector",
            "initial_velocity": "real",
            "time_step": "positive",
            "n_samples": "count",
            "initial_position": "real",
            "initial_state": "choice",
            "applied_force": "real",
            "viscous": "nonnegative",
            "max_events": "count",
        },
        [
            ("mismatch", {"threshold": [0.002]}, "threshold", False),
            ("huge-n", {"n_samples": 10**12}, "n_samples", False),
            ("v0-1e308", {"initial_velocity": 1e308}, "initial_velocity", True),
        ],
        needles={
            "stiffness": "stiffness|threshold",
            "threshold": "threshold|stiffness",
            "time_step": "time_step|n_samples",
        },
    ),
    "friction_inverse": Entry(
        lambda **a: friction_inverse(**a),
        {"model": MODEL},
        {"model": "object"},
        [("density", {"model": DENSITY_MODEL}, "model", False)],
    ),
    "quasi_static_response": Entry(
        lambda **a: quasi_static_response(**a),
        {
            "model": MODEL,
            "applied_force": [0.0, 0.4, -0.4, 0.2],
            "initial_state": None,
            "time": None,
        },
        {
            "model": "object",
            "applied_force": "signal",
            "initial_state": "object?",
            "time": "signal?",
        },
        [
            ("beyond-coulomb-level", {"applied_force": [0.0, 5.0]}, "applied_force", False),
            ("time-mismatch", {"time": [0.0, 1.0]}, "time", False),
            ("time-decreasing", {"time": [0.0, 2.0, 1.0, 3.0]}, "time", False),
            ("state-wrong-size", {"initial_state": PIState(0.0, [0.0])}, "initial_state", False),
        ],
        needles={"applied_force": "applied_force|time", "time": "time|applied_force"},
    ),
    "MotionResult.plot": Entry(
        lambda **a: RESULT.plot(**a), {"kind": "time"}, {"ax": "object?", "kind": "choice"}
    ),
    "MotionBatch.plot": Entry(
        lambda **a: BATCH.plot(**a), {"kind": "velocity"}, {"ax": "object?", "kind": "choice"}
    ),
}


@pytest.mark.parametrize(("entry", "overrides", "needle", "legal"), bad_input_cases(ENTRIES))
def test_bad_input_is_a_clear_error(entry, overrides, needle, legal, tmp_path):
    check_bad_input(entry, overrides, needle, legal, tmp_path)
