"""simulate_network: closed-form checks, the single mass, redundancy, stiction, chunks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from presliding import PIFriction, simulate
from presliding.network import (
    NetworkStructure,
    chain_structure,
    multi_contact_structure,
    simulate_network,
)


def test_friction_oscillator_turning_points_and_rest_in_closed_form():
    """m = k = 1, c1 = 1, x0 = 12, v0 = 6: half cycles about ∓1 (the Siconos example).

    Amplitude about the first centre −1 is A = √(13² + 6²) = √205; each half cycle loses
    2·c1/k = 2, so the k-th turning point is (−1)^(k+1)·(√205 − (2k − 1)) at
    t_k = atan2(6, 13) + (k − 1)π; the 8th, 15 − √205, is inside the stick band |x| <= 1.
    """
    s = NetworkStructure(1.0, 1.0, [[1.0]], [PIFriction(1.0)])
    res = simulate_network(s, 30.0, [12.0], [6.0])
    a = math.sqrt(205.0)
    k = np.arange(1, 8)
    turning = (-1.0) ** (k + 1) * (a - (2 * k - 1))
    times = math.atan2(6.0, 13.0) + (k - 1) * math.pi
    assert res.success and res.n_reversals[0] == 7
    np.testing.assert_allclose(res.reversal_displacements[0], turning, rtol=0, atol=1e-12)
    np.testing.assert_allclose(res.reversal_times[0], times, rtol=0, atol=1e-12)
    assert abs(res.stop_times[0] - (math.atan2(6.0, 13.0) + 7 * math.pi)) <= 1e-12
    assert abs(res.position[-1, 0] - (15.0 - a)) <= 1e-12
    assert res.contact_velocity[-1, 0] == 0.0 and res.contact_mode[-1, 0] == 0.0
    assert np.all(res.stick_intervals[0] == [[res.stop_times[0], 30.0]])


def test_mirror_symmetry():
    s = chain_structure(2, 1.0, 50.0, PIFriction(0.4, [300.0], [0.2]), forcing=[0.0, 1.0])
    m = s.with_forcing([0.0, -1.0])
    a = simulate_network(s, 2.0, [0.01, 0.0], [0.0, -0.3])
    b = simulate_network(m, 2.0, [-0.01, 0.0], [0.0, 0.3])
    np.testing.assert_allclose(a.position, -b.position, rtol=0, atol=1e-14)
    np.testing.assert_array_equal(a.n_reversals, b.n_reversals)


@pytest.mark.parametrize("viscous", [0.0, 5.0])
def test_one_contact_on_one_mass_is_the_single_mass_simulate(viscous):
    """The same motion as `presliding.simulate` to 1e-14 (relative to each array's scale;
    not bit for bit: the network path solves the piece as a 1-DOF modal problem)."""
    model = PIFriction(0.3, [2e4, 5e3, 1.5e3], [0.2, 0.2, 0.3], viscous=viscous)
    u = (np.array([0.0, 0.05, 0.1, 0.15]), np.array([1.0, -1.2, 0.6, 0.0]))
    te = np.linspace(0.0, 0.2, 2001)
    ref = simulate(model, 1.0, applied_force=u, initial_velocity=0.05, t_end=0.2, t_eval=te)
    s = NetworkStructure(1.0, 0.0, [[1.0]], [model], forcing=(u[0], u[1].reshape(-1, 1)))
    res = simulate_network(s, 0.2, [0.0], [0.05], t_eval=te)
    assert res.success and res.n_events == ref.n_events
    for mine, theirs in ((res.position[:, 0], ref.position),
                         (res.velocity[:, 0], ref.velocity),
                         (res.contact_force[:, 0], ref.friction_force),
                         (res.elastic_force[:, 0], ref.elastic_force)):  # fmt: skip
        assert np.max(np.abs(mine - theirs)) <= 1e-14 * np.max(np.abs(theirs))
    np.testing.assert_allclose(res.reversal_times[0], ref.reversal_times, rtol=0, atol=1e-14)
    dissipated = res.energy.coulomb[:, 0] + res.energy.hysteretic[:, 0]
    assert np.max(np.abs(dissipated - ref.energy.dissipated)) <= 1e-14 * ref.energy.dissipated[-1]


def test_redundant_contacts_give_the_unique_motion_and_flag_the_forces():
    """Two Coulomb contacts with the same w act as one with c1 = c1a + c1b."""
    k = [[2.0, -1.0], [-1.0, 1.0]]
    two = NetworkStructure(np.diag([1.0, 2.0]), k, [[1.0, 1.0], [0.0, 0.0]],
                           [PIFriction(0.5), PIFriction(0.7)], forcing=[0.0, 1.5])  # fmt: skip
    one = NetworkStructure(np.diag([1.0, 2.0]), k, [[1.0], [0.0]], [PIFriction(1.2)],
                           forcing=[0.0, 1.5])  # fmt: skip
    a = simulate_network(two, 20.0, [1.0, 3.0], [0.5, 0.0])
    b = simulate_network(one, 20.0, [1.0, 3.0], [0.5, 0.0])
    assert a.success and not a.forces_unique and "not unique" in a.message
    assert b.forces_unique and "not unique" not in b.message
    np.testing.assert_allclose(a.position, b.position, rtol=0, atol=1e-12)
    np.testing.assert_allclose(a.contact_force.sum(axis=1), b.contact_force[:, 0], atol=1e-12)
    stuck = a.contact_mode[:, 0] == 0.0
    assert stuck.any()
    c1 = np.array([0.5, 0.7])
    assert np.all(np.abs(a.contact_force[stuck] - a.elastic_force[stuck]) <= c1 * (1 + 1e-12))


def test_stiction_is_exact_over_long_times():
    """Every contact held below break-away: nothing moves, 0.0 exactly, to t = 1e6 s."""
    s = chain_structure(3, 1.0, 100.0, PIFriction(1.0, [1e3], [0.5]), forcing=[0.3, -0.2, 0.4])
    q0 = np.array([0.001, -0.002, 0.0005])
    res = simulate_network(s, 1e6, q0, None, t_eval=np.linspace(0.0, 1e6, 11))
    assert res.success and res.n_events == 0  # one piece, no event
    assert np.all(res.position - q0 == 0.0) and np.all(res.velocity == 0.0)
    assert np.all(res.stop_times == 0.0)


def test_a_stuck_contact_holds_exactly_while_the_rest_vibrates():
    """Mass 0 on a contact, mass 1 free on a spring: the contact displacement stays exact."""
    s = NetworkStructure(np.eye(2), [[2.0, -1.0], [-1.0, 1.0]], [[1.0], [0.0]],
                         [PIFriction(5.0)])  # fmt: skip
    res = simulate_network(s, 1e4, [0.2, 0.0], [0.0, 1.0], t_eval=np.linspace(0, 1e4, 5001))
    assert res.success
    assert np.all(res.contact_displacement[:, 0] == 0.2)
    assert np.all(res.contact_mode == 0.0)
    assert np.ptp(res.position[:, 1]) > 1.0  # the free mass moves


def test_chunked_runs_equal_the_whole_run():
    model = PIFriction(0.5, [1e4, 2e3], [0.2, 0.3], viscous=2.0)
    force = ([0.0, 0.3, 0.6], [[0, 0, 3.0], [0, 1.0, -2.0], [0, 0, 0]])
    s = chain_structure(3, 1.0, 1e3, model, damping=1.0, forcing=force)
    t = np.linspace(0.0, 1.0, 401)
    whole = simulate_network(s, 1.0, None, [0.2, -0.1, 0.3], t_eval=t)
    first = simulate_network(s, 0.45, None, [0.2, -0.1, 0.3], t_eval=t[t <= 0.45])
    second = simulate_network(s, 1.0, initial_state=first.final_state, t_eval=t[t >= 0.45])
    both = np.vstack([first.position, second.position[1:]])
    assert first.final_state.time == 0.45
    np.testing.assert_allclose(both, whole.position, rtol=0, atol=1e-12)
    reversals = first.n_reversals + second.n_reversals
    np.testing.assert_array_equal(reversals, whole.n_reversals)


def test_mass_on_several_contacts_sticks_by_its_total_friction():
    s = multi_contact_structure(1.0, 0.0, [PIFriction(0.4), PIFriction(0.6)], forcing=0.99)
    held = simulate_network(s, 10.0, [0.0], [0.0])
    assert held.success and np.all(held.position == 0.0)
    moved = simulate_network(s.with_forcing(1.01), 1.0, [0.0], [0.0])
    np.testing.assert_allclose(moved.position[-1, 0], 0.5 * 0.01, rtol=1e-12)


def test_bad_arguments():
    s = NetworkStructure(1.0, 1.0, [[1.0]], [PIFriction(1.0)])
    with pytest.raises(ValueError, match="t_end"):
        simulate_network(s, 0.0)
    with pytest.raises(ValueError, match=r"initial_position` must have shape \(1,\)"):
        simulate_network(s, 1.0, [1.0, 2.0])
    with pytest.raises(ValueError, match="initial_state"):
        simulate_network(s, 1.0, initial_state="saturated")
    with pytest.raises(ValueError, match="t_eval"):
        simulate_network(s, 1.0, t_eval=[0.0, 2.0])
    with pytest.raises(TypeError, match="structure"):
        simulate_network("s", 1.0)


def test_event_limit_is_reported():
    s = NetworkStructure(1.0, 1.0, [[1.0]], [PIFriction(1.0)])
    res = simulate_network(s, 30.0, [12.0], [6.0], max_events=3)
    assert not res.success and res.status == "event_limit" and "max_events=3" in res.message
    assert res.time.shape[0] < 1001


def _square_wave(n_cycles, period, amplitude):
    times = 0.5 * period * np.arange(2 * n_cycles)
    values = amplitude * np.where(np.arange(2 * n_cycles) % 2 == 0, 1.0, -1.0)
    return times, values


@pytest.mark.parametrize("alpha", [1.0, -2.0])
def test_redundant_pair_from_rest_moves_as_one_combined_contact_over_a_long_run(alpha):
    """Two contacts on the same relative displacement (w_b = α·w_a), started at rest and
    driven through 40 stick–slip cycles: the motion is that of one contact with
    c1 = c1a + |α|·c1b and the elements of b scaled to g_a (k·α², r/|α|)."""
    a_model = PIFriction(0.5, [300.0, 80.0], threshold=[0.002, 0.01])
    b_model = PIFriction(0.7, [200.0], threshold=[0.004])
    combined = PIFriction(0.5 + abs(alpha) * 0.7, [300.0, 80.0, 200.0 * alpha**2],
                          threshold=[0.002, 0.01, 0.004 / abs(alpha)])  # fmt: skip
    times, values = _square_wave(40, 5.0, 2.5)
    force = (times, np.column_stack([np.zeros_like(values), values]))
    m, k = np.diag([1.0, 2.0]), [[200.0, -100.0], [-100.0, 100.0]]
    two = NetworkStructure(m, k, [[1.0, alpha], [0.0, 0.0]], [a_model, b_model], forcing=force)
    one = NetworkStructure(m, k, [[1.0], [0.0]], [combined], forcing=force)
    te = np.linspace(0.0, 200.0, 4001)
    a = simulate_network(two, 200.0, t_eval=te)
    b = simulate_network(one, 200.0, t_eval=te)
    assert a.success and b.success and a.n_events == b.n_events > 100
    assert not a.forces_unique and "not unique" in a.message and b.forces_unique
    np.testing.assert_allclose(a.position, b.position, rtol=0, atol=1e-12)
    np.testing.assert_allclose(a.velocity, b.velocity, rtol=0, atol=1e-12)
    total = a.contact_force[:, 0] + alpha * a.contact_force[:, 1]
    scale = np.max(np.abs(b.contact_force))  # the forces to 1e-12 of their largest value
    np.testing.assert_allclose(total, b.contact_force[:, 0], rtol=0, atol=1e-12 * scale)
    np.testing.assert_array_equal(a.contact_mode[:, 0], b.contact_mode[:, 0])
    np.testing.assert_array_equal(a.contact_mode[:, 1], np.sign(alpha) * b.contact_mode[:, 0])
    # each contact's Coulomb force within its own c1, exactly c1 while it slides
    coulomb = np.abs(a.contact_force - a.elastic_force)
    assert np.all(coulomb <= np.array([0.5, 0.7]) * (1 + 1e-12))
    sliding = a.contact_mode != 0.0
    bounds = np.broadcast_to([0.5, 0.7], coulomb.shape)
    np.testing.assert_allclose(coulomb[sliding], bounds[sliding], rtol=1e-12)
    assert np.sum(a.contact_mode[:, 0] == 0.0) > 100  # it sticks, repeatedly
    assert a.energy.max_relative_residual <= 1e-11


def _pi_chain(damping=0.0, viscous=0.0, n=6, forced=True):
    model = PIFriction(0.2, [2e3, 1e3, 500.0, 200.0], [0.1, 0.1, 0.1, 0.1], viscous=viscous)
    force = np.outer([1.0, -1.0, 1.0, -1.0], np.r_[np.zeros(n - 1), 2.0])
    s = chain_structure(n, 0.1, 2e3, model, damping=damping,
                        forcing=([0.0, 0.1, 0.2, 0.3], force) if forced else 0.0)  # fmt: skip
    return s, 0.3 * np.sin(np.arange(n))


def test_compiled_loop_equals_the_general_loop(monkeypatch):
    """Undamped structures run the compiled loop; the general loop (damped structures)
    gives the same motion, forces and energy to 1e-12."""
    import presliding.network.events.exact as exact_module

    s, v0 = _pi_chain()
    te = np.linspace(0.0, 0.4, 801)
    fast = simulate_network(s, 0.4, None, v0, t_eval=te)
    monkeypatch.setattr(exact_module, "_run_compiled", lambda *args: None)
    slow = simulate_network(s, 0.4, None, v0, t_eval=te)
    assert fast.success and slow.success and fast.n_events == slow.n_events > 100
    for name in ("position", "velocity", "contact_force", "elastic_force", "contact_mode"):
        np.testing.assert_allclose(getattr(fast, name), getattr(slow, name), rtol=0, atol=1e-12)
    for name in ("coulomb", "hysteretic", "kinetic", "work"):
        np.testing.assert_allclose(getattr(fast.energy, name), getattr(slow.energy, name),
                                   rtol=0, atol=1e-12)  # fmt: skip
    for a, b in zip(fast.reversal_times, slow.reversal_times, strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)
    assert fast.energy.max_relative_residual <= 1e-11


@pytest.mark.parametrize(("n", "forced", "damping", "viscous"), [
    (1, True, 0.5, 0.0), (2, False, 0.5, 0.0), (6, True, 0.5, 0.0), (3, True, 0.0, 0.3),
    (10, False, 5.0, 0.3),
])  # fmt: skip
def test_compiled_loop_equals_the_general_loop_damped(monkeypatch, n, forced, damping, viscous):
    """Damped structures (dashpots C, a sliding contact's viscous term σ_v) run the
    compiled loop too (complex modes of the first-order system): the same events, motion,
    forces and energies (the dissipations ∫q̇ᵀCq̇ and σ_v·∫ġ² included) as the general
    loop to 1e-11 of each quantity's range."""
    import presliding.network.events.exact as exact_module

    s, v0 = _pi_chain(damping, viscous, n, forced)
    ran = []
    compiled = exact_module._run_compiled
    monkeypatch.setattr(exact_module, "_run_compiled",
                        lambda *args: ran.append(compiled(*args)) or ran[-1])  # fmt: skip
    te = np.linspace(0.0, 0.4, 401)
    fast = simulate_network(s, 0.4, None, v0, t_eval=te)
    assert ran and ran[0] is not None  # the compiled loop ran to the end
    monkeypatch.setattr(exact_module, "_run_compiled", lambda *args: None)
    slow = simulate_network(s, 0.4, None, v0, t_eval=te)
    assert fast.success and slow.success and fast.n_events == slow.n_events > 10
    assert slow.energy.damping[-1] > 0.0 or not damping
    assert np.all(slow.energy.viscous[-1] > 0.0) or not viscous

    def close(a, b):
        scale = max(float(np.max(np.abs(b))), 1e-300)
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-11 * scale)

    for name in ("position", "velocity", "contact_force", "elastic_force", "contact_mode"):
        close(getattr(fast, name), getattr(slow, name))
    for name in ("coulomb", "hysteretic", "viscous", "damping", "kinetic", "work"):
        close(getattr(fast.energy, name), getattr(slow.energy, name))
    for a, b in zip(fast.reversal_times, slow.reversal_times, strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)
    for key in ("isolated", "resolved", "ends"):
        assert fast.certification[key] == slow.certification[key]
    cert = fast.certification
    assert cert["isolated"] + cert["resolved"] + cert["ends"] == fast.n_events + 1
    assert fast.energy.max_relative_residual <= 1e-11


def test_ill_conditioned_damped_modes_take_the_general_loop(monkeypatch):
    """A critically damped piece (m = k = 1, c = 2: a double eigenvalue −1, one
    eigenvector) has no modal closed form: the compiled loop hands the run to the general
    loop (its matrix exponential), which gives the result."""
    import presliding.network.events.exact as exact_module

    s = NetworkStructure(1.0, 1.0, [[1.0]], [PIFriction(0.5)], damping=2.0)
    ran = []
    compiled = exact_module._run_compiled
    monkeypatch.setattr(exact_module, "_run_compiled",
                        lambda *args: ran.append(compiled(*args)) or ran[-1])  # fmt: skip
    res = simulate_network(s, 5.0, [3.0], [2.0], t_eval=[0.0, 5.0])
    assert ran == [None] and res.success and res.n_events == 1
    # x + 0.5 = (3.5 + 5.5·t)·e^{−t} stops at t1 = 4/11; then x − 0.5 creeps to 0 from x1
    t1 = 4.0 / 11.0
    x1 = 5.5 * math.exp(-t1) - 0.5
    np.testing.assert_allclose(res.reversal_times[0], [t1], rtol=1e-12)
    np.testing.assert_allclose(res.reversal_displacements[0], [x1], rtol=1e-12)
    x5 = 0.5 + (x1 - 0.5) * (1.0 + (5.0 - t1)) * math.exp(-(5.0 - t1))
    np.testing.assert_allclose(res.position[-1, 0], x5, rtol=1e-10)
    assert res.energy.max_relative_residual <= 1e-10


def test_chunked_runs_equal_the_whole_run_in_the_compiled_loop():
    s, v0 = _pi_chain()
    t = np.linspace(0.0, 0.4, 401)
    whole = simulate_network(s, 0.4, None, v0, t_eval=t)
    first = simulate_network(s, 0.17, None, v0, t_eval=t[t <= 0.17])
    second = simulate_network(s, 0.4, initial_state=first.final_state, t_eval=t[t >= 0.17])
    np.testing.assert_allclose(np.vstack([first.position, second.position[1:]]), whole.position,
                               rtol=0, atol=1e-12)  # fmt: skip
    np.testing.assert_array_equal(first.n_reversals + second.n_reversals, whole.n_reversals)


def test_t_eval_is_counted_before_it_is_copied():
    """1e9 samples (a float32 array of 4 GB, or a range) are refused before the copy that
    ran out of memory; `simulate`'s cap of 10,000,000 samples holds here too."""
    import time

    s = chain_structure(2, 1.0, 1.0, PIFriction(1.0))
    start = time.process_time()
    with pytest.raises(ValueError, match="`t_eval` must have at most 10,000,000 samples; got "
                                         "1,000,000,000"):  # fmt: skip
        simulate_network(s, 1.0, t_eval=range(10**9))
    with pytest.raises(ValueError, match="at most 10,000,000"):
        simulate_network(s, 1.0, t_eval=np.broadcast_to(np.float32(0.5), (10**9,)))
    assert time.process_time() - start < 0.5


@pytest.mark.parametrize("damping", [0.0, 0.5])
def test_on_a_cold_cache_the_general_loop_runs_while_a_second_process_compiles(
    monkeypatch, damping
):
    """The first run does not wait a minute for the compiler: the general loop gives the
    same events (and says so), one second process is started, and runs use the compiled
    loop once it is cached (undamped and damped structures alike)."""
    from presliding.network.events import _warm

    s, v0 = _pi_chain(damping)
    te = np.linspace(0.0, 0.4, 201)
    compiled = simulate_network(s, 0.4, None, v0, t_eval=te)
    started = []
    monkeypatch.setattr(_warm, "BACKGROUND", True)
    monkeypatch.setattr(_warm, "_process", {})
    monkeypatch.setattr(_warm, "_kernel", lambda: _kernel_with_index({}))
    monkeypatch.setattr(_warm, "_start", lambda: started.append(1) or _warm._process.update(
        compile=_Running()))  # fmt: skip
    first = simulate_network(s, 0.4, None, v0, t_eval=te)
    second = simulate_network(s, 0.4, None, v0, t_eval=te)
    assert started == [1]  # one second process, not one per run
    assert "a second process is compiling it" in first.message
    assert first.n_events == compiled.n_events
    np.testing.assert_allclose(first.position, compiled.position, rtol=0, atol=1e-11)
    assert second.message == first.message
    monkeypatch.setattr(_warm, "_kernel", lambda: _kernel_with_index({"signature": "entry"}))
    third = simulate_network(s, 0.4, None, v0, t_eval=te)
    assert "second process" not in third.message
    np.testing.assert_array_equal(third.position, compiled.position)


def _kernel_with_index(index):
    """A stand-in for numba's dispatcher: nothing compiled here, `index` in its cache."""
    from types import SimpleNamespace

    cache_file = SimpleNamespace(_load_index=lambda: index)
    return SimpleNamespace(overloads={}, _cache=SimpleNamespace(_cache_file=cache_file))


class _Running:
    @staticmethod
    def poll():
        return None
