"""Motion of a mass with PI friction and exact stiction (eqs. 8, 12, 17)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import presliding as ps
from presliding.motion import free_response, simulate, simulate_batch


def one_element_stop(m, c1, k, c, v0):
    """Closed form of a free stop from steady sliding with one element (eq. 17).

    Phase 1 slides (element saturated) at deceleration F_c/m until t1 = m·v0/F_c.
    Then the element sticks: half-periods π·sqrt(m/k) of a harmonic motion about
    f* = ±c1/k, each lowering the elastic force at the turning point by 2·c1,
    F_n = (−1)^n (c − 2·n·c1), until |F_n| <= c1: n = ceil((c − c1)/(2·c1)), n >= 0.
    """
    fc = c1 + c
    t1 = m * v0 / fc
    y1 = m * v0 * v0 / (2 * fc)
    n = max(0, math.ceil((c - c1) / (2 * c1)))
    r = c / k
    f_n = (-1) ** n * (r - 2 * n * c1 / k)
    return t1 + n * math.pi * math.sqrt(m / k), n, y1 - r + f_n


# ----------------------------------------------------------------------- closed forms
def test_pure_coulomb_constant_deceleration_and_stop_time():
    m, fc, v0 = 2.5, 0.7, 1.3
    res = simulate(ps.PIFriction(coulomb=fc), m, initial_velocity=v0, t_end=10.0)
    t_stop = m * v0 / fc
    assert res.stop_time == pytest.approx(t_stop, rel=4e-16)
    moving = res.time < t_stop
    np.testing.assert_allclose(res.acceleration[moving], -fc / m, rtol=1e-15)
    t = res.time[moving]
    np.testing.assert_allclose(res.velocity[moving], v0 - fc / m * t, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(res.position[moving], v0 * t - fc / (2 * m) * t**2, rtol=1e-13)
    assert res.rest_position == pytest.approx(m * v0**2 / (2 * fc), rel=1e-15)
    assert res.n_reversals == 0
    # at rest forever after, bit for bit
    assert np.all(res.position[~moving] == res.rest_position)
    assert np.all(res.velocity[~moving] == 0.0)


def test_stiff_elements_approach_coulomb_stop_time():
    m, v0 = 1.0, 2.0
    model = ps.PIFriction(coulomb=0.5, stiffness=[1e12, 1e12], breakaway=[0.25, 0.75])
    res = simulate(model, m, initial_velocity=v0, initial_state="relaxed", t_end=5.0)
    t_stop = m * v0 / model.coulomb_level
    assert res.stop_time == pytest.approx(t_stop, rel=1e-5)
    # saturated start: the sliding phase is exactly the Coulomb parabola
    sat = simulate(model, m, initial_velocity=v0, initial_state="saturated", t_end=5.0)
    assert sat.reversal_times[0] == pytest.approx(t_stop, rel=4e-16)


@settings(max_examples=60, deadline=None)
@given(
    m=st.floats(0.1, 10.0),
    c1=st.floats(0.05, 1.0),
    ratio=st.floats(0.2, 12.0),
    k=st.floats(1.0, 1e4),
    v0=st.floats(0.01, 5.0),
)
def test_one_element_stop_time_closed_form(m, c1, ratio, k, v0):
    c = ratio * c1
    t_stop, n, y_rest = one_element_stop(m, c1, k, c, v0)
    # skip the knife edge where (c − c1)/(2·c1) is an integer up to rounding
    edge = (c - c1) / (2 * c1)
    if abs(edge - round(edge)) < 1e-9:
        return
    model = ps.PIFriction(coulomb=c1, stiffness=[k], breakaway=[c])
    res = simulate(model, m, initial_velocity=v0, initial_state="saturated", t_end=2 * t_stop)
    assert res.n_reversals == n
    assert res.stop_time == pytest.approx(t_stop, rel=1e-12)
    assert res.rest_position == pytest.approx(y_rest, rel=1e-12, abs=1e-12 * abs(c / k))


def test_equality_sticks():
    # c1 = 1, c = 5, k = m = 1: |F_2| = c − 4·c1 = 1 = c1 exactly, so it sticks after 2.
    model = ps.PIFriction(coulomb=1.0, stiffness=[1.0], breakaway=[5.0])
    res = simulate(model, 1.0, initial_velocity=3.0, initial_state="saturated", t_end=20.0)
    t_stop, n, y_rest = one_element_stop(1.0, 1.0, 1.0, 5.0, 3.0)
    assert (res.n_reversals, n) == (2, 2)
    assert res.stop_time == pytest.approx(t_stop, rel=1e-14)
    assert res.rest_position == pytest.approx(y_rest, rel=1e-14)
    assert abs(res.elastic_force[-1]) == 1.0


def test_forced_start_from_rest_is_harmonic_then_slides():
    # one element, relaxed, u = 3 > c1 = 1: m·ÿ + k·y = u − c1 until k·y = c.
    m, k, c, c1, u = 2.0, 50.0, 1.5, 1.0, 3.0
    model = ps.PIFriction(coulomb=c1, stiffness=[k], breakaway=[c])
    w = math.sqrt(k / m)
    t_slide = math.acos(1 - c / (u - c1)) / w
    t = np.linspace(0, 2 * t_slide, 401)
    res = simulate(model, m, applied_force=u, t_eval=t)
    pre = t < t_slide
    np.testing.assert_allclose(
        res.position[pre], (u - c1) / k * (1 - np.cos(w * t[pre])), rtol=1e-12, atol=1e-15
    )
    post = t > t_slide
    np.testing.assert_allclose(res.acceleration[post], (u - c1 - c) / m, rtol=1e-12)


def test_stuck_below_coulomb_level_stays_put():
    model = ps.PIFriction(coulomb=1.0, stiffness=[10.0, 3.0], breakaway=[0.5, 0.5])
    res = simulate(model, 1.0, applied_force=0.999, initial_position=0.3, t_end=5.0)
    assert res.stop_time == 0.0 and res.n_events == 0
    assert np.all(res.position == 0.3) and np.all(res.velocity == 0.0)
    np.testing.assert_array_equal(res.friction_force, 0.999)


def test_no_creep_over_a_million_implicit_steps():
    model = ps.PIFriction(coulomb=0.4, stiffness=[200.0, 50.0, 5.0], breakaway=[0.2, 0.3, 0.1])
    state = ps.PIState(0.123, np.array([0.123 - 0.001, 0.123 + 0.002, 0.123]), 1.0)
    f_el = float(np.dot(model.stiffness, state.deformation))
    u = f_el + 0.39  # |u − F_el| < c1
    res = simulate(model, 3.0, applied_force=lambda t: u + 0 * t, initial_position=0.123,
                   initial_state=state, t_end=1.0, step=1e-6, method="implicit")  # fmt: skip
    assert res.n_events == 1_000_000
    assert np.all(res.position == 0.123) and np.all(res.velocity == 0.0)
    np.testing.assert_array_equal(res.final_state.play, state.play)
    assert res.stop_time == 0.0


# ----------------------------------------------------------------------- energy, convergence
def random_model(seed, n):
    rng = np.random.default_rng(seed)
    k = rng.uniform(10, 1000, n)
    c = rng.uniform(0.1, 1.0, n)
    return ps.PIFriction(coulomb=rng.uniform(0.05, 1.0), stiffness=k, breakaway=c), rng


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 10_000), n=st.integers(0, 6), sat=st.booleans())
def test_event_energy_balance_is_exact(seed, n, sat):
    model, rng = random_model(seed, n)
    v0 = rng.uniform(0.2, 3.0) * rng.choice([-1, 1])
    res = simulate(model, rng.uniform(0.5, 2), initial_velocity=v0,
                   initial_state="saturated" if sat else "relaxed", t_end=1e4)  # fmt: skip
    e = res.energy
    assert np.max(np.abs(e.residual)) <= 1e-12 * e.initial
    assert res.stop_time is not None  # c1 > 0: free motion stops
    assert e.dissipated[-1] == pytest.approx(e.initial - e.elastic[-1], rel=1e-12)


def test_forced_energy_balance_with_work_of_u():
    model, _ = random_model(3, 4)
    u = (np.linspace(0, 2, 9), np.array([2.0, -1.5, 0.3, 3.0, -3.0, 0.0, 1.0, -0.5, 0.2]))
    res = simulate(model, 1.0, applied_force=u, initial_velocity=0.4, t_end=3.0)
    assert res.energy.max_relative_residual < 1e-13
    assert res.n_reversals >= 3


def test_implicit_converges_to_event_at_first_order():
    model, _ = random_model(11, 4)
    u = (np.array([0.0, 0.4, 0.9]), np.array([2.5, -0.2, 0.0]))
    kw = dict(applied_force=u, initial_velocity=0.3, t_end=2.0, t_eval=np.linspace(0, 2.0, 201))
    exact = simulate(model, 1.0, **kw)
    steps = [4e-4, 2e-4, 1e-4, 5e-5]
    errs = [np.max(np.abs(simulate(model, 1.0, method="implicit", step=h, **kw).position
                          - exact.position)) for h in steps]  # fmt: skip
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all((orders > 0.8) & (orders < 1.25)), orders
    assert errs[-1] < 1e-4


def test_implicit_and_event_agree_on_reversals_and_stop():
    for seed in range(5):
        model, rng = random_model(seed, 3)
        kw = dict(initial_velocity=rng.uniform(0.5, 2.0), initial_state="saturated", t_end=6.0)
        a = simulate(model, 1.0, **kw)
        b = simulate(model, 1.0, method="implicit", step=1e-5, **kw)
        assert a.n_reversals == b.n_reversals
        assert b.stop_time == pytest.approx(a.stop_time, abs=1e-3)
        np.testing.assert_allclose(b.reversal_positions, a.reversal_positions, atol=1e-4)


# ----------------------------------------------------------------------- the paper's experiments
def test_experiment_one_switching_off_the_force():
    # steady sliding at v0 under u = F_c, u switched off at t = 0.05 (Figure 4)
    m, v0 = 1.0, 0.05
    fc, c1 = 1.0, 0.3
    c = (fc - c1) / 4
    model = ps.PIFriction(coulomb=c1, stiffness=[2e4, 5e3, 1.5e3, 500.0], breakaway=[c] * 4)
    u = (np.array([0.0, 0.05]), np.array([fc, 0.0]))
    t = np.linspace(0.0, 0.25, 2501)
    res = simulate(model, m, applied_force=u, initial_velocity=v0, initial_state="saturated",
                   t_eval=t)  # fmt: skip
    before = t < 0.05
    assert np.all(res.velocity[before] == v0)
    t_zero = 0.05 + m * v0 / fc
    sliding = (t > 0.05) & (t < t_zero)
    np.testing.assert_allclose(res.velocity[sliding], v0 - fc / m * (t[sliding] - 0.05),
                               rtol=1e-12, atol=1e-15)  # fmt: skip
    assert res.n_reversals == 1
    assert res.reversal_times[0] == pytest.approx(t_zero, rel=1e-12)
    v_min = res.velocity.min()
    assert -0.1 * v0 < v_min < 0  # one small negative overshoot
    assert res.stop_time is not None and res.stop_time > t_zero
    assert np.all(res.velocity[t > res.stop_time] == 0.0)


def test_experiment_two_free_response_and_phase_portrait():
    fc, c1 = 2.0, 0.5
    c = (fc - c1) / 4
    model = ps.PIFriction(coulomb=c1, stiffness=[4e4, 1e4, 3e3, 1e3], breakaway=[c] * 4)
    res = simulate(model, 1.0, initial_velocity=0.08, initial_state="saturated", t_end=0.2)
    assert res.n_reversals >= 1 and res.stop_time is not None
    # the phase portrait ends at rest, with the reversal a small step back
    back = res.reversal_positions[0] - res.rest_position
    assert 0 < back < 0.05 * res.reversal_positions[0]


# ----------------------------------------------------------------------- batches, forcing, state
def test_batch_and_free_response_equal_simulate():
    model, _ = random_model(5, 4)
    v0 = np.array([0.5, -1.0, 2.0])
    t = np.arange(2000) * 1e-3
    batch = simulate_batch(model, 1.5, v0, initial_state="saturated", t_eval=t)
    for i, v in enumerate(v0):
        one = simulate(model, 1.5, initial_velocity=v, initial_state="saturated", t_eval=t)
        np.testing.assert_array_equal(batch.position[i], one.position)
        assert batch.n_reversals[i] == one.n_reversals
        assert batch.stop_time[i] == (np.inf if one.stop_time is None else one.stop_time)
        free = free_response(1.5, model.coulomb, model.stiffness, model.threshold, v, 1e-3, 2000)
        assert free.success and free.status == "success"
        np.testing.assert_array_equal(free.time, t)
        np.testing.assert_array_equal(free.position, one.position)
        np.testing.assert_array_equal(free.velocity, one.velocity)
        assert free.n_reversals == one.n_reversals and free.stop_time == one.stop_time
    params = simulate_batch(coulomb=[model.coulomb] * 2, stiffness=[model.stiffness] * 2,
                            breakaway=[model.breakaway] * 2, mass=1.5, initial_velocity=v0[:1],
                            initial_state="saturated", t_eval=t)  # fmt: skip
    np.testing.assert_array_equal(params.position[1], batch.position[0])
    mixed = simulate_batch([model, ps.PIFriction(coulomb=0.5)], 1.0, 1.0, t_end=3.0)
    assert mixed.stop_time[1] == pytest.approx(2.0, rel=1e-15)
    assert mixed.success


def test_continuation_from_final_state():
    model, _ = random_model(8, 3)
    kw = dict(applied_force=1.2 * model.coulomb_level)
    whole = simulate(model, 1.0, initial_velocity=-0.5, t_end=1.0, **kw)
    first = simulate(model, 1.0, initial_velocity=-0.5, t_end=0.4, **kw)
    second = simulate(model, 1.0, initial_velocity=first.final_velocity, t_start=0.4, t_end=1.0,
                      initial_position=first.final_state.last_input,
                      initial_state=first.final_state, **kw)  # fmt: skip
    assert second.position[-1] == pytest.approx(whole.position[-1], rel=1e-12)


def test_callable_and_linear_hold_use_the_implicit_method():
    model, _ = random_model(2, 2)
    ts = np.linspace(0, 1, 11)
    res = simulate(model, 1.0, applied_force=(ts, 3 * np.sin(6 * ts)), hold="linear", t_end=1.0)
    fun = simulate(model, 1.0, applied_force=lambda t: np.interp(t, ts, 3 * np.sin(6 * ts)),
                   t_end=1.0)  # fmt: skip
    assert res.method == fun.method == "implicit"
    np.testing.assert_allclose(res.position, fun.position, rtol=1e-12, atol=1e-15)
    scalar = simulate(model, 1.0, applied_force=lambda t: 3 * math.sin(6 * t), t_end=1.0,
                      method="implicit")  # fmt: skip
    assert scalar.success and scalar.position[-1] != 0.0


def test_report_and_plots():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    model, _ = random_model(4, 3)
    res = simulate(model, 1.0, initial_velocity=1.0, initial_state="saturated", t_end=3.0)
    text = res.report()
    assert "stops at t =" in text and "reversals" in text
    for kind in ("time", "phase", "loop"):
        ax = res.plot(kind=kind)
        assert ax.lines
        plt.close(ax.figure)


# ----------------------------------------------------------------------- validation
MODEL = ps.PIFriction(coulomb=1.0, stiffness=[10.0], breakaway=[1.0])


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        (dict(mass=0.0, t_end=1.0), ValueError, "`mass` must be positive"),
        (dict(mass=-1.0, t_end=1.0), ValueError, "`mass` must be positive"),
        (dict(mass=1.0), TypeError, "`t_end` or `t_eval` must be given"),
        (dict(mass=1.0, t_end=0.0), ValueError, "`t_end` must be greater"),
        (dict(mass=1.0, t_end=np.nan), ValueError, "`t_end` must be finite"),
        (dict(mass=1.0, t_eval=[0.0, 0.5, 0.5]), ValueError, "`t_eval` must be strictly incr"),
        (dict(mass=1.0, t_eval=[0.0, 2.0], t_end=1.0), ValueError, "`t_eval` must lie in"),
        (dict(mass=1.0, t_eval=[-1.0, 0.5]), ValueError, "`t_eval` must lie in"),
        (dict(mass=1.0, t_end=1.0, method="rk4"), ValueError, "`method` must be one of"),
        (dict(mass=1.0, t_end=1.0, hold="cubic"), ValueError, "`hold` must be one of"),
        (dict(mass=1.0, t_end=1.0, applied_force=[1.0, 2.0, 3.0]), TypeError, "applied_force"),
        (dict(mass=1.0, t_end=1.0, applied_force=([0.0, 1.0], [1.0])), ValueError, "same length"),
        (
            dict(mass=1.0, t_end=1.0, applied_force=([0.0, 0.0], [1.0, 2.0])),
            ValueError,
            "strictly increasing",
        ),
        (
            dict(mass=1.0, t_end=1.0, applied_force=([0.5, 1.0], [1.0, 2.0])),
            ValueError,
            "must start at or before",
        ),
        (dict(mass=1.0, t_end=1.0, applied_force=lambda t: np.nan * t), ValueError, "finite"),
        (
            dict(mass=1.0, t_end=1.0, applied_force=lambda t: t, method="event"),
            ValueError,
            "piecewise-constant",
        ),
        (
            dict(mass=1.0, t_end=1.0, initial_state="saturated"),
            ValueError,
            r"`initial_velocity` or the applied force at `t_start` must be nonzero .*; got 0.0",
        ),
        (dict(mass=1.0, t_end=1.0, initial_state="hot"), ValueError, "`initial_state` must be"),
        (
            dict(mass=1.0, t_end=1.0, initial_state=ps.PIState(1.0, [1.0])),
            ValueError,
            "must equal `initial_position`",
        ),
        (
            dict(mass=1.0, t_end=1.0, initial_state=ps.PIState(0.0, [5.0])),
            ValueError,
            "threshold",
        ),
        (dict(mass=1.0, t_end=1.0, step=0.0), ValueError, "`step` must be positive"),
        (dict(mass=1.0, t_end=1.0, max_events=0), ValueError, "`max_events` must be a positive"),
        (dict(mass="1", t_end=1.0), TypeError, "`mass` must be a real number"),
    ],
)
def test_bad_input_is_rejected(kwargs, exc, match):
    with pytest.raises(exc, match=match):
        simulate(MODEL, **kwargs)


def test_bad_model_and_batch_inputs():
    with pytest.raises(TypeError, match="`model` must be a PIFriction"):
        simulate("friction", 1.0, t_end=1.0)
    with pytest.raises(ValueError, match="common length"):
        simulate_batch(MODEL, [1.0, 2.0], [1.0, 2.0, 3.0], t_end=1.0)
    with pytest.raises(TypeError, match="not both"):
        simulate_batch(MODEL, coulomb=[1.0], stiffness=[[1.0]], breakaway=[[1.0]], t_end=1.0)
    with pytest.raises(
        ValueError, match=r"`stiffness` must be positive; got -1.0 at index \(0, 0\)"
    ):
        simulate_batch(coulomb=[1.0], stiffness=[[-1.0]], breakaway=[[1.0]], t_end=1.0)
    with pytest.raises(ValueError, match="callable"):
        simulate_batch(MODEL, applied_force=lambda t: t, t_end=1.0)
    with pytest.raises(ValueError, match=r"`threshold` must be positive; got 0\.0 at index 0"):
        free_response(1.0, 0.5, [1.0], [0.0], 1.0, 1e-3, 10)
    with pytest.raises(ValueError, match="same length"):
        free_response(1.0, 0.5, [1.0, 2.0], [1.0], 1.0, 1e-3, 10)
    with pytest.raises(TypeError, match="`n_samples` must be an integer"):
        free_response(1.0, 0.5, [1.0], [1.0], 1.0, 1e-3, 10.5)


def test_event_limit_reports_failure():
    undamped = ps.PIFriction(coulomb=0.0, stiffness=[100.0], breakaway=[10.0])
    res = simulate(undamped, 1.0, initial_velocity=0.1, t_end=100.0, max_events=20)
    assert res.status == "event_limit" and not res.success
    assert "event limit" in res.message
    assert res.time.shape == res.position.shape and res.time[-1] < 100.0


# ----------------------------------------------------------------------- free_response results
def test_free_response_never_returns_unfilled_samples_at_the_event_limit():
    # an undamped oscillation (c1 = 0, amplitude v0/ω = 1e-5 far below r = 1): one
    # event per half-period, so the event limit stops the run long before t = 2000
    res = free_response(1.0, 0.0, [1e10], [1.0], 1.0, 0.01, 200000, initial_state="relaxed",
                        max_events=1000)  # fmt: skip
    assert res.status == "event_limit" and not res.success
    assert "event limit max_events = 1000" in res.message
    assert 0 < res.time.shape[0] < 200000
    assert res.time.shape == res.position.shape == res.velocity.shape
    w = 1e5
    np.testing.assert_allclose(res.position, np.sin(w * res.time) / w, rtol=0, atol=1e-9 / w)
    np.testing.assert_allclose(res.velocity, np.cos(w * res.time), rtol=0, atol=1e-9)
    assert res.stop_time is None
    assert "status event_limit" in res.report() and "not solved to the end" in res.report()


def test_free_response_result_report_and_plot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    # the docstring example of `simulate`: one reversal, stop at 1/3 + π·sqrt(m/k)
    res = free_response(1.0, 1.0, [100.0], [0.02], 1.0, 1e-3, 2000)
    assert res.success and res.n_reversals == 1
    assert res.stop_time == pytest.approx(1 / 3 + math.pi / 10, rel=1e-12)
    assert np.all(res.velocity[res.time > res.stop_time] == 0.0)
    assert "stops at t =" in res.report()
    _, ax = plt.subplots()
    assert res.plot(ax) is ax and ax.lines
    plt.close(ax.figure)
    with pytest.raises(AttributeError):
        res.status = "success"  # frozen


@pytest.mark.parametrize(
    ("args", "kwargs", "exc", "match"),
    [
        (("0.5", [1.0], [1.0]), {}, TypeError, r"`coulomb` must be a real number; got '0.5'\."),
        ((True, [1.0], [1.0]), {}, TypeError, r"`coulomb` must be a real number; got True\."),
        ((None, [1.0], [1.0]), {}, TypeError, r"`coulomb` must be a real number; got None\."),
        ((-0.5, [1.0], [1.0]), {}, ValueError, r"`coulomb` must be nonnegative; got -0.5\."),
        ((0.5, ["a"], [1.0]), {}, TypeError, r"`stiffness` must be a real number .*; got dtype"),
        ((0.5, [1 + 1j], [1.0]), {}, TypeError, r"`stiffness` must be .*; got dtype complex"),
        ((0.5, [True], [1.0]), {}, TypeError, r"`stiffness` must be .*; got dtype bool"),
        ((0.5, [1.0], [np.inf]), {}, ValueError, r"`threshold` must be finite; got inf"),
        (
            (0.5, [1e10], [1e300]),
            {},
            ValueError,
            r"`stiffness` and `threshold` must give a finite, positive breakaway .*; got inf at "
            r"index 0",
        ),
        (
            (0.0, [], []),
            {},
            ValueError,
            r"`coulomb` must be positive when `stiffness` is empty .*; got 0.0\.",
        ),
        (
            (0.5, [1.0], [1.0]),
            {"initial_state": np.zeros(3)},
            TypeError,
            r"`initial_state` must be 'relaxed' or 'saturated'; got ndarray\.",
        ),
        ((0.5, [1.0], [1.0]), {"max_events": 0}, ValueError, r"`max_events` must be a positive"),
    ],
)
def test_free_response_validates_its_inputs(args, kwargs, exc, match):
    with pytest.raises(exc, match=match):
        free_response(1.0, *args, 1.0, 1e-3, 10, **kwargs)


def test_free_response_breakaway_rule_equals_pifriction():
    with pytest.raises(
        ValueError, match="`stiffness` and `threshold` must give a finite, positive breakaway"
    ):
        ps.PIFriction(coulomb=0.5, stiffness=[1e10], threshold=[1e300])
    with pytest.raises(
        ValueError,
        match=r"`stiffness` and `threshold` must give a finite, positive breakaway .*; got 0\.0",
    ):
        free_response(1.0, 0.5, [1e-300], [1e-300], 1.0, 1e-3, 10)


# ----------------------------------------------------------------------- batch validation
BATCH = dict(initial_velocity=1.0, t_end=1.0)


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        (
            dict(coulomb="0.5", stiffness=[[1.0]], breakaway=[[1.0]]),
            TypeError,
            r"`coulomb` must be a real number or array of real numbers; got '0.5'\.",
        ),
        (
            dict(coulomb=0.5, stiffness=[[True]], breakaway=[[1.0]]),
            TypeError,
            r"`stiffness` must be a real number or array of real numbers; got dtype bool\.",
        ),
        (
            dict(coulomb=[True], stiffness=[[1.0]], breakaway=[[1.0]]),
            TypeError,
            r"`coulomb` must be .*; got dtype bool\.",
        ),
        (
            dict(coulomb=0.5, stiffness=[[1.0]], breakaway=[[1.0]], mass="2"),
            TypeError,
            r"`mass` must be a real number or array of real numbers; got '2'\.",
        ),
        (
            dict(coulomb=["a"], stiffness=[[1.0]], breakaway=[[1.0]]),
            TypeError,
            r"`coulomb` must be .*; got dtype <U1\.",
        ),
        (
            dict(coulomb=0.5, stiffness=[[1.0]], threshold=[["x"]]),
            TypeError,
            r"`threshold` must be .*; got dtype <U1\.",
        ),
        (
            dict(coulomb=0.5, stiffness=[[1.0], [1.0, 2.0]], breakaway=1.0),
            ValueError,
            r"`stiffness` must be a rectangular array; got",
        ),
        (
            dict(coulomb=[0.5] * 3, stiffness=[[1.0], [2.0]], breakaway=[[1.0], [1.0]]),
            ValueError,
            r"`coulomb`, `stiffness`, `breakaway` must have length 1 or one common length B "
            r"\(the batch size\); got lengths coulomb 3, stiffness 2, breakaway 2\.",
        ),
        (
            dict(coulomb=[0.5] * 2, stiffness=[[1.0], [2.0]], breakaway=1.0, mass=[1.0] * 3),
            ValueError,
            r"`coulomb`, `stiffness`, `mass` must have length 1 or one common length B",
        ),
        (
            dict(coulomb=0.5, stiffness=[[1e-300, 10.0]], breakaway=[[1e300, 1.0]]),
            ValueError,
            r"`stiffness` and `breakaway` must give a finite, positive threshold .*; got inf at "
            r"index \(0, 0\)\.",
        ),
        (
            dict(coulomb=0.5, stiffness=[[1e10]], threshold=[[1e300]]),
            ValueError,
            r"`stiffness` and `threshold` must give a finite, positive breakaway .*; got inf at "
            r"index \(0, 0\)",
        ),
        (
            dict(coulomb=0.5, stiffness=[[1.0, 2.0]], breakaway=[[1.0]]),
            ValueError,
            r"`breakaway` must have as many elements \(columns\) as `stiffness`; got 1 and 2\.",
        ),
        (
            dict(coulomb=[0.5, 0.0], stiffness=np.empty((1, 0)), breakaway=np.empty((1, 0))),
            ValueError,
            r"`coulomb` must be positive when `stiffness` is empty .*; got 0.0 at index 1\.",
        ),
        (
            dict(coulomb=0.5, stiffness=[[1.0]]),
            TypeError,
            r"`breakaway` or `threshold` must be given, not both; got neither\.",
        ),
        (
            dict(coulomb=0.5, breakaway=[[1.0]]),
            TypeError,
            r"`coulomb` and `stiffness` .* must be given when `models` is not; got no `stiff",
        ),
        (
            dict(coulomb=0.5, stiffness=[[1.0]], breakaway=1.0, initial_state=np.zeros(3)),
            TypeError,
            r"`initial_state` must be 'relaxed' or 'saturated'; got ndarray\.",
        ),
        (
            dict(coulomb=0.5, stiffness=[[1.0]], breakaway=1.0, initial_position=[np.nan]),
            ValueError,
            r"`initial_position` must be finite; got nan at index 0\.",
        ),
    ],
)
def test_batch_parameters_are_validated(kwargs, exc, match):
    with pytest.raises(exc, match=match):
        simulate_batch(**{**BATCH, **kwargs})


def test_batch_threshold_rule_equals_pifriction_and_shared_rows_broadcast():
    with pytest.raises(
        ValueError, match="`stiffness` and `breakaway` must give a finite, positive threshold"
    ):
        ps.PIFriction(coulomb=0.5, stiffness=[1e-300, 10.0], breakaway=[1e300, 1.0])
    with pytest.raises(TypeError, match=r"must be given, not both; got `models` and `threshold`"):
        simulate_batch(MODEL, threshold=[[1.0]], t_end=1.0)
    # one shared stiffness row and a scalar breakaway broadcast over B = 2 members
    batch = simulate_batch(coulomb=[0.5, 1.0], stiffness=[10.0], breakaway=1.0, **BATCH)
    for i, c1 in enumerate((0.5, 1.0)):
        one = simulate(ps.PIFriction(c1, [10.0], [1.0]), 1.0, **BATCH)
        np.testing.assert_array_equal(batch.position[i], one.position)


# ----------------------------------------------------------------------- state, force, plots
def test_array_initial_state_is_a_type_error():
    with pytest.raises(TypeError, match=r"`initial_state` must be 'relaxed', 'saturated' or a "
                                        r"PIState .*; got ndarray\."):  # fmt: skip
        simulate(MODEL, 1.0, t_end=1.0, initial_state=np.zeros(3))


@pytest.mark.parametrize(
    ("func", "got"),
    [
        (lambda t: "x", r"got 'x' at t = 0.0\."),
        (lambda t: np.ones(3), r"got \[1.0, 1.0, 1.0\] at t = 0.0\."),
        (lambda t: True, r"got True at t = 0.0\."),
    ],
)
def test_applied_force_must_return_one_real_number_per_time(func, got):
    with pytest.raises(TypeError, match=r"`applied_force` must return one real number per time; "
                       + got):  # fmt: skip
        simulate(MODEL, 1.0, t_end=1.0, applied_force=func)


def test_result_plot_takes_the_axes_first_and_batches_plot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    res = simulate(MODEL, 1.0, initial_velocity=1.0, t_end=2.0)
    _, ax = plt.subplots()
    assert res.plot(ax) is ax and ax.lines
    assert res.plot(ax, kind="phase") is ax
    plt.close(ax.figure)
    batch = simulate_batch(MODEL, 1.0, [0.5, 1.0, 30.0], t_end=2.0)
    assert batch.stopped.tolist() == [True, True, False]
    _, ax = plt.subplots()
    assert batch.plot(ax) is ax
    # one line per member, one marker line for the two stops
    assert len(ax.lines) == 3 + 1 + 1  # members, stops, zero line
    stops = next(ln for ln in ax.lines if ln.get_label() == "stop")
    np.testing.assert_array_equal(stops.get_xdata(), batch.stop_time[:2])
    np.testing.assert_array_equal(stops.get_ydata(), [0.0, 0.0])
    plt.close(ax.figure)
    ax = batch.plot(kind="position")
    stops = next(ln for ln in ax.lines if ln.get_label() == "stop")
    np.testing.assert_array_equal(stops.get_ydata(), batch.final_position[:2])
    plt.close(ax.figure)
    with pytest.raises(ValueError, match=r"`kind` must be one of 'velocity', 'position'; got 'x'"):
        batch.plot(kind="x")


def test_docstring_examples_run():
    import doctest

    import presliding.motion.batch as batch_module
    import presliding.motion.simulation as motion

    for module in (motion, batch_module):
        result = doctest.testmod(module)
        assert result.attempted >= 2 and result.failed == 0


def test_the_event_limit_message_gives_its_time_with_the_unit():
    """The message said "reached at t = 0.0123", no unit; every time in a message is in s."""
    model = ps.PIFriction(0.3, [2e4, 5e3], [0.175, 0.175])
    res = simulate(model, 1.0, initial_velocity=0.06, t_end=1.0, max_events=3)
    assert res.status == "event_limit"
    assert re.search(r"was reached at t = \S+ s$", res.message), res.message
    free = free_response(1.0, 0.3, [2e4, 5e3], [1e-5, 3e-5], 0.06, 1e-4, 1000,
                         initial_state="relaxed", max_events=1)  # fmt: skip
    assert re.search(r"was reached at t = \S+ s; \d+ of 1000 samples", free.message), free.message
