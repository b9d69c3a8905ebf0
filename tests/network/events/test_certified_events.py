"""Certified event location: no sign change hides between samples of the closed form."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import presliding.network.events.exact as exact_module
from presliding import PIFriction
from presliding.network import (
    NetworkStructure,
    chain_structure,
    simulate_network,
    simulate_network_moreau,
)

#: The reproducer of a missed event: contact 1's velocity crosses zero twice within one
#: cell of the former grid (min(horizon/32, 1/(2ω_max))) near t = 14.1 s.
FRICTION = [PIFriction(0.3, [6.0], threshold=[0.05]),
            PIFriction(0.2, [3.0, 1.0], threshold=[0.04, 0.2]),
            PIFriction(0.4, [2.0], threshold=[0.1])]  # fmt: skip
CHAIN = chain_structure(3, [1, 1.5, 0.7], [2, 1, 3], FRICTION,
                        forcing=([0, 8, 14], [[0, 0, 0], [0, 0, 1.5], [-1.2, 0, 0]]))  # fmt: skip
Q0, V0 = [0.0, 0.4, -0.5], [2.0, 0.0, -1.0]


def general_loop(fn):
    """Run `fn` with the compiled loop switched off (the general loop runs instead)."""
    compiled = exact_module._run_compiled
    exact_module._run_compiled = lambda *args: None
    try:
        return fn()
    finally:
        exact_module._run_compiled = compiled


def test_the_double_crossing_is_found_whatever_t_end():
    """Contact 1 sticks on [14.0532, 14.1167] whether the run ends at 14.2 s or 22 s (the
    grid of a 22 s run stepped over both zeros of its velocity and kept it sliding in −1
    at +5.2e-4 m/s); the compiled and the general loop agree to 1e-12."""
    long = simulate_network(CHAIN, 22.0, Q0, V0, t_eval=[0.0, 14.1, 22.0])
    short = simulate_network(CHAIN, 14.2, Q0, V0)
    for res in (long, short):
        stick = res.stick_intervals[1]
        hit = stick[(stick[:, 0] > 14.0) & (stick[:, 0] < 14.1)]
        assert hit.shape == (1, 2)
        np.testing.assert_allclose(hit[0], [14.05324069, 14.11665055], atol=1e-8)
    assert long.contact_mode[1, 1] == 0.0 and long.contact_velocity[1, 1] == 0.0
    general = general_loop(lambda: simulate_network(CHAIN, 22.0, Q0, V0, t_eval=[0, 14.1, 22]))
    np.testing.assert_allclose(general.position, long.position, rtol=0, atol=1e-12)
    assert general.n_events == long.n_events


def test_the_double_crossing_agrees_with_moreau_jean_extrapolated():
    """q(22): Moreau–Jean (first order) at h and h/10, Richardson-extrapolated, lands within
    1e-6 of the exact path (the missed event put it 1.6e-4 away)."""
    exact = simulate_network(CHAIN, 22.0, Q0, V0, t_eval=[0.0, 22.0]).position[-1]
    coarse, fine = (simulate_network_moreau(CHAIN, 22.0, h, Q0, V0, samples=2).position[-1]
                    for h in (2e-4, 2e-5))  # fmt: skip
    extrapolated = (10.0 * fine - coarse) / 9.0
    assert np.max(np.abs(fine - exact)) < 1e-4  # first order: about 7.5e-5 at 2e-5 s
    assert np.max(np.abs(extrapolated - exact)) < 1e-6


def test_the_result_says_how_each_event_was_certified():
    res = simulate_network(CHAIN, 22.0, Q0, V0)
    cert = res.certification
    # every piece ends at an isolated root, a resolved trigger, or a change of f / the end
    assert cert["isolated"] + cert["resolved"] + cert["ends"] == res.n_events + 1
    assert cert["ends"] == 3 and cert["cells"] > res.n_events
    assert "certified" in res.report()
    general = general_loop(lambda: simulate_network(CHAIN, 22.0, Q0, V0))
    assert general.certification["isolated"] == cert["isolated"]


def _random_structure(rng: np.random.Generator, damped: bool) -> NetworkStructure:
    n, n_c = int(rng.integers(1, 4)), int(rng.integers(1, 4))
    a = rng.normal(size=(n, n))
    k = rng.normal(size=(n, n))
    models = []
    for _ in range(n_c):
        m = int(rng.integers(0, 3))
        models.append(PIFriction(rng.uniform(0.05, 0.5), rng.uniform(0.5, 8.0, m),
                                 threshold=rng.uniform(0.02, 0.3, m),
                                 viscous=rng.choice([0.0, 0.3]) if damped else 0.0))  # fmt: skip
    times = np.array([0.0, 2.0, 4.0])
    force = rng.normal(scale=1.0, size=(3, n))
    return NetworkStructure(a @ a.T + 0.5 * np.eye(n), k @ k.T + 0.5 * np.eye(n),
                            rng.normal(size=(n, n_c)), models,
                            damping=0.05 * np.eye(n) if damped else None,
                            forcing=(times, force))  # fmt: skip


@settings(max_examples=16, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32 - 1), damped=st.booleans())
def test_every_piece_keeps_its_modes_on_a_fine_grid(seed, damped):
    """After every piece, on 2001 samples of the closed form over 6 s (spacing 3 ms, under
    a hundredth of the fastest period): a sliding contact's velocity never has the sign
    against its mode (beyond 1e-10 of the largest contact velocity), a stuck contact's
    Coulomb force never leaves its band ±c1 (beyond 1e-10 of c1)."""
    rng = np.random.default_rng(seed)
    s = _random_structure(rng, damped)
    q0, v0 = rng.normal(scale=0.3, size=s.n_coordinates), rng.normal(size=s.n_coordinates)
    res = simulate_network(s, 6.0, q0, v0, t_eval=np.linspace(0.0, 6.0, 2001))
    assert res.success
    mode, gd = res.contact_mode, res.contact_velocity
    scale = max(float(np.max(np.abs(gd))), 1e-300)
    sliding = mode != 0.0
    assert np.all(mode[sliding] * gd[sliding] >= -1e-10 * scale)
    tau = np.abs(res.contact_force - res.elastic_force)
    c1 = s.coulomb
    assert np.all(np.where(sliding, 0.0, tau - c1) <= 1e-10 * c1)
    cert = res.certification
    assert cert["isolated"] + cert["resolved"] + cert["ends"] == res.n_events + 1


@pytest.mark.parametrize("start", [0.0, 3.0])
def test_a_grazing_velocity_is_not_an_event_loop(start):
    """A contact released exactly at its band (zero net force) starts at zero velocity
    and zero acceleration: the start is not an event (no run of events of zero length)."""
    s = NetworkStructure(1.0, 1.0, [[1.0]], [PIFriction(1.0)], forcing=1.0)
    res = simulate_network(s, 5.0 + start, [0.0], [0.0], t_start=start)
    assert res.success and res.n_events <= 2
    assert np.all(res.position == 0.0)


def _dip(values_at, horizon: float, j: int) -> tuple[float, float]:
    """(t, h(t)): the lowest point of function j on (0, horizon] (a dense grid, then
    golden-section refinement around its lowest sample)."""
    grid = np.linspace(0.0, horizon, 1201)[1:]
    vals = values_at(grid)[:, j]
    i = int(np.argmin(vals))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, grid.shape[0] - 1)]
    g = 0.5 * (np.sqrt(5.0) - 1.0)
    for _ in range(60):
        a, b = hi - g * (hi - lo), lo + g * (hi - lo)
        if values_at(np.array([a]))[0, j] < values_at(np.array([b]))[0, j]:
            hi = b
        else:
            lo = a
    t = 0.5 * (lo + hi)
    return t, float(values_at(np.array([t]))[0, j])


def _check_first(found, values_at, horizon, t_dip, strict):
    """The event found is at or before the dip below zero, and no function triggers on a
    dense grid before it (beyond rounding)."""
    assert found is not None and found[0] <= t_dip * (1 + 1e-12) + 1e-15
    grid = np.linspace(0.0, found[0], 1001)[1:-1]
    if grid.size:
        vals = values_at(grid)
        scale = float(np.max(np.abs(vals)))
        assert np.all(vals > -1e-9 * scale)


def _piece_state(rng, damped):
    s = _random_structure(rng, damped)
    n = s.n_coordinates
    q = rng.normal(scale=0.3, size=n)
    v = rng.normal(size=n)
    return s, q, v


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32 - 1), depth=st.floats(-1e-3, -1e-12), damped=st.booleans())
def test_a_dip_below_zero_between_any_samples_is_found_compiled(seed, depth, damped):
    """A sliding contact's velocity shifted so that its lowest point on the piece dips
    `depth` (relative to its range, down to 1e-12) below zero: the compiled search stops
    at or before that point (a fixed grid misses dips narrower than its cells); damped
    pieces too (complex modes, bounded per cell by |λ|²·|γ|·e^{Re λ·τ})."""
    from presliding.network.events._exact_run import Network
    from presliding.network.events._kernel_events import find_event
    from presliding.network.events._kernel_piece import (
        P_DAMPED,
        P_DIM,
        P_H0,
        P_NLIN,
        build_piece,
        event_values,
    )

    rng = np.random.default_rng(seed)
    s, q, v = _piece_state(rng, damped)
    net = Network(s)
    n_c = s.n_contacts
    modes = rng.choice([-1.0, 1.0], size=n_c)
    e = np.zeros(net.cts.k.shape[0])
    c = np.ascontiguousarray
    cts = net.cts
    pc, general, _ = build_piece(q, v, modes, e, c(s.force_at(0.0)), c(net.m), c(net.k),
                                 c(net.w), c(net.minv_w), cts.c1, cts.k, cts.r, cts.owner,
                                 c(net.c), cts.sigma, damped)  # fmt: skip
    assume(not general)  # damped modes well conditioned (else the general loop runs it)
    assert pc[P_DAMPED] == damped
    horizon = 6.0
    nf = pc[P_H0].shape[0]
    xi = np.empty(3 * pc[P_DIM])

    def values_at(tau):
        out = np.empty((tau.shape[0], nf))
        for i, t in enumerate(tau):
            event_values(pc, float(t), out[i], xi)
        return out

    j = int(rng.integers(0, n_c))  # a velocity function
    t_dip, low = _dip(values_at, horizon, j)
    span = float(np.ptp(values_at(np.linspace(0.0, horizon, 401))[:, j])) + 1e-300
    pc[P_H0][j] += depth * span - low
    assume(values_at(np.zeros(1))[0, j] > 1e-6 * span)  # a dip inside the piece
    pc[P_H0][: pc[P_NLIN]] += np.where(np.arange(pc[P_NLIN]) == j, 0.0, 1e3)  # the others far
    tau, mask = find_event(pc, horizon, np.zeros(5, np.int64))
    _check_first((tau, mask), values_at, horizon, t_dip, False)


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32 - 1), depth=st.floats(-1e-3, -1e-12))
def test_a_dip_below_zero_between_any_samples_is_found_damped(seed, depth):
    """The same for a damped piece (the general loop: modal exponentials, certified with
    |λ|²·|γ|·e^{Re λ·τ})."""
    from presliding.network.events._events import Certificate, scan
    from presliding.network.events._exact_run import Network, RunState

    rng = np.random.default_rng(seed)
    s, q, v = _piece_state(rng, True)
    net = Network(s)
    n_c = s.n_contacts
    z = np.zeros(n_c)
    st_ = RunState(t=0.0, q=q, v=v, g=q @ net.w, e=np.zeros(net.cts.k.shape[0]),
                   s=rng.choice([-1.0, 1.0], size=n_c), last=z.copy(), coulomb=z.copy(),
                   hysteretic=z.copy(), viscous=z.copy())  # fmt: skip
    pc, info = net.piece(st_, s.force_at(0.0))
    fun = net.event_functions(pc, info, st_)
    horizon = 6.0

    def values_at(tau):
        return fun(tau)[0]

    j = int(rng.integers(0, n_c))
    t_dip, low = _dip(values_at, horizon, j)
    span = float(np.ptp(values_at(np.linspace(0.0, horizon, 401))[:, j])) + 1e-300
    fun.h0[j] += depth * span - low
    assume(values_at(np.zeros(1))[0, j] > 1e-6 * span)  # a dip inside the piece
    fun.h0[: fun.n_lin] += np.where(np.arange(fun.n_lin) == j, 0.0, 1e3)
    found = scan(fun, horizon, pc.omega_max, Certificate())
    _check_first(found, values_at, horizon, t_dip, False)
