"""A measurement as the pooled fit reads it (`_pooled_record`): which velocity is a
difference quotient of the position, and the quotient as a matrix."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import Measurement
from presliding.identification.records._pooled_record import (
    as_record,
    difference_matrix,
    difference_order,
)


def _signal(n: int = 400):
    rng = np.random.default_rng(3)
    t = np.cumsum(rng.uniform(0.5e-3, 1.5e-3, n))  # uneven sampling
    y = 1e-3 * np.sin(40 * t) + 1e-6 * np.round(rng.standard_normal(n))
    return t, y


def test_difference_quotient_is_detected_to_rounding():
    t, y = _signal()
    exact = 40e-3 * np.cos(40 * t)  # a measured velocity: not a quotient of y
    assert difference_order(t, y, np.gradient(y, t)) == 1
    assert difference_order(t, y, np.gradient(y, t, edge_order=2)) == 2
    assert difference_order(t, y, exact) == 0
    u = np.zeros_like(t)
    diff = Measurement(t, position=y, velocity=np.gradient(y, t), applied_force=u)
    measured = Measurement(t, position=y, velocity=exact, applied_force=u)
    assert as_record(diff).difference == 1
    assert as_record(diff, "measured").difference == 0
    assert as_record(measured).difference == 0
    assert as_record(measured, "difference").difference == 1
    assert as_record(Measurement(t, position=y, applied_force=u)).difference == 1


@pytest.mark.parametrize("order", [1, 2])
def test_difference_matrix_is_numpy_gradient(order: int):
    t, y = _signal()
    d = difference_matrix(t, order)
    np.testing.assert_allclose(d @ y, np.gradient(y, t, edge_order=order), rtol=1e-12,
                               atol=1e-15 * np.max(np.abs(np.gradient(y, t))))  # fmt: skip
    assert d.nnz <= 3 * t.shape[0] + 6  # three entries a row, more only at the ends
