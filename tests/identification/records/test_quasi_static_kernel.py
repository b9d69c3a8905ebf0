"""The compiled quasi-static kernel with asymmetric friction (each direction its thresholds)."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import Measurement, PIFriction, preloaded_state, quasi_static_response
from presliding.identification.problem._model_spec import ModelSpec
from presliding.identification.records import _quasi_static_kernel as qk
from presliding.identification.records._pooled_record import as_record
from presliding.identification.records._quasi_static_problem import QuasiStaticProblem

RATIO = 0.7
K, C, C1 = [2e4, 6e3], [0.2, 0.2], 0.05
MODEL = PIFriction(C1, K, breakaway=C, coulomb_negative=RATIO * C1,
                   breakaway_negative=[RATIO * c for c in C])  # fmt: skip


def _problem(u: np.ndarray, state: str) -> QuasiStaticProblem:
    t = np.linspace(0.0, 1.0, u.shape[0])
    y = np.linspace(0.0, 1e-5, u.shape[0]) * np.sign(u[1] - u[0])  # a first direction only
    spec = ModelSpec(2, True, None, 32, asymmetric=True)
    return QuasiStaticProblem([as_record(Measurement(t, position=y, applied_force=u))], spec,
                              state, offset=False, suffix=False)  # fmt: skip


@pytest.mark.parametrize("state", ["relaxed", "preload"])
def test_the_kernel_walks_each_side_as_the_library_inverse(state):
    """Positions from the compiled walk of each direction's thresholds equal those of
    `quasi_static_response` (which runs an asymmetric model through the symmetric inverse of
    its mean levels, shifted): two independent routes, to rounding."""
    t = np.linspace(0.0, 1.0, 400)
    u = 0.34 * np.sin(2 * np.pi * 1.5 * t) * (1 - 0.4 * t) - 0.02
    problem = _problem(u, state)
    values = {"coulomb": C1, "coulomb_level": C1 + sum(C), "stiffness_1": K[0],
              "stiffness_2": K[1], "coulomb_level_negative": RATIO * (C1 + sum(C)),
              "initial_position": 0.0, "preload_fraction": 0.3}  # fmt: skip
    o_y, _, status, _ = problem.simulate(np.array([values[x] for x in problem.names]))
    memory = None
    if state == "preload":  # the branch from saturation opposite to the first motion, at 0.3
        d = float(problem.direction[0])  # of the mid band (`preload_deformation_sided`)
        k = np.array(K)
        r_mid = 0.5 * (1 + RATIO) * np.array(C) / k
        shift = float(k @ (0.5 * (1 - RATIO) * np.array(C) / k))
        memory = preloaded_state(MODEL, 0.3 * float(k @ r_mid) + shift, direction=d)
    expected = quasi_static_response(MODEL, u, memory).position
    assert np.all(status == 0) and np.ptp(expected) > 1e-6
    np.testing.assert_allclose(o_y[0], expected, rtol=0, atol=1e-15)


def test_no_response_beyond_either_sides_level():
    """|u| below F_c⁺ but beyond F_c⁻ in −y: no quasi-static response (status −2)."""
    fc_minus = RATIO * (C1 + sum(C))
    u = np.array([0.0, -0.5 * fc_minus, -1.01 * fc_minus])
    problem = _problem(np.array([0.0, 0.01, *u[1:]]), "relaxed")
    values = {
        "coulomb": C1,
        "coulomb_level": C1 + sum(C),
        "stiffness_1": K[0],
        "stiffness_2": K[1],
        "coulomb_level_negative": fc_minus,
        "initial_position": 0.0,
    }
    _, _, status, _ = problem.simulate(np.array([values[x] for x in problem.names]))
    assert status[0, 0] == qk.NO_RESPONSE


def test_the_kernel_refuses_arrays_of_different_shapes():
    k = np.ones((2, 3))
    with pytest.raises(ValueError, match="share their sets and elements"):
        qk.quasi_static_positions(np.ones(2), np.ones(3), k, k, k, np.ones(2))
