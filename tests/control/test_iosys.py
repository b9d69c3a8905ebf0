"""python-control interface: exact friction operator and exact plant steps in closed loops."""

import sys

import numpy as np
import pytest

control = pytest.importorskip("control")

from presliding import PIFriction  # noqa: E402
from presliding.control import iosys_state, to_iosys  # noqa: E402
from presliding.friction.baselines import CoulombFriction, DahlFriction, LuGreFriction  # noqa: E402
from presliding.motion import simulate  # noqa: E402
from presliding.signals import piecewise_linear  # noqa: E402

MODEL = PIFriction(coulomb=0.2, stiffness=[400.0, 60.0], breakaway=[0.3, 0.4])


@pytest.mark.parametrize(
    "model",
    [MODEL, CoulombFriction(0.7), DahlFriction(1.0, 80.0, 1.5)],
    ids=["pi", "coulomb", "dahl"],
)
def test_friction_system_is_the_exact_operator(model):
    y = piecewise_linear([0.0, 0.01, -0.004, 0.006, -0.01], 5e-4)
    t = np.arange(y.size) * 1e-3
    sys_ = to_iosys(model, dt=1e-3)
    resp = control.input_output_response(sys_, t, y, iosys_state(model), return_x=True)
    force, _ = model.force(y)
    np.testing.assert_array_equal(resp.outputs, force)
    # the state at the last sample is the memory after all earlier inputs
    _, before_last = model.force(y[:-1])
    np.testing.assert_array_equal(resp.states[:, -1], iosys_state(model, before_last))


def test_open_loop_plant_equals_simulate():
    dt = 2e-3
    t = np.arange(400) * dt
    u = np.where(t < 0.3, 0.9, -0.1)
    plant = to_iosys(MODEL, mass=2.0, dt=dt)
    x0 = iosys_state(MODEL, mass=2.0, velocity=0.4)
    resp = control.input_output_response(plant, t, u, x0)
    sim = simulate(MODEL, 2.0, (t, u), initial_velocity=0.4, t_eval=t, method="event")
    np.testing.assert_allclose(resp.outputs[0], sim.position, rtol=0, atol=1e-12)
    np.testing.assert_allclose(resp.outputs[1], sim.velocity, rtol=0, atol=1e-12)


def test_pd_position_loop_stops_like_simulate():
    """A discrete PD loop around the exact plant: its stop and reversals equal `simulate`."""
    m, dt, kp, kd, ref = 1.0, 2e-3, 150.0, 1.0, 0.05
    plant = to_iosys(MODEL, mass=m, dt=dt, name="plant")
    pd = control.ss(
        [], [], [], [[kp, -kp, -kd]], dt=dt,
        inputs=["r", "position", "velocity"], outputs=["force"], name="pd",
    )  # fmt: skip
    loop = control.interconnect(
        [plant, pd], inplist=["r"], inputs=["r"],
        outlist=["position", "velocity", "force"], outputs=["position", "velocity", "force"],
    )  # fmt: skip
    t = np.arange(1500) * dt
    resp = control.input_output_response(loop, t, np.full(t.size, ref), iosys_state(MODEL, mass=m))
    y, v, u = resp.outputs
    np.testing.assert_allclose(u, kp * (ref - y) - kd * v, rtol=0, atol=1e-12)
    sim = simulate(MODEL, m, (t, u), hold="zoh", t_eval=t, method="event")
    np.testing.assert_allclose(y, sim.position, rtol=0, atol=1e-12)
    np.testing.assert_allclose(v, sim.velocity, rtol=0, atol=1e-12)
    assert sim.n_reversals >= 3 and sim.stop_time is not None
    after = t > sim.stop_time + dt
    assert np.all(y[after] == y[after][0]) and np.all(v[after] == 0.0)  # no creep at all
    assert y[after][0] == pytest.approx(sim.rest_position, abs=1e-12)
    signs = np.sign(v[v != 0.0])
    assert int(np.count_nonzero(np.diff(signs))) == sim.n_reversals
    # at rest the bank keeps presliding memory: some element is not at its threshold
    assert np.any(np.abs(sim.final_state.deformation) < MODEL.threshold * (1 - 1e-9))
    assert abs(sim.rest_position - ref) <= (MODEL.coulomb_level + 1e-12) / kp


def test_errors():
    with pytest.raises(TypeError, match="`model` must be a PIFriction, CoulombFriction"):
        to_iosys(LuGreFriction(1.0, 1.0, 1.0, 0.0, 0.0, 1.0))
    with pytest.raises(ValueError, match="`dt` must be positive"):
        to_iosys(MODEL, dt=0.0)
    with pytest.raises(
        TypeError, match=r"^`model` must be .* when a `mass` is given; got DahlFriction\.$"
    ):
        to_iosys(DahlFriction(1.0, 1.0), mass=1.0)
    with pytest.raises(ValueError, match="`mass` must be positive"):
        to_iosys(MODEL, mass=-1.0)
    for kwargs in ({}, {"mass": 1.0}):
        with pytest.raises(TypeError, match=r"^`name` must be a string or None; got 5\.$"):
            to_iosys(MODEL, name=5, **kwargs)
    assert to_iosys(MODEL, mass=1.0, name="plant").name == "plant"


def test_missing_control_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "control", None)
    with pytest.raises(ImportError, match=r"pip install presliding\[control\]"):
        to_iosys(MODEL)


def test_module_examples():
    import doctest

    import presliding.control

    assert doctest.testmod(presliding.control.iosys).failed == 0
