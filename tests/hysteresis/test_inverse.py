"""Inverse Prandtl–Ishlinskii operator: exact identity on paths, memory map, errors."""

import doctest

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import presliding.hysteresis.inverse as inverse_module
from presliding.hysteresis.inverse import inverse_state, loading_slopes, pi_inverse
from presliding.hysteresis.operators import PIOperator, PIState, stop

SETTINGS = settings(max_examples=60, deadline=None)

finite = st.floats(-5.0, 5.0, allow_nan=False, allow_infinity=False)


@st.composite
def banks(draw, min_linear=0.05):
    n = draw(st.integers(1, 6))
    r = draw(st.lists(st.floats(0.01, 2.0), min_size=n, max_size=n))
    w = draw(st.lists(st.floats(0.05, 20.0), min_size=n, max_size=n))
    a = draw(st.floats(min_linear, 5.0))
    return PIOperator(r, w, linear=a)


paths = st.lists(finite, min_size=2, max_size=60).map(np.array)


def _scale(x):
    return 1e-12 * max(1.0, float(np.max(np.abs(x))))


@SETTINGS
@given(banks(), paths)
def test_inverse_after_operator_is_identity(op, y):
    force, _ = op.apply(y)
    back, _ = op.inverse().apply(force)
    np.testing.assert_allclose(back, y, rtol=0, atol=_scale(y))


@SETTINGS
@given(banks(), paths)
def test_operator_after_inverse_is_identity(op, force):
    y, _ = op.inverse().apply(force)
    again, _ = op.apply(y)
    np.testing.assert_allclose(again, force, rtol=0, atol=_scale(force))


@SETTINGS
@given(banks(), paths, paths)
def test_inverse_state_continues_a_forward_history(op, history, y):
    """From any reachable memory, the inverse started at inverse_state undoes the operator."""
    _, mid = op.apply(history)
    force, _ = op.apply(y, mid)
    back, _ = op.inverse().apply(force, inverse_state(op, mid))
    np.testing.assert_allclose(back, y, rtol=0, atol=_scale(np.r_[y, history]))


@SETTINGS
@given(banks(), paths, st.integers(1, 59))
def test_inverse_chunked_equals_whole(op, force, cut):
    inv = op.inverse()
    whole, end = inv.apply(force)
    cut = min(cut, force.shape[0] - 1)
    first, mid = inv.apply(force[:cut])
    second, end2 = inv.apply(force[cut:], mid)
    np.testing.assert_array_equal(np.r_[first, second], whole)
    np.testing.assert_array_equal(end2.play, end.play)
    assert end2.last_input == end.last_input and end2.direction == end.direction


@SETTINGS
@given(banks(), paths)
def test_inverse_of_inverse_is_the_operator(op, y):
    twice = op.inverse().inverse()
    r, _ = loading_slopes(op)

    def merged(t):
        # thresholds a rounding apart may merge, or split, on the way there and back
        t = np.sort(t)
        return t[np.concatenate(([True], np.diff(t) > 1e-12 * t[1:]))]

    np.testing.assert_allclose(merged(twice.threshold), merged(r), rtol=1e-12)
    assert twice.linear == pytest.approx(op.linear, rel=1e-12)
    f1, _ = op.apply(y)
    f2, _ = twice.apply(y)
    np.testing.assert_allclose(f2, f1, rtol=0, atol=1e-11 * max(1.0, np.max(np.abs(f1))))


def test_inverse_parameters_closed_form():
    """One element: φ has slopes a + w then a; φ⁻¹ has 1/(a + w) then 1/a."""
    a, w, r = 2.0, 6.0, 0.5
    inv = PIOperator([r], [w], linear=a).inverse()
    assert inv.threshold.tolist() == [(a + w) * r]
    assert inv.linear == 1 / a
    assert inv.weight[0] == pytest.approx(1 / (a + w) - 1 / a, rel=1e-15)


def test_inverse_virgin_curve_is_the_inverted_loading_curve():
    op = PIOperator([0.3, 0.1, 0.6], [4.0, 10.0, 1.0], linear=0.5)
    r, slope = loading_slopes(op)
    np.testing.assert_array_equal(r, [0.1, 0.3, 0.6])
    np.testing.assert_allclose(slope, [15.5, 5.5, 1.5, 0.5])
    y_knots = np.r_[0.0, r, 2.0]
    f_knots = np.r_[0.0, np.cumsum(slope * np.diff(y_knots))]
    force = np.linspace(0.0, f_knots[-1], 301)
    y, _ = op.inverse().apply(force)
    np.testing.assert_allclose(y, np.interp(force, f_knots, y_knots), rtol=0, atol=1e-13)
    inv_slopes = np.diff(y) / np.diff(force)
    assert np.all(np.diff(inv_slopes) > -1e-9)  # convex for positive weights
    assert np.all(op.inverse().weight < 0)


def test_equal_thresholds_are_merged():
    op = PIOperator([0.2, 0.2, 0.5], [1.0, 2.0, 1.0], linear=1.0)
    inv = op.inverse()
    assert inv.n_elements == 2
    y = np.array([0.0, 0.7, -0.4, 0.1, -0.05, 0.9])
    force, st_fwd = op.apply(y)
    np.testing.assert_allclose(inv.apply(force)[0], y, rtol=0, atol=1e-14)
    more = np.array([0.3, -0.6])
    back, _ = inv.apply(op.apply(more, st_fwd)[0], inverse_state(op, st_fwd))
    np.testing.assert_allclose(back, more, rtol=0, atol=1e-14)


def test_mixed_sign_weights_invertible_when_slopes_positive():
    op = PIOperator([0.1, 0.4], [3.0, -0.5], linear=1.0)  # slopes 3.5, 0.5, 1.0
    y = np.array([0.0, 0.8, -0.8, 0.2, -0.1, 0.5])
    force, _ = op.apply(y)
    np.testing.assert_allclose(op.inverse().apply(force)[0], y, rtol=0, atol=1e-14)


def test_saturated_memory_maps_to_saturated_inverse_memory():
    op = PIOperator([0.1, 0.3], [5.0, 2.0], linear=1.0)
    state = PIState.saturated(0.7, op.threshold, -1)
    inv_state = inverse_state(op, state)
    inv = op.inverse()
    np.testing.assert_allclose(inv_state.deformation, -inv.threshold, rtol=1e-15)
    assert inv_state.last_input == pytest.approx(0.7 - 0.5 - 0.6)
    assert inv_state.direction == -1.0


def test_default_operator_unchanged_and_linear_term_added():
    rng = np.random.default_rng(3)
    r, w = rng.uniform(0.1, 1, 4), rng.uniform(1, 5, 4)
    y = np.cumsum(rng.normal(size=200))
    plain, _ = PIOperator(r, w).apply(y)
    zero, _ = PIOperator(r, w, linear=0.0).apply(y)
    np.testing.assert_array_equal(plain, zero)
    with_linear, _ = PIOperator(r, w, linear=2.5).apply(y)
    np.testing.assert_allclose(with_linear, 2.5 * y + plain, rtol=1e-14, atol=1e-12)
    np.testing.assert_allclose(plain, stop(y, r) @ w, rtol=0, atol=1e-11)


def test_friction_bank_alone_is_not_invertible():
    with pytest.raises(ValueError, match=r"saturates at ±Σ w_j r_j = ±2\.0.*positive `linear`"):
        PIOperator([1.0], [2.0]).inverse()


def test_decreasing_loading_curve_is_rejected():
    with pytest.raises(ValueError, match=r"increasing initial loading curve.*got slope -0\.5"):
        pi_inverse(PIOperator([1.0, 2.0], [2.0, -3.0], linear=0.5))


def test_unreachable_memory_is_rejected():
    op = PIOperator([0.1, 0.2], [1.0, 1.0], linear=1.0)
    bad = PIState(0.0, np.array([0.1, -0.2]))  # s = [-0.1, 0.2]: jump 0.3 > 0.1
    with pytest.raises(ValueError, match="reachable from a relaxed or saturated state"):
        inverse_state(op, bad)


def test_type_errors():
    with pytest.raises(TypeError, match="`operator` must be a PIOperator"):
        pi_inverse("op")
    op = PIOperator([0.1], [1.0], linear=1.0)
    with pytest.raises(TypeError, match="`state` must be a PIState"):
        inverse_state(op, None)
    with pytest.raises(TypeError, match="`linear` must be a real number"):
        PIOperator([0.1], [1.0], linear="1")


def test_module_examples():
    assert doctest.testmod(inverse_module).failed == 0


def test_friction_elastic_part_is_not_invertible_but_with_a_spring_it_is():
    from presliding import PIFriction

    model = PIFriction(coulomb=0.2, stiffness=[100.0, 20.0], breakaway=[0.5, 0.5])
    with pytest.raises(ValueError, match=r"saturates at ±Σ w_j r_j = ±1\.0"):
        model.operator.inverse()
    op = model.operator
    with_spring = PIOperator(op.threshold, op.weight, linear=5.0)
    force = np.array([0.0, 1.4, -1.4, 0.3])  # beyond F_m = 1: reachable thanks to the spring
    y, _ = with_spring.inverse().apply(force)
    np.testing.assert_allclose(with_spring.apply(y)[0], force, rtol=0, atol=1e-13)
