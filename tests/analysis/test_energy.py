"""Energy (eq. after 12): stored, total and dissipated; energy is never created."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from presliding import (
    Discrete,
    Exponential,
    GeneralPIOperator,
    MemoryState,
    PIFriction,
    PIState,
    Uniform,
    dissipated_energy,
    elastic_energy,
    total_energy,
)
from presliding.hysteresis.general_pi import run_density
from presliding.signals import piecewise_linear

TURNS = [0.0, 0.8, -0.5, 0.3, -0.1, 1.6, 0.2]


def _work(model, path, state=None):
    """∫ F dy: trapezoid rule for the elastic part on a fine path, c1·∫|dy| exactly."""
    force, _ = model.elastic_force(path, state)
    elastic = np.sum(0.5 * (force[1:] + force[:-1]) * np.diff(path))
    return float(elastic + model.coulomb * np.sum(np.abs(np.diff(path))))


def test_virgin_loading_dissipation_in_closed_form():
    a = 2.0
    model = PIFriction(0.0, density=Uniform(a, 1.0))
    y = np.linspace(0.0, 0.7, 8)
    d = dissipated_energy(model, y)
    # stops with r < y slide: D = ∫_0^y M1(s) ds = a·y³/6
    np.testing.assert_allclose(d, a * y**3 / 6, rtol=1e-13, atol=1e-16)
    _, state = model.force(y)
    e = elastic_energy(model, state)
    # ½∫ min(r, y)² dμ = a·(y³/3 + y²(R − y))/2
    assert e == pytest.approx(a * (0.7**3 / 3 + 0.49 * 0.3) / 2, rel=1e-13)


@pytest.mark.parametrize(
    "model",
    [
        PIFriction(0.3, density=Uniform(2.0, 1.0)),
        PIFriction(0.0, density=Exponential(3.0, 0.3)),
        PIFriction(0.2, [10.0, 4.0, 50.0], [0.1, 0.3, 0.02]),
    ],
    ids=["uniform", "exponential", "finite"],
)
def test_work_equals_stored_plus_dissipated(model):
    coarse = piecewise_linear(TURNS, 0.05)
    fine = piecewise_linear(TURNS, 2e-5)
    d = dissipated_energy(model, coarse)
    _, final = model.force(coarse)
    e_end = elastic_energy(model, final)
    work = _work(model, fine)
    assert d[-1] > 0 and np.all(np.diff(d) >= -1e-15)
    # the trapezoid rule is second order on the fine path
    assert work == pytest.approx(e_end + d[-1], rel=1e-7)


def test_discrete_density_kernel_dissipation_equals_element_slips():
    k, r = np.array([10.0, 4.0, 50.0]), np.array([0.1, 0.3, 0.02])
    model = PIFriction(0.0, k, threshold=r)
    y = piecewise_linear(TURNS, 0.013)
    _, kernel, _ = run_density(Discrete(k, r), y, None, dissipation=True)
    np.testing.assert_allclose(kernel, dissipated_energy(model, y), rtol=1e-12, atol=1e-14)


@settings(max_examples=40, deadline=None)
@given(
    path=st.lists(st.floats(-2.0, 2.0, allow_subnormal=False), min_size=2, max_size=30),
    cut=st.integers(1, 28),
)
def test_energy_is_never_created(path, cut):
    """Along any path: D >= 0 nondecreasing, and chunking with states gives the same D."""
    y = np.array(path)
    model = PIFriction(0.1, density=Exponential(2.0, 0.4, 1.5))
    d = dissipated_energy(model, y)
    assert d[0] == 0.0 and np.all(np.diff(d) >= -1e-14)
    cut = min(cut, len(y) - 1)
    _, s = model.force(y[:cut])
    tail = dissipated_energy(model, y[cut:], s)
    np.testing.assert_allclose(d[cut - 1] + tail, d[cut:], rtol=1e-12, atol=1e-13)


def test_elastic_and_total_energy():
    k, r = np.array([10.0, 4.0]), np.array([0.1, 0.3])
    finite = PIFriction(0.5, k, threshold=r)
    state = finite.saturated_state(0.0, 1.0)
    assert elastic_energy(finite, state) == pytest.approx(0.5 * np.sum(k * r * r))
    assert total_energy(finite, 2.0, 3.0, state) == pytest.approx(9.0 + 0.5 * np.sum(k * r * r))
    u = PIFriction(0.0, density=Uniform(2.0, 1.0))
    sat = u.saturated_state(0.0, -1.0)
    assert elastic_energy(u, sat) == pytest.approx(2.0 / 6, rel=1e-14)  # ½∫ r² dμ = a R³/6
    # a fine discretisation converges to the exact stored energy
    _, s = u.force(piecewise_linear(TURNS, 0.01))
    disc = Uniform(2.0, 1.0).discretize(2000)
    f = s.deformation(disc.threshold)
    assert 0.5 * np.sum(disc.stiffness * f * f) == pytest.approx(elastic_energy(u, s), rel=1e-6)
    assert GeneralPIOperator(u.density).elastic_energy(s) == elastic_energy(u, s)
    with pytest.raises(TypeError, match="MemoryState"):
        elastic_energy(u, PIState.relaxed(0.0, 1))
    with pytest.raises(TypeError, match="PIState"):
        elastic_energy(finite, MemoryState.relaxed(0.0))
    with pytest.raises(ValueError, match="mass"):
        total_energy(finite, -1.0, 0.0, state)


def test_coulomb_only_model_dissipates_c1_per_length():
    model = PIFriction(2.0, [], [])
    d = dissipated_energy(model, [0.0, 1.0, 0.5, 0.75])
    np.testing.assert_allclose(d, [0.0, 2.0, 3.0, 3.5])


def test_dissipated_energy_rejects_a_state_of_the_wrong_type():
    finite = PIFriction(0.5, [10.0, 4.0], threshold=[0.1, 0.3])
    density = PIFriction(0.0, density=Uniform(2.0, 1.0))
    y = [0.0, 0.1]
    with pytest.raises(TypeError, match=r"^`state` must be a PIState or None .*; got str\.$"):
        dissipated_energy(finite, y, state="x")
    with pytest.raises(TypeError, match=r"^`state` must be a PIState .*; got MemoryState\.$"):
        dissipated_energy(finite, y, state=MemoryState.relaxed(0.0))
    with pytest.raises(TypeError, match=r"^`state` must be a MemoryState or None .*; got str\.$"):
        dissipated_energy(density, y, state="x")
    with pytest.raises(TypeError, match=r"^`state` must be a MemoryState .*; got PIState\.$"):
        dissipated_energy(density, y, state=PIState.relaxed(0.0, 1))


def test_viscous_dissipation_along_a_sampled_motion():
    from presliding import PIFriction, simulate, viscous_dissipation

    model = PIFriction(0.2, [300.0, 40.0], [0.3, 0.2], viscous=0.8)
    res = simulate(model, 1.0, initial_velocity=1.0, initial_state="saturated", t_end=3.0,
                   t_eval=np.linspace(0.0, 3.0, 30001))  # fmt: skip
    trap = viscous_dissipation(model, res.time, res.velocity)
    assert trap[0] == 0.0 and np.all(np.diff(trap) >= 0)
    # the trapezoidal rule on fine samples meets the exact record of the motion
    np.testing.assert_allclose(trap, res.energy.viscous, rtol=1e-6, atol=1e-12)
    assert np.all(viscous_dissipation(PIFriction(0.2), res.time, res.velocity) == 0.0)
    # the path function leaves σ out: it is the rate-independent part
    path_loss = dissipated_energy(model, res.position, model.saturated_state(0.0, 1.0))
    np.testing.assert_allclose(path_loss[-1], res.energy.dissipated[-1], rtol=1e-9)
    with pytest.raises(ValueError, match="`time` must be strictly increasing"):
        viscous_dissipation(model, [0.0, 0.0], [1.0, 1.0])
    with pytest.raises(ValueError, match="`time` and `velocity` must have the same length"):
        viscous_dissipation(model, [0.0, 1.0], [1.0])
