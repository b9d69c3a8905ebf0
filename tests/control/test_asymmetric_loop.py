"""`simulate_loop` with asymmetric friction (the exact event method with two sides)."""

from __future__ import annotations

import hashlib

import numpy as np
import pytest

import presliding as ps

K = [500.0, 10.0, 4.0]


def _reference(t):
    return 0.01 * np.sin(3 * t)


def _digest(res) -> str:
    h = hashlib.sha256()
    for a in (res.position, res.velocity, res.acceleration, res.friction_force,
              res.energy.dissipated, res.control):  # fmt: skip
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()[:16]


def _loop(model):
    pid = ps.PID(kp=400.0, ki=2000.0, kd=20.0, dt=1e-3)
    return ps.simulate_loop(model, 1.0, pid, reference=_reference, t_end=3.0, substeps=3)


@pytest.mark.parametrize(
    ("viscous", "digest"), [(0.0, "8ab05fe254ba147f"), (2.0, "9d9c35cba092e55c")]
)
def test_symmetric_loops_are_bit_identical_to_the_symmetric_code(viscous, digest):
    """Digests of the symmetric loop recorded before asymmetric friction existed."""
    assert _digest(_loop(ps.PIFriction(0.5, K, [1.0, 1.0, 1.0], viscous=viscous))) == digest


def test_asymmetric_loop_is_the_open_loop_motion_under_its_control():
    model = ps.PIFriction(0.5, K, [1.0, 1.0, 1.0], coulomb_negative=0.2,
                          breakaway_negative=[0.5, 2.0, 0.75], viscous=1.0,
                          viscous_negative=3.0)  # fmt: skip
    res = _loop(model)
    assert res.success, res.message
    # the same control held piecewise constant, run open loop by simulate
    open_loop = ps.simulate(model, 1.0, applied_force=(res.control_time, res.control),
                            hold="zoh", t_eval=res.time, t_end=float(res.time[-1]))  # fmt: skip
    np.testing.assert_allclose(res.position, open_loop.position, rtol=0, atol=1e-12)
    np.testing.assert_allclose(res.friction_force, open_loop.friction_force, rtol=0, atol=1e-8)
    e = res.energy
    assert np.max(np.abs(e.residual)) <= 1e-9 * max(float(np.max(np.abs(e.work))), 1.0)
    # the asymmetry shows: it differs from the symmetric loop
    sym = _loop(ps.PIFriction(0.5, K, [1.0, 1.0, 1.0], viscous=1.0))
    assert np.max(np.abs(sym.position - res.position)) > 1e-5


def test_loop_batches_say_they_take_only_symmetric_friction():
    model = ps.PIFriction(0.5, K, [1.0, 1.0, 1.0], coulomb_negative=0.2)
    with pytest.raises(NotImplementedError, match="simulate_loop_batch"):
        ps.simulate_loop_batch(model, 1.0, ps.PID(kp=400.0, ki=2000.0, kd=20.0, dt=1e-3),
                               reference=1e-3, kp=[300.0, 400.0], t_end=0.1)  # fmt: skip
