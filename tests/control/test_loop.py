"""simulate_loop and simulate_loop_batch: exact periods, the PID's difference equations,
saturation and anti-windup, batches equal to single runs, validation."""

import numpy as np
import pytest

from presliding import PIFriction, PIState
from presliding.control import (
    PID,
    DiscreteController,
    measure_limit_cycle,
    simulate_loop,
    simulate_loop_batch,
)
from presliding.motion import simulate
from tests.helpers import rounding_break_away

MODEL = PIFriction(coulomb=0.2, stiffness=[400.0, 60.0], breakaway=[0.3, 0.4])


def test_open_loop_periods_are_exact():
    """With a zero controller the loop is a held feedforward: simulate's exact motion."""
    dt = 2e-3
    t = np.arange(801) * dt
    u = 0.9 * np.sin(7 * t) + 0.3 * np.sign(np.sin(2 * t))
    zero = DiscreteController(np.zeros((0, 0)), np.zeros((0, 1)), np.zeros((1, 0)), [[0.0]], dt=dt)
    res = simulate_loop(MODEL, 1.3, zero, 0.0, feedforward=u, substeps=4, initial_velocity=0.1)
    ref = simulate(MODEL, 1.3, (t, u), initial_velocity=0.1, t_eval=res.time, method="event")
    np.testing.assert_allclose(res.position, ref.position, rtol=0, atol=1e-12)
    np.testing.assert_allclose(res.velocity, ref.velocity, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(res.control, u)
    np.testing.assert_array_equal(res.reversal_times.shape, ref.reversal_times.shape)
    assert res.energy.max_relative_residual < 1e-11
    # the instants of a run with substeps are those of a run without
    plain = simulate_loop(MODEL, 1.3, zero, 0.0, feedforward=u, initial_velocity=0.1)
    np.testing.assert_array_equal(plain.position, res.position[::4])
    np.testing.assert_array_equal(plain.time, res.time[::4])


def _pid_reference(pid, y, ref):
    """The PID's difference equations written out (no saturation)."""
    kp, ki, kd, dt, tf = pid.kp, pid.ki, pid.kd, pid.dt, pid.filter_time
    integral, d, prev, out = 0.0, 0.0, None, []
    for yk, rk in zip(y, ref, strict=True):
        e = rk - yk
        sig = -yk
        d = (tf * d + kd * (sig - (sig if prev is None else prev))) / (tf + dt)
        out.append(kp * e + integral + d)
        integral += ki * dt * e
        prev = sig
    return np.array(out)


def test_pid_follows_its_difference_equations():
    pid = PID(500.0, 3000.0, 12.0, dt=1e-3, filter_time=3e-3)
    ref = np.where(np.arange(4001) < 300, 1e-3, -2e-3)
    res = simulate_loop(MODEL, 1.0, pid, ref)
    assert res.success and res.n_reversals >= 1
    np.testing.assert_allclose(res.control, _pid_reference(pid, res.measured, ref),
                               rtol=1e-12, atol=1e-13)  # fmt: skip
    np.testing.assert_array_equal(res.measured, res.position)
    np.testing.assert_array_equal(res.error, ref - res.position)
    # integral action removes the offset against friction
    assert abs(res.error[-1]) < 1e-9


def test_saturation_and_anti_windup():
    ref = np.full(4001, 2e-2)
    kw = {"dt": 1e-3, "limit": 1.5}
    runs = {aw: simulate_loop(MODEL, 1.0, PID(200.0, 2000.0, 20.0, anti_windup=aw, **kw), ref)
            for aw in ("none", "clamping", "back-calculation")}  # fmt: skip
    for res in runs.values():
        assert np.all(np.abs(res.control) <= 1.5) and np.any(res.control == 1.5)
        assert abs(res.error[-1]) < 1e-6
    overshoot = {aw: res.position.max() - 2e-2 for aw, res in runs.items()}
    # a wound-up integral overshoots most
    assert overshoot["none"] > 1.5 * max(overshoot["clamping"], overshoot["back-calculation"])


def test_batch_equals_single_runs():
    pid = PID(300.0, 1000.0, 10.0, dt=1e-3, limit=(-0.5, 0.6))
    kp, ki = np.array([100.0, 300.0, 900.0]), np.array([500.0, 1000.0, 8000.0])
    ref = lambda t: 2e-3 * np.sin(3 * t)  # noqa: E731
    batch = simulate_loop_batch(MODEL, 1.0, pid, ref, kp=kp, ki=ki, t_end=2.0, settle_time=1.0)
    assert batch.success and batch.position.shape == (3, 2001)
    for i in range(3):
        one = simulate_loop(MODEL, 1.0, pid.with_gains(kp[i], ki[i], 10.0), ref, t_end=2.0)
        np.testing.assert_array_equal(batch.position[i], one.measured)
        np.testing.assert_array_equal(batch.control[i], one.control)
        late = one.control_time >= 1.0
        e = one.error[late]
        assert batch.error_rms[i] == pytest.approx(np.sqrt(np.mean(e**2)), rel=1e-12)
        assert batch.error_max[i] == np.max(np.abs(e))
        half = 0.5 * np.ptp(one.measured[late])
        assert batch.half_range[i] == pytest.approx(half, rel=1e-12)
        assert batch.n_reversals[i] == one.n_reversals
    summary = simulate_loop_batch(MODEL, 1.0, pid, ref, kp=kp, ki=ki, t_end=2.0,
                                  settle_time=1.0, outputs="summary")  # fmt: skip
    assert summary.position is None
    np.testing.assert_array_equal(summary.error_rms, batch.error_rms)
    assert "3 closed loops" in batch.report()


def test_pd_loop_stops_and_reports():
    res = simulate_loop(MODEL, 1.0, PID(150.0, 0.0, 1.0, dt=2e-3), 0.05, t_end=3.0)
    assert res.stop_time is not None and res.rest_position == res.position[-1]
    rest = res.time >= res.stop_time
    assert np.all(res.velocity[rest] == 0.0) and np.ptp(res.position[rest]) == 0.0
    assert abs(res.rest_position - 0.05) <= MODEL.coulomb_level / 150.0
    text = res.report()
    assert "PID(kp=150.0" in text and "error: rms" in text
    d = res.to_dict()
    assert d["control"] is res.control and d["success"]


def test_measured_limit_cycle():
    t = np.arange(20) * 0.5
    y = 1e-3 * np.where(np.arange(20) % 2 == 0, 1.0, -1.0)
    cyc = measure_limit_cycle(t, y, 0.0)
    assert cyc.amplitude == pytest.approx(1e-3) and cyc.frequency == pytest.approx(2 * np.pi)
    assert cyc.steady and cyc.cycles == 9
    assert measure_limit_cycle(t[:3], y[:3], 0.0).cycles == 0
    assert measure_limit_cycle(t, y, 8.0).status == "none"  # 3 turning points: too few
    with pytest.raises(ValueError, match=r"^`after` must not lie after the last turning point"):
        measure_limit_cycle(t, y, 9.6)
    res = simulate_loop(MODEL, 1.0, PID(150.0, 0.0, 1.0, dt=2e-3), 0.05, t_end=0.2)
    assert res.limit_cycle(0.2).status == "none"  # a window at the very end: no cycles
    with pytest.raises(ValueError, match=r"^`after` must not lie after the end of the run"):
        res.limit_cycle(0.3)


def test_errors():
    pid = PID(1.0, dt=1e-3)
    with pytest.raises(ValueError, match=r"^`t_end` − `t_start` must be a positive whole number"):
        simulate_loop(MODEL, 1.0, pid, 0.0, t_end=0.0105)
    with pytest.raises(ValueError, match=r"^`feedforward` must hold one sample per instant"):
        simulate_loop(MODEL, 1.0, pid, np.zeros(11), feedforward=np.zeros(12))
    with pytest.raises(TypeError, match=r"^`t_end` must be given unless `reference`"):
        simulate_loop(MODEL, 1.0, pid, 0.0)
    with pytest.raises(TypeError, match=r"^`t_end` must be given unless `reference`"):
        simulate_loop(MODEL, 1.0, pid, np.sin)
    with pytest.raises(TypeError, match=r"^`controller` must be a PID, a DiscreteController"):
        simulate_loop(MODEL, 1.0, "pid", 0.0, t_end=1.0)
    with pytest.raises(ValueError, match=r"^`kp`, `ki` and `kd` must not all be zero"):
        PID(0.0)
    with pytest.raises(ValueError, match=r"^`limit` \(low, high\) must have low < high"):
        PID(1.0, limit=(1.0, -1.0))
    with pytest.raises(ValueError, match=r"^`anti_windup` must be one of"):
        PID(1.0, anti_windup="yes")
    with pytest.raises(ValueError, match=r"^`D` must have 1 column"):
        DiscreteController([[1.0]], [[1.0, 1.0, 1.0]], [[1.0]], [[1.0, 1.0, 1.0]])
    with pytest.raises(ValueError, match=r"^`kp`, `ki` and `kd` must have length 1"):
        simulate_loop_batch(MODEL, 1.0, pid, 0.0, kp=[1.0, 2.0], ki=[1.0, 2.0, 3.0], t_end=1.0)
    with pytest.raises(ValueError, match=r"^`outputs` 'full' would keep"):
        simulate_loop_batch(MODEL, 1.0, pid, 0.0, kp=np.ones(200_000), t_end=1.0)
    with pytest.raises(ValueError, match=r"^`kp` must be nonnegative; got -1\.0 at index 1"):
        simulate_loop_batch(MODEL, 1.0, pid, 0.0, kp=[1.0, -1.0], t_end=1.0)
    with pytest.raises(TypeError, match=r"^`reference` must be a real number or array"):
        simulate_loop(MODEL, 1.0, pid, lambda t: "step", t_end=0.01)
    with pytest.raises(ValueError, match=r"^`settle_time` must lie within the run \[0\.0, 1\.0\]"):
        simulate_loop_batch(MODEL, 1.0, pid, 0.0, kp=[1.0, 2.0], t_end=1.0, settle_time=-0.5)
    with pytest.raises(ValueError, match=r"^`model` and `mass` must give a finite frequency"):
        simulate_loop_batch(MODEL, 1e-320, pid, 0.0, kp=[1.0, 2.0], t_end=1.0)
    with pytest.raises(ValueError, match=r"^`mass` and `initial_velocity` must give a finite"):
        simulate_loop(MODEL, 1.0, pid, 0.0, t_end=0.01, initial_velocity=1e200)
    # a sampled loop far beyond its stable gains diverges: an error at the time it overflows,
    # not inf and NaN in the result
    with pytest.raises(
        ValueError,
        match=r"^`mass` and `controller` must keep the loop in the "
        r"floating-point range; got mass = 1\.0: the motion overflows at t = ",
    ):
        simulate_loop(MODEL, 1.0, PID(1e12, dt=1e-3), 1e-3, t_end=1.0)
    from presliding import Uniform

    with pytest.raises(TypeError, match="continuous density"):
        simulate_loop(PIFriction(0.1, density=Uniform(1e6, 1e-3)), 1.0, pid, 0.0, t_end=1.0)


def test_viscous_term_in_the_loop():
    """σ·ẏ enters the exact periods: a zero controller gives simulate's damped motion."""
    model = PIFriction(0.2, [400.0, 60.0], [0.3, 0.4], viscous=3.0)
    dt = 2e-3
    t = np.arange(501) * dt
    u = 0.9 * np.sin(7 * t)
    zero = DiscreteController(np.zeros((0, 0)), np.zeros((0, 1)), np.zeros((1, 0)), [[0.0]], dt=dt)
    res = simulate_loop(model, 1.3, zero, 0.0, feedforward=u, initial_velocity=0.1)
    ref = simulate(model, 1.3, (t, u), initial_velocity=0.1, t_eval=t, method="event")
    np.testing.assert_allclose(res.position, ref.position, rtol=0, atol=1e-12)
    np.testing.assert_allclose(res.velocity, ref.velocity, rtol=0, atol=1e-12)
    assert res.energy.viscous[-1] > 0 and res.energy.max_relative_residual < 1e-9
    # the friction force carries σ·ẏ while the mass slides
    moving = res.velocity != 0
    assert np.any(np.abs(res.friction_force[moving] - res.elastic_force[moving]) > 0.2 + 1e-9)


def test_loop_at_the_edge_of_the_stick_band_does_not_stall():
    """A PI loop (c1 = 0.005, kp, ki = 400, 4e4) at rest with its preload and the
    feedforward one rounding step outside the stick band: the net force u − c1·s − F_el
    rounds to zero in the order of operations of the piece, although the stick test
    says the mass breaks away. The kernel used to repeat zero-length pieces until
    `max_events` (here after 0 periods); it must move off and finish every period."""
    c1 = 0.005
    u, fel = rounding_break_away(c1)
    model = PIFriction(c1, stiffness=[1.0], threshold=[10.0])
    pid = PID(400.0, 4e4, 0.0, dt=1e-3)
    res = simulate_loop(model, 1.0, pid, 0.0, feedforward=np.full(11, u),
                        initial_state=PIState(0.0, np.array([-fel])), max_events=1000)  # fmt: skip
    assert res.success, res.message
    assert res.n_events <= 20
    np.testing.assert_array_equal(res.control[0], u)
    # it breaks away in the direction of u − F_el, by the rounding unit of F_el at first
    s = np.sign(u - fel)
    assert s * res.position[1] > 0.0 and abs(res.position[1]) < 1e-15


def test_a_batch_member_whose_loop_diverges_is_an_overflow_not_an_event_limit():
    # kp = 1e7 on 1 kg sampled at 1 ms is unstable: the loop leaves the floating-point range
    model = PIFriction(0.0, [1e4, 3e3], breakaway=[0.1, 0.1])
    pid = PID(kp=400.0, ki=4e4, dt=1e-3)
    res = simulate_loop_batch(model, 1.0, pid, 0.0, kp=[400.0, 1e7], ki=[4e4, 4e4],
                                 t_end=2.0, initial_velocity=1e-3)  # fmt: skip
    assert list(res.member_status) == ["success", "overflow"]
    assert res.status == "overflow" and not res.success
    assert "1 of 2 loops left the floating-point range" in res.message
    assert "event limit" not in res.message
    assert np.isfinite(res.error_rms[0]) and np.isnan(res.error_rms[1])


@pytest.mark.parametrize("signal", ["reference", "feedforward"])
@pytest.mark.parametrize("extra", [5, -3, "2d"])
def test_a_function_of_the_wrong_length_is_refused_before_the_kernel(signal, extra):
    """More samples than instants once crashed the interpreter, fewer gave an overflow."""
    model = PIFriction(0.1, [2e4, 5e3], [0.2, 0.2])
    pid = PID(400.0, 4e4, 0.0, dt=1e-3, limit=5.0)

    def bad(t):
        return np.zeros((t.size, 2)) if extra == "2d" else np.zeros(t.size + extra)

    for run in (simulate_loop, simulate_loop_batch):
        with pytest.raises(ValueError, match=rf"^`{signal}` must return one value per instant"):
            run(model, 1.0, pid, t_end=0.1, **{signal: bad})
    # the right length and a scalar are taken
    assert simulate_loop(model, 1.0, pid, t_end=0.1, **{signal: lambda t: 0 * t}).success
    assert simulate_loop(model, 1.0, pid, t_end=0.1, **{signal: lambda t: 0.0}).success


def test_a_short_sampled_reference_and_a_huge_run_are_refused():
    model = PIFriction(0.1, [2e4, 5e3], [0.2, 0.2])
    pid = PID(400.0, 4e4, 0.0, dt=1e-4)
    with pytest.raises(ValueError, match=r"one sample per instant t_k \(K \+ 1 = 1001\); got 50"):
        simulate_loop_batch(model, 1.0, pid, np.zeros(50), kp=[1.0, 2.0], t_end=0.1)
    with pytest.raises(ValueError, match=r"^`t_end` must ask for at most"):
        simulate_loop(model, 1.0, pid, t_end=1e6)  # 1e10 periods


def test_every_number_in_the_reports_has_its_unit():
    """Loop, batch, motion and turning-point reports: energies in J, errors in m, gains."""
    import re

    from presliding import turning_points

    model = PIFriction(0.0, [2e4, 5e3, 1.5e3, 500.0], [0.2] * 4)
    pid = PID(400.0, 4e4, 0.0, dt=1e-4, limit=5.0)
    text = simulate_loop(model, 1.0, pid, 0.0, t_end=0.3, initial_velocity=1e-3).report()
    assert re.search(r"energy: initial \S+ J, dissipated \S+ J, work of u \S+ J", text)
    assert re.search(r"\|u\| max \S+ N", text) and re.search(r"error: rms \S+ m, max", text)
    assert re.search(r"amplitude \S+ m, frequency \S+ rad/s", text)
    batch = simulate_loop_batch(model, 1.0, pid, kp=[300.0, 400.0], t_end=0.1).report()
    assert re.search(r"rms error \S+ \.\. \S+ m, half range of y \S+ \.\. \S+ m", batch)
    assert re.search(r"kp = \S+ N/m, ki = \S+ N/\(m s\), kd = \S+ N s/m", batch)
    tp = turning_points(MODEL, 1.0, 0.8, "saturated").report()
    assert "m with v0 = 0.8 m/s (mass 1 kg)" in tp and "rest position: " in tp
    assert re.search(r"turning point 1: y = \S+ m, F_el = \S+ N", tp)
    assert re.search(r"\|F_el\| = \S+ N <= c1 = 0.2 N", tp)
