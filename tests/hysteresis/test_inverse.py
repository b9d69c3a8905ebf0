"""Inverse Prandtl–Ishlinskii operator: exact identity on paths, memory map, errors."""

import dataclasses
import doctest
import itertools
import pickle

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import presliding.hysteresis.inverse as inverse_module
from presliding.hysteresis.inverse import PIInverse, inverse_state, loading_slopes, pi_inverse
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


def test_friction_bank_alone_is_inverted_on_its_range():
    inv = PIOperator([1.0], [2.0]).inverse()
    assert isinstance(inv, PIInverse) and inv.max_elastic_force == 2.0
    y, _ = inv.apply([0.0, 1.0, 1.999, -1.5])
    np.testing.assert_allclose(y, [0.0, 0.5, 0.9995, -0.75], rtol=0, atol=1e-15)
    assert inv.apply([0.0, -2.0])[0][1] == -1.0  # F_c itself: the end of presliding
    with pytest.raises(ValueError, match=r"not exceed the Coulomb level F_c = .* = 2\.0 .*got -2"):
        inv.apply([0.0, -np.nextafter(2.0, 3.0)])


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


def test_friction_elastic_part_is_inverted_on_its_range_and_with_a_spring_everywhere():
    from presliding import PIFriction

    model = PIFriction(coulomb=0.2, stiffness=[100.0, 20.0], breakaway=[0.5, 0.5])
    inv = model.operator.inverse()
    with pytest.raises(ValueError, match=r"F_c = c1 \+ Σ w_j r_j = 1\.0 in magnitude"):
        inv.apply([0.0, 1.4])
    op = model.operator
    with_spring = PIOperator(op.threshold, op.weight, linear=5.0)
    force = np.array([0.0, 1.4, -1.4, 0.3])  # beyond F_m = 1: reachable thanks to the spring
    y, _ = with_spring.inverse().apply(force)
    np.testing.assert_allclose(with_spring.apply(y)[0], force, rtol=0, atol=1e-13)


# ----------------------------------------------------------------- the inverse on the range


@st.composite
def friction_banks(draw):
    """A bank without a linear term (equal thresholds now and then) and c1 (often 0)."""
    n = draw(st.integers(1, 6))
    r = draw(st.lists(st.floats(0.01, 2.0), min_size=n, max_size=n))
    if n > 1 and draw(st.booleans()):
        r[1] = r[0]
    w = draw(st.lists(st.floats(0.05, 20.0), min_size=n, max_size=n))
    c1 = draw(st.one_of(st.just(0.0), st.floats(0.0, 3.0)))
    return PIOperator(r, w), c1


fractions = st.lists(st.floats(-0.999, 0.999), min_size=2, max_size=60).map(np.array)


@SETTINGS
@given(friction_banks(), paths, fractions)
def test_range_inverse_balances_the_force_from_any_memory(bank, history, fraction):
    """Forward F_el(y) = play_c1[u]; the contact moves only where |u − F_el| = c1."""
    op, c1 = bank
    inv = PIInverse(op, coulomb=c1)
    u = fraction * inv.force_limit
    _, memory = op.apply(history)
    y, end = inv.apply(u, memory)
    fel, fwd_end = op.apply(y, memory)
    expected = inv.elastic_force(u, memory)
    tol = 1e-11 * inv.force_limit
    np.testing.assert_allclose(fel, expected, rtol=0, atol=tol)
    assert np.all(np.abs(u - fel) <= c1 + tol)
    moved = np.abs(np.diff(np.r_[memory.last_input, y])) > 1e-9 * max(1.0, np.max(np.abs(y)))
    if c1 > 0:
        np.testing.assert_allclose(np.abs(u - fel)[moved], c1, rtol=0, atol=tol)
    np.testing.assert_array_equal(end.play, fwd_end.play)


@SETTINGS
@given(friction_banks(), fractions, st.lists(st.integers(0, 60), max_size=5), paths)
def test_range_inverse_chunked_equals_whole(bank, fraction, cuts, history):
    """Chunks at any boundaries (empty chunks aside) give one call's result bit for bit,
    from a relaxed memory or any reachable one, and end in the same memory."""
    op, c1 = bank
    inv = PIInverse(op, coulomb=c1)
    u = fraction * inv.force_limit
    start = None if history.shape[0] < 3 else op.apply(history)[1]
    whole, end = inv.apply(u, start)
    bounds = sorted({0, u.shape[0], *(c for c in cuts if 0 < c < u.shape[0])})
    pieces, state = [], start
    for a, b in itertools.pairwise(bounds):
        y, state = inv.apply(u[a:b], state)
        pieces.append(y)
    np.testing.assert_array_equal(np.concatenate(pieces), whole)
    np.testing.assert_array_equal(state.play, end.play)
    assert state.last_input == end.last_input and state.direction == end.direction


def test_range_inverse_continues_other_memories_from_the_forward_memory():
    """A memory not left by this inverse (another Coulomb element, a changed state, a plain
    PIState) is continued from its forward memory: the same as before, to rounding."""
    op = PIOperator([1e-3, 2.5e-3, 4e-3], [500.0, 300.0, 100.0])
    inv = PIInverse(op, coulomb=0.2)
    u = np.array([0.0, 0.9, 0.3, -0.7, 0.45, 0.2])
    whole, _ = inv.apply(u)
    first, state = inv.apply(u[:3])
    plain = PIState(state.last_input, state.play, state.direction)
    other = PIInverse(op, coulomb=0.1)
    for memory in (plain, dataclasses.replace(state), state):
        second, _ = inv.apply(u[3:], memory)
        np.testing.assert_allclose(np.r_[first, second], whole, rtol=0, atol=1e-15)
    assert repr(state).startswith("PIState(")
    np.testing.assert_allclose(
        other.apply(u[3:], state)[0], other.apply(u[3:], plain)[0], rtol=0, atol=0
    )
    assert np.array_equal(pickle.loads(pickle.dumps(state)).play, state.play)
    np.testing.assert_array_equal(inv.apply(u[3:], pickle.loads(pickle.dumps(state)))[0],
                                  whole[3:])  # fmt: skip


def test_range_inverse_closed_form_one_element_with_coulomb():
    """One element k, r and c1: y = play_c1[u]/k while |F_el| < k·r."""
    k, r, c1 = 50.0, 0.02, 0.3
    inv = PIInverse(PIOperator([r], [k]), coulomb=c1)
    u = np.array([0.0, 0.2, 1.0, 0.8, -0.9, 0.0])
    y, state = inv.apply(u)
    fel = np.array([0.0, 0.0, 0.7, 0.7, -0.6, -0.3])
    np.testing.assert_allclose(y, fel / k, rtol=0, atol=1e-15)
    assert state.direction == 1.0 and state.last_input == pytest.approx(-0.3 / k)


def test_range_inverse_of_saturated_memory_moves_only_away_from_saturation():
    op = PIOperator([0.1, 0.3], [5.0, 2.0])
    inv = PIInverse(op, coulomb=0.1)
    sat = PIState.saturated(0.7, op.threshold, 1)  # F_el = F_m = 1.1
    y, _ = inv.apply([1.15, 1.0, 0.9], sat)
    np.testing.assert_allclose(y[:2], 0.7, rtol=0, atol=1e-15)  # |u − F_m| <= c1: at rest
    # F_el = u + c1 = 1.0 on the way down, with the stiffness Σ w = 7 right after reversal
    assert y[2] == pytest.approx(0.7 - 0.1 / 7.0, rel=1e-12)


def test_range_inverse_errors_and_inverse_of_inverse():
    op = PIOperator([0.1, 0.3], [5.0, 2.0])
    assert PIInverse(op).inverse() is op
    assert inverse_state(op, op.relaxed_state(0.2)).last_input == 0.2
    with pytest.raises(ValueError, match="set-valued at rest"):
        PIInverse(op, coulomb=0.1).inverse()
    with pytest.raises(ValueError, match="must have no linear term"):
        PIInverse(PIOperator([0.1], [1.0], linear=1.0))
    with pytest.raises(ValueError, match="positive weights to be invertible on its range; got"):
        PIInverse(PIOperator([0.1, 0.2], [1.0, -1.0]))
    with pytest.raises(ValueError, match="`coulomb` must be"):
        PIInverse(op, coulomb=-1.0)
    with pytest.raises(TypeError, match="`state` must be a PIState or None"):
        PIInverse(op).apply([0.0], "relaxed")


def test_friction_model_inverse():
    from presliding import PIFriction, Uniform
    from presliding.motion.quasi_static import friction_inverse

    model = PIFriction(0.2, [100.0, 20.0], breakaway=[0.5, 0.5])
    inv = friction_inverse(model)
    assert inv.coulomb == 0.2 and inv.force_limit == pytest.approx(model.coulomb_level)
    with pytest.raises(ValueError, match="must have elasto-plastic elements"):
        friction_inverse(PIFriction(0.5))
    with pytest.raises(ValueError, match="continuous density"):
        friction_inverse(PIFriction(0.1, density=Uniform(1.0, 1.0)))


@settings(max_examples=60, deadline=None)
@given(banks(min_linear=0.0), st.floats(0.0, 2.0), paths, st.integers(1, 59))
def test_inverses_in_chunks(op, coulomb, shape, split):
    """What README states: the inverse of a bank with a linear term is a PIOperator, and
    `PIInverse.apply` (a Coulomb element, or no linear term) carries its own memory in the
    state it returns, so the chunks of both equal one call bit for bit."""
    bank = PIOperator(op.threshold, op.weight)
    inverse = PIInverse(bank, coulomb=coulomb)
    u = 0.95 * inverse.force_limit * np.tanh(shape)
    split = min(split, u.shape[0] - 1)
    y, _ = inverse.apply(u)
    first, state = inverse.apply(u[:split])
    second, _ = inverse.apply(u[split:], state)
    np.testing.assert_array_equal(np.concatenate([first, second]), y)
    if op.linear >= 0.05:  # the inverse of a bank with a linear term: a PIOperator
        exact = pi_inverse(op)
        force, _ = op.apply(shape)
        whole, _ = exact.apply(force)
        a, s = exact.apply(force[:split])
        b, _ = exact.apply(force[split:], s)
        np.testing.assert_array_equal(np.concatenate([a, b]), whole)
