"""fit_presliding and fit_virgin_curve: round trips, Masing's rule, constraints, bad data."""

from __future__ import annotations

import re

import numpy as np
import pytest

from presliding import PIFriction
from presliding.identification.fit_presliding import (
    fit_presliding,
    fit_virgin_curve,
    virgin_samples,
)
from presliding.signals import piecewise_linear

TRUE = PIFriction(0.3, [50.0, 20.0, 5.0], threshold=[0.01, 0.03, 0.1])
PATH = piecewise_linear([0.0, 0.3, -0.3, 0.2, -0.1, 0.25, -0.3, 0.05], 2e-3)
NAMES = {
    "coulomb": 0.3,
    "stiffness_1": 50.0,
    "stiffness_2": 20.0,
    "stiffness_3": 5.0,
    "threshold_1": 0.01,
    "threshold_2": 0.03,
    "threshold_3": 0.1,
}


def _check_exact(res, truth=NAMES, rtol=1e-8):
    for name, value in truth.items():
        assert res.parameters[name] == pytest.approx(value, rel=rtol), name


def test_noise_free_round_trip_recovers_every_parameter():
    force, _ = TRUE.force(PATH)
    res = fit_presliding(PATH, force, 3)
    assert res.success, res.message
    _check_exact(res)
    assert res.model.coulomb_level == pytest.approx(TRUE.coulomb_level, rel=1e-8)
    assert res.derived["initial_stiffness"] == pytest.approx(75.0, rel=1e-8)
    assert res.residual_rms < 1e-10


def test_noisy_fit_lies_within_its_confidence_intervals():
    force, _ = TRUE.force(PATH)
    noisy = force + np.random.default_rng(7).normal(0.0, 0.01, force.shape)
    res = fit_presliding(PATH, noisy, 3, level=0.99)
    assert res.success
    for name, value in NAMES.items():
        lo, hi = res.confidence_interval[name]
        assert lo <= value <= hi, (name, lo, value, hi)
    assert res.residual_rms == pytest.approx(0.01, rel=0.1)


def test_fixed_and_tied_parameters_are_respected():
    model = PIFriction(0.2, [30.0, 30.0], threshold=[0.02, 0.08])
    force, _ = model.force(PATH)
    res = fit_presliding(PATH, force + 0.5, 2, offset=True, fixed={"coulomb": 0.2},
                         tied={"stiffness_2": "stiffness_1"})  # fmt: skip
    assert res.parameters["coulomb"] == 0.2 and "coulomb" in res.fixed
    assert res.parameters["stiffness_2"] == res.parameters["stiffness_1"]
    assert res.parameters["stiffness_1"] == pytest.approx(30.0, rel=1e-8)
    assert res.parameters["offset"] == pytest.approx(0.5, rel=1e-8)


def test_given_thresholds_held_fixed_make_a_linear_fit():
    force, _ = TRUE.force(PATH)
    res = fit_presliding(PATH, force, thresholds=[0.01, 0.03, 0.1], refine_thresholds=False)
    _check_exact(res, rtol=1e-10)
    assert set(res.fixed) == {"threshold_1", "threshold_2", "threshold_3"}


def test_burn_in_discards_an_unknown_history():
    prefix = piecewise_linear([0.0, 0.17, -0.05], 2e-3)
    full = np.concatenate([prefix, PATH[1:] - 0.05])
    force, _ = TRUE.force(full)
    start = prefix.shape[0]
    y, f = full[start:], force[start:]  # the memory at y[0] is not relaxed
    # the first full stroke (0.35 > 2·0.1) after the first reversal wipes every memory
    burn = int(np.argmax(y)) + int(np.argmin(y[np.argmax(y) :]))
    res = fit_presliding(y, f, 3, burn_in=burn)
    _check_exact(res, rtol=1e-7)


def test_virgin_curve_from_loops_and_masing_reproduces_the_loops():
    force, _ = TRUE.force(PATH)
    res = fit_virgin_curve(PATH, force + 0.7, 3)  # an offset cancels in Masing's rule
    _check_exact(res)
    loops, _ = res.model.force(PATH)
    np.testing.assert_allclose(loops, force, atol=1e-10)


def test_virgin_curve_from_a_monotone_loading():
    y = np.linspace(0.0, -0.3, 400)
    force, _ = TRUE.force(y)
    res = fit_virgin_curve(y, force, 3, loops=False)
    _check_exact(res)


def test_virgin_samples_follow_the_doubled_virgin_curve():
    force, _ = TRUE.force(PATH)
    s, fv = virgin_samples(PATH, force)
    np.testing.assert_allclose(fv, TRUE.virgin_curve(s), atol=1e-12)


@pytest.mark.parametrize(
    ("y", "f", "message"),
    [
        (PATH.copy(), np.where(np.arange(PATH.size) == 5, np.nan, 1.0), "`force` must be finite"),
        (np.linspace(0, 1, 50), np.linspace(0, 1, 50), "reverse at least once"),
        (np.zeros(50), np.linspace(0, 1, 50), "`displacement` must vary"),
        (PATH, np.ones_like(PATH), "`force` must vary"),
        (np.array([0.0, 0.1, 0.0, 0.1, 0.0]), np.arange(5.0), "more samples than parameters"),
        (PATH, np.ones(3), "same length"),
    ],
)
def test_bad_data_gives_a_clear_error(y, f, message):
    with pytest.raises(ValueError, match=message):
        fit_presliding(y, f, 3)


def test_bad_options():
    force, _ = TRUE.force(PATH)
    with pytest.raises(ValueError, match="`n_elements` must equal"):
        fit_presliding(PATH, force, 2, thresholds=[0.1, 0.2, 0.3])
    with pytest.raises(ValueError, match="`burn_in`"):
        fit_presliding(PATH, force, 2, burn_in=-1)
    with pytest.raises(ValueError, match="two turning points"):
        fit_virgin_curve(PATH[:200], force[:200], 2)
    with pytest.raises(ValueError, match="monotone"):
        fit_virgin_curve(PATH, force, 2, loops=False)


def test_superfluous_elements_are_flagged_not_hidden():
    model = PIFriction(0.3, [40.0], threshold=[0.05])
    force, _ = model.force(PATH)
    exact = fit_presliding(PATH, force, 1)
    assert exact.success and exact.residual_rms < 1e-12
    for n in (2, 3):
        res = fit_presliding(PATH, force, n)
        assert res.status == "not_identifiable" and not res.success
        assert "do not determine" in res.message and "(singular Jacobian)" in res.report()


PAIR = "must be a parameter name, a (name, factor) pair or a (name, factor, offset) triple"
BAD_FIT_OPTIONS = [
    ({"max_evaluations": 2.5}, TypeError, "`max_evaluations` must be an integer; got 2.5."),
    ({"max_evaluations": -5}, ValueError, "`max_evaluations` must be a positive integer; got -5."),
    ({"grid_size": 0}, ValueError, "`grid_size` must be at least 2; got 0."),
    ({"grid_size": -3}, ValueError, "`grid_size` must be at least 2; got -3."),
    ({"grid_size": 1}, ValueError, "`grid_size` must be at least 2; got 1."),
    ({"grid_size": 2.5}, TypeError, "`grid_size` must be an integer; got 2.5."),
    ({"tolerance": "x"}, TypeError, "`tolerance` must be a real number; got 'x'."),
    ({"tolerance": np.nan}, ValueError, "`tolerance` must be finite; got nan."),
    ({"tolerance": -1.0}, ValueError, "`tolerance` must be positive; got -1.0."),
    ({"level": "0.9"}, TypeError, "`level` must be a real number; got '0.9'."),
    ({"level": 0.0}, ValueError, "`level` must be between 0 and 1 (exclusive); got 0.0."),
    (
        {"fixed": {"coulomb": "abc"}},
        TypeError,
        "`fixed['coulomb']` must be a real number; got 'abc'.",
    ),
    ({"fixed": {"coulomb": np.nan}}, ValueError, "`fixed['coulomb']` must be finite; got nan."),
    ({"tied": {"stiffness_1": 5}}, TypeError, f"`tied['stiffness_1']` {PAIR}; got 5."),
    (
        {"tied": {"stiffness_1": ("stiffness_2", "x")}},
        TypeError,
        "`tied['stiffness_1'][1]` must be a real number; got 'x'.",
    ),
]


@pytest.mark.parametrize(("kwargs", "error", "message"), BAD_FIT_OPTIONS)
@pytest.mark.parametrize("fit", [fit_presliding, fit_virgin_curve])
def test_bad_fit_options_raise_on_entry(fit, kwargs, error, message):
    force, _ = TRUE.force(PATH)
    with pytest.raises(error, match=f"^{re.escape(message)}$"):
        fit(PATH, force, 2, **kwargs)


@pytest.mark.parametrize(
    ("burn_in", "error", "message"),
    [
        (1.5, TypeError, "`burn_in` must be an integer; got 1.5."),
        (-1, ValueError, "`burn_in` must be nonnegative; got -1."),
        (True, TypeError, "`burn_in` must be an integer; got True."),
    ],
)
def test_bad_burn_in(burn_in, error, message):
    force, _ = TRUE.force(PATH)
    with pytest.raises(error, match=f"^{re.escape(message)}$"):
        fit_presliding(PATH, force, 2, burn_in=burn_in)


@pytest.mark.parametrize(
    ("tolerance", "error", "message"),
    [
        (np.nan, ValueError, "`reversal_tolerance` must be finite; got nan."),
        (-1.0, ValueError, "`reversal_tolerance` must be nonnegative; got -1.0."),
        ("x", TypeError, "`reversal_tolerance` must be a real number; got 'x'."),
    ],
)
def test_bad_reversal_tolerance(tolerance, error, message):
    force, _ = TRUE.force(PATH)
    with pytest.raises(error, match=f"^{re.escape(message)}$"):
        fit_virgin_curve(PATH, force, 2, reversal_tolerance=tolerance)


def test_smallest_accepted_options_still_fit_exactly():
    """grid_size=2, max_evaluations and burn_in as numpy integers are accepted and used."""
    model = PIFriction(0.3, [40.0], threshold=[0.05])
    force, _ = model.force(PATH)
    truth = {"coulomb": 0.3, "stiffness_1": 40.0, "threshold_1": 0.05}
    for fit in (fit_presliding, fit_virgin_curve):
        res = fit(PATH, force, 1, grid_size=np.int64(2), tolerance=np.float64(1e-10))
        assert res.success, res.message
        _check_exact(res, truth)
    capped = fit_presliding(PATH, force, 1, grid_size=2, max_evaluations=np.int64(1))
    assert capped.status == "max_evaluations" and capped.n_evaluations == 1
    burned = fit_presliding(PATH, force, 1, burn_in=np.int64(10))
    assert burned.measured.shape[0] == PATH.shape[0] - 10


def _sse(res):
    return float(np.sum((res.fitted - res.measured) ** 2))


def test_global_search_keeps_the_better_start_and_is_reproducible():
    rng = np.random.default_rng(4)
    force, _ = TRUE.force(PATH)
    noisy = force + rng.normal(0.0, 0.01, force.shape)
    grid = fit_presliding(PATH, noisy, 3)
    one = fit_presliding(PATH, noisy, 3, search="global", seed=5, max_generations=40)
    two = fit_presliding(PATH, noisy, 3, search="global", seed=5, max_generations=40)
    assert one.parameters == two.parameters  # the seed fixes the search
    assert "global search (differential evolution: 40 generations" in one.message
    assert _sse(one) <= _sse(grid) * (1 + 1e-12)
    exact = fit_presliding(PATH, force, 3, search="global", seed=0, max_generations=40)
    _check_exact(exact)


@pytest.mark.parametrize(
    ("kwargs", "exc", "message"),
    [
        (dict(search="random"), ValueError, "`search` must be one of 'grid', 'global'; got"),
        (dict(search="global", thresholds=[0.01, 0.1]), ValueError, "`search` must be 'grid'"),
        (dict(search="global", seed=-1), ValueError, "`seed` must be nonnegative; got -1."),
        (dict(seed=1.5), TypeError, "`seed` must be an integer; got 1.5."),
        (dict(max_generations=0), ValueError, "`max_generations` must be a positive integer"),
    ],
)
def test_search_options_are_checked(kwargs, exc, message):
    force, _ = TRUE.force(PATH)
    n = len(kwargs.get("thresholds", [0, 0, 0]))
    with pytest.raises(exc, match=re.escape(message)):
        fit_presliding(PATH, force, n, **kwargs)


def test_asymmetric_coulomb_sides():
    """c1⁺ ≠ c1⁻ (symmetric elements) recovered from noise-free loops; the symmetric fit
    tested against it; with an offset, or without the Coulomb element, refused."""
    model = PIFriction(0.3, [100.0, 40.0], breakaway=[0.32, 0.34], coulomb_negative=0.2)
    path = piecewise_linear([0.0, 0.01, -0.008, 0.006, -0.004], 2e-4)
    fit = fit_presliding(path, model.force(path)[0], 2, asymmetric=True)
    assert fit.success, fit.message
    assert fit.parameters["coulomb"] == pytest.approx(0.3, rel=1e-8)
    assert fit.parameters["coulomb_negative"] == pytest.approx(0.2, rel=1e-8)
    assert fit.derived["coulomb_level_negative"] == pytest.approx(0.86, rel=1e-8)
    assert fit.model.coulomb_negative == pytest.approx(0.2, rel=1e-8)
    assert fit.asymmetry.verdict == "supported" and fit.asymmetry.rss[1] < 1e-12
    with pytest.raises(ValueError, match="needs coulomb=True and offset=False"):
        fit_presliding(path, model.force(path)[0], 2, asymmetric=True, offset=True)


def test_a_fit_without_the_coulomb_element_runs():
    """``coulomb=False`` raised "`bounds` must name parameters of the fit; got 'coulomb'"."""
    import presliding as ps

    truth = ps.PIFriction(0.0, [400.0, 60.0], [0.3, 0.4])
    y = ps.signals.piecewise_linear([0.0, 0.02, -0.015, 0.01], 4e-5)
    fit = ps.fit_presliding(y, truth.force(y)[0], 2, coulomb=False)
    assert fit.success and "coulomb" not in fit.parameters
    assert fit.model.coulomb == 0.0 and fit.model.coulomb_level == pytest.approx(0.7, 1e-6)
