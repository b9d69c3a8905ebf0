"""Motion of a mass with a continuous-density friction model (eqs. 10, 12, 17).

The implicit stepper of `presliding.motion._implicit_density` solves each step's
inclusion exactly with the exact general PI operator; these tests hold it to the
finite-element stepper (a `Discrete` density), to the exact event method and to
the exact work-energy analysis of `presliding.analysis.stops`.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import presliding as ps
from presliding.analysis import turning_points
from presliding.motion import _implicit_density as dens_step
from presliding.motion import simulate, simulate_batch
from presliding.motion._forcing import as_forcing

UNIFORM = ps.Uniform(2.0, 1.0)  # F_m = 1, μ([0, R]) = 2
EXPONENTIAL = ps.Exponential(3.0, 0.4)  # F_m = 0.48, μ([0, ∞)) = 1.2


def density_run(density, c1, m, state, v0, applied, times, h, last_dir=None):
    """The density stepper called directly (also for a Discrete density)."""
    forcing = as_forcing(applied, "zoh", 0.0)
    d = float(np.sign(v0)) if last_dir is None else last_dir
    n_steps = max(int(np.ceil(times[-1] / h * (1.0 - 1e-9))), 1)
    return dens_step.run(density, c1, m, state, v0, d, forcing, times, 0.0, times[-1], n_steps)


def order(errors, ratio=2.0):
    e = np.asarray(errors)
    return np.log(e[:-1] / e[1:]) / np.log(ratio)


# ----------------------------------------------------------------------- Discrete density
K = np.array([400.0, 60.0, 9.0])
R = np.array([0.002, 0.01, 0.05])
C1 = 0.3


@pytest.mark.parametrize("start", ["saturated", "relaxed"])
def test_discrete_density_equals_the_finite_element_stepper(start):
    model = ps.PIFriction(C1, stiffness=K, threshold=R)
    times = np.linspace(0.0, 4.0, 401)
    h = 1e-3
    ref = simulate(model, 1.5, initial_velocity=0.8, initial_state=start, t_eval=times,
                   method="implicit", step=h)  # fmt: skip
    state = ps.MemoryState.saturated(0.0, 1.0, float(R.max()))
    if start == "relaxed":
        state = ps.MemoryState.relaxed(0.0)
    out = density_run(ps.Discrete(K, R), C1, 1.5, state, 0.8, 0.0, times, h)
    scale = np.max(np.abs(ref.position))
    assert np.max(np.abs(out["position"] - ref.position)) <= 1e-12 * scale
    assert np.max(np.abs(out["velocity"] - ref.velocity)) <= 1e-12 * np.max(np.abs(ref.velocity))
    assert np.max(np.abs(out["elastic"] - ref.elastic_force)) <= 1e-12 * float(K @ R)
    np.testing.assert_allclose(out["e_el"], ref.energy.elastic, rtol=1e-10, atol=1e-14)
    np.testing.assert_allclose(out["dissipated"], ref.energy.dissipated, rtol=1e-10, atol=1e-14)
    np.testing.assert_array_equal(out["rev_t"], ref.reversal_times)
    np.testing.assert_allclose(out["rev_y"], ref.reversal_positions, rtol=1e-12)
    assert out["stop"] == ref.stop_time
    assert ref.n_reversals >= 2


def test_discrete_density_under_a_varying_force_equals_the_finite_element_stepper():
    model = ps.PIFriction(C1, stiffness=K, threshold=R)
    times = np.linspace(0.0, 3.0, 301)

    def u(t):
        return 1.2 * np.sin(5.0 * t) * np.exp(-0.3 * t)

    ref = simulate(model, 0.7, applied_force=u, t_eval=times, step=5e-4)
    out = density_run(ps.Discrete(K, R), C1, 0.7, ps.MemoryState.relaxed(), 0.0, u, times, 5e-4)
    assert np.max(np.abs(out["position"] - ref.position)) <= 1e-12 * np.max(np.abs(ref.position))
    assert ref.stop_time is not None and out["stop"] == ref.stop_time  # sticks at the end


def test_discrete_density_stepper_converges_to_the_event_method_at_first_order():
    model = ps.PIFriction(C1, stiffness=K, threshold=R)
    times = np.linspace(0.0, 1.5, 16)
    exact = simulate(model, 1.5, initial_velocity=0.8, initial_state="saturated", t_eval=times,
                     method="event")  # fmt: skip
    state = ps.MemoryState.saturated(0.0, 1.0, float(R.max()))
    errors = []
    for h in (4e-4, 2e-4, 1e-4, 5e-5):
        out = density_run(ps.Discrete(K, R), C1, 1.5, state, 0.8, 0.0, times, h)
        errors.append(np.max(np.abs(out["position"] - exact.position)))
    p = order(errors)
    assert np.all(p > 0.85) and np.all(p < 1.2), (errors, p)
    assert errors[-1] < 1e-4 * np.max(np.abs(exact.position))


# ----------------------------------------------------------------------- continuous densities
SWEEP = [0.04, 0.07, 0.12, 0.2, 0.35, 0.6, 0.9, 1.3]


@pytest.mark.parametrize("density", [UNIFORM, EXPONENTIAL], ids=["uniform", "exponential"])
def test_turning_points_converge_to_the_work_energy_analysis(density):
    """Over a sweep of c1/F_m: same reversal count, turning points and rest position, O(h)."""
    fm = density.max_elastic_force
    m, v0 = 1.0, 1.2
    for ratio in SWEEP:
        model = ps.PIFriction(ratio * fm, density=density)
        tp = turning_points(model, m, v0, "saturated")
        assert tp.status == "stopped"
        errors = []
        for h in (4e-3, 2e-3, 1e-3):
            res = simulate(model, m, initial_velocity=v0, initial_state="saturated",
                           t_end=40.0, step=h, t_eval=[0.0, 40.0])  # fmt: skip
            assert res.method == "implicit" and res.success
            assert res.n_reversals == tp.n_reversals, ratio
            assert res.stop_time is not None
            err_turn = np.max(np.abs(res.reversal_positions - tp.positions[:-1]), initial=0.0)
            err_rest = abs(res.rest_position - tp.rest_position)
            errors.append(max(err_turn, err_rest))
            assert isinstance(res.final_state, ps.MemoryState)
            assert res.final_state.last_input == res.rest_position
        assert errors[-1] <= 5.0 * 1e-3 * abs(v0), (ratio, errors)
        p = order(errors)
        assert np.all(p > 0.8) and np.all(p < 1.25), (ratio, errors, p)


@pytest.mark.parametrize("start", ["relaxed", "memory"])
def test_other_starts_converge_to_the_analysis(start):
    model = ps.PIFriction(0.1, density=EXPONENTIAL)
    if start == "memory":
        state = ps.MemoryState(0.3, np.array([-0.5, 0.4, -0.1]), 0.0, 1.0)
    else:
        state = "relaxed"
    y0 = 0.3 if start == "memory" else 0.0
    tp = turning_points(model, 2.0, -0.7, state, initial_position=y0)
    errors = []
    for h in (2e-3, 1e-3):
        res = simulate(model, 2.0, initial_velocity=-0.7, initial_state=state,
                       initial_position=y0, t_end=40.0, step=h)  # fmt: skip
        assert res.n_reversals == tp.n_reversals >= 1
        errors.append(
            max(
                np.max(np.abs(res.reversal_positions - tp.positions[:-1])),
                abs(res.rest_position - tp.rest_position),
            )
        )
    assert errors[1] < 3e-3
    assert 0.8 < order(errors)[0] < 1.25


def test_fine_discretisation_agrees_with_the_exact_operator():
    """A forced motion: density vs its N = 2000 midpoint discretisation, same step."""
    model = ps.PIFriction(0.2, density=UNIFORM)
    disc = UNIFORM.discretize(2000)
    fe = ps.PIFriction(0.2, stiffness=disc.stiffness, threshold=disc.threshold)
    times = np.linspace(0.0, 6.0, 121)

    def u(t):
        return 1.5 * np.sin(2.0 * t)

    exact = simulate(model, 1.0, applied_force=u, t_eval=times, step=1e-3)
    approx = simulate(fe, 1.0, applied_force=u, t_eval=times, step=1e-3)
    scale = np.max(np.abs(exact.position))
    assert scale > 0.3
    assert np.max(np.abs(exact.position - approx.position)) < 1e-5 * scale
    assert exact.n_reversals == approx.n_reversals >= 2


# ----------------------------------------------------------------------- stiction, energy
def test_stuck_mass_does_not_move_over_a_million_steps():
    model = ps.PIFriction(0.5, density=UNIFORM)
    res = simulate(model, 1.0, applied_force=lambda t: 0.49 * np.sin(40.0 * t),
                   initial_position=0.25, t_end=1.0, step=1e-6)  # fmt: skip
    assert res.n_events == 1_000_000
    assert np.all(res.position == 0.25) and np.all(res.velocity == 0.0)
    assert res.n_reversals == 0 and res.stop_time == 0.0
    # static friction balances u (held at the step midpoints) and never exceeds c1
    np.testing.assert_allclose(res.friction_force, res.applied_force, atol=2e-5)
    assert np.max(np.abs(res.friction_force)) <= 0.5
    assert res.final_state.last_input == 0.25 and res.final_state.turning.size == 0


def test_after_a_stop_the_mass_stays_exactly_put():
    model = ps.PIFriction(0.15, density=EXPONENTIAL)
    free = simulate(model, 1.0, initial_velocity=1.0, initial_state="saturated", t_end=30.0,
                    step=1e-3)  # fmt: skip
    rest = free.rest_position
    after = free.time > free.stop_time
    assert np.all(free.position[after] == rest) and np.all(free.velocity[after] == 0.0)
    # then a force with |u − F_el| < c1 for a long time: not a single bit moves
    f_el = free.elastic_force[-1]
    more = simulate(model, 1.0, applied_force=lambda t: f_el + 0.149 * np.cos(t),
                    initial_position=rest, initial_state=free.final_state, t_end=50.0,
                    step=1e-4)  # fmt: skip
    assert np.all(more.position == rest) and np.all(more.velocity == 0.0)
    np.testing.assert_array_equal(more.final_state.turning, free.final_state.turning)


def test_energy_balance_residual_is_first_order_and_the_energy_never_grows():
    model = ps.PIFriction(0.05, density=UNIFORM)
    residuals = []
    for h in (2e-3, 5e-4, 1.25e-4):
        res = simulate(model, 1.0, initial_velocity=1.0, initial_state="relaxed", t_end=15.0,
                       step=h, t_eval=np.linspace(0.0, 15.0, 3001))  # fmt: skip
        e = res.energy
        residuals.append(e.max_relative_residual)
        # the scheme only dissipates: residual <= 0 and E_mech + dissipated <= E0
        assert np.all(e.residual <= 1e-12 * e.initial)
        mech = e.kinetic + e.elastic
        assert np.all(np.diff(mech) <= 1e-12 * e.initial)
        assert np.all(np.diff(e.dissipated) >= 0.0)
    assert residuals[-1] < 1e-3
    p = order(residuals, 4.0)
    assert np.all(p > 0.85) and np.all(p < 1.2), (residuals, p)


def test_forced_energy_balance_includes_the_work_of_u():
    model = ps.PIFriction(0.1, density=EXPONENTIAL)
    out = []
    for h in (1e-3, 2.5e-4):
        res = simulate(model, 1.0, applied_force=lambda t: 0.8 * np.sin(3.0 * t), t_end=8.0,
                       step=h)  # fmt: skip
        out.append(res.energy.max_relative_residual)
        assert abs(res.energy.work[-1]) > 0.01
    assert out[1] < out[0] / 3.0 and out[1] < 1e-2


@pytest.mark.parametrize("density", [UNIFORM, EXPONENTIAL], ids=["uniform", "exponential"])
def test_without_coulomb_element_the_oscillation_decays(density):
    """c1 = 0, continuous μ: infinitely many reversals of decaying amplitude, never a stop."""
    model = ps.PIFriction(0.0, density=density)
    res = simulate(model, 1.0, initial_velocity=0.6, initial_state="relaxed", t_end=60.0,
                   step=1e-3, t_eval=np.linspace(0.0, 60.0, 6001))  # fmt: skip
    assert res.stop_time is None and res.final_velocity != 0.0
    assert res.n_reversals >= 8
    amp = np.abs(np.diff(res.reversal_positions))
    assert np.all(np.diff(amp) < 0.0)  # each swing shorter than the one before
    e = res.energy
    assert np.all(np.diff(e.kinetic + e.elastic) <= 1e-12 * e.initial)
    # the swings follow the exact analysis (which says: never stops)
    tp = turning_points(model, 1.0, 0.6, "relaxed", max_reversals=4)
    assert tp.status == "never_stops"
    np.testing.assert_allclose(res.reversal_positions[:4], tp.positions[:4], atol=3e-3)


# ----------------------------------------------------------------------- states, results
def test_continuation_from_the_final_state_and_result_objects():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    model = ps.PIFriction(0.1, density=UNIFORM)
    kw = dict(applied_force=lambda t: 1.3 * np.sin(2.5 * t), step=1e-3)
    whole = simulate(model, 1.0, t_eval=np.linspace(0.0, 4.0, 401), **kw)
    first = simulate(model, 1.0, t_eval=np.linspace(0.0, 2.0, 201), **kw)
    second = simulate(model, 1.0, t_eval=np.linspace(2.0, 4.0, 201), t_start=2.0,
                      initial_position=first.position[-1], initial_velocity=first.final_velocity,
                      initial_state=first.final_state, **kw)  # fmt: skip
    np.testing.assert_allclose(second.position, whole.position[200:], rtol=1e-9, atol=1e-12)
    assert whole.final_state.turning.size >= 1
    text = whole.report()
    assert "implicit" in text and "reversals" in text
    for kind in ("time", "phase", "loop"):
        ax = whole.plot(kind=kind)
        assert ax.lines
        plt.close(ax.figure)


@pytest.mark.parametrize(
    "density",
    [
        ps.PiecewiseConstant([0.0, 0.3, 1.0], [3.0, 1.0]),
        ps.Density.from_function(lambda r: 2.0 + math.cos(4.0 * r), 1.0),
        ps.Exponential(3.0, 0.4, 0.8),
    ],
    ids=["piecewise", "tabulated", "exp-truncated"],
)
def test_every_density_kind_stops_like_the_analysis(density):
    model = ps.PIFriction(0.1 * density.max_elastic_force, density=density)
    tp = turning_points(model, 1.0, 1.0, "saturated")
    res = simulate(model, 1.0, initial_velocity=1.0, initial_state="saturated", t_end=40.0,
                   step=5e-4)  # fmt: skip
    assert res.n_reversals == tp.n_reversals >= 1
    assert res.rest_position == pytest.approx(tp.rest_position, abs=2e-3)


def test_initial_acceleration_and_friction_force_at_rest():
    model = ps.PIFriction(0.2, density=UNIFORM)
    res = simulate(model, 2.0, applied_force=1.0, t_end=1.0)
    assert res.acceleration[0] == pytest.approx((1.0 - 0.2) / 2.0)
    assert res.friction_force[0] == pytest.approx(0.2)
    assert res.position[-1] > 0.0 and res.n_reversals == 0


def test_validation_of_density_motions():
    model = ps.PIFriction(0.2, density=UNIFORM)
    with pytest.raises(ValueError, match="`method` 'event' needs a finite-element model"):
        simulate(model, 1.0, initial_velocity=1.0, t_end=1.0, method="event")
    with pytest.raises(TypeError, match="MemoryState; got a PIState"):
        simulate(model, 1.0, t_end=1.0, initial_state=ps.PIState.relaxed(0.0, 2))
    with pytest.raises(ValueError, match="must equal `initial_position`"):
        simulate(model, 1.0, t_end=1.0, initial_state=ps.MemoryState.relaxed(0.5))
    with pytest.raises(ValueError, match="must be nonzero for `initial_state` 'saturated'"):
        simulate(model, 1.0, t_end=1.0, initial_state="saturated")
    with pytest.raises(ValueError, match="`initial_state` must be 'relaxed'"):
        simulate(model, 1.0, t_end=1.0, initial_state="hot")
    with pytest.raises(TypeError, match=r"or a MemoryState; got ndarray\."):
        simulate(model, 1.0, t_end=1.0, initial_state=np.zeros(3))
    with pytest.raises(ValueError, match="`step` must be positive"):
        simulate(model, 1.0, t_end=1.0, step=-1.0)
    with pytest.raises(TypeError, match="continuous density"):
        simulate_batch(model, t_end=1.0)
    auto = simulate(model, 1.0, initial_velocity=1.0, t_end=1.0)
    assert auto.method == "implicit"
