"""`simulate` with asymmetric friction: the exact event method with two sides."""

from __future__ import annotations

import hashlib

import numpy as np
import pytest

import presliding as ps

K = [500.0, 10.0, 4.0]
T_U = np.array([0.0, 0.7, 1.5, 2.2, 3.1])
U = np.array([2.5, -2.0, 0.4, -3.0, 0.0])


def _digest(res, *extra) -> str:
    """The digest of a run's main arrays (with the acceleration: the one of implicit runs)."""
    h = hashlib.sha256()
    first = (res.position, res.velocity, *extra)
    for a in (*first, res.friction_force, res.energy.dissipated, res.energy.elastic):
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()[:16]


def _run(model, u=U, v0=0.3, **kw):
    return ps.simulate(model, 1.0, applied_force=(T_U, u), hold="zoh", t_end=4.0,
                       initial_velocity=v0, method="event", **kw)  # fmt: skip


@pytest.mark.parametrize(
    ("viscous", "digest", "digest_implicit"),
    [(0.0, "0f9717837f7d90be", "086684f2a006db72"), (1.5, "f9bd91e230d1bfcc", "d89e69966ee2d8b3")],
)
def test_symmetric_motion_is_bit_identical_to_the_symmetric_code(viscous, digest,
                                                                 digest_implicit):  # fmt: skip
    """Digests of symmetric event and implicit runs recorded before asymmetric friction
    existed."""
    model = ps.PIFriction(0.5, K, [1.0, 1.0, 1.0], viscous=viscous)
    assert _digest(_run(model)) == digest
    t = np.linspace(0, 4, 41)
    u = 3 * np.sin(2 * t) + 0.5 * np.cos(7 * t)
    implicit = ps.simulate(model, 1.0, applied_force=(t, u), hold="linear", t_end=4.0,
                           initial_velocity=-0.3, method="implicit", step=1e-3)  # fmt: skip
    assert _digest(implicit, implicit.acceleration) == digest_implicit
    equal_sides = ps.PIFriction(0.5, K, [1.0, 1.0, 1.0], viscous=viscous,
                                coulomb_negative=0.5, breakaway_negative=[1.0, 1.0, 1.0],
                                viscous_negative=viscous)  # fmt: skip
    assert _digest(_run(equal_sides)) == digest


def test_nearly_equal_sides_approach_the_symmetric_motion():
    sym = _run(ps.PIFriction(0.5, K, [1.0, 1.0, 1.0], viscous=1.5))
    near = _run(ps.PIFriction(0.5, K, [1.0, 1.0, 1.0], viscous=1.5,
                              coulomb_negative=0.5 * (1 + 1e-12)))  # fmt: skip
    np.testing.assert_allclose(near.position, sym.position, rtol=0, atol=1e-9)


@pytest.mark.parametrize(("u", "sticks"), [(-0.4, True), (-0.8, False), (0.9, True), (1.3, False)])
def test_coulomb_only_stop_against_the_closed_form(u, sticks):
    """c1⁺ = 1, c1⁻ = 0.5, mass 2, v0 = 2: decelerates at (u − c1⁺)/m, stops at
    t1 = m·v0/(c1⁺ − u); then sticks iff −c1⁻ <= u <= c1⁺, else slides at (u + c1⁻)/m
    (or (u − c1⁺)/m upwards)."""
    c1p, c1n, m, v0 = 1.0, 0.5, 2.0, 2.0
    model = ps.PIFriction(c1p, coulomb_negative=c1n)
    t_end = 50.0
    res = ps.simulate(model, m, applied_force=u, initial_velocity=v0, t_end=t_end)
    if u >= c1p:  # never decelerates to rest
        assert res.stop_time is None
        np.testing.assert_allclose(res.position[-1], v0 * t_end + 0.5 * (u - c1p) / m * t_end**2)
        return
    a1 = (u - c1p) / m
    t1 = -v0 / a1
    y1 = v0 * t1 + 0.5 * a1 * t1**2
    if sticks:
        assert res.stop_time == pytest.approx(t1, rel=1e-13)
        assert res.rest_position == pytest.approx(y1, rel=1e-13)
        assert res.friction_force[-1] == pytest.approx(u, rel=1e-13)
    else:
        assert res.stop_time is None
        a2 = (u + c1n) / m
        tau = t_end - t1
        np.testing.assert_allclose(res.position[-1], y1 + 0.5 * a2 * tau**2, rtol=1e-12)
        assert res.n_reversals == 1


def _swapped(model):
    def side(neg, pos):
        return pos if neg is None else neg

    return ps.PIFriction(side(model.coulomb_negative, model.coulomb), model.stiffness,
                         side(model.breakaway_negative, model.breakaway),
                         coulomb_negative=model.coulomb, breakaway_negative=model.breakaway,
                         viscous=side(model.viscous_negative, model.viscous),
                         viscous_negative=model.viscous)  # fmt: skip


@pytest.mark.parametrize(("sigma_pos", "sigma_neg"), [(0.0, 0.0), (1.0, 3.0), (0.0, 2.0)])
def test_mirror_symmetry_and_energy_balance(sigma_pos, sigma_neg):
    model = ps.PIFriction(0.6, K, [1.0, 1.0, 1.0], coulomb_negative=0.2,
                          breakaway_negative=[0.5, 2.0, 0.75], viscous=sigma_pos,
                          viscous_negative=sigma_neg)  # fmt: skip
    res = _run(model)
    mirror = _run(_swapped(model), u=-U, v0=-0.3)
    scale = float(np.ptp(res.position))
    np.testing.assert_allclose(mirror.position, -res.position, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(mirror.friction_force, -res.friction_force, rtol=0, atol=1e-9)
    e = res.energy
    assert np.max(np.abs(e.residual)) <= 1e-9 * max(float(np.max(np.abs(e.work))), 1.0)
    assert np.all(np.diff(e.dissipated) >= -1e-12) and np.all(np.diff(e.viscous) >= -1e-12)
    # the friction force stays within the two sliding levels plus the viscous force
    fp, fn = model.coulomb_levels
    visc = model.viscous_force(res.velocity)
    assert np.all(res.friction_force - visc <= fp + 1e-9)
    assert np.all(res.friction_force - visc >= -fn - 1e-9)


def test_continuation_follows_the_whole_run_and_states_keep_the_band():
    model = ps.PIFriction(0.6, K, [1.0, 1.0, 1.0], coulomb_negative=0.2,
                          breakaway_negative=[0.5, 2.0, 0.75], viscous_negative=2.0)  # fmt: skip
    whole = ps.simulate(model, 1.0, applied_force=(T_U, U), hold="zoh", t_end=4.0,
                        initial_velocity=0.3, t_eval=np.linspace(0.0, 4.0, 401))  # fmt: skip
    head = ps.simulate(model, 1.0, applied_force=(T_U, U), hold="zoh", t_end=2.0,
                       initial_velocity=0.3, t_eval=np.linspace(0.0, 2.0, 201))  # fmt: skip
    tail = ps.simulate(model, 1.0, applied_force=(T_U, U), hold="zoh", t_start=2.0, t_end=4.0,
                       initial_position=head.position[-1], initial_velocity=head.final_velocity,
                       initial_state=head.final_state,
                       t_eval=np.linspace(2.0, 4.0, 201))  # fmt: skip
    np.testing.assert_allclose(np.concatenate([head.position, tail.position[1:]]),
                               whole.position, rtol=0, atol=1e-14)  # fmt: skip
    f = whole.final_state.deformation
    assert np.all(f <= model.threshold + 1e-15)
    assert np.all(f >= -model.threshold_negative - 1e-15)
    saturated_down = ps.simulate(model, 1.0, initial_velocity=-1.0, initial_state="saturated",
                                 t_end=0.5)  # fmt: skip
    assert saturated_down.elastic_force[0] == pytest.approx(-3.25)


def test_routes_without_asymmetric_friction_say_so():
    model = ps.PIFriction(0.6, K, [1.0, 1.0, 1.0], coulomb_negative=0.2)
    with pytest.raises(NotImplementedError, match="simulate_batch"):
        ps.simulate_batch([model, model], 1.0, t_end=1.0)
    with pytest.raises(NotImplementedError, match="friction_inverse"):
        ps.friction_inverse(model)
    with pytest.raises(NotImplementedError, match="describing_function"):
        ps.describing_function(model, 0.01)
    with pytest.raises(NotImplementedError, match="dissipated_energy"):
        ps.dissipated_energy(model, [0.0, 0.5])
    damped = ps.PIFriction(0.6, viscous=1.0, viscous_negative=3.0)
    t = np.array([0.0, 1.0, 2.0])
    # σ⁺·1² over the first second, σ⁻·1² over the second (trapezoid on constant pieces)
    np.testing.assert_allclose(ps.viscous_dissipation(damped, t[:2], [1.0, 1.0]), [0.0, 1.0])
    np.testing.assert_allclose(ps.viscous_dissipation(damped, t[:2], [-1.0, -1.0]), [0.0, 3.0])


@pytest.mark.parametrize(("sigma_pos", "sigma_neg"), [(0.0, 0.0), (1.0, 3.0)])
def test_implicit_method_converges_to_the_exact_motion(sigma_pos, sigma_neg):
    """First order in the step; the energy balance misses only the scheme's numerical loss;
    the mirror model on the mirrored force gives the mirrored motion."""
    model = ps.PIFriction(0.6, K, [1.0, 1.0, 1.0], coulomb_negative=0.2,
                          breakaway_negative=[0.5, 2.0, 0.75], viscous=sigma_pos,
                          viscous_negative=sigma_neg)  # fmt: skip
    exact = _run(model)
    errors = []
    for step in (4e-4, 2e-4):
        res = ps.simulate(model, 1.0, applied_force=(T_U, U), hold="zoh", t_end=4.0,
                          initial_velocity=0.3, method="implicit", step=step)  # fmt: skip
        errors.append(float(np.max(np.abs(res.position - exact.position))))
    assert errors[1] < 0.7 * errors[0] and errors[1] < 2e-3 * np.ptp(exact.position)
    mirror = ps.simulate(_swapped(model), 1.0, applied_force=(T_U, -U), hold="zoh", t_end=4.0,
                         initial_velocity=-0.3, method="implicit", step=2e-4)  # fmt: skip
    np.testing.assert_allclose(mirror.position, -res.position, rtol=0, atol=1e-12)
    assert np.all(np.diff(res.energy.dissipated) >= -1e-12)


def test_implicit_coulomb_only_sticks_inside_the_band():
    model = ps.PIFriction(1.0, coulomb_negative=0.5)
    for u, moves in ((-0.45, False), (0.95, False), (-0.55, True), (1.05, True)):
        res = ps.simulate(model, 2.0, applied_force=lambda t, u=u: np.full_like(t, u),
                          t_end=1.0, step=1e-3)  # fmt: skip
        assert res.method == "implicit"
        assert (res.position[-1] != 0.0) == moves, u
        if moves:  # uniformly accelerated from rest at (u − c1±)/m
            a = (u - 1.0) / 2.0 if u > 0 else (u + 0.5) / 2.0
            assert res.position[-1] == pytest.approx(0.5 * a, rel=2e-3)


def test_quasi_static_response_of_an_asymmetric_model():
    """Moving samples balance u against the friction force along the response; at rest u stays
    inside the stick band; the mirror model on −u gives −y."""
    model = ps.PIFriction(0.3, K, [1.0, 1.0, 1.0], coulomb_negative=0.1,
                          breakaway_negative=[0.5, 2.0, 0.75])  # fmt: skip
    fp, fn = model.coulomb_levels
    u = ps.signals.piecewise_linear([0.0, 0.9 * fp, -0.9 * fn, 0.5 * fp, -0.2], step=1e-3)
    res = ps.quasi_static_response(model, u)
    force, _ = model.force(res.position)
    moving = np.flatnonzero(np.diff(res.position) != 0) + 1
    assert moving.size > 100
    np.testing.assert_allclose(force[moving], u[moving], rtol=0, atol=1e-9)
    gap = u - res.elastic_force
    assert np.all(gap <= model.coulomb + 1e-9) and np.all(gap >= -model.coulomb_negative - 1e-9)
    mirror = ps.quasi_static_response(_swapped(model), -u)
    np.testing.assert_allclose(mirror.position, -res.position, rtol=0, atol=1e-12)
    f = res.final_state.deformation
    assert np.all(f <= model.threshold + 1e-12) and np.all(f >= -model.threshold_negative - 1e-12)
    with pytest.raises(ValueError, match="F_c"):
        ps.quasi_static_response(model, [0.0, -fn])


@pytest.mark.parametrize("fraction", [-0.9, 0.0, 0.6])
def test_sides_of_one_share_move_as_the_mean_model_under_a_shifted_force(fraction):
    """Every negative level ρ times its positive one: from a preload on the branch (or
    saturated), the motion is that of the symmetric model of the mean levels under
    u − (F_c⁺ − F_c⁻)/2 (the play band shifted by (r⁺ − r⁻)/2). The pooled fits rest on it:
    their data fix the difference of the levels, not how it splits (`_model_spec`)."""
    rho, c = 0.8, np.array([1.0, 1.0, 1.0])
    sided = ps.PIFriction(0.5, K, c, coulomb_negative=rho * 0.5, breakaway_negative=rho * c)
    mean = ps.PIFriction(0.5 * (1 + rho) * 0.5, K, 0.5 * (1 + rho) * c)
    fp, fn = sided.coulomb_levels
    shift = 0.5 * (1 - rho) * float(c.sum())  # Σ k_j (r_j⁺ − r_j⁻)/2
    f_mean = fraction * mean.max_elastic_force
    a = _run(sided, initial_state=ps.preloaded_state(sided, f_mean + shift, direction=1.0))
    b = _run(mean, u=U - 0.5 * (fp - fn),
             initial_state=ps.preloaded_state(mean, f_mean, direction=1.0))  # fmt: skip
    assert a.success and a.n_reversals >= 2
    np.testing.assert_allclose(a.position, b.position, rtol=0, atol=1e-12)
    np.testing.assert_allclose(a.velocity, b.velocity, rtol=0, atol=1e-11)
