"""Bad input to every public entry point of the hysteresis layer (the review's table)."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import (
    Density,
    Discrete,
    Exponential,
    GeneralPIOperator,
    MemoryState,
    PIBatch,
    PIBatchState,
    PiecewiseConstant,
    PIInverse,
    PIOperator,
    PIState,
    Tabulated,
    Uniform,
    inverse_state,
    pi_inverse,
    play,
    stop,
)
from tests.helpers import Entry, bad_input_cases, check_bad_input

OP = PIOperator([0.1, 0.2], [1.0, 2.0])
OP_LINEAR = PIOperator([0.1, 0.2], [1.0, 2.0], linear=1.0)
STATE = OP.relaxed_state()
BATCH = PIBatch([[0.1, 0.2], [0.2, 0.3]], [[1.0, 2.0], [2.0, 1.0]])
BATCH_STATE = BATCH.relaxed_state()
DENSITY = Uniform(2.0, 0.5)
GENERAL = GeneralPIOperator(DENSITY)
MEMORY = GENERAL.relaxed_state()
INVERSE = PIInverse(OP, coulomb=0.5)
Y = [0.0, 0.3, -0.2, 0.1]
WRONG_STATE = [
    ("state-wrong-size", {"state": PIState(0.0, [0.0, 0.0, 0.0])}, "state", False),
    ("state-memory", {"state": MemoryState.relaxed()}, "state", False),
    ("state-str", {"state": "relaxed-ish"}, "state", False),
    ("state-float", {"state": 1.0}, "state", False),
]
ENTRIES = {
    "play": Entry(
        lambda **a: play(**a),
        {"y": Y, "threshold": 0.1, "initial": None},
        {"y": "signal", "threshold": "nonnegative_vector", "initial": "real_vector?"},
        [
            (
                "initial-length",
                {"threshold": [0.1, 0.2], "initial": [0.0, 0.0, 0.0]},
                "initial",
                False,
            )
        ],
    ),
    "stop": Entry(
        lambda **a: stop(**a),
        {"y": Y, "threshold": [0.1, 0.2], "initial": None},
        {"y": "signal", "threshold": "nonnegative_vector", "initial": "real_vector?"},
    ),
    "PIOperator": Entry(
        lambda **a: PIOperator(**a),
        {"threshold": [0.1, 0.2], "weight": [1.0, 2.0], "linear": 0.0},
        {"threshold": "nonnegative_vector", "weight": "real_vector", "linear": "real"},
        [("mismatch", {"threshold": [0.1, 0.2, 0.3]}, "threshold", False)],
    ),
    "PIOperator.relaxed_state": Entry(
        lambda **a: OP.relaxed_state(**a), {"position": 0.0}, {"position": "real"}
    ),
    "PIOperator.apply": Entry(
        lambda **a: OP.apply(**a),
        {"y": Y, "state": None, "out": None},
        {"y": "signal", "state": "object?"},
        [
            *WRONG_STATE,
            ("out-shape", {"out": np.zeros(3)}, "out", False),
            ("out-dtype", {"out": np.zeros(4, dtype=np.int64)}, "out", False),
            ("out-list", {"out": [0.0] * 4}, "out", False),
        ],
    ),
    "PIOperator.inverse": Entry(
        lambda **a: PIOperator(**a).inverse(),
        {"threshold": [0.1, 0.2], "weight": [1.0, 2.0], "linear": 1.0},
        {"linear": "nonnegative"},
        [("huge-weight", {"weight": [1e308, 1e308]}, "weight", True)],
    ),
    "PIState": Entry(
        lambda **a: PIState(**a),
        {"last_input": 0.0, "play": [0.0, 0.0], "direction": 0.0},
        {"last_input": "real", "play": "real_vector*", "direction": "real"},
        [("direction-2", {"direction": 2.0}, "direction", False)],
    ),
    "PIState.relaxed": Entry(
        lambda **a: PIState.relaxed(**a),
        {"position": 0.0, "n_elements": 2},
        {"position": "real", "n_elements": "count0"},
    ),
    "PIState.saturated": Entry(
        lambda **a: PIState.saturated(**a),
        {"position": 0.0, "threshold": [0.1, 0.2], "direction": 1.0},
        {"position": "real", "threshold": "nonnegative_vector*", "direction": "real"},
        [("direction-0.5", {"direction": 0.5}, "direction", False)],
    ),
    "PIState.check_against": Entry(
        lambda **a: STATE.check_against(**a),
        {"threshold": np.array([0.1, 0.2])},
        {"threshold": "nonnegative_vector"},
        [("threshold-length", {"threshold": np.array([0.1, 0.2, 0.3])}, "state", False)],
    ),
    "PIBatch": Entry(
        lambda **a: PIBatch(**a),
        {"threshold": [[0.1, 0.2]], "weight": [[1.0, 2.0]], "linear": 0.0, "coulomb": 0.0},
        {
            "threshold": "nonnegative_vector",
            "weight": "real_vector",
            "linear": "real",
            "coulomb": "nonnegative",
        },
        [
            ("mismatch", {"weight": [[1.0, 2.0, 3.0]]}, "weight", False),
            ("3d", {"threshold": [[[0.1, 0.2]]]}, "threshold", False),
        ],
    ),
    "PIBatch.stack": Entry(
        lambda **a: PIBatch.stack(**a),
        {"operators": [OP, OP]},
        {"operators": "object"},
        [
            ("empty", {"operators": []}, "operators", False),
            ("mixed", {"operators": [OP, "x"]}, "operators", False),
            ("sizes", {"operators": [OP, PIOperator([0.1], [1.0])]}, "operators", False),
        ],
    ),
    "PIBatch.member": Entry(
        lambda **a: BATCH.member(**a),
        {"b": 0},
        {"b": "count0"},
        [("out-of-range", {"b": 2}, "b", False)],
    ),
    "PIBatch.relaxed_state": Entry(
        lambda **a: BATCH.relaxed_state(**a), {"position": 0.0}, {"position": "real"}
    ),
    "PIBatch.apply": Entry(
        lambda **a: BATCH.apply(**a),
        {"y": Y, "state": None},
        {"y": "signal", "state": "object?"},
        [
            ("state-single", {"state": STATE}, "state", False),
            ("out-shape", {"out": np.zeros((3, 4))}, "out", False),
        ],
    ),
    "PIBatchState": Entry(
        lambda **a: PIBatchState(**a),
        {"last_input": 0.0, "play": [[0.0, 0.0]], "direction": 0.0},
        {"last_input": "real", "play": "matrix", "direction": "real"},
    ),
    "PIBatchState.member": Entry(
        lambda **a: BATCH_STATE.member(**a),
        {"b": 0},
        {"b": "count0"},
        [("out-of-range", {"b": 5}, "b", False)],
    ),
    "PIBatchState.stack": Entry(
        lambda **a: PIBatchState.stack(**a),
        {"states": [STATE, STATE]},
        {"states": "object"},
        [
            ("empty", {"states": []}, "states", False),
            ("mixed", {"states": [STATE, MEMORY]}, "states", False),
        ],
    ),
    "GeneralPIOperator": Entry(
        lambda **a: GeneralPIOperator(**a), {"density": DENSITY}, {"density": "object"}
    ),
    "GeneralPIOperator.relaxed_state": Entry(
        lambda **a: GENERAL.relaxed_state(**a), {"position": 0.0}, {"position": "real"}
    ),
    "GeneralPIOperator.saturated_state": Entry(
        lambda **a: GENERAL.saturated_state(**a),
        {"position": 0.0, "direction": 1.0},
        {"position": "real", "direction": "real"},
    ),
    "GeneralPIOperator.apply": Entry(
        lambda **a: GENERAL.apply(**a),
        {"y": Y, "state": None},
        {"y": "signal", "state": "object?"},
        [("state-pi", {"state": STATE}, "state", False)],
    ),
    "GeneralPIOperator.force_at": Entry(
        lambda **a: GENERAL.force_at(**a),
        {"y": 0.1, "state": MEMORY},
        {"y": "real", "state": "object"},
    ),
    "GeneralPIOperator.elastic_energy": Entry(
        lambda **a: GENERAL.elastic_energy(**a), {"state": MEMORY}, {"state": "object"}
    ),
    "MemoryState": Entry(
        lambda **a: MemoryState(**a),
        {"last_input": 0.0, "turning": [], "base": 0.0, "direction": 0.0},
        {"last_input": "real", "turning": "real_vector*", "direction": "real"},
    ),
    "MemoryState.relaxed": Entry(
        lambda **a: MemoryState.relaxed(**a), {"position": 0.0}, {"position": "real"}
    ),
    "MemoryState.saturated": Entry(
        lambda **a: MemoryState.saturated(**a),
        {"position": 0.0, "direction": 1.0, "max_threshold": 1.0},
        {"position": "real", "direction": "real", "max_threshold": "positive~"},
    ),
    "MemoryState.deformation": Entry(
        lambda **a: MEMORY.deformation(**a),
        {"threshold": [0.1]},
        {"threshold": "nonnegative_vector"},
    ),
    "MemoryState.play": Entry(
        lambda **a: MEMORY.play(**a), {"threshold": [0.1]}, {"threshold": "nonnegative_vector"}
    ),
    "MemoryState.working_memory": Entry(
        lambda **a: MEMORY.working_memory(**a), {"density": DENSITY}, {"density": "object"}
    ),
    "MemoryState.from_working_memory": Entry(
        lambda **a: MemoryState.from_working_memory(**a),
        {"head": np.array([0.0, 0.0]), "stack": np.zeros((0, 2))},
        {"head": "real_vector", "stack": "real_vector"},
    ),
    "Uniform": Entry(
        lambda **a: Uniform(**a),
        {"height": 2.0, "max_threshold": 0.5},
        {"height": "positive", "max_threshold": "positive"},
    ),
    "Exponential": Entry(
        lambda **a: Exponential(**a),
        {"height": 2.0, "length": 0.1, "max_threshold": 1.0},
        {"height": "positive", "length": "positive", "max_threshold": "positive~"},
    ),
    "PiecewiseConstant": Entry(
        lambda **a: PiecewiseConstant(**a),
        {"breaks": [0.0, 0.1, 0.3], "heights": [2.0, 1.0]},
        {"breaks": "real_vector", "heights": "nonnegative_vector"},
        [
            ("mismatch", {"heights": [2.0, 1.0, 1.0]}, "heights", False),
            ("decreasing", {"breaks": [0.0, 0.3, 0.1]}, "breaks", False),
        ],
    ),
    "Discrete": Entry(
        lambda **a: Discrete(**a),
        {"stiffness": [10.0, 5.0], "threshold": [0.1, 0.2]},
        {"stiffness": "positive_vector", "threshold": "positive_vector"},
        [("mismatch", {"threshold": [0.1]}, "threshold", False)],
    ),
    "Tabulated": Entry(
        lambda **a: Tabulated(**a),
        {
            "grid": [0.0, 0.5, 1.0],
            "values": [1.0, 1.0, 1.0],
            "moments": np.zeros((3, 3)),
            "interpolation_error": 0.0,
        },
        {
            "grid": "real_vector",
            "values": "nonnegative_vector",
            "interpolation_error": "nonnegative",
        },
        [
            ("grid-uneven", {"grid": [0.0, 0.2, 1.0]}, "grid", False),
            ("moments-shape", {"moments": np.zeros((2, 3))}, "moments", False),
        ],
    ),
    "Density.from_function": Entry(
        lambda **a: Density.from_function(**a),
        {"function": lambda r: 1.0, "max_threshold": 1.0, "rtol": 1e-6},
        {"function": "callable", "max_threshold": "positive", "rtol": "positive"},
        [
            ("function-nan", {"function": lambda r: float("nan")}, "function", False),
            ("function-negative", {"function": lambda r: -1.0}, "function", False),
            ("function-raises", {"function": lambda r: 1.0 / 0.0}, "function", False),
            ("max-inf", {"max_threshold": float("inf")}, "max_threshold", False),
        ],
    ),
    "Density.discretize": Entry(
        lambda **a: DENSITY.discretize(**a),
        {"n": 4, "max_threshold": None},
        {"n": "count", "max_threshold": "positive?"},
    ),
    "Density.virgin_curve": Entry(
        lambda **a: DENSITY.virgin_curve(**a), {"displacement": Y}, {"displacement": "signal"}
    ),
    "Density.M1": Entry(lambda **a: DENSITY.M1(**a), {"r": [0.1]}, {"r": "nonnegative_vector*~"}),
    "PIInverse": Entry(
        lambda **a: PIInverse(**a),
        {"operator": OP, "coulomb": 0.5},
        {"operator": "object", "coulomb": "nonnegative"},
    ),
    "PIInverse.relaxed_state": Entry(
        lambda **a: INVERSE.relaxed_state(**a), {"position": 0.0}, {"position": "real"}
    ),
    "PIInverse.apply": Entry(
        lambda **a: INVERSE.apply(**a),
        {"force": [0.0, 0.5, -0.3], "state": None},
        {"force": "signal", "state": "object?"},
        [*WRONG_STATE, ("beyond-saturation", {"force": [0.0, 100.0]}, "force", False)],
    ),
    "PIInverse.elastic_force": Entry(
        lambda **a: INVERSE.elastic_force(**a),
        {"force": [0.0, 0.5, -0.3], "state": None},
        {"force": "signal", "state": "object?"},
    ),
    "pi_inverse": Entry(
        lambda **a: pi_inverse(**a), {"operator": OP_LINEAR}, {"operator": "object"}
    ),
    "inverse_state": Entry(
        lambda **a: inverse_state(**a),
        {"operator": OP_LINEAR, "state": STATE},
        {"operator": "object", "state": "object"},
        [("state-wrong-size", {"state": PIState(0.0, [0.0, 0.0, 0.0])}, "state", False)],
    ),
}


#: Open gaps of the review (issue 16), each a strict expected failure: fixing one makes its
#: test fail until its id is taken out of this list.
KNOWN: frozenset[str] = frozenset()


@pytest.mark.parametrize(("entry", "overrides", "needle", "legal"), bad_input_cases(ENTRIES, KNOWN))
def test_bad_input_is_a_clear_error(entry, overrides, needle, legal, tmp_path):
    check_bad_input(entry, overrides, needle, legal, tmp_path)
