"""Motion with a viscous term σ·ẏ (eq. 17 plus σ·ẏ): exact damped pieces and their events.

References: the closed form of a Coulomb-plus-viscous stop evaluated in 50-digit
decimal arithmetic, textbook solutions of the damped oscillator in its three
regimes, an event-located DOP853 integration written from the physics
(`tests._reference.damped_motion`), the implicit method as the step goes to 0,
and the energy balance with the viscous loss integrated on its own.
"""

from __future__ import annotations

import itertools
import math
import warnings
from decimal import Decimal, getcontext

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import presliding as ps
from presliding.motion import _implicit_density as dens_step
from presliding.motion import free_response, simulate, simulate_batch
from presliding.motion._forcing import as_forcing
from tests._reference import damped_motion


def log_uniform(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(math.log10(lo), math.log10(hi)).map(lambda e: float(10.0**e))


def coulomb_viscous_stop(m: float, sigma: float, fc: float, v0: float) -> tuple[float, float]:
    """Stop time (m/σ)·ln(1 + σ·v0/F_c) and distance (m·F_c/σ²)·(x − ln(1 + x)), x = σ·v0/F_c.

    From m·v̇ = −F_c − σ·v, in 50-digit decimal arithmetic (no cancellation left).
    """
    getcontext().prec = 50
    mm, s, f, v = (Decimal(repr(float(a))) for a in (m, sigma, fc, abs(v0)))
    x = s * v / f
    log = (1 + x).ln()
    return float(mm / s * log), float(mm * f / (s * s) * (x - log))


# ----------------------------------------------------------------------- the Coulomb–viscous stop
@settings(max_examples=80, deadline=None)
@given(
    m=log_uniform(1e-2, 1e2),
    sigma=log_uniform(1e-4, 1e3),
    fc=log_uniform(1e-2, 1e2),
    v0=log_uniform(1e-3, 10.0),
    sign=st.sampled_from([-1.0, 1.0]),
    y0=st.floats(-1.0, 1.0),
)
def test_coulomb_viscous_stop_matches_the_closed_form(m, sigma, fc, v0, sign, y0):
    t_stop, dist = coulomb_viscous_stop(m, sigma, fc, v0)
    model = ps.PIFriction(fc, viscous=sigma)
    res = simulate(model, m, initial_velocity=sign * v0, initial_position=y0,
                   t_eval=[0.0, 1.5 * t_stop])  # fmt: skip
    assert res.success and res.n_events == 1 and res.n_reversals == 0
    assert res.stop_time == pytest.approx(t_stop, rel=1e-12)
    assert res.rest_position - y0 == pytest.approx(sign * dist, rel=1e-12, abs=1e-15 * abs(y0))
    # the velocity on the way: v(t) = (v0 + F_c/σ)·e^{−σt/m} − F_c/σ
    res = simulate(model, m, initial_velocity=sign * v0, t_eval=np.linspace(0, t_stop, 7)[:-1])
    v_ref = v0 + (v0 + fc / sigma) * np.expm1(-sigma * res.time / m)
    np.testing.assert_allclose(res.velocity, sign * v_ref, rtol=0, atol=1e-13 * v0)


def test_coulomb_viscous_stop_tends_to_the_coulomb_stop_as_sigma_vanishes():
    m, fc, v0 = 2.0, 3.0, 1.5
    plain = simulate(ps.PIFriction(fc), m, initial_velocity=v0, t_end=2.0)
    for sigma in (1e-6, 1e-9, 1e-12):
        damped = simulate(ps.PIFriction(fc, viscous=sigma), m, initial_velocity=v0, t_end=2.0)
        # dt_stop/dσ = −m·v0²/(2·F_c²) at σ = 0; the distance changes by −m·v0³/(3·F_c²)·σ
        assert damped.stop_time - plain.stop_time == pytest.approx(
            -m * v0**2 / (2 * fc**2) * sigma, rel=1e-3, abs=2e-15
        )
        assert damped.rest_position - plain.rest_position == pytest.approx(
            -m * v0**3 / (3 * fc**2) * sigma, rel=1e-3, abs=2e-15
        )


def test_forced_coulomb_viscous_sliding_reaches_the_terminal_velocity():
    m, fc, sigma, u = 1.0, 0.5, 2.0, 3.0  # v∞ = (u − F_c)/σ = 1.25
    res = simulate(ps.PIFriction(fc, viscous=sigma), m, applied_force=u, t_end=20.0)
    t = res.time
    v_ref = (u - fc) / sigma * -np.expm1(-sigma * t / m)
    np.testing.assert_allclose(res.velocity, v_ref, rtol=1e-12, atol=1e-15)
    assert res.energy.max_relative_residual < 1e-12
    # at v∞ the viscous term takes σ·v∞/u = 5/6 of the power u·v∞
    assert res.energy.viscous[-1] / res.energy.work[-1] == pytest.approx(5 / 6, rel=0.02)


# ----------------------------------------------------------------------- damped oscillations
def _textbook(regime, m, k, sigma, u, v0, t):
    """y(t) of m·ÿ + σ·ẏ + k·y = u, y(0) = 0, ẏ(0) = v0 (the textbook solutions)."""
    gam, w0 = sigma / (2 * m), math.sqrt(k / m)
    a = -u / k
    if regime == "under":
        wd = math.sqrt(w0**2 - gam**2)
        return u / k + np.exp(-gam * t) * (
            a * np.cos(wd * t) + (v0 + gam * a) / wd * np.sin(wd * t)
        )
    if regime == "critical":
        return u / k + np.exp(-gam * t) * (a + (v0 + gam * a) * t)
    wh = math.sqrt(gam**2 - w0**2)
    l1, l2 = -gam + wh, -gam - wh
    c2 = (v0 - l1 * a) / (l2 - l1)
    return u / k + (a - c2) * np.exp(l1 * t) + c2 * np.exp(l2 * t)


@pytest.mark.parametrize("regime", ["under", "critical", "over"])
@pytest.mark.parametrize("u", [0.0, 0.7])
def test_presliding_piece_is_the_textbook_damped_oscillator(regime, u):
    # c1 = 0 and a threshold never reached: m·ÿ + σ·ẏ + k·y = u, y(0) = 0, ẏ(0) = v0
    m, k, v0 = 1.0, 4.0, 0.3
    sigma = {"under": 0.4, "critical": 4.0, "over": 9.0}[regime]  # critical: σ² = 4·m·k exactly
    model = ps.PIFriction(0.0, [k], threshold=[1e3], viscous=sigma)
    t = np.linspace(0.0, 12.0, 1201)
    res = simulate(model, m, applied_force=u, initial_velocity=v0, t_eval=t)
    ref = _textbook(regime, m, k, sigma, u, v0, t)
    w0 = math.sqrt(k / m)
    assert np.max(np.abs(res.position - ref)) <= 1e-12 * max(abs(u / k), v0 / w0)
    assert res.energy.max_relative_residual < 1e-12
    # every velocity zero of the reference is a reversal (c1 = 0: the mass never sticks)
    fine = np.linspace(0.0, 12.0, 200_001)
    v_ref = np.gradient(_textbook(regime, m, k, sigma, u, v0, fine), fine)
    assert res.n_reversals == np.count_nonzero(np.diff(np.sign(v_ref[1:-1])))


# ----------------------------------------------------------------------- against an ODE reference
CASES = {
    # free stop from steady sliding, light damping: several reversals in presliding
    "light": dict(c1=0.05, sigma=0.05, v0=0.8, u=0.0, sat=True),
    # strong damping: over-damped presliding pieces
    "heavy": dict(c1=0.3, sigma=25.0, v0=0.8, u=0.0, sat=True),
    # forced start from rest: the elements reach their thresholds one after the other
    "forced": dict(c1=0.3, sigma=1.5, v0=0.0, u=5.0, sat=False),
    # near critical damping of the stiffest bank
    "critical": dict(c1=0.1, sigma=2.0 * math.sqrt(469.0 * 1.5), v0=-0.6, u=0.2, sat=True),
}
K = np.array([400.0, 60.0, 9.0])
R = np.array([0.002, 0.01, 0.05])


@pytest.mark.parametrize("case", sorted(CASES))
def test_event_method_matches_an_event_located_ode_reference(case):
    p = CASES[case]
    m = 1.5
    model = ps.PIFriction(p["c1"], K, threshold=R, viscous=p["sigma"])
    t = np.linspace(0.0, 4.0, 801)
    res = simulate(model, m, applied_force=p["u"], initial_velocity=p["v0"],
                   initial_state="saturated" if p["sat"] else "relaxed", t_eval=t)  # fmt: skip
    f0 = np.sign(p["v0"]) * R if p["sat"] else np.zeros(3)
    y_ref, v_ref, stop = damped_motion(m, p["c1"], p["sigma"], K, R, f0, p["v0"], p["u"], t)
    scale_y = np.max(np.abs(y_ref))
    scale_v = np.max(np.abs(v_ref))
    assert np.max(np.abs(res.position - y_ref)) <= 1e-9 * scale_y
    assert np.max(np.abs(res.velocity - v_ref)) <= 1e-8 * scale_v
    if stop is None:
        assert res.stop_time is None
    else:
        assert res.stop_time == pytest.approx(stop, rel=1e-9)
    assert res.energy.max_relative_residual <= 1e-12


@pytest.mark.parametrize("sigma", [0.05, 2.0, 40.0])
def test_implicit_converges_to_the_event_method_at_first_order(sigma):
    model = ps.PIFriction(0.3, K, threshold=R, viscous=sigma)
    u = (np.array([0.0, 0.4, 0.9]), np.array([2.5, -0.2, 0.0]))
    kw = dict(applied_force=u, initial_velocity=0.3, t_eval=np.linspace(0.0, 2.0, 201))
    exact = simulate(model, 1.0, method="event", **kw)
    steps = np.array([4e-4, 2e-4, 1e-4, 5e-5])
    errs = np.array([np.max(np.abs(simulate(model, 1.0, method="implicit", step=h, **kw).position
                                   - exact.position)) for h in steps])  # fmt: skip
    order = np.polyfit(np.log(steps), np.log(errs), 1)[0]
    assert order == pytest.approx(1.0, abs=0.1), (order, errs)
    assert errs[-1] < 1e-4
    # the implicit energy balance misses only the numerical dissipation ½·m·(v' − v)², O(h)
    res = [simulate(model, 1.0, method="implicit", step=h, **kw).energy for h in steps[[0, -1]]]
    assert all(np.all(e.residual <= 1e-12 * e.initial + 1e-15) for e in res)
    assert abs(res[1].residual[-1]) < 0.25 * abs(res[0].residual[-1])
    np.testing.assert_allclose(res[1].viscous[-1], exact.energy.viscous[-1], rtol=1e-2)


def test_sigma_to_zero_is_continuous_and_sigma_zero_is_the_undamped_method():
    base = ps.PIFriction(0.3, K, threshold=R)
    kw = dict(initial_velocity=0.8, initial_state="saturated", t_eval=np.linspace(0, 2, 401))
    plain = simulate(base, 1.5, **kw)
    zero = simulate(ps.PIFriction(0.3, K, threshold=R, viscous=0.0), 1.5, **kw)
    for name in ("position", "velocity", "acceleration", "friction_force"):
        np.testing.assert_array_equal(getattr(zero, name), getattr(plain, name))
    assert zero.stop_time == plain.stop_time and np.all(zero.energy.viscous == 0.0)
    diffs = []
    for sigma in (1e-7, 1e-8):
        damped = simulate(ps.PIFriction(0.3, K, threshold=R, viscous=sigma), 1.5, **kw)
        assert damped.n_reversals == plain.n_reversals
        diffs.append(np.max(np.abs(damped.position - plain.position)))
    assert 0 < diffs[1] < 0.2 * diffs[0]  # O(σ) as σ → 0
    assert diffs[0] < 1e-6


# ----------------------------------------------------------------------- stiction, energy, chunks
@pytest.mark.parametrize("method", ["event", "implicit"])
def test_stiction_is_exact_with_a_viscous_term(method):
    model = ps.PIFriction(0.5, K, threshold=R, viscous=3.0)
    deformation = [0.001, -0.004, 0.0]
    state = ps.PIState(0.0, -np.array(deformation), 1.0)
    fel = 0.0
    for kj, fj in zip(K, deformation, strict=True):  # summed in the kernel's order
        fel += float(kj) * fj
    # |u − F_el| <= c1 throughout, equality included: the mass stays put, bit for bit
    u = (np.array([0.0, 0.3, 0.6]), np.array([fel + 0.5, fel - 0.5, fel + 0.2]))
    assert abs(u[1][0] - fel) == 0.5 and abs(u[1][1] - fel) == 0.5
    res = simulate(model, 1.0, applied_force=u, initial_state=state, t_end=1.0, method=method,
                   hold="zoh")  # fmt: skip
    assert np.all(res.position == 0.0) and np.all(res.velocity == 0.0)
    assert res.stop_time == 0.0 and res.n_reversals == 0
    np.testing.assert_array_equal(res.final_state.play, state.play)
    assert np.all(res.energy.viscous == 0.0)


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 10_000), n=st.integers(0, 5), sat=st.booleans(),
       sigma=log_uniform(1e-3, 1e2))  # fmt: skip
def test_energy_balance_with_viscous_loss_is_exact(seed, n, sat, sigma):
    rng = np.random.default_rng(seed)
    model = ps.PIFriction(rng.uniform(0.05, 1.0), rng.uniform(10, 1000, n),
                          rng.uniform(0.1, 1.0, n), viscous=sigma)  # fmt: skip
    v0 = rng.uniform(0.2, 3.0) * rng.choice([-1, 1])
    res = simulate(model, rng.uniform(0.5, 2.0), initial_velocity=v0,
                   initial_state="saturated" if sat else "relaxed", t_end=50.0)  # fmt: skip
    e = res.energy
    assert np.max(np.abs(e.residual)) <= 1e-12 * e.initial
    assert np.all(np.diff(e.viscous) >= -1e-15 * e.initial) and e.viscous[-1] > 0
    np.testing.assert_allclose(e.total_dissipated, e.dissipated + e.viscous)


def test_forced_energy_balance_with_viscous_loss():
    model = ps.PIFriction(0.2, [300.0, 40.0, 5.0], [0.3, 0.2, 0.4], viscous=0.8)
    u = (np.linspace(0, 2, 9), np.array([2.0, -1.5, 0.3, 3.0, -3.0, 0.0, 1.0, -0.5, 0.2]))
    res = simulate(model, 1.0, applied_force=u, initial_velocity=0.4, t_end=3.0)
    assert res.energy.max_relative_residual < 1e-12
    assert res.n_reversals >= 3
    # the friction force includes σ·ẏ: u − m·ÿ = c1·s + σ·ẏ + F_el while moving
    moving = res.velocity != 0
    expected = (0.2 * np.sign(res.velocity) + 0.8 * res.velocity + res.elastic_force)[moving]
    np.testing.assert_allclose(res.friction_force[moving], expected, rtol=1e-9, atol=1e-12)
    assert "viscous" in res.report()


def test_continued_run_equals_the_whole_run():
    model = ps.PIFriction(0.3, K, threshold=R, viscous=1.2)
    kw = dict(applied_force=0.9 * model.coulomb_level)
    whole = simulate(model, 1.0, initial_velocity=-0.5, t_eval=np.linspace(0, 1.0, 11), **kw)
    first = simulate(model, 1.0, initial_velocity=-0.5, t_eval=np.linspace(0, 0.4, 5), **kw)
    second = simulate(model, 1.0, initial_velocity=first.final_velocity, t_start=0.4,
                      initial_position=first.final_state.last_input,
                      initial_state=first.final_state, t_eval=np.linspace(0.4, 1.0, 7),
                      **kw)  # fmt: skip
    joined = np.concatenate([first.position, second.position[1:]])
    np.testing.assert_allclose(joined, whole.position, rtol=1e-12, atol=1e-15)
    assert second.final_velocity == pytest.approx(whole.final_velocity, rel=1e-10, abs=1e-14)


def test_batch_and_free_response_take_viscous_per_member():
    models = [ps.PIFriction(0.3, K, threshold=R, viscous=s) for s in (0.0, 0.5, 30.0)]
    t = np.arange(1500) * 2e-3
    batch = simulate_batch(models, 1.5, 0.8, initial_state="saturated", t_eval=t)
    params = simulate_batch(coulomb=0.3, stiffness=K, threshold=R, viscous=[0.0, 0.5, 30.0],
                            mass=1.5, initial_velocity=0.8, initial_state="saturated",
                            t_eval=t)  # fmt: skip
    for i, model in enumerate(models):
        one = simulate(model, 1.5, initial_velocity=0.8, initial_state="saturated", t_eval=t)
        np.testing.assert_array_equal(batch.position[i], one.position)
        np.testing.assert_array_equal(params.position[i], one.position)
        assert batch.stop_time[i] == (np.inf if one.stop_time is None else one.stop_time)
        free = free_response(1.5, 0.3, K, R, 0.8, 2e-3, 1500, viscous=model.viscous)
        np.testing.assert_array_equal(free.position, one.position)
        np.testing.assert_array_equal(free.velocity, one.velocity)
        assert free.stop_time == one.stop_time
    assert not np.array_equal(batch.position[0], batch.position[1])


def test_density_stepper_with_viscous_equals_the_finite_element_stepper():
    model = ps.PIFriction(0.3, stiffness=K, threshold=R, viscous=2.5)
    times = np.linspace(0.0, 3.0, 301)
    ref = simulate(model, 1.5, initial_velocity=0.8, initial_state="saturated", t_eval=times,
                   method="implicit", step=1e-3)  # fmt: skip
    state = ps.MemoryState.saturated(0.0, 1.0, float(R.max()))
    forcing = as_forcing(0.0, "zoh", 0.0)
    out = dens_step.run(ps.Discrete(K, R), 0.3, 1.5, state, 0.8, 1.0, forcing, times, 0.0,
                        3.0, 3000, 2.5)  # fmt: skip
    np.testing.assert_allclose(out["position"], ref.position, rtol=0, atol=1e-12)
    np.testing.assert_allclose(out["viscous"], ref.energy.viscous, rtol=1e-10, atol=1e-15)
    # and a continuous density: the viscous loss is counted, the energy never grows
    dens = ps.PIFriction(0.2, density=ps.Uniform(2.0, 1.0), viscous=2.5)
    res = simulate(dens, 1.0, initial_velocity=0.8, initial_state="saturated", t_end=3.0)
    assert res.energy.viscous[-1] > 0
    assert np.all(res.energy.residual <= 1e-12 * res.energy.initial)


def test_overdamped_return_creeps_to_the_stick_band_without_stopping():
    # σ² > 4·m·Σk: after the first stop the mass returns towards |F_el| = c1 only as t → ∞
    model = ps.PIFriction(0.3, K, threshold=R, viscous=200.0)
    res = simulate(model, 1.5, initial_velocity=0.8, initial_state="saturated", t_end=10.0)
    assert res.stop_time is None and res.n_reversals == 1
    assert 0 < abs(res.final_velocity) < 1e-6
    assert abs(abs(res.elastic_force[-1]) - 0.3) < 1e-6


@pytest.mark.parametrize(
    ("value", "exc", "match"),
    [
        (-1.0, ValueError, "`viscous` must be nonnegative; got -1.0"),
        (float("nan"), ValueError, "`viscous` must be finite"),
        (float("inf"), ValueError, "`viscous` must be finite"),
        ("1.0", TypeError, "`viscous` must be a real number"),
        (True, TypeError, "`viscous` must be a real number"),
        ([1.0], TypeError, "`viscous` must be a real number"),
    ],
)
def test_bad_viscous_is_rejected_everywhere(value, exc, match):
    with pytest.raises(exc, match=match):
        ps.PIFriction(0.3, K, threshold=R, viscous=value)
    with pytest.raises(exc, match=match):
        free_response(1.0, 0.3, K, R, 0.5, 1e-3, 10, viscous=value)


def test_bad_batch_viscous_is_rejected():
    with pytest.raises(ValueError, match=r"`viscous` must be nonnegative; got -2.0 at index 1"):
        simulate_batch(coulomb=0.3, stiffness=K, threshold=R, viscous=[1.0, -2.0], t_end=1.0)
    with pytest.raises(ValueError, match="`viscous`, `initial_velocity` must have length 1"):
        simulate_batch(coulomb=0.3, stiffness=K, threshold=R, viscous=[1.0, 2.0],
                       initial_velocity=[1.0, 2.0, 3.0], t_end=1.0)  # fmt: skip
    with pytest.raises(TypeError, match="got `models` and `viscous`"):
        simulate_batch(ps.PIFriction(0.3, K, threshold=R), viscous=1.0, t_end=1.0)


# ----------------------------------------------------------------------- the viscous loss
def _quad_square(v0, a0, gam, w0sq, h):
    """∫_0^h v² by adaptive quadrature of the closed-form velocity (an independent route)."""
    from scipy.integrate import IntegrationWarning, quad

    from presliding.motion import _damped

    def v2(t):
        return _damped.state(v0, a0, gam, w0sq, t)[1] ** 2

    points = np.linspace(0.0, h, 65)
    with warnings.catch_warnings():  # quad at its rounding limit says so; the sum is fine
        warnings.simplefilter("ignore", IntegrationWarning)
        return sum(quad(v2, a, b, epsabs=0.0, epsrel=2e-14, limit=200)[0]
               for a, b in itertools.pairwise(points))  # fmt: skip


@pytest.mark.parametrize(
    "w0sq_over_gam2",
    [0.0, 1e-12, 1e-6, 0.25, 1.0 - 1e-9, 1.0, 1.0 + 1e-9, 1.0 + 1e-3, 4.0, 1e4],
    ids=lambda x: f"w0^2/g^2={x:g}",
)
@pytest.mark.parametrize("gam_h", [1e-5, 0.3, 4.0, 60.0])
def test_viscous_loss_closed_form_matches_quadrature(w0sq_over_gam2, gam_h):
    from presliding.motion import _damped

    gam = 0.7
    w0sq = w0sq_over_gam2 * gam * gam
    h = gam_h / gam
    for v0, a0 in ((1.3, -0.4), (0.8, -2.0 * gam * 0.8), (0.2, 1.5)):
        got = _damped.square_integral(v0, a0, gam, w0sq, h)
        ref = _quad_square(v0, a0, gam, w0sq, h)
        assert got == pytest.approx(ref, rel=5e-13, abs=1e-300)
    # intervals add up: restarting at an inner time gives the same total
    whole = _damped.square_integral(1.3, -0.4, gam, w0sq, h)
    split = _damped.velocity_square_integral(1.3, -0.4, gam, w0sq, 0.0, 0.4 * h)
    split += _damped.velocity_square_integral(1.3, -0.4, gam, w0sq, 0.4 * h, h)
    assert split == pytest.approx(whole, rel=1e-12)


def test_viscous_loss_is_an_independent_check_of_the_closed_forms():
    # the energy balance closes to 1e-12 only because the loss integrates the true velocity:
    # a loss 1e-9 off would show in the residual
    model = ps.PIFriction(coulomb=0.05, stiffness=[300.0, 80.0], breakaway=[0.4, 0.3], viscous=0.9)
    res = simulate(model, 1.2, initial_velocity=0.9, initial_state="saturated", t_end=30.0)
    e = res.energy
    assert np.max(np.abs(e.residual)) <= 1e-12 * e.initial
    assert e.viscous[-1] > 1e-3 * e.initial
    shifted = e.residual + 1e-9 * e.viscous
    assert np.max(np.abs(shifted)) > 1e-12 * e.initial


@settings(max_examples=40, deadline=None)
@given(
    coulomb=st.floats(0.0, 1.0),
    stiffness=st.lists(st.floats(10.0, 2e3), min_size=1, max_size=4),
    breakaway=st.floats(0.05, 1.0),
    viscous=st.floats(0.05, 5.0),
    forces=st.lists(st.floats(-3.0, 3.0), min_size=1, max_size=6),
    v0=st.floats(-1.0, 1.0),
    split=st.integers(1, 59),
)
# split on the change of u at t = 0.9 (t[36]): moving, without and with a Coulomb element,
# and from rest (the mass sticks under 0.2 and slides under 5.0 from t = 0.9 on)
@example(coulomb=0.0, stiffness=[10.0], breakaway=0.5, viscous=1.0, forces=[1.0, 0.0], v0=0.0,
         split=36)  # fmt: skip
@example(coulomb=0.3, stiffness=[10.0, 50.0], breakaway=0.5, viscous=1.0,
         forces=[0.2, -2.0, 5.0], v0=0.0, split=36)  # fmt: skip
@example(coulomb=0.3, stiffness=[10.0, 50.0], breakaway=0.5, viscous=1.0, forces=[0.2, 5.0],
         v0=0.0, split=36)  # fmt: skip
def test_an_event_run_with_viscous_continued_from_its_final_state_is_bit_identical(
    coulomb, stiffness, breakaway, viscous, forces, v0, split
):
    """Split anywhere (in a damped piece, at rest, mid-interval of u): the same bits."""
    model = ps.PIFriction(coulomb, stiffness, [breakaway] * len(stiffness), viscous=viscous)
    u = (np.linspace(0.0, 0.9, len(forces)), np.array(forces))
    t = np.linspace(0.0, 1.5, 61)
    kw = dict(applied_force=u, method="event")
    whole = simulate(model, 1.3, initial_velocity=v0, t_eval=t, **kw)
    first = simulate(model, 1.3, initial_velocity=v0, t_eval=t[: split + 1], **kw)
    second = simulate(model, 1.3, initial_velocity=first.final_velocity, t_start=t[split],
                      initial_position=first.final_state.last_input,
                      initial_state=first.final_state, t_eval=t[split:], **kw)  # fmt: skip
    for name in ("position", "velocity", "friction_force", "applied_force", "acceleration"):
        joined = np.concatenate([getattr(first, name), getattr(second, name)[1:]])
        np.testing.assert_array_equal(joined, getattr(whole, name), err_msg=name)
    assert second.final_velocity == whole.final_velocity
    np.testing.assert_array_equal(second.final_state.play, whole.final_state.play)


@pytest.mark.parametrize("viscous", [0.0, 1.0])
def test_a_run_ending_on_a_change_of_u_samples_the_force_after_it(viscous):
    """u is continuous from the right: the last sample at a change of u has the new u."""
    model = ps.PIFriction(0.3, [10.0, 50.0], [0.5, 0.5], viscous=viscous)
    u = (np.array([0.0, 0.9]), np.array([0.2, 5.0]))  # sticks under 0.2, slides under 5.0
    t = np.linspace(0.0, 1.5, 61)
    kw = dict(applied_force=u, method="event")
    whole = simulate(model, 1.3, t_eval=t, **kw)
    first = simulate(model, 1.3, t_eval=t[:37], **kw)
    assert first.applied_force[-1] == whole.applied_force[36] == 5.0
    assert first.acceleration[-1] == whole.acceleration[36] > 0.0
    assert first.friction_force[-1] == whole.friction_force[36]
    # at rest at t = 0.9, since t = 0: the stop time is kept
    assert first.final_velocity == 0.0 and first.stop_time == 0.0
