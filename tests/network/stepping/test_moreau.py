"""simulate_network_moreau: first-order convergence to the exact path, no creep."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import PIFriction
from presliding.network import (
    NetworkStructure,
    chain_structure,
    simulate_network,
    simulate_network_moreau,
)
from tests.network.events.test_energy import _random_structure

PI = PIFriction(0.5, [1e4, 2e3, 500.0, 100.0], [0.2, 0.3, 0.1, 0.1])


def _chain():
    return chain_structure(4, [1.0, 0.5, 2.0, 1.0], 800.0, PI,
                           forcing=([0.0, 0.4], [[0, 0, 0, 4.0], [0, -2.0, 0, 0]]))  # fmt: skip


@pytest.mark.parametrize(
    ("theta", "largest"),
    [(1.0, 2.5e-4), (0.5, 1e-3)],  # θ = 1 (the default) damps: first order from smaller steps
)
def test_first_order_convergence_to_the_exact_path(theta, largest):
    """Mean position error over the run against the exact path: log-log slope ≈ 1."""
    s = _chain()
    v0 = [0.4, -0.2, 0.3, 0.6]
    steps = largest / 2.0 ** np.arange(4)
    errors = []
    for h in steps:
        res = simulate_network_moreau(s, 1.0, h, None, v0, samples=401, theta=theta)
        exact = simulate_network(s, 1.0, None, v0, t_eval=res.time)
        assert res.success and res.method == "moreau"
        errors.append(np.mean(np.abs(res.position - exact.position)))
    slope = np.polyfit(np.log(steps), np.log(errors), 1)[0]
    assert 0.85 <= slope <= 1.15, (slope, errors)


def test_friction_oscillator_rests_near_the_exact_rest():
    s = NetworkStructure(1.0, 1.0, [[1.0]], [PIFriction(1.0)])
    # θ = 1/2: no numerical damping over the 5 undamped cycles (θ = 1 loses enough
    # energy at this step to end 0.07 away, in the next band of rest positions)
    res = simulate_network_moreau(s, 30.0, 1e-3, [12.0], [6.0], theta=0.5)
    assert abs(res.position[-1, 0] - (15.0 - 205**0.5)) < 1e-4
    spacing = res.time[1] - res.time[0]  # stops are read off the samples
    stop = np.arctan2(6.0, 13.0) + 7 * np.pi
    assert res.n_reversals[0] == 7 and abs(res.stop_times[0] - stop) <= spacing
    assert res.velocity[-1, 0] == 0.0


def test_no_creep_below_breakaway_over_a_million_steps():
    s = chain_structure(3, 1.0, 100.0, PIFriction(1.0, [1e3], [0.5]), forcing=[0.3, -0.2, 0.4])
    q0 = np.array([0.001, -0.002, 0.0005])
    res = simulate_network_moreau(s, 1e3, 1e-3, q0, None, samples=11)
    assert res.n_events == 1_000_000
    assert np.all(res.position - q0 == 0.0) and np.all(res.contact_displacement - q0 == 0.0)
    assert np.all(res.contact_mode == 0.0)
    held = np.array([0.3, -0.2, 0.4]) - s.stiffness @ q0  # W·λ = f − K·q0, W = I
    np.testing.assert_allclose(res.contact_force[-1], held, rtol=0, atol=1e-12)


def test_a_stuck_contact_does_not_creep_while_the_structure_vibrates():
    s = NetworkStructure(np.eye(2), [[2.0, -1.0], [-1.0, 1.0]], [[1.0], [0.0]],
                         [PIFriction(5.0)])  # fmt: skip
    res = simulate_network_moreau(s, 100.0, 1e-3, [0.2, 0.0], [0.0, 1.0])
    assert np.all(res.contact_displacement[:, 0] == 0.2)
    assert np.ptp(res.position[:, 1]) > 1.0


def test_energy_is_never_created():
    """The residual is the scheme's numerical dissipation: not positive beyond rounding."""
    res = simulate_network_moreau(_chain(), 1.0, 1e-4, None, [0.4, -0.2, 0.3, 0.6])
    assert np.max(res.energy.residual) <= 1e-12 * res.energy.initial
    assert res.energy.residual[-1] < 0.0


@pytest.mark.parametrize("seed", range(8))
def test_the_default_theta_never_creates_energy_on_random_structures(seed):
    """θ = 1 (the default): no energy created, with redundant pairs, damping, viscous
    contacts and a step change of the force; θ = 1/2 may create some (documented)."""
    rng = np.random.default_rng(seed)
    s = _random_structure(rng)
    q0, v0 = rng.normal(size=s.n_coordinates) * 0.1, rng.normal(size=s.n_coordinates)
    for h in (1e-3, 1e-4):
        res = simulate_network_moreau(s, 1.0, h, q0, v0)
        assert res.success
        assert np.max(res.energy.residual) <= 1e-12 * res.energy.initial


def test_bad_arguments():
    s = NetworkStructure(1.0, 1.0, [[1.0]], [PIFriction(1.0)])
    with pytest.raises(ValueError, match="theta"):
        simulate_network_moreau(s, 1.0, 1e-3, theta=0.2)
    with pytest.raises(ValueError, match="step"):
        simulate_network_moreau(s, 1.0, 0.0)
    with pytest.raises(ValueError, match="step"):
        simulate_network_moreau(s, 1e9, 1e-12)


def _bar_dissipation(n, ea=1.0, tau=1.0, force=0.5, length=1.0):
    """Coulomb dissipation over one steady load cycle ±F of a bar on a Coulomb foundation,
    fixed at x = 0 and pulled at x = L, cut into n masses and sliders (the end node has half
    the tributary length: half the mass and half the friction τ·Δx). Masses tiny against
    the springs at the step: backward Euler steps are the quasi-static response."""
    dx = length / n
    models = [PIFriction(tau * dx)] * (n - 1) + [PIFriction(0.5 * tau * dx)]
    mass = np.full(n, 1e-10)
    mass[-1] *= 0.5
    per = 8  # load samples per quarter cycle, each held 1 s (4 steps)
    values = np.concatenate([np.linspace(0.0, force, per + 1)]
                            + [np.linspace(force, -force, 2 * per + 1)[1:],
                               np.linspace(-force, force, 2 * per + 1)[1:]] * 2)  # fmt: skip
    times = np.arange(values.shape[0], dtype=float)
    f = np.zeros((values.shape[0], n))
    f[:, -1] = values
    s = chain_structure(n, mass, ea / dx, models, forcing=(times, f))
    t_end = times[-1] + 1.0
    res = simulate_network_moreau(s, t_end, 0.25, samples=int(t_end / 0.25) + 1,
                                  max_sweeps=100_000, tolerance=1e-14)  # fmt: skip
    assert res.success
    dissipated = res.energy.coulomb.sum(axis=1)
    # from +F after the first cycle to +F after the second
    i_a, i_b = np.searchsorted(res.time, [times[5 * per] + 0.99, times[9 * per] + 0.99])
    return dissipated[i_b] - dissipated[i_a], 2 * force**3 / (3 * ea * tau)


def test_bar_on_a_coulomb_foundation_dissipates_2f3_over_3_ea_tau_at_second_order():
    """Dissipation per cycle → 2F³/(3·EA·τ) (slip zone F/τ shorter than the bar), the
    error O(N⁻²): halving the spacing divides it by 4."""
    errors = []
    for n in (4, 8, 16):
        w, exact = _bar_dissipation(n)
        errors.append(abs(w - exact) / exact)
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert errors[-1] < 0.01
    np.testing.assert_allclose(ratios, 4.0, rtol=0.02)


def test_a_sparse_chain_steps_like_the_dense_one():
    """Gauss–Seidel on the velocities (sparse, no Ŵ⁻¹) solves the same step as PGS on the
    Delassus matrix: the motions agree to rounding, contacts that stick do not creep."""
    model = PIFriction(0.2, [2e3, 1e3, 500.0], [0.1, 0.1, 0.1])
    force = np.zeros(30)
    force[-1] = 2.0
    v0 = 0.3 * np.sin(np.arange(30))
    dense = chain_structure(30, 0.1, 2e3, model, damping=0.3, forcing=force)
    sparse = chain_structure(30, 0.1, 2e3, model, damping=0.3, forcing=force, sparse=True)
    a = simulate_network_moreau(dense, 0.3, 1e-4, None, v0, samples=31)
    b = simulate_network_moreau(sparse, 0.3, 1e-4, None, v0, samples=31)
    assert a.success and b.success and "Gauss–Seidel on the velocities" in b.message
    scale = np.max(np.abs(a.position))
    assert np.max(np.abs(a.position - b.position)) <= 1e-12 * scale
    assert np.max(np.abs(a.energy.residual - b.energy.residual)) <= 1e-10 * a.energy.initial
    stuck = (b.contact_mode[1:] == 0.0) & (b.contact_mode[:-1] == 0.0)
    assert stuck.any()
    assert np.all(np.diff(b.contact_displacement, axis=0)[stuck] == 0.0)


def test_a_sparse_structure_with_coupling_contacts_runs_the_delassus_path():
    """Contacts between two masses (two entries in a column of W) are not separable: the
    dense Delassus path runs (checked for size), with the same result as dense input."""
    import scipy.sparse

    w = np.array([[1.0, 0.0], [-1.0, 1.0]])
    k = np.array([[2.0, -1.0], [-1.0, 1.0]])
    models = [PIFriction(0.3), PIFriction(0.2)]
    dense = NetworkStructure(np.eye(2), k, w, models, forcing=[0.0, 1.0])
    sparse = NetworkStructure(scipy.sparse.identity(2), scipy.sparse.csr_array(k),
                              scipy.sparse.csr_array(w), models, forcing=[0.0, 1.0])  # fmt: skip
    a = simulate_network_moreau(dense, 2.0, 1e-3, None, [0.5, 0.0], samples=21)
    b = simulate_network_moreau(sparse, 2.0, 1e-3, None, [0.5, 0.0], samples=21)
    assert "PGS" in b.message
    np.testing.assert_array_equal(a.position, b.position)
