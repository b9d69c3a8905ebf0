"""Reversal counting on quantised records; cross_validate and predict errors."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import cross_validate, fit_presliding
from presliding.identification.prediction import count_reversals, reversal_tolerance


def test_quantisation_and_noise_are_not_counted_as_reversals():
    t = np.linspace(0, 1, 2000)
    y = 1e-4 * np.sin(2 * np.pi * 2 * t)  # four turning points
    rng = np.random.default_rng(0)
    noisy = 1e-6 * np.round((y + 3e-7 * rng.standard_normal(t.shape)) / 1e-6)
    assert count_reversals(y) == 4
    assert count_reversals(noisy) == 4
    assert reversal_tolerance(noisy) == pytest.approx(3e-6, rel=1e-9)  # three quanta
    assert count_reversals(noisy, tolerance=0.0) > 4  # flicker counted without a tolerance
    assert count_reversals(np.zeros(10)) == 0
    with pytest.raises(ValueError, match="`tolerance` must be nonnegative"):
        count_reversals(y, tolerance=-1.0)


def test_cross_validate_and_predict_errors():
    with pytest.raises(ValueError, match="at least two records"):
        cross_validate([object()])
    with pytest.raises(ValueError, match="`fit` must be one of"):
        cross_validate([1, 2], fit="virgin")
    with pytest.raises(TypeError, match="`fit` must be a fit function"):
        cross_validate([1, 2], fit=3)
    y = np.sin(np.linspace(0, 12, 400))
    fit = fit_presliding(y, np.tanh(5 * y), 2)
    with pytest.raises(ValueError, match="cannot predict other records"):
        fit.predict(None)
