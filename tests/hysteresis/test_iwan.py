"""The Iwan family as densities: Segalman, Mindlin–Deresiewicz, the microslip bar."""

import math

import numpy as np
import pytest
from scipy import integrate

from presliding import MicroslipBar, MindlinContact, PIFriction, SegalmanIwan
from presliding.hysteresis.iwan import mindlin_bracket


def _loop_energy(density, a):
    """D(a) = 4·(a·M1(a) − M2(a)): the dissipation of the stops cycled between ±a."""
    return 4.0 * (a * density.M1(a) - density.M2(a))


def test_segalman_parameters_from_the_formulas():
    kt, fs, chi, beta = 2.0, 3.0, -0.1, 0.1
    d = SegalmanIwan(stiffness=kt, slip_force=fs, exponent=chi, mass_ratio=beta)
    den = beta + (chi + 1) / (chi + 2)
    phi = fs * (1 + beta) / (kt * den)
    assert d.max_threshold == pytest.approx(phi, rel=1e-12)
    assert d.height == pytest.approx(fs * (chi + 1) / (phi ** (chi + 2) * den), rel=1e-12)
    assert d.point_mass == pytest.approx(fs * beta / (phi * den), rel=1e-12)
    # the published rounded values
    assert round(d.max_threshold, 6) == pytest.approx(2.876147, abs=1e-6)
    assert round(d.height, 6) == pytest.approx(0.632339, abs=1e-6)
    assert round(d.point_mass, 6) == pytest.approx(0.181818, abs=1e-6)
    # the joint stiffness and the macroslip force come back (eq. 7, F_m)
    assert d.total_stiffness == pytest.approx(kt, rel=1e-12)
    assert d.max_elastic_force == pytest.approx(fs, rel=1e-12)


@pytest.mark.parametrize("chi, beta", [(-0.1, 0.1), (-0.5, 0.0), (-0.9, 2.0), (0.0, 0.3)])
def test_segalman_dissipation_closed_form_and_slope(chi, beta):
    d = SegalmanIwan(2.0, 3.0, chi, beta)
    phi, rr, s = d.max_threshold, d.height, d.point_mass
    a = np.geomspace(1e-6, 0.99, 25) * phi
    closed = 4 * rr * a ** (chi + 3) / ((chi + 2) * (chi + 3))
    np.testing.assert_allclose(d.loop_energy(a), closed, rtol=1e-12)
    np.testing.assert_allclose(_loop_energy(d, a), closed, rtol=1e-12)
    # slope chi + 3 in log-log below phi_max
    slope = np.log(d.loop_energy(2 * a[:10]) / d.loop_energy(a[:10])) / math.log(2.0)
    np.testing.assert_allclose(slope, chi + 3, rtol=1e-12)
    # above phi_max the point mass adds 4 S phi (a - phi)
    big = phi * np.array([1.0, 1.5, 4.0])
    above = 4 * rr * phi ** (chi + 3) / ((chi + 2) * (chi + 3)) + 4 * rr * phi ** (chi + 2) / (
        chi + 2
    ) * (big - phi)
    above = above + 4 * s * phi * (big - phi)
    np.testing.assert_allclose(_loop_energy(d, big), above, rtol=1e-12)
    np.testing.assert_allclose(d.loop_energy(big), above, rtol=1e-12)


def test_segalman_operator_gives_the_masing_loop_and_coulomb_level():
    d = SegalmanIwan(2.0, 3.0, -0.1, 0.1)
    model = PIFriction(0.5, density=d)
    assert model.coulomb_level == pytest.approx(3.5, rel=1e-12)
    a = 0.7 * d.max_threshold
    y = np.concatenate([np.linspace(0, a, 50), np.linspace(a, -a, 101)[1:]])
    f, _ = model.force(y)
    virgin = d.virgin_curve(y[:50])
    np.testing.assert_allclose(f[:50], virgin + 0.5 * (y[:50] > 0), rtol=1e-12, atol=1e-14)
    down = y[50:]
    masing = d.virgin_curve(np.array([a]))[0] - 2 * d.virgin_curve((a - down) / 2)
    np.testing.assert_allclose(f[50:], masing - 0.5, rtol=1e-12, atol=1e-13)


def test_mindlin_virgin_curve_and_stiffness():
    mu_p, d0 = 40.0, 2e-5
    d = MindlinContact(slip_force=mu_p, slip_displacement=d0)
    delta = np.linspace(0.0, d0, 17)
    np.testing.assert_allclose(
        d.virgin_curve(delta), mu_p * (1 - (1 - delta / d0) ** 1.5), rtol=1e-13, atol=1e-13
    )
    assert d.total_stiffness == pytest.approx(1.5 * mu_p / d0, rel=1e-14)
    assert d.max_elastic_force == pytest.approx(mu_p, rel=1e-14)
    # the primitives agree with quadrature of 3μP/(4δ0²)(1 − r/δ0)^(−1/2)
    r = 0.37 * d0
    rho = lambda s: 0.75 * mu_p / d0**2 * (1 - s / d0) ** -0.5  # noqa: E731
    m1 = integrate.quad(lambda s: s * rho(s), 0, r, epsrel=1e-14)[0]
    m2 = integrate.quad(lambda s: s * s * rho(s), 0, r, epsrel=1e-14)[0]
    assert d.M1(r) == pytest.approx(m1, rel=1e-12)
    assert d.M2(r) == pytest.approx(m2, rel=1e-12)


def test_mindlin_loop_energy_against_the_density():
    mu_p, d0 = 40.0, 2e-5
    d = MindlinContact(mu_p, d0)
    q = np.linspace(0.1, 0.99, 90)
    a = d0 * (1 - (1 - q) ** (2 / 3))  # displacement amplitude of the force amplitude q·μP
    numeric = _loop_energy(d, a)
    closed = 4.8 * mu_p * d0 * (1 - (1 - q) ** (5 / 3) - (5 * q / 6) * (1 + (1 - q) ** (2 / 3)))
    np.testing.assert_allclose(d.loop_energy_at_force(q * mu_p), numeric, rtol=1e-12)
    np.testing.assert_allclose(closed, numeric, rtol=1e-11)  # the textbook form, cancellation
    # an independent quadrature of ∫ 4r(a − r) dμ(r) (singular weight at δ0)
    for qi, ai in zip(q[::15], a[::15], strict=True):
        w = integrate.quad(
            lambda s, ai=ai: 4 * s * (ai - s) * 0.75 * mu_p / d0**2 * (1 - s / d0) ** -0.5,
            0,
            ai,
            epsrel=1e-13,
            limit=200,
        )[0]
        assert d.loop_energy_at_force(qi * mu_p) == pytest.approx(w, rel=1e-11)


def test_mindlin_bracket_series_at_small_force():
    q = np.geomspace(1e-6, 1e-2, 20)
    coefficients = [5 / 162, 5 / 243, 7 / 486, 70 / 6561, 325 / 39366, 130 / 19683, 8645 / 1594323]
    series = sum(c * q ** (k + 3) for k, c in enumerate(coefficients))
    np.testing.assert_allclose(mindlin_bracket(q), series, rtol=1e-12)
    assert mindlin_bracket(np.array([0.0]))[0] == 0.0
    assert mindlin_bracket(np.array([1.0]))[0] == pytest.approx(1 / 6, rel=1e-15)


def test_microslip_bar_virgin_curve_and_dissipation():
    ea, tau, length = 2.0e6, 5.0e3, 0.4
    bar = MicroslipBar(axial_stiffness=ea, shear_strength=tau, length=length)
    force = np.linspace(0.0, tau * length, 13)
    u = force**2 / (2 * ea * tau)
    np.testing.assert_allclose(bar.virgin_curve(u), force, rtol=1e-13, atol=1e-9)
    assert bar.max_elastic_force == pytest.approx(tau * length, rel=1e-14)
    assert bar.total_stiffness == math.inf
    # D = 2F³/(3EAτ) for a cycle of force amplitude F (between −F and +F)
    np.testing.assert_allclose(
        bar.loop_energy_at_force(force[1:]), _loop_energy(bar, u[1:]), rtol=1e-12
    )
    # the operator stays finite at a standstill and on a reversal
    model = PIFriction(0.0, density=bar)
    y = np.array([0.0, 0.0, u[5], u[5], -u[3], -u[3], u[2]])
    f, _ = model.force(y)
    assert np.isfinite(f).all()
    assert f[2] == pytest.approx(force[5], rel=1e-13)
    expected = force[5] - 2 * bar.virgin_curve((u[5] + u[3]) / 2)
    assert f[4] == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize(
    "build, match",
    [
        (lambda: SegalmanIwan(-1.0, 3.0, -0.1, 0.1), "stiffness"),
        (lambda: SegalmanIwan(2.0, 0.0, -0.1, 0.1), "slip_force"),
        (lambda: SegalmanIwan(2.0, 3.0, -1.0, 0.1), "exponent"),
        (lambda: SegalmanIwan(2.0, 3.0, -0.1, -0.1), "mass_ratio"),
        (lambda: MindlinContact(1.0, math.nan), "slip_displacement"),
        (lambda: MicroslipBar(1.0, 1.0, 0.0), "length"),
        (lambda: MindlinContact(1.0, 1.0).loop_energy_at_force(1.5), "force_amplitude"),
        (lambda: MicroslipBar(1.0, 1.0, 1.0).loop_energy_at_force(-1.0), "force_amplitude"),
    ],
)
def test_bad_parameters_are_named(build, match):
    with pytest.raises(ValueError, match=match):
        build()


def test_motion_tools_refuse_the_infinitely_stiff_bar():
    import presliding as ps

    model = PIFriction(0.5, density=MicroslipBar(1e6, 1e3, 0.05))
    with pytest.raises(ValueError, match="finite stiffness"):
        ps.simulate(model, 1.0, initial_velocity=0.05, t_end=0.5)
    with pytest.raises(ValueError, match="finite stiffness"):
        ps.turning_points(model, 1.0, 0.05)


def test_an_exponent_that_is_not_a_number_is_named():
    """Not numpy's "could not convert string to float"."""
    with pytest.raises(TypeError, match="`exponent` must be a real number; got 'a'"):
        SegalmanIwan(2.0, 3.0, "a", 0.1)


@pytest.mark.parametrize("slip_force", [3.0, 0.5])
def test_an_exponent_beyond_floating_point_is_refused_on_construction(slip_force):
    """χ = 1e6 puts R and φ_max^(χ+3) beyond 1e±300 (an OverflowError or a division by zero
    before, in the density or later in amplitude_response); χ = 300 still works to the end."""
    with pytest.raises(ValueError, match=r"`exponent` must keep the density .* got 1000000\.0"):
        SegalmanIwan(2.0, slip_force, 1e6, 0.1)
    from presliding import amplitude_response

    res = amplitude_response(SegalmanIwan(2.0, 3.0, 300.0, 0.1), [0.5, 1.4, 50.0])
    assert np.all(np.isfinite(res.dissipation)) and np.all(np.diff(res.dissipation) > 0)
