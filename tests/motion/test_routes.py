"""Every route gives the same motion, bit for bit where promised (issue: routes must agree).

Reversals are sign changes of the trajectory's velocity (a start from rest is
never one), a mass that never moves keeps its memory, the implicit motion does
not depend on the output grid, a rest reached at t_end is a stop, and an event
run continued from its final state is the whole run.
"""

from __future__ import annotations

import numpy as np
import pytest

import presliding as ps
from presliding import analysis
from presliding.hysteresis import _general_pi as gk
from presliding.motion import free_response, simulate, simulate_batch


def same_memory(a: ps.MemoryState, b: ps.MemoryState) -> bool:
    return (a.last_input, a.base, a.direction) == (b.last_input, b.base, b.direction) and (
        np.array_equal(a.turning, b.turning))  # fmt: skip


MODEL = ps.PIFriction(coulomb=0.2, stiffness=[100.0, 50.0], breakaway=[1.0, 0.5])
DENSITY = ps.PIFriction(0.1, density=ps.Uniform(2.0, 1.0))


# ----------------------------------------------------------------------- reversals from rest
@pytest.mark.parametrize("v0", [0.0, -1e-12])
def test_a_break_away_from_rest_is_not_a_reversal_in_any_route(v0):
    # memory saturated at +r, at rest: the elastic force F_m > c1 pulls the mass back
    state = ps.PIState.saturated(0.0, MODEL.threshold, 1)
    tp = analysis.turning_points(MODEL, 1.0, v0, state)
    event = simulate(MODEL, 1.0, initial_velocity=v0, initial_state=state, t_end=5.0)
    implicit = simulate(MODEL, 1.0, initial_velocity=v0, initial_state=state, t_end=5.0,
                        method="implicit", step=1e-5)  # fmt: skip
    assert tp.n_reversals == event.n_reversals == implicit.n_reversals == 3
    assert event.reversal_times[0] > 0.2  # the first one is the first turning point, not t = 0
    assert event.rest_position == tp.rest_position
    np.testing.assert_allclose(event.reversal_positions, tp.positions[:-1], rtol=1e-12)


def test_the_count_is_continuous_at_zero_initial_velocity():
    state = ps.PIState.saturated(0.0, MODEL.threshold, 1)
    counts = [simulate(MODEL, 1.0, initial_velocity=v0, initial_state=state, t_end=5.0).n_reversals
              for v0 in (-1e-9, -1e-12, 0.0)]  # fmt: skip
    assert counts == [3, 3, 3]
    # moving the other way first is one more reversal, at once
    ahead = simulate(MODEL, 1.0, initial_velocity=1e-12, initial_state=state, t_end=5.0)
    assert ahead.n_reversals == 4 and ahead.reversal_times[0] < 1e-9


@pytest.mark.parametrize("v0", [0.0, -1e-12])
def test_density_routes_count_reversals_alike(v0):
    state = ps.MemoryState.saturated(0.0, 1.0, 1.0)
    tp = analysis.turning_points(DENSITY, 1.0, v0, state)
    res = simulate(DENSITY, 1.0, initial_velocity=v0, initial_state=state, t_end=60.0, step=1e-4)
    assert tp.n_reversals == res.n_reversals == 3
    assert res.reversal_times[0] > 0.5
    np.testing.assert_allclose(res.reversal_positions, tp.positions[:-1], rtol=1e-3)


def test_saturated_string_at_rest_under_a_small_force_counts_alike_in_every_route():
    u = 0.1  # 0 < u < F_c: saturated in the direction of u, the elements pull back
    kw = dict(applied_force=u, initial_state="saturated", t_end=5.0)
    event = simulate(MODEL, 1.0, **kw)
    implicit = simulate(MODEL, 1.0, method="implicit", step=1e-5, **kw)
    batch = simulate_batch(MODEL, 1.0, [0.0, 0.0], **kw)
    free = free_response(1.0, MODEL.coulomb, MODEL.stiffness, MODEL.threshold, 0.0, 1e-3, 5001,
                         applied_force=u)  # fmt: skip
    state = simulate(MODEL, 1.0, applied_force=u, t_end=5.0,
                     initial_state=ps.PIState.saturated(0.0, MODEL.threshold, 1))  # fmt: skip
    assert event.n_reversals == implicit.n_reversals == state.n_reversals == 2
    assert list(batch.n_reversals) == [2, 2] and free.n_reversals == 2
    assert event.reversal_times[0] > 0.0
    np.testing.assert_array_equal(event.position, state.position)


# ----------------------------------------------------------------------- a stuck memory stays
@pytest.mark.parametrize("method", ["event", "implicit"])
def test_a_stuck_mass_keeps_its_memory_bit_for_bit(method):
    y0 = 0.37
    r = MODEL.threshold
    play = y0 - r * (1.0 - 10 * np.finfo(float).eps)  # within rounding of saturation
    state = ps.PIState(y0, play, 1.0)
    f_el = float(MODEL.stiffness @ state.deformation)
    res = simulate(MODEL, 1.0, applied_force=f_el + 0.1, initial_position=y0,
                   initial_state=state, t_end=1.0, method=method)  # fmt: skip
    assert np.all(res.position == y0) and res.stop_time == 0.0
    np.testing.assert_array_equal(res.final_state.play, play)
    assert res.final_state.last_input == y0 and res.final_state.direction == 1.0


def test_a_stuck_density_mass_keeps_its_memory():
    state = ps.MemoryState.saturated(0.2, 1.0, 1.0)
    res = simulate(DENSITY, 1.0, applied_force=0.95, initial_position=0.2, initial_state=state,
                   t_end=1.0)  # fmt: skip
    assert np.all(res.position == 0.2) and res.stop_time == 0.0
    assert same_memory(res.final_state, state)


# ----------------------------------------------------------------------- output grids
@pytest.mark.parametrize("model", [MODEL, DENSITY], ids=["elements", "density"])
def test_the_output_grid_does_not_change_the_implicit_motion(model):
    kw = dict(applied_force=lambda t: 1.4 * np.sin(3.0 * t), t_end=4.0, step=1e-3)
    t = np.linspace(0.0, 4.0, 1001)
    runs = [simulate(model, 1.0, t_eval=t[::every], **kw) for every in (100, 10, 1)]
    runs.append(simulate(model, 1.0, t_eval=np.sort(np.random.default_rng(1).uniform(0, 4, 77)),
                         **kw))  # fmt: skip
    ends = {(r.final_state.last_input, r.final_velocity, r.stop_time, r.n_reversals) for r in runs}
    assert len(ends) == 1
    np.testing.assert_array_equal(runs[0].position, runs[2].position[::100])
    np.testing.assert_array_equal(runs[1].velocity, runs[2].velocity[::10])
    # samples between grid points lie on the step's straight line
    fine = simulate(model, 1.0, t_eval=np.linspace(0.0, 4.0, 4001), **kw)
    odd = runs[3]
    np.testing.assert_allclose(odd.position, np.interp(odd.time, fine.time, fine.position),
                               rtol=0, atol=1e-12)  # fmt: skip


def test_samples_between_steps_carry_the_exact_partial_memory():
    kw = dict(applied_force=lambda t: 1.4 * np.sin(3.0 * t), t_end=2.0, step=1e-2)
    grid = np.linspace(0.0, 2.0, 201)
    odd = np.array([0.123, 0.5071, 1.0371, 1.9999])
    res = simulate(MODEL, 1.0, t_eval=np.sort(np.concatenate([grid, odd])), **kw)
    on_grid = simulate(MODEL, 1.0, t_eval=grid, **kw)
    assert res.final_state.last_input == on_grid.final_state.last_input
    # the motion is monotone within a step: the operator along the samples is exact there
    force, _ = MODEL.operator.apply(res.position)
    np.testing.assert_allclose(res.elastic_force, force, rtol=0, atol=1e-13)
    assert np.all(np.diff(res.energy.dissipated) >= 0)  # dissipation never decreases


# ----------------------------------------------------------------------- stop at t_end
def test_a_rest_reached_exactly_at_t_end_is_a_stop():
    coulomb = ps.PIFriction(coulomb=1.0)  # v0 = 1, m = 1: v = 1 − t, rest at t = 1 exactly
    res = simulate(coulomb, 1.0, initial_velocity=1.0, t_end=1.0)
    assert res.stop_time == 1.0 and res.rest_position == 0.5 and res.final_velocity == 0.0
    later = simulate(coulomb, 1.0, initial_velocity=1.0, t_end=2.0)
    assert later.stop_time == 1.0 and later.rest_position == 0.5
    # an element reaching its threshold exactly at t_end is set exactly
    one = ps.PIFriction(coulomb=0.5, stiffness=[1.0], threshold=[0.5])
    full = simulate(one, 1.0, initial_velocity=1.0, t_end=3.0)
    assert full.stop_time is not None
    at = simulate(one, 1.0, initial_velocity=1.0, t_end=full.stop_time)
    assert at.stop_time == full.stop_time and at.rest_position == full.rest_position


# ----------------------------------------------------------------------- continuation
def _split(model, t_split, t_end, **kw):
    t = np.linspace(0.0, t_end, 401)
    whole = simulate(model, 1.0, t_eval=t, **kw)
    first = simulate(model, 1.0, t_eval=t[t <= t_split], t_end=t_split, **kw)
    rest = {k: v for k, v in kw.items() if k not in ("initial_velocity", "initial_state")}
    second = simulate(model, 1.0, t_eval=np.concatenate([[t_split], t[t > t_split]]),
                      t_end=t_end, t_start=t_split,
                      initial_velocity=first.final_velocity, initial_state=first.final_state,
                      initial_position=first.final_state.last_input, **rest)  # fmt: skip
    return t, whole, first, second


@pytest.mark.parametrize(
    "model, kw",
    [
        (MODEL, dict(initial_velocity=1.3, initial_state="saturated")),
        (
            MODEL,
            dict(
                applied_force=(np.array([0.0, 0.7, 1.9]), np.array([0.9, -0.6, 0.25])),
                initial_velocity=-0.4,
            ),
        ),
        (
            ps.PIFriction(coulomb=0.2, stiffness=[100.0, 50.0], breakaway=[1.0, 0.5], viscous=0.7),
            dict(initial_velocity=1.3, initial_state="saturated"),
        ),
    ],
    ids=["free", "forced", "viscous"],
)
@pytest.mark.parametrize("t_split", [0.1, 0.4375, 1.3, 2.95])
def test_an_event_run_continued_from_its_final_state_is_the_whole_run(model, kw, t_split):
    t, whole, first, second = _split(model, t_split, 4.0, **kw)
    n1 = first.time.shape[0]
    np.testing.assert_array_equal(first.position, whole.position[:n1])
    k = whole.time.shape[0] - second.time.shape[0] + 1  # its first sample is at t_split
    np.testing.assert_array_equal(second.position[1:], whole.position[k:])
    np.testing.assert_array_equal(second.velocity[1:], whole.velocity[k:])
    np.testing.assert_array_equal(second.elastic_force[1:], whole.elastic_force[k:])
    assert second.position[0] == first.position[-1] or t_split not in t
    assert second.final_state.last_input == whole.final_state.last_input
    np.testing.assert_array_equal(second.final_state.play, whole.final_state.play)
    assert second.stop_time == whole.stop_time
    times = np.concatenate([first.reversal_times, second.reversal_times])
    np.testing.assert_array_equal(times, whole.reversal_times)
    # the energy of the second part counts from its start and balances
    assert second.energy.max_relative_residual < 1e-12
    assert second.energy.dissipated[0] == 0.0 and second.energy.work[0] == 0.0


def test_a_changed_model_or_state_starts_afresh():
    _, _, first, _ = _split(MODEL, 0.4375, 4.0, initial_velocity=1.3,
                                initial_state="saturated")  # fmt: skip
    other = ps.PIFriction(coulomb=0.25, stiffness=[100.0, 50.0], breakaway=[1.0, 0.5])
    res = simulate(other, 1.0, t_start=0.4375, t_end=4.0, initial_velocity=first.final_velocity,
                   initial_state=first.final_state,
                   initial_position=first.final_state.last_input)  # fmt: skip
    fresh = simulate(other, 1.0, t_start=0.4375, t_end=4.0,
                     initial_velocity=first.final_velocity,
                     initial_position=first.final_state.last_input,
                     initial_state=ps.PIState(first.final_state.last_input,
                                              first.final_state.play,
                                              first.final_state.direction))  # fmt: skip
    np.testing.assert_array_equal(res.position, fresh.position)


# ----------------------------------------------------------------------- the fused density loop
@pytest.mark.parametrize("dens", [ps.Uniform(2.0, 1.0), ps.Exponential(3.0, 0.4)],
                         ids=["uniform", "exponential"])  # fmt: skip
def test_the_density_loop_commits_what_the_operator_gives(dens):
    model = ps.PIFriction(0.1 * dens.max_elastic_force, density=dens)
    amp = 1.5 * model.coulomb_level
    n = 4000
    t = np.linspace(0.0, 8.0, n + 1)
    res = simulate(model, 1.0, applied_force=lambda s: amp * np.sin(2.0 * s), t_eval=t,
                   step=8.0 / n)  # fmt: skip
    assert res.n_reversals >= 3
    # replaying the positions through the operator gives the same forces and memory
    head, stack = model.relaxed_state(0.0).working_memory(dens)
    forces = np.empty(n + 1)
    stack = gk.run(res.position, head, stack, dens._kind, dens._par, dens._tab, forces,
                   np.empty(0))  # fmt: skip
    np.testing.assert_array_equal(forces, res.elastic_force)
    assert same_memory(ps.MemoryState.from_working_memory(head, stack), res.final_state)
    # the energy never grows
    assert np.all(res.energy.residual <= 1e-12 * max(res.energy.initial, 1.0) + 1e-15)


# ----------------------------------------------------------------------- clear errors
def test_overflowing_motions_name_the_argument_passed():
    # a time span beyond 1e12 s is refused before anything runs, whatever the motion
    for kwargs in ({"applied_force": 5.0}, {"initial_velocity": 1.0}):
        with pytest.raises(ValueError, match=r"`t_end` must keep the simulated time span within"):
            simulate(MODEL, 1.0, t_end=1e308, **kwargs)
    with pytest.raises(ValueError, match="`initial_velocity` must give a finite kinetic energy"):
        simulate(MODEL, 1.0, initial_velocity=1e200, t_end=1.0)
    with pytest.raises(ValueError, match="`initial_velocity`"):
        simulate(MODEL, 1.0, initial_velocity=1e200, t_end=1.0, method="implicit")
    with pytest.raises(ValueError, match=r"`step` must give at most 1e\+10 implicit steps"):
        simulate(MODEL, 1.0, applied_force=lambda t: 0 * t, t_end=1e3, step=1e-12)
    with pytest.raises(ValueError, match="`t_end` must keep the simulated time span within"):
        simulate(MODEL, 1.0, t_start=-1e308, t_end=1e308, method="implicit")
    with pytest.raises(ValueError, match="`n_samples` must ask for at most"):
        free_response(1.0, 0.2, [100.0], [0.01], 1.0, 1e-3, 10**12)
    # a free motion over the longest span is fine: it stops
    assert simulate(MODEL, 1.0, initial_velocity=1.0, t_end=1e12).stop_time is not None


@pytest.mark.parametrize("dens", [ps.Uniform(2.0, 1.0), ps.Exponential(3.0, 0.4)],
                         ids=["uniform", "exponential"])  # fmt: skip
def test_the_density_loop_dissipates_what_the_operator_dissipates(dens):
    model = ps.PIFriction(0.1 * dens.max_elastic_force, density=dens)
    amp = 1.5 * model.coulomb_level
    n = 4000
    t = np.linspace(0.0, 8.0, n + 1)
    res = simulate(model, 1.0, applied_force=lambda s: amp * np.sin(2.0 * s), t_eval=t,
                   step=8.0 / n)  # fmt: skip
    head, stack = model.relaxed_state(0.0).working_memory(dens)
    forces, stops = np.empty(n + 1), np.empty(n + 1)
    gk.run(res.position, head, stack, dens._kind, dens._par, dens._tab, forces, stops)
    coulomb = model.coulomb * np.concatenate([[0.0], np.cumsum(np.abs(np.diff(res.position)))])
    scale = res.energy.dissipated[-1]
    np.testing.assert_allclose(res.energy.dissipated, coulomb + stops, rtol=0, atol=1e-12 * scale)
