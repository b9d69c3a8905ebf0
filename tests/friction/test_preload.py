"""preloaded_state: memories with a given elastic force (branch and virgin families)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from presliding import Exponential, PIFriction, PIState, Uniform, preloaded_state
from tests.helpers import PROPERTY, friction_models


@PROPERTY
@given(friction_models(), st.floats(-1.0, 1.0), st.sampled_from([1.0, -1.0]),
       st.sampled_from(["branch", "virgin"]))  # fmt: skip
def test_elastic_force_is_the_preload(model, fraction, direction, path):
    if model.n_elements == 0:
        return
    f0 = fraction * model.max_elastic_force
    state = preloaded_state(model, f0, direction=direction, position=0.25, path=path)
    assert state.last_input == 0.25
    force, _ = model.elastic_force(np.array([0.25]), state)
    assert force[0] == pytest.approx(f0, abs=1e-12 * model.max_elastic_force)
    if path == "branch":
        assert state.direction == direction


def test_branch_ends_are_the_saturated_memories_and_virgin_zero_is_relaxed():
    model = PIFriction(0.1, [100.0, 30.0], breakaway=[0.2, 0.3])
    fm = model.max_elastic_force
    up = preloaded_state(model, fm, direction=1.0)
    np.testing.assert_allclose(up.deformation, model.threshold, rtol=1e-15)
    reversal = preloaded_state(model, -fm, direction=1.0)
    np.testing.assert_allclose(reversal.deformation, -model.threshold, rtol=1e-15)
    relaxed = preloaded_state(model, 0.0, path="virgin")
    np.testing.assert_array_equal(relaxed.deformation, 0.0)
    # branch memory half way: elements with 2r below the travel saturate
    mid = preloaded_state(model, 0.0, direction=1.0)
    assert isinstance(mid, PIState) and abs(model.stiffness @ mid.deformation) < 1e-15


@pytest.mark.parametrize("density", [Uniform(100.0, 0.01), Exponential(1e4, 0.003)])
@pytest.mark.parametrize("path", ["branch", "virgin"])
def test_densities(density, path):
    model = PIFriction(0.1, density=density)
    fm = model.max_elastic_force
    for fraction in (-1.0, -0.6, 0.0, 0.3, 1.0):
        for d in (1.0, -1.0):
            state = preloaded_state(model, fraction * fm, direction=d, position=0.3, path=path)
            force, _ = model.elastic_force(np.array([0.3]), state)
            assert force[0] == pytest.approx(fraction * fm, abs=1e-9 * fm)


def test_errors():
    model = PIFriction(0.1, [100.0], breakaway=[0.2])
    with pytest.raises(ValueError, match=r"`elastic_force` must be at most F_m = 0\.2"):
        preloaded_state(model, 0.3)
    with pytest.raises(ValueError, match="`direction` must be 1 or -1"):
        preloaded_state(model, 0.1, direction=0.0)
    with pytest.raises(ValueError, match="`path` must be one of"):
        preloaded_state(model, 0.1, path="other")
    with pytest.raises(TypeError, match="`model` must be a PIFriction"):
        preloaded_state("model", 0.1)


def test_asymmetric_memories_carry_each_sides_forces():
    """An asymmetric bank: saturated memories hold F_m⁺ and −F_m⁻; branch and virgin memories
    any force between, with deformations inside the asymmetric band [−r⁻, r⁺]."""
    model = PIFriction(0.2, [300.0, 40.0], breakaway=[0.6, 0.3], coulomb_negative=0.1,
                       breakaway_negative=[0.4, 0.25])  # fmt: skip
    k, rp, rn = model.stiffness, model.threshold, model.threshold_negative
    up = preloaded_state(model, 0.9, direction=1.0)  # F_m⁺ = 0.9
    np.testing.assert_allclose(up.last_input - up.play, rp, rtol=1e-12)
    down = preloaded_state(model, -0.65, direction=-1.0)  # F_m⁻ = 0.65
    np.testing.assert_allclose(up.last_input - down.play, -rn, rtol=1e-12)
    for force in (-0.6, -0.1, 0.0, 0.3, 0.85):
        for path in ("branch", "virgin"):
            state = preloaded_state(model, force, direction=-1.0, position=0.01, path=path)
            f = state.last_input - state.play
            assert float(k @ f) == pytest.approx(force, abs=1e-12), (force, path)
            assert np.all(f <= rp * (1 + 1e-12)) and np.all(f >= -rn * (1 + 1e-12))
    with pytest.raises(ValueError, match=r"\[−F_m⁻, F_m⁺\]"):
        preloaded_state(model, -0.7)
