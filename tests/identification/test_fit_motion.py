"""fit_motion: eq. 17 as a regression, round trips, constraints and bad data."""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

from presliding import PIFriction
from presliding.identification.fit_motion import fit_motion, predict_motion_force
from presliding.measurement.measurement import Measurement

T = np.arange(3000) * 1e-3
W1, W2 = 2 * np.pi * 1.0, 2 * np.pi * 3.3
Y = 0.02 * np.sin(W1 * T) + 0.005 * np.sin(W2 * T)
V = 0.02 * W1 * np.cos(W1 * T) + 0.005 * W2 * np.cos(W2 * T)
A = -0.02 * W1**2 * np.sin(W1 * T) - 0.005 * W2**2 * np.sin(W2 * T)
MODEL = PIFriction(2.0, [3000.0, 500.0], threshold=[0.001, 0.006])
TRUTH = {"mass": 3.0, "coulomb": 2.0, "viscous": 15.0, "offset": -0.7,
         "stiffness_1": 3000.0, "stiffness_2": 500.0, "threshold_1": 0.001,
         "threshold_2": 0.006}  # fmt: skip


def _measurement(noise: float = 0.0, seed: int = 0) -> Measurement:
    elastic, _ = MODEL.elastic_force(Y)
    u = 3.0 * A + 2.0 * np.sign(V) + elastic + 15.0 * V - 0.7
    u = u + np.random.default_rng(seed).normal(0.0, noise, u.shape) if noise else u
    return Measurement(T, position=Y, velocity=V, acceleration=A, applied_force=u)


def test_noise_free_round_trip():
    res = fit_motion(_measurement(), 2, viscous=True, offset=True)
    assert res.success, res.message
    for name, value in TRUTH.items():
        assert res.parameters[name] == pytest.approx(value, rel=1e-8), name
    assert res.model.coulomb_level == pytest.approx(MODEL.coulomb_level, rel=1e-8)
    np.testing.assert_allclose(predict_motion_force(res, _measurement()),
                               _measurement().applied_force, atol=1e-8)  # fmt: skip


def test_round_trip_without_viscous_and_offset_terms():
    elastic, _ = MODEL.elastic_force(Y)
    u = 3.0 * A + 2.0 * np.sign(V) + elastic
    res = fit_motion(Measurement(T, position=Y, velocity=V, acceleration=A, applied_force=u), 2)
    assert res.success, res.message
    assert "viscous" not in res.parameters and "offset" not in res.parameters
    for name in ("mass", "coulomb", "stiffness_1", "stiffness_2", "threshold_1", "threshold_2"):
        assert res.parameters[name] == pytest.approx(TRUTH[name], rel=1e-8), name


def test_noisy_round_trip_within_confidence_intervals():
    res = fit_motion(_measurement(noise=0.2, seed=3), 2, viscous=True, offset=True, level=0.99)
    for name, value in TRUTH.items():
        lo, hi = res.confidence_interval[name]
        assert lo <= value <= hi, (name, lo, value, hi)


def test_without_elements_it_is_ordinary_least_squares():
    m = _measurement(noise=0.1)
    res = fit_motion(m, viscous=True, offset=True)
    x = np.column_stack([A, np.sign(V), V, np.ones_like(V)])
    beta, *_ = np.linalg.lstsq(x, m.applied_force, rcond=None)
    np.testing.assert_allclose([res.parameters[k] for k in ("mass", "coulomb", "viscous",
                                "offset")], beta, rtol=1e-8)  # fmt: skip


def test_fixed_and_tied_parameters():
    res = fit_motion(_measurement(), 2, viscous=True, offset=True, fixed={"mass": 3.0},
                     tied={"threshold_2": ("threshold_1", 6.0)})  # fmt: skip
    assert res.parameters["mass"] == 3.0 and "mass" in res.fixed
    assert res.parameters["threshold_2"] == 6.0 * res.parameters["threshold_1"]
    assert res.parameters["stiffness_1"] == pytest.approx(3000.0, rel=1e-8)


def test_zero_applied_force_needs_a_scale():
    zero = np.zeros_like(T)
    decel = -(2.0 * np.sign(V) + 15.0 * V) / 3.0  # m·ÿ + c1·sign(ẏ) + F_v·ẏ = 0
    free = Measurement(T, position=Y, velocity=V, acceleration=decel, applied_force=zero)
    with pytest.raises(ValueError, match="common factor"):
        fit_motion(free, viscous=True)
    res = fit_motion(free, viscous=True, fixed={"mass": 3.0})
    assert res.parameters["coulomb"] == pytest.approx(2.0, rel=1e-10)
    assert res.parameters["viscous"] == pytest.approx(15.0, rel=1e-10)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"velocity": None}, "must hold `velocity`"),
        ({"velocity": np.abs(V) + 0.01}, "change sign"),
        ({"position": np.full_like(T, 0.3)}, "`position` must vary"),
    ],
)
def test_bad_data(change, message):
    m = _measurement()
    fields = {"position": Y, "velocity": V, "acceleration": A, "applied_force": m.applied_force}
    fields.update(change)
    with pytest.raises(ValueError, match=message):
        fit_motion(Measurement(T, **fields), 1, offset=True)


def test_monotone_position_with_elements_is_rejected():
    ramp = Measurement(T, position=T + T**2 / 2, velocity=1.0 + T, acceleration=np.ones_like(T),
                       applied_force=1.0 + T)  # fmt: skip
    with pytest.raises(ValueError, match="reverse at least once"):
        fit_motion(ramp, 1)


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({"max_evaluations": 2.5}, TypeError, "`max_evaluations` must be an integer; got 2.5."),
        (
            {"max_evaluations": 0},
            ValueError,
            "`max_evaluations` must be a positive integer; got 0.",
        ),
        ({"grid_size": 0}, ValueError, "`grid_size` must be at least 2; got 0."),
        ({"grid_size": 2.5}, TypeError, "`grid_size` must be an integer; got 2.5."),
        ({"tolerance": np.nan}, ValueError, "`tolerance` must be finite; got nan."),
        ({"tolerance": "x"}, TypeError, "`tolerance` must be a real number; got 'x'."),
        ({"level": "0.9"}, TypeError, "`level` must be a real number; got '0.9'."),
        ({"fixed": {"mass": "x"}}, TypeError, "`fixed['mass']` must be a real number; got 'x'."),
        (
            {"tied": {"threshold_2": 6.0}},
            TypeError,
            "`tied['threshold_2']` must be a parameter name, a (name, factor) pair or a "
            "(name, factor, offset) triple; got 6.0.",
        ),
    ],
)
def test_bad_fit_options_raise_on_entry(kwargs, error, message):
    with pytest.raises(error, match=f"^{re.escape(message)}$"):
        fit_motion(_measurement(), 2, **kwargs)


def test_prediction_checks_its_arguments():
    m = _measurement()
    res = fit_motion(m, viscous=True, offset=True)
    wrong = r"^`result` must be a FitResult of fit_motion; got 3\.0\.$"
    with pytest.raises(TypeError, match=wrong):
        predict_motion_force(3.0, m)
    without_mass = dataclasses.replace(res, parameters={"coulomb": 2.0})
    with pytest.raises(TypeError, match="got a FitResult without a mass"):
        predict_motion_force(without_mass, m)
    with pytest.raises(TypeError, match=r"^`measurement` must be a Measurement; got ndarray\.$"):
        predict_motion_force(res, np.zeros(4))


def test_asymmetric_round_trip():
    """F_c⁺ ≠ F_c⁻ and σ⁺ ≠ σ⁻ recovered from noise-free data; the model carries both sides."""
    elastic, _ = MODEL.elastic_force(Y)
    pos, neg = V > 0, V < 0
    u = 3.0 * A + 2.0 * pos - 1.2 * neg + np.where(pos, 15.0, 22.0) * V + elastic
    m = Measurement(T, position=Y, velocity=V, acceleration=A, applied_force=u)
    res = fit_motion(m, 2, viscous=True, asymmetric=True)
    assert res.success, res.message
    truth = {"mass": 3.0, "coulomb": 2.0, "coulomb_negative": 1.2, "viscous": 15.0,
             "viscous_negative": 22.0, "threshold_1": 0.001, "threshold_2": 0.006}  # fmt: skip
    for name, value in truth.items():
        assert res.parameters[name] == pytest.approx(value, rel=1e-8), name
    model = res.model
    assert not model.is_symmetric
    assert (model.coulomb, model.coulomb_negative) == pytest.approx((2.0, 1.2), rel=1e-8)
    assert (model.viscous, model.viscous_negative) == pytest.approx((15.0, 22.0), rel=1e-8)
    assert model.coulomb_levels[0] - model.coulomb_levels[1] == pytest.approx(0.8, rel=1e-6)
    np.testing.assert_allclose(predict_motion_force(res, m), u, atol=1e-8)
    # the symmetric fit of the same data is tested against it: both sides' differences count
    test = res.asymmetry
    assert test.verdict == "supported" and test.degrees_of_freedom[0] == 2
    assert "coulomb_negative" not in test.symmetric.parameters and test.rss[1] < test.rss[0]
    # without viscous terms: only the Coulomb sides
    coulomb_only = fit_motion(m, 2, asymmetric=True, refine_thresholds=False,
                              thresholds=[0.001, 0.006])  # fmt: skip
    assert "viscous_negative" not in coulomb_only.parameters


def test_asymmetric_excludes_the_offset_and_needs_both_directions():
    with pytest.raises(ValueError, match="offset"):
        fit_motion(_measurement(), 0, asymmetric=True, offset=True)
    with pytest.raises(TypeError, match="asymmetric"):
        fit_motion(_measurement(), 0, asymmetric="yes")
    one_way = Measurement(T, position=T + T**2, velocity=1.0 + 2 * T,
                          acceleration=np.full_like(T, 2.0), applied_force=4.0 + 2 * T)  # fmt: skip
    with pytest.raises(ValueError, match="two Coulomb levels"):
        fit_motion(one_way, 0, asymmetric=True)


def test_symmetric_noisy_data_do_not_support_an_asymmetry():
    """c1⁺ = c1⁻ and σ⁺ = σ⁻ with noise: the F test of the two nested fits does not reject."""
    elastic, _ = MODEL.elastic_force(Y)
    u = 3.0 * A + 2.0 * np.sign(V) + elastic + 15.0 * V  # no offset: both sides equal
    u = u + np.random.default_rng(3).normal(0.0, 0.05, u.shape)
    m = Measurement(T, position=Y, velocity=V, acceleration=A, applied_force=u)
    res = fit_motion(m, 2, viscous=True, asymmetric=True)
    assert res.asymmetry.verdict == "not supported", res.asymmetry.message
    assert res.asymmetry.scale == pytest.approx(1.0)  # a direct fit: ordinary covariance
