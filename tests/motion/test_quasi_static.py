"""quasi_static_response: the exact torque-in/position-out limit of eq. 17."""

from __future__ import annotations

import doctest

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import presliding.motion.quasi_static as qs_module
from presliding import PIFriction, Uniform, preloaded_state, quasi_static_response, simulate
from tests.helpers import PROPERTY

MODEL = PIFriction(0.1, [2e4, 5e3], breakaway=[0.3, 0.3])


def test_dynamic_response_with_vanishing_mass_converges_to_it_at_first_order():
    """Event-method motion (m = 1e-9) under zoh samples of u: error O(sample step)."""
    t = np.linspace(0.0, 2.0, 401)
    exact = quasi_static_response(MODEL, 0.6 * np.sin(2 * np.pi * t), time=t)
    errors = []
    for n in (4001, 40001):
        fine = np.linspace(0.0, 2.0, n)
        dyn = simulate(MODEL, 1e-9, (fine, 0.6 * np.sin(2 * np.pi * fine)), t_eval=t)
        assert dyn.success
        errors.append(np.max(np.abs(dyn.position - exact.position)) / np.ptp(exact.position))
    assert errors[1] < 3e-4
    assert 7.0 < errors[0] / errors[1] < 13.0  # first order in the step of u


@PROPERTY
@given(st.lists(st.floats(-0.99, 0.99), min_size=2, max_size=80), st.floats(-1.0, 1.0))
def test_balance_holds_and_contact_moves_only_at_the_coulomb_edge(fractions, preload):
    u = np.array(fractions) * MODEL.coulomb_level
    start = preloaded_state(MODEL, preload * MODEL.max_elastic_force, direction=1.0)
    res = quasi_static_response(MODEL, u, start)
    fel, _ = MODEL.elastic_force(res.position, start)
    np.testing.assert_allclose(fel, res.elastic_force, rtol=0, atol=1e-12)
    gap = np.abs(u - fel)
    assert np.all(gap <= MODEL.coulomb + 1e-12)
    moved = np.abs(np.diff(np.r_[start.last_input, res.position])) > 1e-15
    np.testing.assert_allclose(gap[moved], MODEL.coulomb, rtol=0, atol=1e-12)


def test_chunks_continue_from_the_final_state():
    u = 0.65 * np.sin(np.linspace(0, 6 * np.pi, 300)) * np.linspace(1, 0.3, 300)
    whole = quasi_static_response(MODEL, u)
    first = quasi_static_response(MODEL, u[:120])
    second = quasi_static_response(MODEL, u[120:], first.final_state)
    np.testing.assert_allclose(
        np.r_[first.position, second.position], whole.position, rtol=0, atol=1e-18
    )


def test_loops_close_and_follow_masing():
    """A symmetric force cycle: branch = 2·virgin(Δ/2) in force; the loop closes."""
    model = PIFriction(0.0, [1e4, 3e3, 1e3], breakaway=[0.2, 0.2, 0.2])
    amp = 0.5
    u = np.r_[np.linspace(0, amp, 50), np.linspace(amp, -amp, 100), np.linspace(-amp, amp, 100)]
    y = quasi_static_response(model, u).position
    np.testing.assert_allclose(y[-1], y[49], rtol=0, atol=1e-18)  # the loop closes
    # descending branch from the tip: y_tip − y = 2·ψ((F_tip − F)/2), ψ the inverse virgin curve
    s = np.linspace(0, 2 * y[49], 2001)
    virgin = model.virgin_curve(s)
    down = y[49] - y[50:150]
    expected = 2 * np.interp((amp - u[50:150]) / 2, virgin, s)
    np.testing.assert_allclose(down, expected, rtol=0, atol=2e-9)


def test_errors():
    above = np.nextafter(MODEL.coulomb_level, np.inf)  # the first value refused
    with pytest.raises(ValueError, match=r"not exceed the Coulomb level F_c = .* = 0\.7 in mag"):
        quasi_static_response(MODEL, [0.0, 0.5, above])
    with pytest.raises(ValueError, match="must have elasto-plastic elements"):
        quasi_static_response(PIFriction(1.0), [0.0, 0.5])
    with pytest.raises(ValueError, match="continuous density"):
        quasi_static_response(PIFriction(0.1, density=Uniform(1e6, 1e-3)), [0.0, 0.1])
    with pytest.raises(TypeError, match="`model` must be a PIFriction"):
        quasi_static_response("model", [0.0])
    with pytest.raises(ValueError, match="`initial_state` must be a PIState, 'relaxed' or None"):
        quasi_static_response(MODEL, [0.0], "saturated")
    with pytest.raises(ValueError, match="`time` must be strictly increasing"):
        quasi_static_response(MODEL, [0.0, 0.1], time=[0.0, 0.0])
    with pytest.raises(ValueError, match="same length"):
        quasi_static_response(MODEL, [0.0, 0.1], time=[0.0])


def test_result_interface(tmp_path):
    t = np.linspace(0, 1, 50)
    res = quasi_static_response(MODEL, 0.5 * np.sin(2 * np.pi * t), "relaxed", time=t)
    assert res.success and "Quasi-static response" in res.report()
    d = res.to_dict()
    assert set(d) >= {"time", "applied_force", "position", "elastic_force", "status"}
    np.testing.assert_array_equal(res.friction_force, res.applied_force)
    import matplotlib

    matplotlib.use("Agg")
    ax = res.plot()
    assert ax.get_xlabel().startswith("applied force")
    pytest.importorskip("pandas")
    assert list(res.to_pandas().columns)[:2] == ["time", "applied_force"]


def test_module_examples():
    assert doctest.testmod(qs_module).failed == 0


@pytest.mark.parametrize(
    "model",
    [
        MODEL,
        PIFriction(0.1, [3e4, 7e3, 1.3e3], breakaway=[0.1, 0.37, 0.29]),
        PIFriction(0.0, [3e4], breakaway=[0.1]),
        PIFriction(0.3, [1e5, 3e3], threshold=[1e-6, 7e-5]),
    ],
)
def test_the_coulomb_level_itself_is_accepted_as_the_end_of_presliding(model):
    """u = ±F_c: every element saturated, the position where the largest threshold is reached."""
    fc = model.coulomb_level
    res = quasi_static_response(model, [0.0, fc, -fc, fc])
    fm = fc - model.coulomb
    np.testing.assert_allclose(res.elastic_force[1:], [fm, -fm, fm], rtol=1e-12)
    assert np.all(np.isfinite(res.position))
    # from relaxed, the virgin curve reaches F_m at the largest threshold r_max
    assert res.position[1] == pytest.approx(float(np.max(model.threshold)), rel=1e-9)
    with pytest.raises(ValueError, match="not exceed the Coulomb level"):
        quasi_static_response(model, [0.0, -np.nextafter(fc, np.inf)])
