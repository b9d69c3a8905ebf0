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
