"""masing_check reads F_r at the turning point itself on displacement-driven records, and
at the first sample of the rest on force-driven ones."""

from __future__ import annotations

import numpy as np
import pytest

import presliding as ps
from presliding.identification import masing_check

MODEL = ps.PIFriction(0.2, [4000.0, 800.0, 150.0], breakaway=[0.3, 0.4, 0.3])


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_a_displacement_driven_loop_follows_masing_exactly_with_a_wide_tolerance(sign):
    """A sine of displacement, densely sampled: many samples lie within the reversal
    tolerance before each turn, where the force is still rising; F_r is read at the
    turning point, so the exact model's own loops pass with no discrepancy."""
    t = np.linspace(0.0, 5.0 * np.pi, 5001)
    y = sign * 2e-3 * np.sin(t) * (1.0 - 0.05 * t / t[-1])
    f = MODEL.force(y)[0]
    check = masing_check(MODEL, (y, f), reversal_tolerance=5e-5)
    assert check.passed
    assert check.discrepancy < 1e-9


def test_a_force_driven_loop_reads_the_first_sample_of_the_rest():
    u = np.concatenate([np.linspace(0, 0.9, 300), np.linspace(0.9, -0.9, 600),
                        np.linspace(-0.9, 0.6, 500)])  # fmt: skip
    res = ps.quasi_static_response(MODEL, u)
    check = masing_check(MODEL, (res.position, u), reversal_tolerance=1e-12)
    assert check.passed and check.discrepancy < 1e-9
