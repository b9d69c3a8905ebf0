"""Hardening of the hysteresis layer: overflow, sizes, zero thresholds, chunked = whole.

Every error is one sentence in the house style naming the argument the user passed.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from presliding import (
    Discrete,
    Exponential,
    GeneralPIOperator,
    PiecewiseConstant,
    PIOperator,
    PIState,
    Uniform,
    inverse_state,
    pi_inverse,
    play,
    stop,
)
from tests.helpers import paths
from tests.test_validation import assert_rejects


# ---------------------------------------------------------------------- overflow
@pytest.mark.parametrize(
    ("make", "names", "quantity"),
    [
        (lambda: PIOperator([1e300], [1e300]), ("weight", "threshold"), "saturation bound"),
        (lambda: PIOperator([0.1, 0.2], [1e308] * 2, linear=1.0), ("weight",), "total stiffness"),
        (lambda: Uniform(1e308, 1e308), ("height", "max_threshold"), "total stiffness"),
        (lambda: Uniform(1e200, 1e60), ("height", "max_threshold"), "largest elastic force"),
        (lambda: Discrete([1.0], [1e200]), ("stiffness", "threshold"), "stored energy"),
        (lambda: Exponential(1e290, 1e10), ("height", "length"), "largest elastic force"),
        (
            lambda: PiecewiseConstant([0.0, 1e200], [1e200]),
            ("breaks", "heights"),
            "total stiffness",
        ),
    ],
)
def test_derived_quantities_that_overflow_are_errors_naming_the_arguments(make, names, quantity):
    message = assert_rejects(make, ValueError, names[0])
    assert all(f"`{n}`" in message for n in names), message
    assert quantity in message and "got inf" in message, message


def test_operator_input_path_rule():
    """|F| <= |a|·max|y| + Σ|w_j| r_j and max|y| + max r_j must be finite (else an error)."""
    op = PIOperator([1.0], [1.0], linear=1e10)
    message = assert_rejects(lambda: op.apply([0.0, 1e300]), ValueError, "y")
    assert "`linear`" in message and "output bound" in message
    wide = PIOperator([1e308], [1e-300])  # a bank that is fine on its own
    message = assert_rejects(lambda: wide.apply([0.0, 1e308]), ValueError, "y")
    assert "`threshold`" in message and "reach" in message
    assert_rejects(lambda: play([0.0, 1.7e308], 1e308), ValueError, "y")
    # at the edge of the range the outputs are exact and finite
    f, _ = PIOperator([1.0], [2.0], linear=1.0).apply([0.0, 1e307, -1e307])
    assert np.all(np.isfinite(f)) and f.tolist() == [0.0, 1e307 + 2.0, -1e307 - 2.0]


def test_inverse_with_overflowing_reciprocals_names_linear():
    message = assert_rejects(
        lambda: PIOperator([0.1, 0.2], [1.0, 1.0], linear=1e-320).inverse(), ValueError, "linear"
    )
    assert "1/a" in message
    message = assert_rejects(
        # slopes K = [1, a + w_2, a] with a + w_2 one subnormal ulp: 1/K overflows
        lambda: pi_inverse(
            PIOperator([1.0, 2.0], [1.0, -np.nextafter(1e-300, 0.0)], linear=1e-300)
        ),
        ValueError,
        "weight",
    )
    assert "inverse weights" in message
    # an inverse without correct digits (it maps back to zeros) is refused too
    message = assert_rejects(
        lambda: PIOperator([0.1, 0.2], [1e300, 1e300], linear=1.0).inverse(), ValueError, "linear"
    )
    assert "4 significant digits" in message
    # a finite, well-conditioned inverse still round-trips
    op = PIOperator([0.1, 0.2], [1e300, 1e300], linear=1e290)
    y = np.array([0.0, 0.15, -0.3, 0.05])
    force, _ = op.apply(y)
    back, _ = op.inverse().apply(force)
    kappa = (2.0 / 1e290) * (1e290 + 2e300)  # (|1/a| + Σ|v_k|)·K_1
    np.testing.assert_allclose(back, y, rtol=0, atol=kappa * np.finfo(float).eps * 0.3)


# ---------------------------------------------------------------------- sizes
def test_absurd_sizes_are_refused_before_allocating(monkeypatch):
    message = assert_rejects(lambda: PIState.relaxed(0.0, 10**12), ValueError, "n_elements")
    assert "1000000000000 elements" in message and "TiB" in message and "at most" in message
    message = assert_rejects(lambda: Uniform(1.0, 1.0).discretize(10**12), ValueError, "n")
    assert "cells" in message
    monkeypatch.setattr("presliding._validation.MAX_ALLOCATION_BYTES", 8 * 10**6)
    message = assert_rejects(lambda: play(np.zeros(1001), np.full(1000, 0.1)), ValueError, "y")
    assert "at most 1000000 play outputs (7.63 MiB)" in message and "1001000" in message
    assert play(np.zeros(1000), np.full(1000, 0.1)).shape == (1000, 1000)
    monkeypatch.undo()
    # ordinary sizes pass
    assert PIState.relaxed(1.0, 3).play.tolist() == [1.0, 1.0, 1.0]
    assert Uniform(1.0, 1.0).discretize(1000).stiffness.shape == (1000,)


# ---------------------------------------------------------------------- zero thresholds
def test_play_with_threshold_zero_is_the_identity():
    y = np.array([0.0, 1.0, -0.5, 0.25, 0.25, 2.0])
    np.testing.assert_array_equal(play(y, 0.0), y)
    np.testing.assert_array_equal(stop(y, 0.0), np.zeros_like(y))
    both = play(y, [0.0, 0.5])
    np.testing.assert_array_equal(both[:, 0], y)
    np.testing.assert_array_equal(both[:, 1], play(y, 0.5))


def test_operator_elements_with_threshold_zero_add_nothing():
    y = np.array([0.0, 0.3, -0.2, 0.1, 0.4])
    with_zero, state = PIOperator([0.0, 0.1, 0.25], [7.0, 10.0, 4.0]).apply(y)
    without, _ = PIOperator([0.1, 0.25], [10.0, 4.0]).apply(y)
    np.testing.assert_array_equal(with_zero, without)
    assert state.play[0] == y[-1]
    saturated = PIState.saturated(1.0, [0.0, 0.5], 1.0)
    assert saturated.deformation.tolist() == [0.0, 0.5]
    # the inverse of a bank with a zero threshold (and a linear term) still inverts it
    op = PIOperator([0.0, 0.1, 0.25], [3.0, 10.0, 4.0], linear=2.0)
    force, fstate = op.apply(y)
    back, _ = op.inverse().apply(force)
    np.testing.assert_allclose(back, y, rtol=0, atol=1e-14)
    assert inverse_state(op, fstate).play.shape == (3,)


# ---------------------------------------------------------------------- chunked = whole
CHUNK_DENSITIES = [
    Uniform(2.0, 0.5),
    Exponential(2.0, 0.3, 1.5),
    PiecewiseConstant([0.1, 0.3, 0.7], [1.0, 3.0]),
]


def _assert_chunks_equal_whole(op: GeneralPIOperator, y: np.ndarray) -> None:
    whole, final = op.apply(y)
    for cut in range(1, y.shape[0]):
        a, s1 = op.apply(y[:cut])
        b, s2 = op.apply(y[cut:], s1)
        assert np.array_equal(np.concatenate([a, b]), whole), (cut, y.tolist())
        assert s2.base == final.base and np.array_equal(s2.turning, final.turning)


def test_chunked_equals_whole_far_from_the_origin_regression():
    """A reversal after saturation at |y| >> R: the new base y − d·R is rounded.

    The level it opens was computed from the exact R in a whole run, but from
    |y − base| != R after a chunk boundary (1 ulp apart in the force).
    """
    op = GeneralPIOperator(PiecewiseConstant([0.1, 0.3, 0.7], [1.0, 3.0]))
    _assert_chunks_equal_whole(op, np.array([24.7, 22.4, 23.4, 23.7]))
    _assert_chunks_equal_whole(
        GeneralPIOperator(Uniform(2.0, 0.5)), np.array([-160.0, -161.0, -160.2, -159.7])
    )


@settings(max_examples=150, deadline=None)
@given(
    which=st.sampled_from(range(len(CHUNK_DENSITIES))),
    exponent=st.integers(1, 7),
    sign=st.sampled_from([-1.0, 1.0]),
    data=st.data(),
)
def test_chunked_equals_whole_bit_for_bit_when_y_is_far_beyond_r(which, exponent, sign, data):
    density = CHUNK_DENSITIES[which]
    big_r = density.max_threshold
    y = data.draw(
        paths(scale=4.0 * big_r, min_size=2, max_size=12, offset=sign * big_r * 10.0**exponent)
    )
    _assert_chunks_equal_whole(GeneralPIOperator(density), np.asarray(y))
