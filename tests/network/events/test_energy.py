"""Energy per contact along exact network motions: the balance closes to rounding."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import PIFriction
from presliding.network import chain_structure, modal_structure, simulate_network

PI = PIFriction(0.5, [1e4, 2e3, 500.0, 100.0], [0.2, 0.3, 0.1, 0.1])


@pytest.mark.parametrize(("viscous", "damping"), [(0.0, 0.0), (2.0, 0.0), (0.0, 1.5), (3.0, 0.7)])
def test_balance_closes_to_1e_11_of_the_initial_energy(viscous, damping):
    model = PIFriction(0.5, PI.stiffness, PI.breakaway, viscous=viscous)
    s = chain_structure(4, [1.0, 0.5, 2.0, 1.0], 800.0, model, damping=damping,
                        forcing=([0.0, 0.4], [[0, 0, 0, 4.0], [0, -2.0, 0, 0]]))  # fmt: skip
    res = simulate_network(s, 1.5, None, [0.4, -0.2, 0.3, 0.6])
    en = res.energy
    assert res.success and res.n_events > 20
    assert np.max(np.abs(en.residual)) <= 1e-11 * en.initial
    # dissipation never decreases, per contact and in total; nothing is created
    for arr in (en.coulomb, en.hysteretic, en.viscous):
        assert np.all(np.diff(arr, axis=0) >= -1e-15)
    assert np.all(np.diff(en.damping) >= -1e-15)
    assert np.any(en.hysteretic[-1] > 0.0) and np.all(en.coulomb[-1] > 0.0)
    if viscous:
        assert np.all(en.viscous[-1] > 0.0)
    if damping:
        assert en.damping[-1] > 0.0


def test_free_decay_dissipates_the_initial_energy():
    """Free decay to rest: all stored energy (but what the elements keep) is dissipated."""
    s = modal_structure([3.0, 11.0], [[1.0, 0.6], [0.4, -1.0]], PIFriction(0.05, [40.0], [0.02]),
                        damping_ratios=0.02)  # fmt: skip
    res = simulate_network(s, 60.0, [0.3, -0.1], [0.0, 0.5])
    en = res.energy
    assert res.success and np.all(np.isfinite(res.stop_times))
    assert res.velocity[-1].tolist() == [0.0, 0.0]
    stored = en.kinetic[-1] + en.potential[-1] + en.elastic[-1]
    assert abs(stored + en.dissipated[-1] - en.initial) <= 1e-11 * en.initial
    assert en.work[-1] == 0.0


def _random_structure(rng):
    from presliding.network import NetworkStructure

    n, n_c = int(rng.integers(1, 5)), int(rng.integers(1, 5))
    a = rng.normal(size=(n, n))
    b = rng.normal(size=(n, n))
    w = rng.normal(size=(n, n_c))
    if n_c > 1 and rng.uniform() < 0.3:  # a redundant pair
        w[:, 1] = w[:, 0] * rng.choice([1.0, -2.0])
    models = [PIFriction(rng.uniform(0.1, 1.0)) if rng.uniform() < 0.4 else
              PIFriction(rng.uniform(0.1, 1.0), rng.uniform(10, 1000, 3), rng.uniform(0.05, 0.5, 3),
                         viscous=rng.choice([0.0, 0.5])) for _ in range(n_c)]  # fmt: skip
    return NetworkStructure(a @ a.T + n * np.eye(n), b @ b.T * rng.uniform(0, 100), w, models,
                            damping=np.eye(n) * rng.choice([0.0, 0.3]),
                            forcing=([0.0, 0.5], rng.normal(size=(2, n))))  # fmt: skip


@pytest.mark.parametrize("seed", range(8))
def test_random_structures_balance_energy_and_hold_within_the_friction_bounds(seed):
    rng = np.random.default_rng(seed)
    s = _random_structure(rng)
    res = simulate_network(s, 1.0, rng.normal(size=s.n_coordinates) * 0.1,
                           rng.normal(size=s.n_coordinates))  # fmt: skip
    assert res.success
    assert res.energy.max_relative_residual <= 1e-11
    stuck = res.contact_mode == 0.0
    coulomb = np.abs(res.contact_force - res.elastic_force)
    assert np.all(coulomb[stuck] <= (s.coulomb * (1 + 1e-9) + 1e-12)[np.nonzero(stuck)[1]])
    sliding = ~stuck
    np.testing.assert_allclose(
        (res.contact_force - res.elastic_force - s.viscous * res.contact_velocity)[sliding],
        (res.contact_mode * s.coulomb)[sliding],
        rtol=0,
        atol=1e-12,
    )
