"""Hardening of the identification layer: filter orders, sample budgets of a fit."""

from __future__ import annotations

import time

import numpy as np
import pytest

from presliding import PIFriction, fit_presliding
from presliding.measurement._filters import MAX_ORDER, estimate_derivatives, lowpass
from tests.test_validation import assert_rejects

T = np.linspace(0.0, 1.0, 1001)


def test_filter_order_has_a_limit_instead_of_a_hang():
    estimate_derivatives(T, np.sin(T), 5.0, method="savgol", order=3)  # imports done
    start = time.perf_counter()
    for method in ("butter", "savgol"):
        message = assert_rejects(
            lambda m=method: estimate_derivatives(T, np.sin(T), 5.0, method=m, order=10**6),
            ValueError,
            "order",
        )
        assert message == f"`order` must be at most {MAX_ORDER}; got 1000000."
    assert time.perf_counter() - start < 1.0


def test_high_order_butterworth_at_a_low_cutoff_stays_accurate():
    # in (b, a) form this filter was unstable; in second-order sections it is exact
    t = np.linspace(0.0, 1.0, 20001)
    smooth = lowpass(t, np.sin(t), 5.0, order=10)
    np.testing.assert_allclose(smooth, np.sin(t), atol=0.05)  # the end rings (a 1 s record)
    np.testing.assert_allclose(smooth[:-8000], np.sin(t)[:-8000], atol=2e-3)


@pytest.fixture(scope="module")
def loops():
    y = np.sin(np.linspace(0.0, 20.0, 400)) * 1e-3
    force, _ = PIFriction(0.1, [1000.0, 100.0], [0.5, 0.5]).force(y)
    return y, force


def test_fit_presliding_names_burn_in_and_element_count(loops):
    y, force = loops
    message = assert_rejects(lambda: fit_presliding(y, force, burn_in=10**9), ValueError, "burn_in")
    assert "at most 392 for 400 samples" in message
    message = assert_rejects(lambda: fit_presliding(y, force, 1000), ValueError, "n_elements")
    assert "at most 199 elements" in message
    message = assert_rejects(
        lambda: fit_presliding(y, force, thresholds=np.linspace(1e-5, 1e-3, 300)),
        ValueError,
        "thresholds",
    )
    message = assert_rejects(
        lambda: fit_presliding(y, force, 2, burn_in=395, offset=True), ValueError, "burn_in"
    )
    assert "(6)" in message


def test_bootstrap_resamples_are_limited_and_their_time_left_is_shown():
    from presliding.identification.plans import _response_setup as setup

    assert setup.MAX_BOOTSTRAP == 10_000
    assert [setup._duration(s) for s in (12.4, 600.0, 3 * 3600.0)] == ["12 s", "10 min", "3.0 h"]
