"""Asymmetric friction of `PIFriction`: separate levels for the two directions of sliding."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import presliding as ps
from tests.helpers import PROPERTY, paths, sample_between, turning_points

K = [500.0, 10.0, 4.0]
C_POS = [1.0, 1.0, 1.0]
C_NEG = [0.5, 2.0, 0.75]


def asymmetric(**kw) -> ps.PIFriction:
    args = dict(coulomb_negative=0.2, breakaway_negative=C_NEG)
    args.update(kw)
    return ps.PIFriction(0.5, K, C_POS, **args)


def swapped(model: ps.PIFriction) -> ps.PIFriction:
    """The mirror model: the sides exchanged."""
    return ps.PIFriction(
        model.coulomb_negative if model.coulomb_negative is not None else model.coulomb,
        model.stiffness,
        model.breakaway_negative if model.breakaway_negative is not None else model.breakaway,
        coulomb_negative=model.coulomb,
        breakaway_negative=model.breakaway,
        viscous=model.viscous_negative if model.viscous_negative is not None else model.viscous,
        viscous_negative=model.viscous,
    )


@st.composite
def asymmetric_models(draw: st.DrawFn) -> ps.PIFriction:
    n = draw(st.integers(1, 5))
    level = st.floats(1e-2, 10.0)
    k = [draw(st.floats(1.0, 1e4)) for _ in range(n)]
    cp = [draw(level) for _ in range(n)]
    cn = [draw(level) for _ in range(n)]
    c1 = st.floats(0.0, 5.0)
    return ps.PIFriction(draw(c1), k, cp, coulomb_negative=draw(c1), breakaway_negative=cn)


def test_equal_sides_are_the_symmetric_model():
    sym = ps.PIFriction(0.5, K, C_POS, viscous=2.0)
    given_equal = ps.PIFriction(0.5, K, C_POS, viscous=2.0, coulomb_negative=0.5,
                                breakaway_negative=C_POS, viscous_negative=2.0)  # fmt: skip
    assert given_equal.is_symmetric and given_equal == sym and repr(given_equal) == repr(sym)
    assert given_equal.coulomb_negative is None and given_equal.breakaway_negative is None
    by_threshold = ps.PIFriction(0.5, K, C_POS, threshold_negative=np.array(C_POS) / K)
    assert by_threshold.is_symmetric
    y = ps.signals.piecewise_linear([0.0, 0.3, -0.3, 0.1], step=1e-3)
    assert np.array_equal(given_equal.force(y)[0], sym.force(y)[0])


def test_asymmetric_levels_repr_equality_and_pickle():
    model = asymmetric(viscous=1.0, viscous_negative=3.0)
    assert not model.is_symmetric
    assert model.coulomb_levels == (0.5 + 3.0, 0.2 + 3.25)
    np.testing.assert_allclose(model.threshold_negative, np.array(C_NEG) / K)
    assert "coulomb_negative=0.2" in repr(model) and "viscous_negative=3.0" in repr(model)
    assert model == asymmetric(viscous=1.0, viscous_negative=3.0)
    assert model != asymmetric(viscous=1.0)
    assert model != ps.PIFriction(0.5, K, C_POS, viscous=1.0)
    assert pickle.loads(pickle.dumps(model)) == model
    assert model.steady_force(-2.0) == -(0.2 + 3.25) - 6.0 and model.steady_force(2.0) == 3.5 + 2.0
    assert model.viscous_force(-1.0) == -3.0
    with pytest.raises(NotImplementedError, match="coulomb_level"):
        _ = model.coulomb_level
    with pytest.raises(NotImplementedError, match="operator"):
        _ = model.operator


def test_nearly_equal_sides_approach_the_symmetric_model():
    sym = ps.PIFriction(0.5, K, C_POS)
    near = ps.PIFriction(0.5, K, C_POS, breakaway_negative=np.array(C_POS) * (1 + 1e-13))
    assert not near.is_symmetric
    y = ps.signals.piecewise_linear([0.0, 0.3, -0.3, 0.1, -0.05], step=1e-3)
    np.testing.assert_allclose(near.force(y)[0], sym.force(y)[0], rtol=0, atol=1e-11)


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"coulomb_negative": -1.0}, ValueError, "coulomb_negative"),
        ({"viscous_negative": np.nan}, ValueError, "viscous_negative"),
        ({"breakaway_negative": [1.0, 2.0]}, ValueError, "breakaway_negative"),
        ({"breakaway_negative": [1.0, -2.0, 1.0]}, ValueError, "breakaway_negative"),
        ({"breakaway_negative": C_NEG, "threshold_negative": C_NEG}, TypeError, "not both"),
    ],
)
def test_bad_negative_sides(kwargs, error, match):
    with pytest.raises(error, match=match):
        ps.PIFriction(0.5, K, C_POS, **kwargs)


def test_a_continuous_density_takes_no_negative_side():
    with pytest.raises(ValueError, match="finite elements"):
        ps.PIFriction(0.5, density=ps.Uniform(2.0, 1.0), coulomb_negative=0.2)


def test_band_of_each_element_and_saturated_states():
    model = asymmetric()
    y = ps.signals.piecewise_linear([0.0, 0.5, -0.5, 0.2, -0.4, 0.5], step=1e-3)
    force, state = model.force(y)
    fp, fn = model.coulomb_levels
    assert force.max() == pytest.approx(fp) and force.min() == pytest.approx(-fn)
    f = state.deformation
    assert np.all(f <= model.threshold * (1 + 1e-12))
    assert np.all(f >= -model.threshold_negative * (1 + 1e-12))
    up = model.saturated_state(0.0, 1.0)
    down = model.saturated_state(0.0, -1.0)
    np.testing.assert_allclose(up.deformation * K, C_POS)
    np.testing.assert_allclose(down.deformation * K, -np.array(C_NEG))
    # the force continues from an explicit state as from the whole path
    whole, _ = model.force(y)
    head, mid = model.force(y[:900])
    tail, _ = model.force(y[900:], mid)
    np.testing.assert_allclose(np.concatenate([head, tail]), whole, rtol=0, atol=1e-12)
    with pytest.raises(ValueError, match="threshold_negative"):
        model.force(y, ps.PIState(0.0, np.array([0.0, 0.0, 0.3]), 1.0))


def test_virgin_curve_has_each_sides_levels():
    model = asymmetric()
    big = model.virgin_curve(np.array([-10.0, 10.0]))
    assert big[0] == pytest.approx(-model.coulomb_levels[1])
    assert big[1] == pytest.approx(model.coulomb_levels[0])
    assert model.virgin_curve(0.0) == 0.0


@PROPERTY
@given(model=asymmetric_models(), y=paths())
def test_mirror_symmetry_of_the_force(model, y):
    """The model with its sides swapped, on the mirrored path, gives the negated force."""
    force, _ = model.force(y)
    mirrored, _ = swapped(model).force(-y)
    scale = sum(model.coulomb_levels)
    np.testing.assert_allclose(mirrored, -force, rtol=0, atol=1e-9 * scale)


@PROPERTY
@given(model=asymmetric_models(), points=turning_points(scale=0.5))
def test_wiping_out(model, points):
    """A minor loop inside the last two turning points is forgotten once the input
    passes the earlier turning point (the state equals the one without the loop)."""
    a, b = points[-2], points[-1]
    lo, span = min(a, b), abs(a - b)
    inner = [lo + 0.7 * span, lo + 0.3 * span] if b < a else [lo + 0.3 * span, lo + 0.7 * span]
    beyond = a + (span if a > b else -span)
    _, with_loop = model.force(np.array([*points, *inner, beyond]))
    _, without = model.force(np.array([*points, beyond]))
    np.testing.assert_allclose(with_loop.play, without.play, rtol=0, atol=1e-12 * (1 + span))


@PROPERTY
@given(model=asymmetric_models(), points=turning_points(scale=0.5))
def test_no_energy_is_created_along_a_closed_path(model, points):
    """The work of the friction force over a closed path is nonnegative (dissipation)."""
    closed = sample_between([*points, points[0]], 1e-4)
    force, _ = model.force(closed)
    work = np.sum(0.5 * (force[1:] + force[:-1]) * np.diff(closed))
    scale = sum(model.coulomb_levels) * np.ptp(closed)
    assert work >= -1e-6 * scale
