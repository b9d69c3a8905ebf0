"""Measurement.segments: stops, loops and ramps cut from long records."""

from __future__ import annotations

import numpy as np
import pytest

import presliding as ps
from presliding.measurement import Measurement
from presliding.measurement.segments import turning_indices
from presliding.signals import piecewise_linear

MODEL = ps.PIFriction(0.3, [4000.0, 1000.0], breakaway=[0.35, 0.35])
DT = 1e-3


def servo_record(n_stops=4, quantum=1e-6, seed=0):
    """Pushes of alternating sign, each followed by a deceleration to rest (quantised)."""
    rng = np.random.default_rng(seed)
    t = np.arange(n_stops * 500) * DT
    u = np.zeros_like(t)
    for k in range(n_stops):
        begin = 0.05 + 0.5 * k
        u[(t >= begin) & (t < begin + rng.uniform(0.08, 0.12))] = rng.uniform(1.8, 2.4) * (-1) ** k
    res = ps.simulate(MODEL, 2.0, applied_force=(t, u), t_eval=t)
    assert res.success
    y = quantum * np.round(res.position / quantum) if quantum > 0 else res.position
    return t, y, u, res


def test_stops_from_the_inputs_drop():
    t, y, u, _ = servo_record()
    m = Measurement(t, position=y, applied_force=u)
    seg = m.segments("stops")
    assert len(seg) == 4
    rows = seg.table()
    assert [r["from"] for r in rows] == ["input drop"] * 4
    for piece in seg:
        drop = np.flatnonzero(np.diff(piece.applied_force) != 0)
        assert drop.size == 1  # each piece holds its drop, and only one
        v = np.gradient(piece.position, piece.time)
        assert np.all(np.abs(v[-20:]) < 1e-3)  # and ends at rest
    for a, b in zip(seg.spans, seg.spans[1:], strict=False):
        assert a[1] <= b[0]  # pieces never overlap
    assert "4 stops cut from record" in seg.report()


def test_stops_from_the_velocity_with_a_lead_in():
    t, _y, _, res = servo_record(3, quantum=0.0)
    m = Measurement(t, velocity=res.velocity)
    seg = m.segments("stops", lead_in=0.02)
    assert len(seg) == 3 and {r["from"] for r in seg.table()} == {"speed peak"}
    for piece in seg:
        peak = int(np.argmax(np.abs(piece.velocity)))
        assert piece.time[peak] - piece.time[0] == pytest.approx(0.02, abs=1.5 * DT)


def test_each_stop_is_a_pooled_record():
    t, y, u, _ = servo_record()
    m = Measurement(t, position=y, applied_force=u)
    # the stops determine one element (two coalesce: not_identifiable, honestly)
    fit = ps.fit_response(list(m.segments("stops")), 1, signal="position")
    assert fit.success, fit.message
    assert fit.model.coulomb_level == pytest.approx(MODEL.coulomb_level, rel=0.03)
    assert fit.parameters["mass"] == pytest.approx(2.0, rel=0.05)


def _ramps(quantum=1e-6, retreat=4):
    points = [0.0, 1e-3, -0.5e-3, 0.8e-3, -0.2e-3]
    y = piecewise_linear(points, 2e-7)
    t = np.arange(y.shape[0]) * DT
    rng = np.random.default_rng(1)
    y = y + (retreat * quantum) * (rng.random(y.shape[0]) < 0.003) * -np.sign(np.gradient(y))
    return t, quantum * np.round(y / quantum), len(points) - 1


def test_ramps_and_loops_with_quantised_retreats_of_several_quanta():
    t, y, n_ramps = _ramps(retreat=2)
    m = Measurement(t, position=y)
    ramps = m.segments("ramps")
    assert len(ramps) == n_ramps
    for piece in ramps:  # monotone up to the retreats
        d = np.diff(piece.position)
        assert np.all(d >= -2.5e-6) or np.all(d <= 2.5e-6)
    loops = m.segments("loops")
    assert len(loops) == n_ramps // 2
    # a retreat of 4 quanta is a turning point at the default tolerance of 3 quanta
    t, y, _ = _ramps(retreat=4)
    assert len(Measurement(t, position=y).segments("ramps", tolerance=5e-6)) == n_ramps


def test_turning_indices_of_a_zigzag():
    y = np.array([0.0, 1, 2, 3, 2, 1, 2, 5, 4, 4.5, 0])
    np.testing.assert_array_equal(turning_indices(y, 0.6), [3, 5, 7])
    np.testing.assert_array_equal(turning_indices(y[::-1].copy(), 0.6), [3, 5, 7])


def test_bad_requests():
    t = np.arange(100) * DT
    m = Measurement(t, position=np.zeros(100))
    with pytest.raises(ValueError, match="`kind` must be one of 'stops', 'loops', 'ramps'"):
        m.segments("cycles")
    with pytest.raises(ValueError, match="never moves"):
        m.segments("stops")
    with pytest.raises(ValueError, match="must hold `position` for cutting ramps"):
        Measurement(t, applied_force=np.ones(100)).segments("ramps")
