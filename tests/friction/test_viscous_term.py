"""The viscous term σ·ẏ of `PIFriction` (eq. 8 plus σ·ẏ): parameter, derived quantities, docs."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import presliding as ps
from tests.helpers import PROPERTY, friction_models, paths

K = [500.0, 10.0, 4.0]
C = [1.0, 1.0, 1.0]


def test_default_is_the_papers_assumption_i():
    model = ps.PIFriction(0.5, K, C)
    assert model.viscous == 0.0 and type(model.viscous) is float
    assert (
        repr(model)
        == "PIFriction(coulomb=0.5, stiffness=[500.0, 10.0, 4.0], breakaway=[1.0, 1.0, 1.0])"
    )


def test_viscous_enters_repr_equality_and_pickles():
    model = ps.PIFriction(0.5, K, C, viscous=2)
    assert model.viscous == 2.0 and type(model.viscous) is float
    assert repr(model).endswith("breakaway=[1.0, 1.0, 1.0], viscous=2.0)")
    assert model == ps.PIFriction(0.5, K, C, viscous=2.0)
    assert model != ps.PIFriction(0.5, K, C)
    assert model != ps.PIFriction(0.5, K, C, viscous=2.5)
    dens = ps.PIFriction(0.5, density=ps.Uniform(2.0, 1.0), viscous=0.25)
    assert dens.viscous == 0.25 and "viscous=0.25" in repr(dens)
    assert dens != ps.PIFriction(0.5, density=ps.Uniform(2.0, 1.0))
    assert pickle.loads(pickle.dumps(model)) == model
    assert ps.PIFriction(0.0, viscous=1.0, stiffness=K, breakaway=C).viscous == 1.0


def test_rate_independent_quantities_do_not_depend_on_sigma():
    plain = ps.PIFriction(0.5, K, C)
    damped = ps.PIFriction(0.5, K, C, viscous=3.0)
    assert damped.coulomb_level == plain.coulomb_level
    assert damped.max_elastic_force == plain.max_elastic_force
    assert damped.initial_stiffness == plain.initial_stiffness
    y = ps.signals.piecewise_linear([0.0, 0.3, -0.3, 0.1], step=1e-3)
    np.testing.assert_array_equal(damped.force(y)[0], plain.force(y)[0])
    np.testing.assert_array_equal(damped.virgin_curve(y), plain.virgin_curve(y))


@PROPERTY
@given(model=friction_models(), sigma=st.floats(0.0, 100.0), y=paths())
def test_the_whole_law_is_force_plus_viscous_force(model, sigma, y):
    damped = ps.PIFriction(model.coulomb, model.stiffness, threshold=model.threshold,
                           viscous=sigma)  # fmt: skip
    v = np.linspace(-1.0, 2.0, y.shape[0])
    force, _ = damped.force(y)
    np.testing.assert_array_equal(force, model.force(y)[0])  # rate independent
    np.testing.assert_array_equal(damped.viscous_force(v), sigma * v)
    assert damped.viscous_force(0.7) == sigma * 0.7
    # steady sliding: F_c·sign(v) + σ·v, odd in v
    vs = np.array([-2.0, -0.1, 0.0, 0.1, 2.0])
    steady = damped.steady_force(vs)
    np.testing.assert_allclose(steady, damped.coulomb_level * np.sign(vs) + sigma * vs)
    np.testing.assert_array_equal(steady, -damped.steady_force(-vs))


@pytest.mark.parametrize(
    ("value", "exc", "match"),
    [
        (-0.5, ValueError, r"`viscous` must be nonnegative; got -0.5\."),
        (float("nan"), ValueError, r"`viscous` must be finite; got nan\."),
        (float("-inf"), ValueError, r"`viscous` must be finite; got -inf\."),
        (None, TypeError, r"`viscous` must be a real number; got None\."),
        ("2", TypeError, r"`viscous` must be a real number; got '2'\."),
        (np.array([1.0, 2.0]), ValueError, r"`viscous` must be a scalar; got shape \(2,\)\."),
    ],
)
def test_bad_viscous_names_the_argument(value, exc, match):
    with pytest.raises(exc, match=match):
        ps.PIFriction(0.5, K, C, viscous=value)
    with pytest.raises(exc, match=match):
        ps.PIFriction(0.5, density=ps.Uniform(2.0, 1.0), viscous=value)


def test_viscous_force_validates_the_velocity():
    model = ps.PIFriction(0.5, K, C, viscous=1.0)
    with pytest.raises(ValueError, match="`velocity` must be finite"):
        model.viscous_force([0.0, np.nan])
    with pytest.raises(TypeError, match="`velocity` must be a real number"):
        model.steady_force("fast")


def test_docstring_examples_run():
    import doctest

    import presliding.friction.pi_friction as module

    result = doctest.testmod(module)
    assert result.attempted >= 3 and result.failed == 0
