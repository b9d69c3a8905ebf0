"""Creep: PI friction in series with a Kelvin–Voigt element (quasi-static, torque-driven)."""

import numpy as np
import pytest

from presliding import CreepingFriction, PIFriction, quasi_static_response

PI = PIFriction(0.1, [2e4, 5e3], [0.3, 0.3])


def test_without_compliance_the_response_is_the_pi_models_bit_for_bit():
    t = np.linspace(0.0, 2.0, 301)
    u = 0.6 * np.sin(3.0 * t) * np.exp(-t)
    plain = quasi_static_response(PI, u, time=t)
    creep = quasi_static_response(CreepingFriction(PI, 0.0, 0.3), u, time=t)
    np.testing.assert_array_equal(creep.position, plain.position)
    np.testing.assert_array_equal(creep.creep_deflection, 0.0)


def test_a_force_ramp_then_held_creeps_to_a_limit_in_closed_form():
    """u = U·t/T0 up to T0, then U: τẏ + y = J·u has y = J·U·(1 − τ/T0·(e^(T0/τ) − 1)·e^(−t/τ))
    after T0 (from rest), and tends to J·U: bounded creep, no drift beyond it."""
    compliance, tau, big_u, t0 = 2e-6, 0.2, 0.5, 0.1
    t = np.linspace(0.0, 3.0, 601)
    u = big_u * np.minimum(t / t0, 1.0)
    model = CreepingFriction(PI, compliance, tau)
    res = quasi_static_response(model, u, time=t)
    after = t >= t0
    exact = compliance * big_u * (1 - tau / t0 * np.expm1(t0 / tau) * np.exp(-t[after] / tau))
    np.testing.assert_allclose(res.creep_deflection[after], exact, rtol=1e-12, atol=1e-20)
    ramp = ~after
    exact_ramp = compliance * big_u / t0 * (t[ramp] - tau * (1 - np.exp(-t[ramp] / tau)))
    np.testing.assert_allclose(res.creep_deflection[ramp], exact_ramp, rtol=1e-12, atol=1e-20)
    plain = quasi_static_response(PI, u)
    np.testing.assert_array_equal(res.position - res.creep_deflection, plain.position)
    assert abs(res.position[-1] - res.position[-2]) < 1e-6 * compliance * big_u  # at its limit


def test_a_zero_creep_time_is_a_series_spring_and_needs_no_time():
    u = np.array([0.0, 0.2, 0.5, 0.1, -0.3])
    res = quasi_static_response(CreepingFriction(PI, 1e-6, 0.0), u)
    np.testing.assert_allclose(res.creep_deflection, 1e-6 * u, rtol=1e-15)


def test_arguments_are_checked():
    with pytest.raises(ValueError, match=r"`compliance` must be nonnegative"):
        CreepingFriction(PI, -1.0, 0.1)
    with pytest.raises(TypeError, match=r"`friction` must be a PIFriction"):
        CreepingFriction("PI", 1e-6, 0.1)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"`time` must be given for a CreepingFriction"):
        quasi_static_response(CreepingFriction(PI, 1e-6, 0.1), [0.0, 0.1])
    with pytest.raises(ValueError, match=r"`initial_creep` is the deflection"):
        quasi_static_response(PI, [0.0, 0.1], initial_creep=0.0)
    model = CreepingFriction(PI, 1e-6, 0.1)
    res = quasi_static_response(model, [0.2, 0.2], time=[0.0, 0.1], initial_creep=0.0)
    np.testing.assert_allclose(res.creep_deflection[-1], 2e-7 * (1 - np.exp(-1.0)), rtol=1e-13)
    assert "compliance=1e-06" in repr(model) and model.coulomb_level == PI.coulomb_level
