"""Densities μ of the general PI model (section 3): primitives in closed form, validation."""

import math

import numpy as np
import pytest
from scipy.special import gammainc

from presliding import Density, Discrete, Exponential, PiecewiseConstant, Tabulated, Uniform

R_GRID = np.array([0.0, 1e-9, 1e-4, 0.03, 0.2, 0.5, 0.999, 1.0, 1.7, 10.0])


def test_uniform_primitives_and_summaries_in_closed_form():
    a, big_r = 2.5, 1.0
    d = Uniform(a, big_r)
    r = np.minimum(R_GRID, big_r)
    np.testing.assert_allclose(d.M0(R_GRID), a * r, rtol=1e-15, atol=2e-16 * a * big_r)
    np.testing.assert_allclose(d.M1(R_GRID), a * r**2 / 2, rtol=1e-15, atol=0)
    np.testing.assert_allclose(d.M2(R_GRID), a * r**3 / 3, rtol=1e-15, atol=0)
    np.testing.assert_allclose(d.tail(R_GRID), a * (big_r - r), rtol=1e-15, atol=0)
    assert d.max_elastic_force == pytest.approx(a * big_r**2 / 2, rel=1e-15)
    assert d.total_stiffness == pytest.approx(a * big_r, rel=1e-15)
    assert d.min_threshold == 0.0 and d.max_threshold == big_r


@pytest.mark.parametrize("big_r", [math.inf, 1.3])
def test_exponential_primitives_match_incomplete_gamma(big_r):
    a, b = 3.0, 0.4
    d = Exponential(a, b, big_r)
    r = np.minimum(R_GRID, big_r)
    x = r / b
    np.testing.assert_allclose(d.M1(R_GRID), a * b**2 * gammainc(2, x), rtol=1e-13, atol=0)
    np.testing.assert_allclose(d.M2(R_GRID), 2 * a * b**3 * gammainc(3, x), rtol=1e-13, atol=0)
    tail = a * b * (np.exp(-x) - math.exp(-big_r / b))
    np.testing.assert_allclose(d.tail(R_GRID), tail, rtol=1e-13, atol=1e-300)
    fm = a * b**2 * (gammainc(2, big_r / b) if math.isfinite(big_r) else 1.0)
    assert d.max_elastic_force == pytest.approx(fm, rel=1e-14)


def test_virgin_curves_in_closed_form():
    y = np.linspace(-3.0, 3.0, 61)
    u = Uniform(2.0, 1.0)
    ay = np.abs(y)
    expected = np.sign(y) * np.where(ay < 1.0, 2.0 * (ay - ay**2 / 2), 1.0)
    np.testing.assert_allclose(u.virgin_curve(y), expected, rtol=1e-14, atol=1e-15)
    e = Exponential(3.0, 0.5)  # a·b²·(1 − exp(−|y|/b)): the Dahl-like shape
    np.testing.assert_allclose(
        e.virgin_curve(y), np.sign(y) * 0.75 * (1 - np.exp(-ay / 0.5)), rtol=1e-13, atol=1e-15
    )


def test_discrete_primitives_are_the_sums():
    k = np.array([5.0, 1.0, 2.0])
    r = np.array([0.3, 0.1, 0.2])
    d = Discrete(k, r)
    for rho in [0.0, 0.05, 0.1, 0.15, 0.2, 0.3, 1.0]:
        below = r <= rho
        assert d.M0(rho) == pytest.approx(k[below].sum(), abs=1e-15)
        assert d.M1(rho) == pytest.approx((k * r)[below].sum(), abs=1e-15)
        assert d.M2(rho) == pytest.approx((k * r * r)[below].sum(), abs=1e-15)
    assert d.max_elastic_force == pytest.approx(2.0, rel=1e-15) and d.min_threshold == 0.1
    assert Discrete([], []).max_elastic_force == 0.0


def test_piecewise_constant_equals_uniform_pieces():
    p = PiecewiseConstant([0.0, 0.4, 1.0], [2.0, 2.0])
    u = Uniform(2.0, 1.0)
    for name in ("M1", "M2", "tail", "M0"):  # M0 = μ([0,R]) − T is exact to eps·μ([0,R])
        got, want = getattr(p, name)(R_GRID), getattr(u, name)(R_GRID)
        np.testing.assert_allclose(got, want, rtol=1e-14, atol=1e-15)
    q = PiecewiseConstant([0.2, 0.5, 1.0], [0.0, 3.0])
    assert q.min_threshold == 0.5
    assert q.M1(0.7) == pytest.approx(3.0 * (0.49 - 0.25) / 2, rel=1e-14)
    assert q.tail(0.1) == pytest.approx(1.5, rel=1e-14)


def test_from_function_reaches_its_tolerance():
    d = Density.from_function(lambda r: 3.0 * math.exp(-r / 0.4), 1.3, rtol=1e-10)
    ref = Exponential(3.0, 0.4, 1.3)
    assert isinstance(d, Tabulated) and d.interpolation_error <= 1e-10
    r = np.linspace(0.0, 1.3, 997)
    for name in ("M1", "M2", "tail"):
        got, want = getattr(d, name)(r), getattr(ref, name)(r)
        assert np.max(np.abs(got - want)) <= 1e-10 * np.max(np.abs(want))


def test_discretize_keeps_the_stiffness_and_converges():
    d = Uniform(2.0, 1.0)
    for n in (10, 100):
        disc = d.discretize(n)
        assert disc.stiffness.sum() == pytest.approx(d.total_stiffness, rel=1e-14)
        assert disc.max_elastic_force == pytest.approx(d.max_elastic_force, rel=1e-14)
    with pytest.raises(ValueError, match="max_threshold"):
        Exponential(1.0, 1.0).discretize(10)


@pytest.mark.parametrize(
    ("factory", "match"),
    [
        (lambda: Uniform(-1.0, 1.0), "height"),
        (lambda: Uniform(1.0, math.inf), "max_threshold"),
        (lambda: Exponential(1.0, 0.0), "length"),
        (lambda: Discrete([1.0, 2.0], [0.1]), "same length"),
        (lambda: Discrete([1.0], [-0.1]), "threshold"),
        (lambda: PiecewiseConstant([0.0, 1.0], [1.0, 2.0]), "one entry more"),
        (lambda: PiecewiseConstant([0.0, 1.0, 0.5], [1.0, 2.0]), "increasing"),
        (lambda: PiecewiseConstant([0.0, 1.0], [0.0]), "all be zero"),
        (lambda: Density.from_function(lambda r: -1.0, 1.0), "nonnegative"),
        (lambda: Density.from_function(3.0, 1.0), "callable"),
    ],
)
def test_bad_parameters_are_rejected(factory, match):
    with pytest.raises((ValueError, TypeError), match=match):
        factory()


def test_densities_are_frozen_and_compare_by_value():
    assert Uniform(1.0, 2.0) == Uniform(1.0, 2.0)
    assert Discrete([1.0], [0.5]) == Discrete([1.0], [0.5])
    assert Discrete([1.0], [0.5]) != Discrete([1.0], [0.6])
    with pytest.raises(AttributeError):
        Uniform(1.0, 2.0).height = 3.0  # type: ignore[misc]
