"""Measurement: validation, readers, resampling and zero-phase differentiation."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import io, signal

from presliding.measurement.measurement import Measurement, estimate_derivatives, lowpass


def test_stores_read_only_signals_and_properties():
    t = np.linspace(0.0, 1.0, 11)
    m = Measurement(t, position=t**2, applied_force=np.ones(11))
    assert m.n_samples == 11 and m.duration == 1.0 and m.is_uniform
    assert m.sampling_step == pytest.approx(0.1)
    assert set(m.signals()) == {"position", "applied_force"}
    with pytest.raises(ValueError):
        m.position[0] = 1.0


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"time": [0.0, 1.0, 1.0], "position": [0.0, 1.0, 2.0]}, "strictly increasing"),
        ({"time": [0.0, 1.0, 2.0], "position": [0.0, np.nan, 2.0]}, "`position` must be finite"),
        ({"time": [0.0, 1.0, 2.0], "position": [0.0, 1.0]}, "same length"),
        ({"time": [0.0], "position": [0.0]}, "at least 2 samples"),
        ({"time": [0.0, 1.0]}, "at least one signal"),
    ],
)
def test_bad_input_is_named(kwargs, message):
    with pytest.raises(ValueError, match=message):
        Measurement(**kwargs)


def test_require_names_the_missing_signal():
    m = Measurement([0.0, 1.0], position=[0.0, 1.0])
    with pytest.raises(ValueError, match="`applied_force`"):
        m.require("position", "applied_force", purpose="a test")
    m.require("position")  # present: no error


@pytest.mark.parametrize("name", ["speed", 3, None])
def test_require_rejects_unknown_signal_names(name):
    m = Measurement([0.0, 1.0], position=[0.0, 1.0])
    with pytest.raises(ValueError, match=r"^`names` must be one of 'position', .*; got "):
        m.require(name)


@pytest.mark.parametrize(
    ("bounds", "error", "message"),
    [
        ((np.nan, 1.0), ValueError, r"^`start` must be finite; got nan\.$"),
        ((0.0, np.inf), ValueError, r"^`end` must be finite; got inf\.$"),
        (("0", 1.0), TypeError, r"^`start` must be a real number; got '0'\.$"),
        ((0.0, True), TypeError, r"^`end` must be a real number; got True\.$"),
        ((0.8, 0.2), ValueError, r"^`end` must be at least `start` 0\.8; got 0\.2\.$"),
        ((5.0, 6.0), ValueError, r"^`start` and `end` must enclose at least 2 samples; got 0 "),
    ],
)
def test_window_bounds_are_validated(bounds, error, message):
    m = Measurement(np.linspace(0.0, 1.0, 11), position=np.arange(11.0))
    with pytest.raises(error, match=message):
        m.window(*bounds)
    np.testing.assert_array_equal(m.window(None, 0.25).position, [0.0, 1.0, 2.0])


def test_from_csv_by_name_and_index_with_units_and_scale(tmp_path):
    path = tmp_path / "data.txt"
    path.write_text("Time [s]\tPos [mm]\tF [uN]\n0\t1.0\t10\n0.5\t2.0\t20\n1.0\t3.0\t30\n")
    m = Measurement.from_csv(
        path, "Time [s]", position="Pos [mm]", friction_force=2, scale={"friction_force": -2.0}
    )
    np.testing.assert_allclose(m.position, [1e-3, 2e-3, 3e-3])  # mm from the header
    np.testing.assert_allclose(m.friction_force, [-2e-5, -4e-5, -6e-5])  # uN, then × -2
    with pytest.raises(ValueError, match="no column 'nope' for `position`"):
        Measurement.from_csv(path, "Time [s]", position="nope")
    with pytest.raises(ValueError, match="signal names"):
        Measurement.from_csv(path, "Time [s]", speed="Pos [mm]")


def test_from_mat_with_scale_from_a_variable(tmp_path):
    path = tmp_path / "d.mat"
    t = np.arange(5) * 0.1
    io.savemat(path, {"t": t[:, None], "q": (t**2)[:, None], "vir": np.ones((5, 1)), "g": 3.0})
    m = Measurement.from_mat(path, position="q", applied_force="vir", scale={"applied_force": "g"})
    np.testing.assert_allclose(m.applied_force, 3.0)
    np.testing.assert_allclose(m.position, t**2)
    with pytest.raises(ValueError, match="variable 'zz'"):
        Measurement.from_mat(path, position="zz")


def test_resample_is_exact_for_linear_signals_and_window_selects():
    t = np.sort(np.random.default_rng(0).uniform(0, 1, 50))
    m = Measurement(t, position=3.0 * t + 1.0)
    r = m.resample(0.01)
    assert r.is_uniform
    np.testing.assert_allclose(r.position, 3.0 * r.time + 1.0, rtol=1e-12)
    w = m.window(0.2, 0.5)
    assert w.time.min() >= 0.2 and w.time.max() <= 0.5
    with pytest.raises(ValueError, match="at least 2 samples"):
        m.window(5.0, 6.0)


@settings(max_examples=25, deadline=None)
@given(
    slope=st.floats(-10, 10),
    offset=st.floats(-5, 5),
    method=st.sampled_from(["butter", "savgol"]),
)
def test_derivatives_of_a_ramp_are_exact(slope, offset, method):
    t = np.arange(400) * 1e-3
    v, a = estimate_derivatives(t, slope * t + offset, 50.0, method=method)
    np.testing.assert_allclose(v, slope, atol=1e-9 * (1 + abs(slope)))
    np.testing.assert_allclose(a, 0.0, atol=1e-5 * (1 + abs(slope)))


def test_quantised_sine_velocity_is_accurate_and_has_no_lag():
    t = np.arange(5000) * 1e-3
    q = 5e-8
    y = np.round(0.01 * np.sin(2 * np.pi * 1.0 * t) / q) * q
    m = Measurement(t, position=y).differentiate(cutoff=20.0)
    exact = 0.01 * 2 * np.pi * np.cos(2 * np.pi * t)
    inner = slice(200, -200)
    assert np.max(np.abs(m.velocity[inner] - exact[inner])) < 1e-3 * np.max(np.abs(exact))
    lags = np.arange(-5, 6)
    corr = [np.dot(np.roll(m.velocity, k)[inner], exact[inner]) for k in lags]
    assert lags[int(np.argmax(corr))] == 0


@pytest.mark.parametrize("order", [2, 3, 4])
def test_savgol_window_puts_minus_3_db_at_the_cutoff(order):
    fs, fc = 1000.0, 40.0
    t = np.arange(2000) / fs
    y = np.zeros_like(t)
    y[1000] = 1.0  # impulse response = the smoothing taps (mirrored)
    taps = lowpass(t, y, fc, method="savgol", order=order)[1000 - 300 : 1000 + 301]
    taps = taps[taps != 0]
    gain = abs(signal.freqz(taps, worN=[fc], fs=fs)[1][0])
    longer = signal.savgol_coeffs(taps.shape[0] + 2, order)
    gain_longer = abs(signal.freqz(longer, worN=[fc], fs=fs)[1][0])
    assert gain >= np.sqrt(0.5) > gain_longer
    y = np.sin(2 * np.pi * 5.0 * t)
    smooth = lowpass(t, y, fc, method="savgol", order=order)
    np.testing.assert_allclose(smooth[50:-50], y[50:-50], atol=2e-3)


def test_differentiate_needs_uniform_sampling_and_a_valid_cutoff():
    t = np.r_[np.arange(100) * 1e-3, 0.2 + np.arange(100) * 1e-3]
    m = Measurement(t, position=np.sin(t))
    with pytest.raises(ValueError, match="resample"):
        m.differentiate(10.0)
    u = m.resample(1e-3)
    with pytest.raises(ValueError, match="Nyquist"):
        u.differentiate(600.0)
    out = u.differentiate(10.0, filter_forces=True)
    assert out.velocity is not None and out.acceleration is not None


@pytest.mark.parametrize(("cutoff", "order"), [(2.0, 6), (10.0, 6), (2.0, 10), (50.0, 4)])
def test_derivatives_of_a_long_fast_record_match_the_analytic_ones(cutoff, order):
    # 10 kHz for 10 s: a cut-off of 2e-4 of Nyquist, where the (b, a) form gave 4.7e48 m/s
    t = np.arange(100_000) * 1e-4
    w = 2 * np.pi * 1.0
    y = 1e-3 * np.sin(w * t)
    m = Measurement(t, position=y).differentiate(cutoff, order=order)
    gain = 1.0 / (1.0 + (1.0 / cutoff) ** (2 * order))  # |H|² of the zero-phase filter at 1 Hz
    inner = slice(30_000, -30_000)  # the start-up of the filter has died out
    v_true, a_true = 1e-3 * w * np.cos(w * t), -1e-3 * w**2 * np.sin(w * t)
    np.testing.assert_allclose(m.velocity[inner], gain * v_true[inner], atol=5e-3 * 1e-3 * w)
    np.testing.assert_allclose(m.acceleration[inner], gain * a_true[inner], atol=1e-2 * 1e-3 * w**2)
    assert np.max(np.abs(m.velocity)) < 1.5 * 1e-3 * w  # the edges ring a little, no more
