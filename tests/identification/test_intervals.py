"""Confidence intervals of bounded parameters: never outside the parameter's range, the
Wald interval where it stays inside, and reports that print the bounds."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

import presliding as ps
from presliding.identification.solve._least_squares import bounded_interval
from presliding.signals import piecewise_linear

VALUES = st.floats(1e-6, 1e6)
HALVES = st.floats(0.0, 1e9)


@given(VALUES, HALVES)
def test_an_interval_never_leaves_a_lower_bound(value, half):
    lo, hi = bounded_interval(value, half, 0.0, math.inf)
    assert 0.0 <= lo <= value <= hi
    if value - half >= 0.0:  # inside the range: the usual value ± half
        assert (lo, hi) == (value - half, value + half)


@given(VALUES, HALVES)
def test_where_it_is_moved_off_the_bound_it_reaches_at_least_as_far_up(value, half):
    """lo + d·exp(half/d) >= value + half: never shorter above than the Wald interval."""
    hi = bounded_interval(value, half, 0.0, math.inf)[1]
    assert hi >= (value + half) * (1 - 1e-12)


@given(VALUES, HALVES)
def test_where_the_wald_interval_crosses_the_bound_the_interval_reaches_it(value, half):
    """A Wald test cannot exclude the bound there, so neither may the interval: it holds the
    clipped Wald interval [0, value + half] (and so covers the truth at least as often)."""
    lo, hi = bounded_interval(value, half, 0.0, math.inf)
    if value - half < 0.0:
        assert lo == 0.0 and hi >= (value + half) * (1 - 1e-12)


@given(st.floats(-10.0, 10.0), HALVES)
def test_an_interval_stays_within_two_bounds(value, half):
    lo, hi = bounded_interval(value, half, -10.0, 10.0)
    assert -10.0 <= lo <= value <= hi <= 10.0


def test_a_value_on_its_bound_and_an_infinite_error_reach_to_the_bound():
    assert bounded_interval(0.0, 0.5, 0.0, math.inf) == (0.0, 0.5)
    assert bounded_interval(2.0, math.inf, 0.0, math.inf) == (0.0, math.inf)
    assert bounded_interval(2.0, math.inf, -math.inf, math.inf) == (-math.inf, math.inf)


def test_a_noisy_fit_gives_no_interval_below_zero_and_prints_the_bounds():
    """Weak elements (large errors): the Wald interval would go negative, this one does not."""
    model = ps.PIFriction(0.3, [100.0, 50.0, 1.0], [0.002, 0.003, 0.004])
    y = piecewise_linear([0.0, 0.02, -0.02, 0.01, -0.01], 0.0002)
    force = model.force(y)[0] + 0.05 * np.random.default_rng(1).standard_normal(y.size)
    res = ps.fit_presliding(y, force, 3)
    wald_below = [n for n, v in res.parameters.items() if v - 2 * res.standard_error[n] < 0]
    assert wald_below, "the case must be one where the Wald interval crosses 0"
    for name, (lo, hi) in res.confidence_interval.items():
        low_bound = res.bounds[name][0]
        assert lo >= low_bound >= 0.0 and hi >= res.parameters[name], (name, lo, hi)
    report = res.report()
    assert "bounds:" in report and "[0, inf): coulomb, stiffness_1" in report
    assert res.to_dict()["bounds"]["coulomb"] == [0.0, math.inf]
