"""A mass with GMS, LuGre and Dahl friction (`simulate`, the implicit step of `_rate_step`)."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from presliding import (
    DahlFriction,
    DahlState,
    GMSFriction,
    LuGreFriction,
    PIFriction,
    simulate,
)

PI = PIFriction(0.3, [4000.0, 1500.0, 500.0], [0.2, 0.25, 0.25], viscous=0.5)
GMS = GMSFriction.from_pi(PI, static_level=1.4, stribeck_velocity=0.01, lag_time=0.004)
LUGRE = LuGreFriction(1.0, 1.3, 3e3, 40.0, 0.4, 0.01)
DAHL = DahlFriction(1.0, 5e3, viscous=0.3)


def test_without_stribeck_drop_and_lag_a_stop_is_the_pi_models_implicit_stop():
    """F_S = F_C, τ = 0: the GMS step solves the PI step's inclusion (to rounding), for a
    sampled force, samples between the steps and the viscous term."""
    t = np.linspace(0.0, 0.7, 353)  # samples fall between the steps
    u = np.where(t < 0.05, -0.4, np.where(t < 0.4, 0.0, 0.15))
    kw = dict(applied_force=(t, u), initial_velocity=0.06, initial_position=1e-3,
              initial_state="saturated", t_eval=t, method="implicit", step=2e-4)  # fmt: skip
    gms = simulate(GMSFriction.from_pi(PI), 2.0, **kw)
    pi = simulate(PI, 2.0, **kw)
    for name in ("position", "velocity", "acceleration", "friction_force", "elastic_force"):
        a, b = getattr(gms, name), getattr(pi, name)
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * max(np.max(np.abs(b)), 1e-300))
    np.testing.assert_allclose(gms.energy.dissipated, pi.energy.dissipated, rtol=1e-12, atol=1e-15)
    assert gms.stop_time == pi.stop_time and gms.n_reversals == pi.n_reversals >= 1
    np.testing.assert_allclose(gms.final_state.forces,
                               PI.stiffness * (pi.final_state.last_input - pi.final_state.play),
                               rtol=0, atol=1e-12)  # fmt: skip


def test_at_rest_below_break_away_nothing_drifts_bit_for_bit():
    """After the stop, with a constant force below break-away and slipping elements still
    lagging behind the static level, the position, the velocity and every element's force
    stay exactly as they are: the GMS rates carry sign(ẏ) = 0."""
    damped = GMSFriction.from_pi(
        PIFriction(0.3, PI.stiffness, PI.breakaway, viscous=300.0),
        static_level=1.4,
        stribeck_velocity=0.01,
        lag_time=0.004,
    )
    t = np.linspace(0.0, 5.0, 2501)
    res = simulate(damped, 2.0, applied_force=0.5, initial_velocity=0.05,
                   initial_state="saturated", t_eval=t, method="implicit", step=1e-4)  # fmt: skip
    assert res.stop_time is not None and res.stop_time < 0.1 and res.n_reversals == 0
    rest = t >= res.stop_time
    assert np.all(res.position[rest] == res.rest_position)
    assert np.all(res.velocity[rest] == 0.0)
    end = res.final_state
    assert np.all(end.slipping == 1.0)  # every element still slipping, its force lagging
    assert np.all(end.forces < damped.breakaway * damped.static_ratio)
    later = simulate(
        damped,
        2.0,
        applied_force=0.5,
        initial_position=res.rest_position,
        initial_state=end,
        t_start=5.0,
        t_end=500.0,
        method="implicit",
    )
    assert np.all(later.position == res.rest_position)
    np.testing.assert_array_equal(later.final_state.forces, end.forces)


def test_break_away_is_the_static_level():
    """From rest the contact holds any force up to c1·F_S/F_C plus what the elements carry:
    a force just below it leaves the mass exactly in place, just above it moves it."""
    model = GMSFriction(0.5, [1e4], [0.5], static_level=1.5, stribeck_velocity=0.01)
    kw = dict(initial_state="relaxed", t_end=0.2, method="implicit", step=1e-4)
    held = simulate(model, 1.0, applied_force=0.5 * 1.5 * (1 - 1e-9), **kw)
    assert np.all(held.position == 0.0)
    moved = simulate(model, 1.0, applied_force=0.5 * 1.5 * (1 + 1e-6), **kw)
    assert moved.position[-1] > 0.0


def _lugre_rhs(t, x, m, model):
    _, v, z = x
    g = model.coulomb + (model.static - model.coulomb) * np.exp(
        -((v / model.stribeck_velocity) ** 2)
    )
    zdot = v - model.stiffness * abs(v) * z / g
    force = model.stiffness * z + model.damping * zdot + model.viscous * v
    return [v, -force / m, zdot]


def _dahl_rhs(t, x, m, model):
    _, v, f = x
    s = np.sign(v)
    fdot = model.stiffness * (1 - f / model.coulomb * s) * v
    return [v, -(f + model.viscous * v) / m, fdot]


@pytest.mark.parametrize("model", [LUGRE, DAHL], ids=["lugre", "dahl"])
def test_lugre_and_dahl_converge_to_an_independent_ode_solution_at_first_order(model):
    """A short slide (no reversal) against scipy's Radau at tight tolerances: the error of
    the implicit step halves with the step (first order) and is small at the finest."""
    m, v0, t_end = 2.0, 0.05, 0.04
    t = np.linspace(0.0, t_end, 41)
    rhs, x0 = (_lugre_rhs, [0.0, v0, 0.0]) if model is LUGRE else (_dahl_rhs, [0.0, v0, 0.0])
    ref = solve_ivp(rhs, (0.0, t_end), x0, method="Radau", t_eval=t, rtol=1e-11, atol=1e-14,
                    args=(m, model))  # fmt: skip
    errors = []
    for step in (4e-5, 2e-5, 1e-5):
        res = simulate(model, m, initial_velocity=v0, initial_state="relaxed", t_eval=t,
                       method="implicit", step=step)  # fmt: skip
        assert np.all(res.velocity > 0)
        errors.append(np.max(np.abs(res.velocity - ref.y[1])))
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    np.testing.assert_allclose(ratios, 2.0, rtol=0.1)
    assert errors[-1] < 2e-4 * v0


def test_the_friction_force_of_the_motion_is_the_models_force_along_it():
    """At the steps, u − m·ÿ of the motion equals `GMSFriction.force` along the simulated
    positions (where the mass moves), and the energy balance misses only the scheme's
    numerical dissipation ½·m·Δv² per step, small; the dissipation never falls."""
    h = 1e-4
    t = np.arange(0.0, 0.4 + h / 2, h)
    u = np.where(t < 0.05, -0.3, 0.0)
    res = simulate(GMS, 2.0, applied_force=(t, u), initial_velocity=0.05, initial_state="saturated",
                   t_eval=t, method="implicit", step=h)  # fmt: skip
    start = GMS.saturated_state(0.0, 0.0, 1.0, 0.05)
    force, _ = GMS.force(res.position[1:], t[1:], start)
    moving = res.velocity[1:] != 0.0
    np.testing.assert_allclose(res.friction_force[1:][moving], force[moving], rtol=1e-9,
                               atol=1e-9)  # fmt: skip
    assert np.all(np.diff(res.energy.total_dissipated) >= -1e-15)
    assert res.energy.max_relative_residual < 5e-3


def test_states_continue_and_the_event_method_is_refused():
    t = np.linspace(0.0, 0.2, 101)
    whole = simulate(DAHL, 1.0, initial_velocity=0.03, t_eval=t, method="implicit", step=1e-4)
    first = simulate(DAHL, 1.0, initial_velocity=0.03, t_eval=t[:51], method="implicit",
                     step=1e-4)  # fmt: skip
    assert isinstance(first.final_state, DahlState)
    rest = simulate(DAHL, 1.0, initial_velocity=first.final_velocity,
                    initial_position=first.final_state.last_input, initial_state=first.final_state,
                    t_start=0.1, t_eval=t[50:], method="implicit", step=1e-4)  # fmt: skip
    np.testing.assert_allclose(rest.position, whole.position[50:], rtol=0, atol=1e-15)
    with pytest.raises(ValueError, match=r"`method` 'event' needs the PI model's closed-form"):
        simulate(GMS, 1.0, t_end=1.0, method="event")
    with pytest.raises(TypeError, match=r"`initial_state` must be 'relaxed', 'saturated' or a "
                                        r"GMSState"):  # fmt: skip
        simulate(GMS, 1.0, t_end=1.0, initial_state=DahlState(0.0, 0.0))
    with pytest.raises(ValueError, match=r"`initial_state.last_input` must equal"):
        simulate(LUGRE, 1.0, t_end=1.0, initial_state=LUGRE.relaxed_state(1.0))
