"""Fits that know when the model is wrong (issue 34): each misfit class named by the judge,
a correctly specified fit left converged (`_adequacy`, rule ``adequacy`` of `_status`)."""

from __future__ import annotations

import numpy as np

from presliding import PIFriction, fit_presliding, fit_response
from tests.helpers import sine_records

#: m = 1.5 kg, c1 = 0.2 N, F_c = 0.8 N, three elements of equal break-away force
MODEL = PIFriction(0.2, [6000.0, 2000.0, 700.0], breakaway=[0.2, 0.2, 0.2])
OPTIONS = {"signal": "both", "initial_state": "preload"}


def _fit(records, n=3):
    return fit_response(records, n, **OPTIONS)


def test_a_correctly_specified_fit_passes_the_residual_tests_and_stays_converged():
    fit = _fit(sine_records(0, MODEL))
    assert fit.status == "converged", fit.message
    assert fit.adequacy is not None and fit.adequacy.passed
    assert fit.intervals_calibrated and fit.to_dict()["intervals_calibrated"]
    assert all(0.7 < x < 1.3 for x in fit.adequacy.levels)
    assert "residual tests: passed" in fit.report()


def test_a_force_recorded_three_samples_late_is_named_with_its_delay():
    """Before: converged with F_c outside its interval (z −4.8 to −11.7 in the review)."""
    fit = _fit(sine_records(3, MODEL, delay=3))
    assert fit.status == "model_inadequate", fit.message
    assert fit.message.startswith("rule adequacy: model inadequate")
    assert fit.adequacy.cause.name == "delay"
    assert -4.0 < fit.adequacy.cause.estimate < -1.5  # 3 samples earlier, to first order
    assert "recorded late" in fit.message and not fit.success
    assert not fit.intervals_calibrated and "not calibrated" in fit.report()
    assert fit.to_dict()["adequacy"]["cause"]["name"] == "delay"


def test_unmodelled_viscous_friction_is_named_a_velocity_dependence():
    truth = PIFriction(0.2, [6000.0, 2000.0, 700.0], breakaway=[0.2, 0.2, 0.2], viscous=6.0)
    fit = _fit(sine_records(2, truth))
    assert fit.status == "model_inadequate", fit.message
    assert fit.adequacy.cause.name == "velocity" and "viscous=True" in fit.message
    assert 2.0 < fit.adequacy.cause.estimate < 10.0  # σ = 6 N·s/m, to first order


def test_unmodelled_asymmetry_sends_the_user_to_the_asymmetric_fit():
    """Friction 30 % stronger in −y (c1 and the break-away forces): before, local_minimum
    ("rule search"), which sent the user to more restarts."""
    truth = PIFriction(0.2, [6000.0, 2000.0, 700.0], breakaway=[0.2, 0.2, 0.2],
                       coulomb_negative=0.26, breakaway_negative=[0.26, 0.26, 0.26])  # fmt: skip
    fit = _fit(sine_records(4, truth, base=MODEL))
    assert fit.status == "model_inadequate", fit.message
    assert fit.adequacy.cause.name == "asymmetry"
    assert 0.1 < fit.adequacy.cause.estimate < 0.5  # 30 % stronger in −y, to first order
    assert "asymmetric=True" in fit.message and "--asymmetric" in fit.message


def test_too_few_elements_are_named_not_blamed_on_the_search():
    """Before: N = 0 on a three-element truth was converged 39 times above the noise floor."""
    fit = _fit(sine_records(4, MODEL), n=1)
    assert fit.status == "model_inadequate", fit.message
    assert fit.adequacy.cause.name == "elements" and "too few elements" in fit.message
    assert any(f.test == "level" for f in fit.adequacy.findings)


def test_a_direct_fit_with_too_few_elements_is_model_inadequate():
    """fit_presliding of a three-element loop with one element: its residual is far above
    the force's noise, structured, and one element more takes it up."""
    truth = PIFriction(0.2, [4000.0, 400.0, 100.0], breakaway=[0.2, 0.2, 0.2])
    t = np.linspace(0.0, 2.0, 800)
    y = 3e-3 * np.sin(2 * np.pi * t) * (1 + 0.3 * np.sin(5 * t))
    force = truth.force(y)[0] + 1e-3 * np.random.default_rng(5).standard_normal(800)
    fit = fit_presliding(y, force, 1)
    assert fit.status == "model_inadequate", fit.message
    assert fit.adequacy.cause is not None and fit.adequacy.cause.name == "elements"
    good = fit_presliding(y, force, 3)
    assert good.status in ("converged", "at_bound"), good.message
    assert good.adequacy.passed
