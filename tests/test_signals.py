"""Piecewise-linear test paths (signals module)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal

from presliding.signals import FIGURE3_TURNING_POINTS, piecewise_linear
from tests.helpers import PROPERTY, figure3_model, turning_points


def _vertex_indices(points, step):
    idx = [0]
    for a, b in itertools.pairwise(points):
        idx.append(idx[-1] + max(1, int(np.ceil(abs(b - a) / step))))
    return np.array(idx)


def test_small_example():
    assert_allclose(piecewise_linear([0.0, 1.0, 0.5], 0.25), [0, 0.25, 0.5, 0.75, 1.0, 0.75, 0.5])
    assert_allclose(piecewise_linear([0.0, 1.0], 0.3), [0.0, 0.25, 0.5, 0.75, 1.0])
    assert_array_equal(piecewise_linear([2.0, 2.0, 3.0], 5.0), [2.0, 2.0, 3.0])


@PROPERTY
@given(points=turning_points(), step=st.floats(1e-3, 0.5))
def test_path_visits_every_turning_point_and_is_monotone_between(points, step):
    y = piecewise_linear(points, step)
    idx = _vertex_indices(points, step)
    assert y.size == idx[-1] + 1
    assert_array_equal(y[idx], points)  # exactly, so turning points are samples
    for i0, i1, a, b in zip(idx[:-1], idx[1:], points[:-1], points[1:], strict=True):
        seg = y[i0 : i1 + 1]
        assert np.all(np.diff(seg) * np.sign(b - a) >= 0)  # monotone between turning points
        assert np.max(np.abs(np.diff(seg))) <= step * (1 + 1e-12)  # never coarser than step
        assert_allclose(np.diff(seg), (b - a) / (i1 - i0), rtol=1e-9, atol=1e-15)  # uniform


def test_figure3_turning_points_make_nested_minor_loops():
    tp = FIGURE3_TURNING_POINTS
    assert tp[0] == 0.0  # starts from the relaxed state at 0
    assert tp[1] == -tp[2] == tp[-1] == -tp[-2]  # a major loop, closed again at the end
    # every Figure 3 model saturates on the major loop: |y| beyond 2·r_j on each swing
    for k1 in (500.0, 50.0, 5.0):
        assert tp[1] > np.max(figure3_model(k1).threshold)
    # the minor loops nest inside the major one: 0.15 → −0.05 → 0.08 stay within the previous
    # pair of turning points
    for n in range(3, 6):
        lo, hi = sorted((tp[n - 2], tp[n - 1]))
        assert lo < tp[n] < hi
    # ... and the descent to −0.3 passes the minor loop's reversal points (wiping them out)
    assert tp[6] < min(tp[3:6])
    y = piecewise_linear(tp, 1e-3)
    assert y[0] == 0.0 and y[-1] == 0.3


@pytest.mark.parametrize("step", [1e-3, 0.07, 10.0])
def test_the_step_bounds_the_spacing(step):
    y = piecewise_linear(FIGURE3_TURNING_POINTS, step)
    assert np.max(np.abs(np.diff(y))) <= step * (1 + 1e-12)


def test_signals_is_reachable_from_the_package():
    import presliding as ps

    assert ps.signals.piecewise_linear is piecewise_linear  # as the README uses it
