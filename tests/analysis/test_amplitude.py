"""Amplitude-dependent dissipation, stiffness and damping (Masing loops of PI models)."""

import math

import matplotlib
import numpy as np
import pytest

import presliding as ps
from presliding import MicroslipBar, MindlinContact, PIFriction, SegalmanIwan, amplitude_response

matplotlib.use("Agg")

MODELS = {
    "elements": PIFriction(0.3, [100.0, 40.0, 7.0], breakaway=[0.32, 0.34, 0.2]),
    "uniform": PIFriction(0.1, density=ps.Uniform(300.0, 0.02)),
    "exponential": PIFriction(0.0, density=ps.Exponential(1e4, 2e-3)),
    "segalman": PIFriction(0.2, density=SegalmanIwan(2e5, 30.0, -0.4, 0.3)),
    "mindlin": PIFriction(0.0, density=MindlinContact(40.0, 2e-5)),
    "bar": PIFriction(0.0, density=MicroslipBar(2e6, 5e3, 0.4)),
}


def _cycle_dissipation(model, a):
    """D from the exact dissipation of the operator over a cycle −a → +a after the virgin rise."""
    y = np.array([0.0, a, -a, a])
    d = ps.dissipated_energy(model, y)
    return d[3] - d[1]


@pytest.mark.parametrize("name", sorted(MODELS))
def test_dissipation_matches_the_operator_over_a_cycle(name):
    model = MODELS[name]
    big_r = model.density.max_threshold
    scale = big_r if math.isfinite(big_r) else 0.01
    amps = scale * np.array([0.013, 0.2, 0.61, 0.97, 1.8])
    res = amplitude_response(model, amps)
    for a, dis in zip(amps, res.dissipation, strict=True):
        assert dis == pytest.approx(_cycle_dissipation(model, a), rel=1e-11, abs=1e-300)
    # the backbone is the virgin curve; derived quantities follow
    np.testing.assert_allclose(res.force, model.virgin_curve(amps), rtol=1e-13)
    np.testing.assert_allclose(res.secant_stiffness * amps, res.force, rtol=1e-14)
    np.testing.assert_allclose(res.loss_factor, 2 * res.damping_ratio, rtol=1e-15)
    ok = res.dissipation > 0
    np.testing.assert_allclose(
        res.damping_ratio[ok],
        res.dissipation[ok] / (2 * math.pi * res.force[ok] * amps[ok]),
        rtol=1e-14,
    )


@pytest.mark.parametrize("name", ["uniform", "exponential", "segalman", "mindlin", "bar"])
def test_slopes_are_the_log_log_derivatives(name):
    model = MODELS[name]
    big_r = model.density.max_threshold
    scale = big_r if math.isfinite(big_r) else 0.01
    a = scale * np.array([0.05, 0.3, 0.7])
    h = 1e-5
    res = amplitude_response(model, a)
    lo, hi = amplitude_response(model, a * math.exp(-h)), amplitude_response(model, a * math.exp(h))
    for name_, slope in [
        ("dissipation", res.dissipation_slope),
        ("force", res.force_slope),
        ("secant_stiffness", res.stiffness_slope),
        ("damping_ratio", res.damping_slope),
    ]:
        numeric = (np.log(getattr(hi, name_)) - np.log(getattr(lo, name_))) / (2 * h)
        np.testing.assert_allclose(slope, numeric, rtol=1e-7, atol=1e-8, err_msg=name_)


def test_segalman_slope_and_closed_form():
    d = SegalmanIwan(2.0, 3.0, -0.1, 0.1)
    a = np.geomspace(1e-6, 0.9, 30) * d.max_threshold
    res = amplitude_response(d, a)
    np.testing.assert_allclose(res.dissipation, d.loop_energy(a), rtol=1e-12)
    np.testing.assert_allclose(res.dissipation_slope, 2.9, rtol=1e-12)
    assert res.status == "success"


def test_mindlin_and_bar_in_force_amplitude():
    mindlin = MindlinContact(40.0, 2e-5)
    q = np.linspace(0.1, 0.99, 40)
    res = amplitude_response(mindlin, 2e-5 * (1 - (1 - q) ** (2 / 3)))
    np.testing.assert_allclose(res.force, 40.0 * q, rtol=1e-13)
    np.testing.assert_allclose(res.dissipation, mindlin.loop_energy_at_force(res.force), rtol=1e-12)
    bar = MicroslipBar(2e6, 5e3, 0.4)
    force = np.linspace(50.0, 2e3, 30)
    res = amplitude_response(bar, force**2 / (2 * 2e6 * 5e3))
    np.testing.assert_allclose(res.force, force, rtol=1e-13)
    np.testing.assert_allclose(res.dissipation, 2 * force**3 / (3 * 2e6 * 5e3), rtol=1e-12)
    np.testing.assert_allclose(res.dissipation_slope, 1.5, rtol=1e-12)  # D ∝ a^(3/2)


def test_below_every_threshold_nothing_dissipates_and_says_so():
    model = PIFriction(0.0, [100.0, 40.0], breakaway=[0.32, 0.34])
    res = amplitude_response(model, [1e-4, 1e-2])
    assert res.status == "no_dissipation" and res.success
    assert "undefined" in res.message
    assert res.dissipation[0] == 0.0 and np.isnan(res.dissipation_slope[0])
    assert res.secant_stiffness[0] == pytest.approx(140.0, rel=1e-14)
    assert np.isfinite(res.dissipation_slope[1])


def test_result_convention_and_plots():
    import matplotlib.pyplot as plt

    res = amplitude_response(MODELS["segalman"], np.geomspace(1e-7, 1e-3, 20))
    assert "AmplitudeResponse(n=20" in repr(res) and len(repr(res)) < 120
    assert "<table>" in res._repr_html_() and res.status in res._repr_html_()
    frame = res.to_pandas()
    assert frame.shape[0] == 20 and frame.attrs["status"] == "success"
    np.testing.assert_array_equal(frame["dissipation"].to_numpy(), res.dissipation)
    for quantity in ("dissipation", "force", "stiffness", "damping", "loss"):
        ax = res.plot(quantity=quantity)
        assert "[" in ax.get_xlabel() and "[" in ax.get_ylabel()
        plt.close(ax.figure)
    with pytest.raises(ValueError, match="quantity"):
        res.plot(quantity="phase")


@pytest.mark.parametrize(
    "amps, match", [([0.0, 1.0], "amplitudes"), ([np.nan], "amplitudes"), ([[1.0]], "amplitudes")]
)
def test_bad_amplitudes_are_named(amps, match):
    with pytest.raises(ValueError, match=match):
        amplitude_response(MODELS["uniform"], amps)


def test_model_type_is_checked():
    with pytest.raises(TypeError, match="model"):
        amplitude_response("joint", [1.0])
