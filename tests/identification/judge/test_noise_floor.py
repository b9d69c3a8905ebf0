"""The noise floor estimated from the data (`_noise_floor`)."""

from __future__ import annotations

import numpy as np
import pytest

from presliding.identification.judge._noise_floor import noise_variance, quantum


@pytest.mark.parametrize("q", [1e-6, 2e-8, 1e-3])
def test_the_quantum_of_a_drive_velocity_is_that_of_its_position_over_two_steps(q):
    """A quantised position's difference quotient has steps of q/(2·Δt), and steps of a
    few ulps where the position stands still between moving neighbours. Before, such
    a step was taken for the quantum (8.9e-16 m/s for q = 20 nm), the floor of a stiff
    stage's records mostly at rest came out a thousandth of the noise and fits at the
    truth 5–10 times above it."""
    dt = 1e-3
    t = np.arange(1000) * dt
    scale = q / 2e-8  # the same motion in quanta
    x = scale * (np.where(t < 0.1, 0.3 * t - 1.5 * t**2, 0.015)
                 + 1e-6 * np.exp(-5 * t) * np.sin(900 * t))  # fmt: skip
    y = q * np.round(x / q)
    v = np.gradient(y, t)
    assert quantum(y) == pytest.approx(q, rel=1e-6)
    assert quantum(v) == pytest.approx(q / (2 * dt), rel=1e-6)
    assert noise_variance(v) >= (q / (2 * dt)) ** 2 / 12


def test_a_smooth_signal_has_no_quantum():
    t = np.linspace(0.0, 1.0, 500)
    assert quantum(np.sin(3 * t) + 0.1) == 0.0
