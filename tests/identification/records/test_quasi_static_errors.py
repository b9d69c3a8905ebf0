"""The error floor of runs of equal quantised samples (`_quasi_static_errors`)."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import (
    Measurement,
    PIFriction,
    fit_quasi_static,
    preloaded_state,
    quasi_static_response,
)
from presliding.identification.records._quasi_static_errors import floor_variances

MODEL = PIFriction(0.05, [2e4, 6e3, 2e3], breakaway=[0.15, 0.15, 0.15])
QUANTUM = 1e-8


def test_a_run_of_equal_samples_counts_once():
    """A constant fitted to n equal samples: its variance is σ², not σ²/n; independent
    samples (runs of one) give the ordinary σ²/n."""
    from scipy import sparse

    n, sigma = 8, 3e-9
    jac = np.ones((n, 1))
    one_run = sparse.csr_matrix(np.full((1, n), sigma))
    singles = sparse.csr_matrix(np.eye(n) * sigma)
    assert floor_variances(jac, one_run)[0] == pytest.approx(sigma**2)
    assert floor_variances(jac, singles)[0] == pytest.approx(sigma**2 / n)


def _loops(seed: int, n: int = 4) -> tuple[list, list]:
    """The torque loops of the identification study: preload, 10 nm encoder, 2 nm noise."""
    rng = np.random.default_rng(seed)
    out, truth = [], []
    t = np.linspace(0.0, 4.0, 600)
    for _ in range(n):
        f0 = rng.uniform(-0.8, 0.8) * 0.25 * MODEL.max_elastic_force
        d = rng.choice([-1.0, 1.0])
        u = f0 + d * rng.uniform(0.25, 0.33) * np.sin(np.pi * t) * (1 - 0.1 * t / 4)
        y0 = rng.uniform(-1e-5, 1e-5)
        y = quasi_static_response(MODEL, u, preloaded_state(MODEL, f0, direction=-d,
                                                            position=y0)).position  # fmt: skip
        y = QUANTUM * np.round((y + 2e-9 * rng.standard_normal(600)) / QUANTUM)
        out.append(Measurement(t, position=y, applied_force=u))
        truth.append(y0)
    return out, truth


def test_initial_positions_fixed_by_a_quantised_run_keep_the_quantisation_error():
    """Each record's initial position is fixed by its first samples alone (the contact
    sticks until the force has changed by c1), which an encoder reads as one value: its
    error is the quantisation error of that run, about q/√12, however many samples the
    run holds. The sandwich alone gave 2.6e-14 m (10⁶ times too small) on one of these."""
    records, truth = _loops(7000)
    fit = fit_quasi_static(records, 3)
    assert fit.status == "converged", fit.message
    for i, y0 in enumerate(truth):
        name = f"initial_position_{i + 1}"
        assert fit.standard_error[name] > 0.1 * QUANTUM / np.sqrt(12), name
        lo, hi = fit.confidence_interval[name]
        assert lo <= y0 <= hi, name
