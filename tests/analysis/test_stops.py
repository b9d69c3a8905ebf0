"""Stop analysis (eqs. 12–16): closed forms, reversal counts, energy balance, statuses."""

import math

import numpy as np
import pytest
from scipy.special import lambertw

from presliding import (
    Exponential,
    GeneralPIOperator,
    MemoryState,
    PIFriction,
    Uniform,
    dissipated_energy,
    elastic_energy,
    phi,
    stops_at_turning_point,
    turning_point,
    turning_points,
)


def _uniform_ye(a, big_r, c1):
    # eq. 15 with V(ρ) = a·R·ρ²/2 − a·ρ³/6: a quadratic in y after dividing by y
    return 3 * big_r - 6 * math.sqrt(big_r**2 / 12 + c1 / (3 * a))


def _exponential_ye(b, gamma):
    # eq. 15 ⇔ exp(−x) = 1 − β·x, x = y/(2b), β = (1 + c1/F_m)/2: a Lambert-W root
    beta = (1 + gamma) / 2
    z = -beta * lambertw(-math.exp(-1 / beta) / beta, 0).real
    return 2 * b * (1 - z) / beta


@pytest.mark.parametrize("ratio", [0.0, 0.05, 0.3, 0.6, 0.95])
def test_turning_point_closed_forms(ratio):
    a, big_r = 2.0, 1.0
    fm = a * big_r**2 / 2
    ye = turning_point(PIFriction(ratio * fm, density=Uniform(a, big_r)))
    assert ye == pytest.approx(_uniform_ye(a, big_r, ratio * fm), rel=1e-10)
    a, b = 3.0, 0.5
    ye = turning_point(PIFriction(ratio * a * b * b, density=Exponential(a, b)))
    assert ye == pytest.approx(_exponential_ye(b, ratio), rel=1e-10)


def test_phi_eq14():
    model = PIFriction(0.1, density=Uniform(2.0, 1.0))
    assert phi(model, 0.0) == pytest.approx(-1.0)
    assert phi(model, 2.5) == pytest.approx(1.0)
    y = np.linspace(0.0, 2.0, 11)
    # eq. 14 directly: ∫_0^{y/2} r a dr + ∫_{y/2}^R (y − r) a dr
    direct = a_int = 2.0 * ((y / 2) ** 2 / 2 + y * (1 - y / 2) - (1 - (y / 2) ** 2) / 2)
    np.testing.assert_allclose(phi(model, y), direct, rtol=1e-13, atol=1e-15)
    del a_int
    with pytest.raises(ValueError, match=r"^`displacement` must be nonnegative; got -1\.0\.$"):
        phi(model, -1.0)


@pytest.mark.parametrize("bad", ["0.5", "abc", True, None, [0.2, "x"], 1 + 2j])
def test_phi_rejects_non_real_displacement(bad):
    model = PIFriction(0.1, density=Uniform(2.0, 1.0))
    with pytest.raises(TypeError, match=r"^`displacement` must be a real number or array .*; got "):
        phi(model, bad)


def test_phi_rejects_non_finite_or_negative_entries():
    model = PIFriction(0.1, [1.0, 2.0], [0.5, 1.0])
    with pytest.raises(ValueError, match=r"^`displacement` must be finite; got nan at index 1\.$"):
        phi(model, [0.1, np.nan])
    with pytest.raises(ValueError, match=r"^`displacement` must be finite; got inf\.$"):
        phi(model, np.inf)
    with pytest.raises(
        ValueError, match=r"^`displacement` must be nonnegative; got -0\.5 at index 2"
    ):
        phi(model, [0.0, 1.0, -0.5])
    assert phi(model, np.array([0, 3])).tolist() == [-1.5, 1.5]  # integers are real input


@pytest.mark.parametrize(
    ("c", "c1"), [(3.0, 1.0), (10.0, 1.0), (10.0, 0.7), (1.0, 2.0), (5.0, 1.0)]
)
def test_one_element_number_of_reversals(c, c1):
    """One element k, c from saturation: the force amplitude at turning point n is
    c − 2(n−1)·c1 (the element never slides again), and the mass sticks at the
    first one <= c1, so the number of reversals is max(0, ceil((c − c1)/(2·c1)))."""
    k = 4.0
    res = turning_points(PIFriction(c1, [k], [c]), 2.0, 3.0, "saturated")
    assert res.status == "stopped"
    assert res.n_reversals == max(0, math.ceil((c - c1) / (2 * c1)))
    amp = np.abs(res.elastic_forces)
    np.testing.assert_allclose(amp, np.abs(c - 2 * c1 * np.arange(len(amp))), rtol=1e-13)
    # first turning point: K0 = (c1 + c)·d1
    assert res.positions[0] == pytest.approx(0.5 * 2.0 * 9.0 / (c1 + c), rel=1e-14)


MODELS = {
    "uniform": lambda c1: PIFriction(c1, density=Uniform(2.0, 1.0)),
    "exponential": lambda c1: PIFriction(c1, density=Exponential(3.0, 0.5, 2.0)),
    "finite": lambda c1: PIFriction(c1, [50.0, 10.0, 4.0], [0.3, 0.3, 0.4]),
}


@pytest.mark.parametrize("name", list(MODELS))
def test_turning_points_agree_with_eqs_15_16_over_a_sweep(name):
    fm = MODELS[name](0.0).max_elastic_force
    seen = set()
    for ratio in np.linspace(0.02, 1.2, 25):
        model = MODELS[name](ratio * fm)
        res = turning_points(model, 1.0, -4.0, "saturated")  # the paper: negative momentum
        assert res.status == "stopped"
        if ratio >= 1.0:
            assert res.n_reversals == 0 and stops_at_turning_point(model)
            continue
        ye = turning_point(model)
        assert res.positions[1] - res.positions[0] == pytest.approx(ye, rel=1e-10)
        one = stops_at_turning_point(model)
        assert (res.n_reversals == 1) == one
        assert res.n_reversals >= 1
        seen.add(one)
    assert seen == {True, False}


@pytest.mark.parametrize("name", list(MODELS))
@pytest.mark.parametrize("start", ["relaxed", "saturated"])
def test_energy_balance_at_rest(name, start):
    """½ m v0² + E_el(start) = E_el(rest) + D(path through the turning points)."""
    model = MODELS[name](0.15 * MODELS[name](0.0).max_elastic_force)
    m, v0 = 1.5, 0.9
    res = turning_points(model, m, v0, start, initial_position=0.2)
    s0 = model.relaxed_state(0.2) if start == "relaxed" else model.saturated_state(0.2, 1.0)
    path = np.concatenate([[0.2], res.positions])
    dissipated = dissipated_energy(model, path, s0)[-1]
    lhs = 0.5 * m * v0**2 + elastic_energy(model, s0)
    rhs = elastic_energy(model, res.final_state) + dissipated
    assert rhs == pytest.approx(lhs, rel=1e-12)
    assert res.rest_position == res.positions[-1]


def test_element_walk_and_level_walk_agree_for_finite_elements():
    model = PIFriction(0.01, [50.0, 10.0, 4.0], [0.01, 0.05, 0.2])
    exact = turning_points(model, 1.0, 2.0, "relaxed")
    walked = turning_points(model, 1.0, 2.0, MemoryState.relaxed(0.0))
    assert exact.n_reversals == walked.n_reversals >= 3
    np.testing.assert_allclose(walked.positions, exact.positions, rtol=1e-10, atol=1e-12)
    # from a memory with history (finite elements: PIState and MemoryState of the same path)
    path = np.array([0.0, 0.3, -0.12, 0.05, -0.02])
    _, pi_state = model.force(path)
    _, mem_state = GeneralPIOperator(model.density).apply(path)
    a = turning_points(model, 1.0, -0.2, pi_state)
    b = turning_points(model, 1.0, -0.2, mem_state)
    assert a.n_reversals == b.n_reversals >= 2
    np.testing.assert_allclose(b.positions, a.positions, rtol=1e-10, atol=1e-12)


def test_agrees_with_the_event_simulation():
    from presliding import simulate

    for c1 in (0.05, 0.2, 0.6):
        model = PIFriction(c1, [50.0, 10.0, 4.0], [0.01, 0.05, 0.2])
        res = turning_points(model, 2.0, 1.5, "saturated")
        sim = simulate(model, 2.0, initial_velocity=1.5, initial_state="saturated", t_end=30.0)
        assert sim.n_reversals == res.n_reversals
        assert sim.rest_position == pytest.approx(res.rest_position, rel=1e-9, abs=1e-12)


def test_statuses_and_limits():
    # c1 > F_m: no reversal
    res = turning_points(PIFriction(2.0, density=Uniform(2.0, 1.0)), 1.0, 1.0, "saturated")
    assert res.n_reversals == 0 and res.status == "stopped"
    # c1 = 0, one element: an undamped oscillation inside presliding
    res = turning_points(PIFriction(0.0, [4.0], [3.0]), 1.0, 3.0, "saturated")
    assert res.status == "oscillating" and res.rest_position is None
    assert abs(res.positions[-1] - res.positions[-2]) == pytest.approx(1.5)
    # c1 = 0 with a continuous density: never stops, capped
    res = turning_points(PIFriction(0.0, density=Exponential(2.0, 1.0)), 1.0, 3.0, max_reversals=30)
    assert res.status == "never_stops" and res.n_reversals == 30 and "never stops" in res.message
    swings = np.abs(np.diff(res.positions))
    assert np.all(np.diff(swings) < 0)  # vanishing amplitude
    # c1 > 0 but the cap reached
    res = turning_points(PIFriction(1e-4, density=Uniform(2.0, 1.0)), 1.0, 3.0, max_reversals=5)
    assert res.status == "max_reversals" and len(res.positions) == 5
    assert "reversals" in res.report()
    # at rest: sticks (equality sticks) or starts to move against the force
    sat = PIFriction(1.0, [4.0], [1.0])
    res = turning_points(sat, 1.0, 0.0, sat.saturated_state(0.0, 1.0))
    assert res.status == "stopped" and res.n_reversals == 0 and res.rest_position == 0.0
    sat = PIFriction(0.5, [4.0], [1.0])
    res = turning_points(sat, 1.0, 0.0, sat.saturated_state(0.0, 1.0))
    assert res.positions[0] == pytest.approx(-0.25)  # (c − c1)·2/k back, then sticks
    with pytest.raises(
        ValueError,
        match=r"^`model\.coulomb` must be below F_m .*positive root.*; got 2\.0 >= 1\.0\.$",
    ):
        turning_point(PIFriction(2.0, density=Uniform(2.0, 1.0)))
    with pytest.raises(ValueError, match="nonzero"):
        turning_points(sat, 1.0, 0.0, "saturated")
    with pytest.raises(ValueError, match="mass"):
        turning_points(sat, 0.0, 1.0)
    with pytest.raises(ValueError, match="initial_state"):
        turning_points(sat, 1.0, 1.0, "virgin")


# ----------------------------------------------------------------------- the viscous term
@pytest.mark.parametrize("name", ["turning_points", "turning_point", "stops_at_turning_point"])
@pytest.mark.parametrize("discrete", [True, False])
def test_stop_analysis_with_a_viscous_term_points_to_simulate(name, discrete):
    from presliding import PIFriction, Uniform, analysis

    if discrete:
        model = PIFriction(0.2, [100.0, 10.0], [1.0, 1.0], viscous=0.5)
    else:
        model = PIFriction(0.2, density=Uniform(2.0, 1.0), viscous=0.5)
    func = getattr(analysis, name)
    args = (model, 1.0, 0.5, "saturated") if name == "turning_points" else (model,)
    with pytest.raises(ValueError, match=r"`model.viscous` = 0.5.*presliding.simulate"):
        func(*args)
    # Φ (eq. 14) is the elastic force alone: it does not depend on σ
    plain = PIFriction(0.2, [100.0, 10.0], [1.0, 1.0])
    if discrete:
        assert analysis.phi(model, 0.01) == analysis.phi(plain, 0.01)
