"""python-control interface: names that connect by themselves, exact blocks, params, dt=True."""

import sys
import warnings

import numpy as np
import pytest

control = pytest.importorskip("control")

from presliding import PIFriction  # noqa: E402
from presliding.control import (  # noqa: E402
    PID,
    DiscreteController,
    iosys_state,
    simulate_loop,
    to_iosys,
)
from presliding.friction.baselines import CoulombFriction, DahlFriction, LuGreFriction  # noqa: E402
from presliding.motion import simulate  # noqa: E402
from presliding.signals import piecewise_linear  # noqa: E402

MODEL = PIFriction(coulomb=0.2, stiffness=[400.0, 60.0], breakaway=[0.3, 0.4])


@pytest.mark.parametrize(
    "model",
    [MODEL, CoulombFriction(0.7), DahlFriction(1.0, 80.0, 1.5)],
    ids=["pi", "coulomb", "dahl"],
)
@pytest.mark.parametrize("dt", [1e-3, True])
def test_friction_system_is_the_exact_operator(model, dt):
    y = piecewise_linear([0.0, 0.01, -0.004, 0.006, -0.01], 5e-4)
    t = np.arange(y.size) * (1e-3 if dt is not True else 1.0)
    sys_ = to_iosys(model, dt=dt)
    assert sys_.input_labels == ["position"] and sys_.output_labels == ["friction"]
    resp = control.input_output_response(sys_, t, y, iosys_state(model), return_x=True)
    force, _ = model.force(y)
    np.testing.assert_array_equal(resp.outputs, force)
    _, before_last = model.force(y[:-1])
    np.testing.assert_array_equal(resp.states[:, -1], iosys_state(model, before_last))


def test_open_loop_plant_equals_simulate():
    dt = 2e-3
    t = np.arange(400) * dt
    u = np.where(t < 0.3, 0.9, -0.1)
    plant = to_iosys(MODEL, mass=2.0, dt=dt)
    assert plant.input_labels == ["u"] and plant.output_labels == ["position", "velocity"]
    x0 = iosys_state(MODEL, mass=2.0, velocity=0.4)
    resp = control.input_output_response(plant, t, u, x0)
    sim = simulate(MODEL, 2.0, (t, u), initial_velocity=0.4, t_eval=t, method="event")
    np.testing.assert_allclose(resp.outputs[0], sim.position, rtol=0, atol=1e-12)
    np.testing.assert_allclose(resp.outputs[1], sim.velocity, rtol=0, atol=1e-12)


def _pid_loop(ctrl, model, mass):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an unconnected signal would warn
        return control.interconnect(
            [to_iosys(ctrl), to_iosys(model, mass=mass, dt=ctrl.dt)],
            inputs="reference", outputs=["position", "velocity", "u"],
        )  # fmt: skip


@pytest.mark.parametrize(
    "pid",
    [
        PID(400.0, 2000.0, 20.0, dt=1e-3),
        PID(900.0, 9000.0, 5.0, dt=5e-4, limit=0.45, filter_time=2e-3),
        PID(900.0, 9000.0, 5.0, dt=5e-4, limit=(-0.2, 0.5), anti_windup="back-calculation"),
        PID(300.0, 3000.0, 0.0, dt=1e-3, limit=0.3, anti_windup="none", derivative_on="error"),
    ],
    ids=["plain", "clamping", "back-calculation", "none"],
)
def test_interconnected_pid_loop_equals_simulate_loop(pid):
    """A PID and the mass connect by their names alone, and give simulate_loop's samples."""
    loop = _pid_loop(pid, MODEL, 1.5)
    n = 600
    t = np.arange(n) * pid.dt
    ref = np.where(t < 0.1, 2e-3, -1e-3)
    x0 = np.concatenate([iosys_state(pid), iosys_state(MODEL, mass=1.5)])
    resp = control.input_output_response(loop, t, ref, x0)
    res = simulate_loop(MODEL, 1.5, pid, ref)
    y, v, u = resp.outputs
    np.testing.assert_allclose(y, res.measured, rtol=0, atol=1e-12)
    np.testing.assert_allclose(v, res.velocity, rtol=0, atol=1e-12)
    np.testing.assert_allclose(u, res.control, rtol=0, atol=1e-12)
    assert res.n_reversals >= 1  # the loop does reverse: memory matters
    if pid.limit is not None:
        low, high = pid.limits
        assert np.any((u == low) | (u == high)) and np.all((u >= low) & (u <= high))


def test_interconnected_state_space_controller_equals_simulate_loop():
    dt = 1e-3
    # a discrete PI on the error, from python-control's own objects
    ctrl = control.ss([[1.0]], [[dt]], [[1500.0]], [[300.0]], dt=dt)
    sim_ctrl = DiscreteController.from_lti(ctrl)
    loop = _pid_loop(sim_ctrl, MODEL, 1.0)
    t = np.arange(500) * dt
    x0 = np.concatenate([iosys_state(sim_ctrl), iosys_state(MODEL, mass=1.0)])
    resp = control.input_output_response(loop, t, np.full(t.size, 1e-3), x0)
    res = simulate_loop(MODEL, 1.0, ctrl, 1e-3, t_end=t[-1])
    np.testing.assert_allclose(resp.outputs[0], res.measured, rtol=0, atol=1e-12)
    np.testing.assert_allclose(resp.outputs[2], res.control, rtol=0, atol=1e-12)


def test_pid_mass_and_friction_blocks_connect_by_name():
    """Three blocks (PID, a linear mass with inputs u and friction, the friction law) close
    the loop by their signal names: no unused signal, every input driven."""
    m, dt = 1.0, 1e-3
    pid = PID(200.0, 0.0, 30.0, dt=dt)
    mass = control.ss([[1.0, dt], [0.0, 1.0]], [[0.0, 0.0], [dt / m, -dt / m]], np.eye(2),
                      np.zeros((2, 2)), dt=dt, inputs=["u", "friction"],
                      outputs=["position", "velocity"], name="mass")  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        loop = control.interconnect(
            [to_iosys(pid), mass, to_iosys(MODEL, dt=dt)], inputs="reference",
            outputs=["position", "velocity", "u", "friction"],
        )  # fmt: skip
    t = np.arange(400) * dt
    resp = control.input_output_response(loop, t, np.full(t.size, 5e-3))
    y, _, u, fr = resp.outputs
    # the friction block saw the mass's position, the mass saw both forces
    np.testing.assert_array_equal(fr, MODEL.force(y, MODEL.relaxed_state(0.0))[0])
    assert fr[0] == 0.0 and y[2] == pytest.approx(dt * dt / m * u[0], rel=1e-12)
    assert 0.0 < y[-1] < 1e-2


def test_params_are_honoured():
    pid = PID(400.0, 2000.0, 20.0, dt=1e-3)
    loop = _pid_loop(pid, MODEL, 1.0)
    t = np.arange(300) * pid.dt
    x0 = np.concatenate([iosys_state(pid), iosys_state(MODEL, mass=1.0)])
    params = {"mass": 2.5, "coulomb": 0.05, "stiffness": [500.0, 90.0], "kp": 600.0}
    resp = control.input_output_response(loop, t, np.full(t.size, 1e-3), x0, params=params)
    model = PIFriction(0.05, [500.0, 90.0], MODEL.breakaway)  # break-away forces kept
    res = simulate_loop(model, 2.5, pid.with_gains(600.0, 2000.0, 20.0), 1e-3, t_end=t[-1])
    np.testing.assert_allclose(resp.outputs[0], res.measured, rtol=0, atol=1e-12)
    # thresholds instead of break-away forces
    resp = control.input_output_response(loop, t, np.full(t.size, 1e-3), x0,
                                         params={"threshold": [1e-3, 2e-3]})  # fmt: skip
    res = simulate_loop(PIFriction(0.2, MODEL.stiffness, threshold=[1e-3, 2e-3]), 1.0, pid,
                        1e-3, t_end=t[-1])  # fmt: skip
    np.testing.assert_allclose(resp.outputs[0], res.measured, rtol=0, atol=1e-12)
    # the friction law alone reads the model keys
    fr = to_iosys(MODEL, dt=1e-3)
    y = piecewise_linear([0.0, 0.01, -0.01], 1e-3)
    resp = control.input_output_response(fr, np.arange(y.size) * 1e-3, y, params={"coulomb": 1.0})
    other = PIFriction(1.0, MODEL.stiffness, MODEL.breakaway)
    np.testing.assert_array_equal(resp.outputs, other.force(y)[0])


@pytest.mark.parametrize(
    ("params", "match"),
    [
        ({"mass": -1.0}, r"^`mass` must be positive; got -1\.0\.$"),
        ({"coulomb": -0.1}, r"^`coulomb` must be nonnegative; got -0\.1\.$"),
        ({"stiffness": [1.0, 2.0, 3.0]}, r"`breakaway` must have the same length"),
        ({"breakaway": 1.0, "threshold": 1.0}, r"not both"),
        ({"kp": -1.0}, r"^`kp` must be nonnegative; got -1\.0\.$"),
        ({"stiffness": "stiff"}, r"must be a number or array; got 'stiff'"),
    ],
)
def test_bad_params_are_rejected_clearly(params, match):
    pid = PID(400.0, 2000.0, 20.0, dt=1e-3)
    loop = _pid_loop(pid, MODEL, 1.0)
    t = np.arange(5) * pid.dt
    with pytest.raises((ValueError, TypeError), match=match):
        control.input_output_response(loop, t, np.zeros(t.size), params=params)


def test_dahl_system_refuses_friction_params():
    fr = to_iosys(DahlFriction(1.0, 80.0, 1.5), dt=1e-3)
    with pytest.raises(ValueError, match="`params` key `coulomb` does not apply to a Dahl"):
        control.input_output_response(fr, [0.0, 1e-3], [0.0, 1e-3], params={"coulomb": 1.0})


def test_default_names_are_readable_and_unique():
    a, b = to_iosys(MODEL), to_iosys(MODEL, mass=1.0)
    c = to_iosys(PID(1.0, dt=1e-3))
    assert a.name.startswith("friction[") and b.name.startswith("mass[")
    assert c.name.startswith("pid[") and len({a.name, b.name, c.name}) == 3
    assert to_iosys(MODEL, mass=1.0, name="plant").name == "plant"
    assert to_iosys(MODEL, mass=1.0, inputs="force").input_labels == ["force"]


def test_pd_position_loop_stops_like_simulate():
    """A discrete PD loop around the exact plant: its stop and reversals equal `simulate`."""
    m, dt, kp, kd, ref = 1.0, 2e-3, 150.0, 1.0, 0.05
    plant = to_iosys(MODEL, mass=m, dt=dt, name="plant")
    pd = control.ss(
        [], [], [], [[kp, -kp, -kd]], dt=dt,
        inputs=["r", "position", "velocity"], outputs=["u"], name="pd",
    )  # fmt: skip
    loop = control.interconnect(
        [plant, pd], inplist=["r"], inputs=["r"],
        outlist=["position", "velocity", "u"], outputs=["position", "velocity", "u"],
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
    assert np.any(np.abs(sim.final_state.deformation) < MODEL.threshold * (1 - 1e-9))
    assert abs(sim.rest_position - ref) <= (MODEL.coulomb_level + 1e-12) / kp


def test_mass_state_keeps_deformations():
    state = MODEL.saturated_state(0.3, -1.0)
    x0 = iosys_state(MODEL, state, mass=1.0, velocity=0.2)
    np.testing.assert_allclose(x0, [0.3, 0.2, *(-MODEL.threshold), 1.0], rtol=0, atol=1e-15)
    np.testing.assert_array_equal(iosys_state(MODEL, mass=1.0), np.zeros(5))


def test_errors():
    with pytest.raises(TypeError, match="`model` must be a PIFriction, CoulombFriction"):
        to_iosys(LuGreFriction(1.0, 1.0, 1.0, 0.0, 0.0, 1.0))
    with pytest.raises(ValueError, match="`dt` must be positive"):
        to_iosys(MODEL, dt=0.0)
    with pytest.raises(ValueError, match=r"^`dt` must be the sample period in seconds"):
        to_iosys(MODEL, mass=1.0, dt=True)
    with pytest.raises(
        TypeError, match=r"^`model` must be .* when a `mass` is given; got DahlFriction\.$"
    ):
        to_iosys(DahlFriction(1.0, 1.0), mass=1.0)
    with pytest.raises(ValueError, match="`mass` must be positive"):
        to_iosys(MODEL, mass=-1.0)
    for kwargs in ({}, {"mass": 1.0}):
        with pytest.raises(TypeError, match=r"^`name` must be a string or None; got 5\.$"):
            to_iosys(MODEL, name=5, **kwargs)
    with pytest.raises(ValueError, match=r"^`dt` must be None or the controller's dt"):
        to_iosys(PID(1.0, dt=1e-3), dt=2e-3)
    with pytest.raises(ValueError, match=r"^`inputs` must be 1 signal name"):
        to_iosys(MODEL, mass=1.0, inputs=["a", "b"])


def test_missing_control_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "control", None)
    with pytest.raises(ImportError, match=r'pip install "presliding\[control\]"'):
        to_iosys(MODEL)


def test_module_examples():
    import doctest

    import presliding.control

    assert doctest.testmod(presliding.control.iosys).failed == 0


def test_viscous_model_in_python_control():
    model = PIFriction(0.2, [400.0, 60.0], [0.3, 0.4], viscous=2.0)
    pid = PID(400.0, 2000.0, 20.0, dt=1e-3)
    loop = _pid_loop(pid, model, 1.0)
    t = np.arange(400) * pid.dt
    x0 = np.concatenate([iosys_state(pid), iosys_state(model, mass=1.0)])
    resp = control.input_output_response(loop, t, np.full(t.size, 2e-3), x0)
    res = simulate_loop(model, 1.0, pid, 2e-3, t_end=t[-1])
    np.testing.assert_allclose(resp.outputs[0], res.measured, rtol=0, atol=1e-12)
    # σ as a parameter of a model without it
    resp = control.input_output_response(_pid_loop(pid, MODEL, 1.0), t, np.full(t.size, 2e-3),
                                         x0, params={"viscous": 2.0})  # fmt: skip
    res = simulate_loop(PIFriction(0.2, MODEL.stiffness, MODEL.breakaway, viscous=2.0), 1.0,
                        pid, 2e-3, t_end=t[-1])  # fmt: skip
    np.testing.assert_allclose(resp.outputs[0], res.measured, rtol=0, atol=1e-12)
    # the friction law alone reads the velocity too
    fr = to_iosys(model, dt=1e-3)
    assert fr.input_labels == ["position", "velocity"]
    y = np.array([0.0, 1e-3, 2e-3])
    v = np.array([0.0, 0.5, 0.5])
    out = control.input_output_response(fr, np.array([0.0, 1e-3, 2e-3]), np.vstack([y, v])).outputs
    np.testing.assert_allclose(np.ravel(out), model.force(y)[0] + 2.0 * v, rtol=1e-15)
