"""The PI friction model of eq. 8: levels (eqs. 6, 7, 9), virgin curve, loops, limits."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal

from presliding import PIFriction, PIOperator, PIState
from presliding.signals import FIGURE3_TURNING_POINTS
from tests._reference import drive_springs, virgin_force
from tests.helpers import (
    FIGURE3_FIRST_STIFFNESS,
    PROPERTY,
    figure3_model,
    friction_models,
    paths,
    sample_between,
    turning_points,
)

# ----------------------------------------------------------------------------- levels


def test_levels_of_eqs_6_7_9():
    model = PIFriction(coulomb=0.5, stiffness=[500.0, 10.0, 4.0], breakaway=[1.0, 2.0, 3.0])
    assert model.n_elements == 3
    assert model.max_elastic_force == pytest.approx(6.0, rel=1e-15)  # F_m = Σ c_j
    assert model.coulomb_level == pytest.approx(6.5, rel=1e-15)  # F_c = c1 + Σ c_j (eq. 9)
    assert model.initial_stiffness == pytest.approx(514.0, rel=1e-15)  # Σ k_j (eq. 7)
    assert_allclose(model.threshold, [1 / 500, 2 / 10, 3 / 4], rtol=1e-15)  # r = c/k (eq. 6)
    assert_array_equal(model.operator.threshold, model.threshold)
    assert_array_equal(model.operator.weight, model.stiffness)


def test_threshold_constructor_gives_the_same_model():
    by_c = PIFriction(0.5, [500.0, 10.0, 4.0], [1.0, 2.0, 3.0])
    by_r = PIFriction(0.5, [500.0, 10.0, 4.0], threshold=by_c.threshold)
    assert_allclose(by_r.breakaway, by_c.breakaway, rtol=1e-15)
    assert by_r.coulomb_level == pytest.approx(by_c.coulomb_level, rel=1e-15)
    assert PIFriction(1.0, [2.0], [3.0]) == PIFriction(1.0, [2.0], [3.0])
    assert PIFriction(1.0, [2.0], [3.0]) != PIFriction(1.0, [2.0], [3.5])
    assert "PIFriction(coulomb=1.0" in repr(PIFriction(1.0, [2.0], [3.0]))


def test_parameters_are_read_only():
    model = PIFriction(0.5, [500.0, 10.0], threshold=[0.1, 0.2])
    for arr in (model.stiffness, model.breakaway, model.threshold):
        with pytest.raises(ValueError):
            arr[0] = 1.0


# ----------------------------------------------------------------------------- virgin curve


@pytest.mark.parametrize("k1", FIGURE3_FIRST_STIFFNESS)
def test_virgin_curve_closed_form_figure3(k1):
    # F_v(y) = Σ k_j·sign(y)·min(|y|, r_j), r = [1/k1, 0.1, 0.25]
    model = figure3_model(k1)
    r1 = 1.0 / k1
    for y in [0.0, 0.001, 0.05, 0.15, 0.3, 1.0]:
        expected = k1 * min(y, r1) + 10.0 * min(y, 0.1) + 4.0 * min(y, 0.25)
        assert model.virgin_curve(y) == pytest.approx(expected, rel=1e-14, abs=1e-15)
        assert model.virgin_curve(-y) == pytest.approx(-expected, rel=1e-14, abs=1e-15)
    assert model.virgin_curve(0.3) == pytest.approx(3.0, rel=1e-15)  # saturated: F_m
    assert model.virgin_curve(1e-4) == pytest.approx((k1 + 14.0) * 1e-4, rel=1e-12)  # eq. 7


def test_virgin_curve_with_coulomb_element():
    model = PIFriction(coulomb=0.5, stiffness=[10.0], breakaway=[1.0])
    y = np.array([-1.0, -0.05, 0.0, 0.05, 1.0])
    assert_allclose(model.virgin_curve(y), [-1.5, -1.0, 0.0, 1.0, 1.5], rtol=1e-15)
    assert_allclose(model.virgin_curve(y, elastic_only=True), [-1.0, -0.5, 0.0, 0.5, 1.0])
    assert isinstance(model.virgin_curve(0.05), float)
    assert model.virgin_curve(y).shape == (5,)


@PROPERTY
@given(model=friction_models(), data=st.data())
def test_virgin_curve_is_the_loading_from_the_relaxed_state(model, data):
    y0 = data.draw(st.floats(-3, 3))
    end = y0 + data.draw(st.floats(-3, 3).filter(lambda v: v != 0))
    y = sample_between([y0, end], 0.01)
    force, _ = model.force(y)
    tol = 1e-12 * model.coulomb_level
    assert_allclose(force[1:], model.virgin_curve(y[1:] - y0), rtol=0, atol=tol)
    assert force[0] == 0.0  # no motion yet: no Coulomb force, no deformation


# ----------------------------------------------------------------------------- limits


def test_zero_elements_is_pure_coulomb():
    model = PIFriction(coulomb=2.0)
    assert model.n_elements == 0
    assert model.max_elastic_force == 0.0
    assert model.coulomb_level == 2.0
    assert model.initial_stiffness == 0.0
    y = np.array([0.0, 0.0, 1.0, 1.0, 0.5, 0.5, 3.0])
    force, state = model.force(y)
    assert_array_equal(force, [0.0, 0.0, 2.0, 2.0, -2.0, -2.0, 2.0])
    elastic, _ = model.elastic_force(y)
    assert_array_equal(elastic, np.zeros(7))
    assert state.direction == 1.0
    assert state.play.shape == (0,)
    assert_array_equal(model.virgin_curve(np.array([-1.0, 0.0, 1e-9])), [-2.0, 0.0, 2.0])
    assert model.saturated_state(0.0, -1).direction == -1.0
    assert model.force([3.0, 3.0], state)[0].tolist() == [2.0, 2.0]


@pytest.mark.parametrize("k1", FIGURE3_FIRST_STIFFNESS)
def test_without_coulomb_element_the_force_is_the_pi_operator(k1):
    model = figure3_model(k1)
    y = sample_between(FIGURE3_TURNING_POINTS, 0.003)
    force, state = model.force(y)
    out, op_state = PIOperator(model.threshold, model.stiffness).apply(y)
    assert_array_equal(force, out)
    assert_array_equal(state.play, op_state.play)
    assert_array_equal(model.elastic_force(y)[0], out)


def test_very_stiff_elements_give_classical_coulomb_friction():
    """k_j → ∞ at fixed c_j: F → F_c·sign(ẏ) (Section 2)."""
    y = sample_between([0.0, 0.4, -0.3, 0.1, 0.05, 0.6], 0.01)
    direction = np.sign(np.diff(y))
    deviations = []
    for scale in (1e0, 1e1, 1e6):
        model = PIFriction(
            coulomb=0.5, stiffness=scale * np.array([10.0, 20.0]), breakaway=[1.0, 2.0]
        )
        force, _ = model.force(y)
        assert force[0] == 0.0
        deviations.append(np.max(np.abs(force[1:] - model.coulomb_level * direction)))
    assert deviations[0] > 1.0  # soft elements: presliding after every reversal
    assert deviations[1] > 0.1  # r_j = 0.01: a move of 0.01 < 2·r_j is still presliding
    assert deviations[2] <= 1e-8 * 3.5  # every sample slides: exactly F_c·sign(ẏ)


# ----------------------------------------------------------------------------- Figure 3

# Turning points 0, 0.3, −0.3, 0.15, −0.05, 0.08, −0.3, 0.3; r = [1/k1, 0.1, 0.25].
# Vertex forces by the Masing rule from the virgin curve
# F_v(u) = k1·min(u, 1/k1) + 10·min(u, 0.1) + 4·min(u, 0.25):
#   0.3: all slide, F_m = 3;  −0.3: 3 − 2F_v(0.3) = −3;  0.15: −3 + 2F_v(0.225) = −3 + 2·2.9 = 2.8;
#   −0.05: 2.8 − 2F_v(0.1) = 2.8 − 2·(k1·min(0.1, 1/k1) + 1 + 0.4);
#   0.08: F(−0.05) + 2F_v(0.065) = F(−0.05) + 2·(k1·min(0.065, 1/k1) + 0.65 + 0.26);
#   −0.3: the minor loop closes at −0.05 and the descent goes on along the branch from
#   0.15: 2.8 − 2F_v(0.225) = −3;  0.3: −3 + 2F_v(0.3) = 3.
FIGURE3_VERTICES = {
    500.0: [0.0, 3.0, -3.0, 2.8, -2.0, 1.82, -3.0, 3.0],  # element 1 slides within 0.002
    50.0: [0.0, 3.0, -3.0, 2.8, -2.0, 1.82, -3.0, 3.0],  # ... within 0.02
    5.0: [0.0, 3.0, -3.0, 2.8, -1.0, 1.47, -3.0, 3.0],  # r1 = 0.2: 0.5 and 0.325 only
}


def _figure3_path(step: float) -> tuple[np.ndarray, np.ndarray]:
    """The Figure 3 path and the sample index of every turning point."""
    y = sample_between(list(FIGURE3_TURNING_POINTS), step)
    points = list(FIGURE3_TURNING_POINTS)
    idx = np.array([_index_of_vertex(y, points, n, step) for n in range(len(points))])
    return y, idx


@pytest.mark.parametrize("coulomb", [0.0, 0.4])
def test_figure3_loop_vertices(figure3, coulomb):
    model = PIFriction(coulomb, figure3.stiffness, figure3.breakaway)
    y, idx = _figure3_path(step=1e-3)
    force, _ = model.force(y)
    k1 = float(figure3.stiffness[0])
    # the Coulomb element adds c1·sign of the move that reached the vertex
    arriving = np.sign(np.diff(FIGURE3_TURNING_POINTS, prepend=0.0))
    expected = np.array(FIGURE3_VERTICES[k1]) + coulomb * arriving
    assert_allclose(force[idx], expected, rtol=0, atol=1e-12)


def test_figure3_slope_after_every_reversal_is_the_initial_stiffness(figure3):
    """eq. 7: right after each reversal every element sticks: dF/dy = Σ k_j."""
    h = float(np.min(figure3.threshold)) / 8  # below the smallest threshold
    y, idx = _figure3_path(step=h)
    force, _ = figure3.force(y)
    total = figure3.initial_stiffness
    for i in idx[1:-1]:  # every reversal
        after = (force[i + 1] - force[i]) / (y[i + 1] - y[i])
        assert after == pytest.approx(total, rel=1e-9)
    # ... and at the two major vertices every element slid just before: slope 0
    for i in idx[[1, 2, 7]]:
        assert (force[i] - force[i - 1]) / (y[i] - y[i - 1]) == pytest.approx(0.0, abs=1e-9)
    # from any state, a small step reversing the last move has slope Σ k_j
    for i in idx[1:-1]:
        _, state = figure3.force(y[: i + 1])
        probe = y[i] - h * state.direction
        f_probe, _ = figure3.force([probe], state)
        assert (f_probe[0] - force[i]) / (probe - y[i]) == pytest.approx(total, rel=1e-9)


def test_figure3_minor_loop_closes_and_the_older_branch_continues(figure3):
    y, idx = _figure3_path(step=1e-3)
    force, _ = figure3.force(y)
    k, r = figure3.stiffness, figure3.threshold

    def branch(y_r, f_r, ys):  # Masing branch from the reversal (y_r, f_r)
        return np.array([f_r - 2 * virgin_force((y_r - v) / 2, k, r) for v in ys])

    # descent 0.08 → −0.3 (vertex 5 → 6) meets the older branch at −0.05 (vertex 4)
    seg = np.arange(idx[5], idx[6] + 1)
    before = seg[y[seg] >= -0.05]
    after = seg[y[seg] < -0.05]
    assert_allclose(force[before], branch(0.08, force[idx[5]], y[before]), atol=1e-12)
    assert force[idx[4]] == pytest.approx(FIGURE3_VERTICES[float(k[0])][4], abs=1e-12)
    # beyond −0.05 it is the branch from 0.15 (vertex 3), as if the minor loop never was
    assert_allclose(force[after], branch(0.15, 2.8, y[after]), atol=1e-12)
    assert np.max(np.abs(force[after] - branch(0.08, force[idx[5]], y[after]))) > 0.1


# ----------------------------------------------------------------------------- Madelung/Masing


def _check_masing(model: PIFriction, points: list[float], step: float, elastic: bool) -> None:
    y = sample_between(points, step)
    force = model.elastic_force(y)[0] if elastic else model.force(y)[0]
    c1 = 0.0 if elastic else model.coulomb
    k, r = model.stiffness, model.threshold

    def virgin(u: float) -> float:  # the total virgin curve, built independently
        return c1 * np.sign(u) + virgin_force(u, k, r)

    tol = 1e-12 * model.coulomb_level * (1 + np.max(np.abs(y)))
    checked = 0
    for n in range(1, len(points) - 1):
        y_prev, y_r = points[n - 1], points[n]
        i_r = _index_of_vertex(y, points, n, step)
        reach = abs(y_r - y_prev)  # the branch holds until it meets the older branch
        seg = np.arange(i_r + 1, _index_of_vertex(y, points, n + 1, step) + 1)
        seg = seg[np.abs(y[seg] - y_r) <= reach]
        expected = [force[i_r] - 2 * virgin((y_r - v) / 2) for v in y[seg]]
        assert_allclose(force[seg], expected, rtol=0, atol=tol)
        checked += seg.size
    assert checked > 0 or len(points) < 3


def _index_of_vertex(y: np.ndarray, points: list[float], n: int, step: float) -> int:
    i = 0
    for a, b in itertools.pairwise(points[: n + 1]):
        i += max(1, int(np.ceil(abs(b - a) / step)))
    assert y[i] == points[n]
    return i


@pytest.mark.parametrize("coulomb", [0.0, 0.4])
def test_masing_rule_figure3(figure3, coulomb):
    model = PIFriction(coulomb, figure3.stiffness, figure3.breakaway)
    _check_masing(model, list(FIGURE3_TURNING_POINTS), 1e-3, elastic=True)
    _check_masing(model, list(FIGURE3_TURNING_POINTS), 1e-3, elastic=False)


@PROPERTY
@given(model=friction_models(), points=turning_points(max_size=8))
def test_masing_rule_random(model, points):
    """After a reversal at (y_r, F_r): F = F_r − 2·F_v((y_r − y)/2), elastic and total."""
    step = min(0.02, float(np.min(np.abs(np.diff(points)))) / 4)  # samples on every branch
    _check_masing(model, points, step, elastic=True)
    _check_masing(model, points, step, elastic=False)


# ----------------------------------------------------------------------------- reference


def _reference_force(model: PIFriction, y: np.ndarray, state: PIState | None = None):
    if state is None:
        run = drive_springs(y, model.stiffness, model.threshold)
    else:
        run = drive_springs(
            y,
            model.stiffness,
            model.threshold,
            deformation=state.deformation,
            previous_input=state.last_input,
            direction=state.direction,
        )
    return run.elastic + model.coulomb * run.direction, run


@PROPERTY
@given(model=friction_models(), y=paths())
def test_force_agrees_with_spring_reference(model, y):
    force, state = model.force(y)
    ref, run = _reference_force(model, y)
    assert np.max(np.abs(force - ref)) <= 1e-12 * model.coulomb_level
    assert state.direction == run.direction[-1]
    elastic, _ = model.elastic_force(y)
    assert np.max(np.abs(elastic - run.elastic)) <= 1e-12 * model.coulomb_level


@PROPERTY
@given(model=friction_models(), y=paths(min_size=2), data=st.data())
def test_force_agrees_with_spring_reference_from_a_state(model, y, data):
    n = model.n_elements
    u = np.array(data.draw(st.lists(st.floats(-1, 1), min_size=n, max_size=n)))
    y_prev = data.draw(st.floats(-3, 3))
    d = data.draw(st.sampled_from([-1, 0, 1]))
    state = PIState(y_prev, y_prev - u * model.threshold, d)
    force, final = model.force(y, state)
    ref, run = _reference_force(model, y, state)
    assert np.max(np.abs(force - ref)) <= 1e-12 * model.coulomb_level
    assert final.direction == run.direction[-1]


# ----------------------------------------------------------------------------- states


def test_relaxed_and_saturated_states(figure3):
    assert figure3.elastic_force([0.7], figure3.relaxed_state(0.7))[0][0] == 0.0
    up = figure3.saturated_state(0.7, 1)
    assert figure3.elastic_force([0.7], up)[0][0] == pytest.approx(3.0, rel=1e-14)
    down = figure3.saturated_state(0.7, -1)
    assert figure3.elastic_force([0.7], down)[0][0] == pytest.approx(-3.0, rel=1e-14)
    # continuing downwards from the saturated state: still −F_m; reversing: slope Σ k_j
    h = 1e-4
    assert figure3.elastic_force([0.7 - h], down)[0][0] == pytest.approx(-3.0, rel=1e-12)
    rise = figure3.elastic_force([0.7 + h], down)[0][0] + 3.0
    assert rise / h == pytest.approx(figure3.initial_stiffness, rel=1e-9)


def test_coulomb_direction_is_carried_by_the_state():
    model = PIFriction(coulomb=1.0, stiffness=[10.0], breakaway=[1.0])
    _, state = model.force([0.0, 0.5])
    assert state.direction == 1.0
    still, _ = model.force([0.5, 0.5], state)  # no motion: the last direction holds
    assert_allclose(still, [2.0, 2.0], rtol=1e-15)
    back, _ = model.force([0.45], state)
    assert back[0] == pytest.approx(-1.0 + 0.5, rel=1e-12)


@PROPERTY
@given(model=friction_models(), y=paths(min_size=2, max_size=80), data=st.data())
def test_chunked_force_equals_whole_bit_for_bit(model, y, data):
    cuts = sorted(set(data.draw(st.lists(st.integers(1, y.size - 1), max_size=5))))
    whole, final = model.force(y)
    parts, state = [], None
    for chunk in np.split(y, cuts):
        out, state = model.force(chunk, state)
        parts.append(out)
    assert_array_equal(np.concatenate(parts), whole)
    assert_array_equal(state.play, final.play)
    assert state.direction == final.direction


@PROPERTY
@given(model=friction_models(), loop=paths(min_size=2))
def test_friction_never_creates_energy(model, loop):
    """∮ F dy >= c1·(travel) >= 0 around a closed input cycle (positive stiffnesses)."""
    y = np.append(loop, loop[0])
    force, _ = model.force(y)
    elastic, _ = model.elastic_force(y)
    moves = np.diff(y)
    # the Coulomb element does c1·|Δy| on every move ...
    assert_allclose((force - elastic)[1:] * moves, model.coulomb * np.abs(moves), atol=1e-12)
    # ... and the springs store and release: ∮ Σ k_j f_j dy >= 0 (exact per move: f is
    # clip(f_start + s) along each move, antiderivative G)
    r, k = model.threshold, model.stiffness
    f = y[:-1, None] - _play_before(model, y)  # deformations at the start of every move
    g_end = _g(f + moves[:, None], r)
    g_start = _g(f, r)
    work = float(np.sum((g_end - g_start) @ k)) if r.size else 0.0
    assert work >= -1e-12 * max(model.max_elastic_force, 1.0) * (np.sum(np.abs(moves)) + 1)


def _play_before(model: PIFriction, y: np.ndarray) -> np.ndarray:
    """Play positions x_j at the start of every move (the samples y[:-1])."""
    from presliding import play

    if model.n_elements == 0:
        return np.empty((y.size - 1, 0))
    return play(y[:-1], model.threshold)


def _g(v: np.ndarray, r: np.ndarray) -> np.ndarray:
    return np.where(np.abs(v) <= r, 0.5 * v * v, r * np.abs(v) - 0.5 * r * r)
