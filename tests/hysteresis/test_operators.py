"""Play and stop operators, the PI sum (eq. 3, 4, 5, 11) and the PI state."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal

from presliding import PIFriction, PIOperator, PIState, play, stop
from presliding.hysteresis import _kernels
from tests._reference import drive_springs
from tests.helpers import PROPERTY, banks, paths, sample_between, turning_points

# ----------------------------------------------------------------------------- helpers


def triangle(amplitude: float, periods: int, step: float) -> np.ndarray:
    """0 → A → −A → A ... (`periods` full swings after the first quarter)."""
    points = [0.0, amplitude]
    for _ in range(periods):
        points += [-amplitude, amplitude]
    return sample_between(points, step)


def triangle_stop(y: np.ndarray, amplitude: float, r: float) -> np.ndarray:
    """Closed form of the stop output (unit stiffness) on `triangle`, amplitude > r.

    Virgin loading min(y, r); on a descent from +A the element sticks for 2r
    and then slides at −r: max(y − A + r, −r); on an ascent from −A:
    min(y + A − r, r).
    """
    out = np.empty_like(y)
    rising, seen_top = True, False
    for t, yt in enumerate(y):
        if t > 0 and yt < y[t - 1]:
            rising, seen_top = False, True
        elif t > 0 and yt > y[t - 1]:
            rising = True
        if not seen_top:
            out[t] = min(yt, r)
        elif rising:
            out[t] = min(yt + amplitude - r, r)
        else:
            out[t] = max(yt - amplitude + r, -r)
    return out


def segment_work(f_start: np.ndarray, move: float, r: np.ndarray) -> np.ndarray:
    """∫ f dy of unit springs over one monotone move, from deformations f_start.

    Along the move the deformation is clip(f_start + s, −r, r) (stick, then
    slide), whose antiderivative is G(v) = v²/2 for |v| <= r, r|v| − r²/2 beyond.
    """

    def g(v: np.ndarray) -> np.ndarray:
        return np.where(np.abs(v) <= r, 0.5 * v * v, r * np.abs(v) - 0.5 * r * r)

    return g(f_start + move) - g(f_start)


def reduce_memory(points: list[float]) -> list[float]:
    """Wiping-out rule: the turning points that remain in memory after `points`.

    The bank starts saturated downwards at points[0] (as if it came from +∞).
    A pair of turning points (a, b) is erased when the input reaches or passes
    a again; a move that continues the previous one replaces its end point.
    """
    memory = [points[0]]
    for p in points[1:]:
        while True:
            if not memory:  # the base minimum was passed: saturated downwards at p
                memory.append(p)
                break
            if len(memory) == 1:
                if p <= memory[0]:
                    memory[0] = p  # still descending from +∞
                else:
                    memory.append(p)
                break
            a, b = memory[-2], memory[-1]
            if (p - b) * (b - a) >= 0:  # no reversal at b
                memory.pop()
                continue
            if (p - a) * (b - a) <= 0:  # reaches or passes a: the loop (a, b) is wiped out
                del memory[-2:]
                continue
            memory.append(p)
            break
    return memory


# ----------------------------------------------------------------------------- closed forms


@pytest.mark.parametrize("r", [0.1, 0.25, 0.7])
def test_stop_on_triangle_wave_matches_closed_form(r):
    a = 1.0
    y = triangle(a, periods=3, step=0.01)
    assert_allclose(stop(y, r), triangle_stop(y, a, r), rtol=0, atol=1e-14)
    assert_allclose(play(y, r), y - triangle_stop(y, a, r), rtol=0, atol=1e-14)


def test_play_inside_the_zone_never_moves():
    y = triangle(0.3, periods=2, step=0.01)  # |y| <= 0.3 < r
    assert_array_equal(play(y, 0.5), np.zeros_like(y))
    assert_array_equal(stop(y, 0.5), y)


def test_play_and_stop_vector_thresholds_stack_the_scalar_ones():
    y = triangle(1.0, periods=2, step=0.03)
    r = np.array([0.05, 0.3, 2.0])
    x = play(y, r)
    assert x.shape == (y.size, 3)
    for j, rj in enumerate(r):
        assert_array_equal(x[:, j], play(y, rj))
    assert_array_equal(stop(y, r), y[:, None] - x)
    assert play(y, 0.3).shape == (y.size,)
    assert play(y, [0.3]).shape == (y.size, 1)


def test_play_initial_state_is_the_state_at_the_first_sample():
    y = np.array([0.0, 0.2, 0.5, -0.5])
    # saturated upwards at y0 = 0 (x = −r): moving up drags it immediately
    assert_allclose(play(y, 0.25, initial=-0.25), [-0.25, -0.05, 0.25, -0.25])
    assert_allclose(stop(y, 0.25, initial=-0.25), [0.25, 0.25, 0.25, -0.25])
    # scalar initial broadcasts over a vector of thresholds
    assert_allclose(play(y, [0.25, 1.0], initial=0.1)[1], [0.1, 0.1])


def test_pi_operator_weighted_stop_sum_closed_form():
    op = PIOperator(threshold=[0.1, 0.25], weight=[10.0, 4.0])
    y = np.array([0.0, 0.05, 0.3, 0.2, -0.2])
    out, state = op.apply(y)
    # 0.05: both stick; 0.3: both slide (10·0.1 + 4·0.25); 0.2: 10·0 + 4·0.15;
    # −0.2: element 1 at −0.1, element 2 at 0.15 − 0.4 = −0.25
    assert_allclose(out, [0.0, 0.7, 2.0, 0.6, -2.0], rtol=0, atol=1e-14)
    assert_allclose(state.deformation, [-0.1, -0.25], rtol=0, atol=1e-15)
    assert state.last_input == -0.2
    assert state.direction == -1.0
    assert_allclose(out, stop(y, op.threshold) @ op.weight, rtol=0, atol=1e-14)


def test_pi_operator_negative_and_zero_weights_are_allowed():
    op = PIOperator(threshold=[0.1, 0.2, 0.3], weight=[1.0, -2.0, 0.0])
    y = triangle(0.5, periods=1, step=0.02)
    out, _ = op.apply(y)
    assert_allclose(out, stop(y, op.threshold) @ op.weight, rtol=0, atol=1e-14)


def test_pi_state_constructors():
    relaxed = PIState.relaxed(0.5, 3)
    assert_array_equal(relaxed.play, [0.5, 0.5, 0.5])
    assert_array_equal(relaxed.deformation, [0.0, 0.0, 0.0])
    assert relaxed.direction == 0.0
    up = PIState.saturated(1.0, [0.1, 0.5], 1)
    assert_allclose(up.deformation, [0.1, 0.5])
    assert up.direction == 1.0
    down = PIState.saturated(1.0, [0.1, 0.5], -1)
    assert_allclose(down.deformation, [-0.1, -0.5])
    assert down.direction == -1.0
    down.check_against(np.array([0.1, 0.5]))
    with pytest.raises(ValueError, match="`state`"):
        down.check_against(np.array([0.1, 0.4]))
    assert PIOperator([0.1, 0.2], [1.0, 1.0]).relaxed_state(2.0).play.tolist() == [2.0, 2.0]


def test_pi_state_arrays_are_read_only():
    state = PIState(0.0, np.array([0.1, -0.1]), 1)
    with pytest.raises(ValueError):
        state.play[0] = 3.0
    op = PIOperator([0.1], [1.0])
    with pytest.raises(ValueError):
        op.threshold[0] = 3.0


def test_the_caller_arrays_are_not_modified():
    y = np.array([0.0, 1.0, -1.0])
    x0 = np.array([0.05, -0.05])
    before = (y.copy(), x0.copy())
    play(y, [0.1, 0.2], initial=x0)
    state = PIState(0.0, x0)
    PIOperator([0.1, 0.2], [1.0, 1.0]).apply(y, state)
    assert_array_equal(y, before[0])
    assert_array_equal(x0, before[1])
    assert_array_equal(state.play, before[1])


def test_closed_loop_area_is_the_dissipated_energy():
    # a stop of stiffness k between ±A dissipates 4·k·r·(A − r) per cycle (the
    # parallelogram loop: height 2kr, width 2(A − r))
    k, r, a = 3.0, 0.2, 1.0
    op = PIOperator([r], [k])
    _, state = op.apply(np.array([0.0, a]))  # onto the major loop
    y = sample_between([a, -a, a], 0.1)
    out, _ = op.apply(y, state)
    work = np.sum(0.5 * (out[1:] + out[:-1]) * np.diff(y))  # exact: F is linear between samples
    assert work == pytest.approx(4 * k * r * (a - r), rel=1e-12)


# ----------------------------------------------------------------------------- reference


def _check_against_reference(k, r, y, x0=None, rtol=1e-12):
    op = PIOperator(r, k)
    if x0 is None:
        out, state = op.apply(y)
        ref = drive_springs(y, k, r)
    else:
        out, state = op.apply(y, PIState(y[0], x0))
        ref = drive_springs(y, k, r, deformation=y[0] - x0)
    f_m = float(k @ r)
    assert np.max(np.abs(out - ref.elastic)) <= rtol * f_m
    assert np.max(np.abs(stop(y, r, x0) - ref.deformation)) <= rtol * np.max(r)
    assert np.max(np.abs(play(y, r, x0) - ref.play_positions(y))) <= rtol * np.max(r)
    assert_allclose(state.deformation, ref.deformation[-1], rtol=0, atol=rtol * np.max(r))


@PROPERTY
@given(bank=banks(), y=paths())
def test_agrees_with_spring_reference(bank, y):
    k, r = bank
    _check_against_reference(k, r, y)


@PROPERTY
@given(bank=banks(), y=paths(), data=st.data())
def test_agrees_with_spring_reference_from_any_state(bank, y, data):
    k, r = bank
    u = np.array(data.draw(st.lists(st.floats(-1, 1), min_size=r.size, max_size=r.size)))
    _check_against_reference(k, r, y, x0=y[0] - u * r)


@PROPERTY
@given(bank=banks(threshold_decades=(-3.0, -2.0)), y=paths(scale=0.01, offset=1.0))
def test_agrees_with_spring_reference_offset_path(bank, y):
    # |y| / r up to about 1e3: float64 play positions still give 1e-12·F_m
    k, r = bank
    _check_against_reference(k, r, y)


@pytest.mark.parametrize("n", [1, 5, 15, 16, 17, 64, 300])
def test_both_kernel_compilations_agree_with_the_reference(n):
    rng = np.random.default_rng(n)
    k = 10 ** rng.uniform(-1, 3, n)
    r = 10 ** rng.uniform(-2, 0, n)
    y = np.concatenate([[0.0], np.cumsum(rng.normal(0.0, 0.3, 500))])
    _check_against_reference(k, r, y)


@pytest.mark.parametrize("n", [3, 40])
def test_both_kernel_compilations_give_bit_identical_play_states(n):
    rng = np.random.default_rng(7)
    k = 10 ** rng.uniform(-1, 3, n)
    r = 10 ** rng.uniform(-2, 0, n)
    y = np.cumsum(rng.normal(0.0, 0.3, 2000))
    states, outputs = [], []
    for kernel in (_kernels._stop_sum_short, _kernels._stop_sum_long):
        x = np.full(n, y[0])
        out = np.empty(y.size)
        kernel(y, r, k, x, out)
        states.append(x)
        outputs.append(out)
    x_play = np.full(n, y[0])
    _kernels.play_outputs(y, r, x_play, np.empty((y.size, n)))
    assert_array_equal(states[0], states[1])
    assert_array_equal(states[0], x_play)
    assert_allclose(outputs[0], outputs[1], rtol=0, atol=1e-12 * float(k @ r))


def test_large_offset_error_is_within_float64_play_positions():
    """y ~ 1e3 with r ~ 1e-3: the play positions x_j are stored as float64 numbers
    near y, so each carries a rounding of half an ulp of y; the force error is at
    most Σ k_j·ulp(|y|), whatever the path length."""
    rng = np.random.default_rng(3)
    for _ in range(5):
        n = int(rng.integers(1, 8))
        k = 10 ** rng.uniform(-1, 3, n)
        r = 10 ** rng.uniform(-3.3, -2.7, n)
        y = 1e3 + np.cumsum(rng.normal(0.0, 1e-3, 3000))
        out, _ = PIOperator(r, k).apply(y)
        ref = drive_springs(y, k, r)
        bound = 1e-12 * float(k @ r) + float(np.sum(k)) * np.spacing(np.max(np.abs(y)))
        assert np.max(np.abs(out - ref.elastic)) <= bound


# ----------------------------------------------------------------------------- properties


@PROPERTY
@given(bank=banks(), y=paths(), data=st.data())
def test_play_stays_within_threshold(bank, y, data):
    _, r = bank
    u = np.array(data.draw(st.lists(st.floats(-1, 1), min_size=r.size, max_size=r.size)))
    x = play(y, r, initial=y[0] - u * r)
    slack = 4 * np.finfo(float).eps * (np.abs(y)[:, None] + r)
    assert np.all(np.abs(y[:, None] - x) <= r + slack)


@PROPERTY
@given(bank=banks(), y=paths(min_size=2), data=st.data())
def test_rate_independence(bank, y, data):
    """Extra samples inside a monotone move change nothing at the shared samples."""
    k, r = bank
    gaps = data.draw(st.lists(st.integers(0, y.size - 2), min_size=1, max_size=10))
    pieces, where = [], []
    for t in range(y.size):
        where.append(sum(p.size for p in pieces))
        pieces.append(y[t : t + 1])
        if t < y.size - 1 and t in gaps:
            theta = np.sort(data.draw(st.lists(st.floats(0, 1), min_size=1, max_size=4)))
            lo, hi = sorted((y[t], y[t + 1]))
            pieces.append(np.clip(y[t] + theta * (y[t + 1] - y[t]), lo, hi))
    dense = np.concatenate(pieces)
    assert_array_equal(play(dense, r)[where], play(y, r))
    out, state = PIOperator(r, k).apply(y)
    out_dense, state_dense = PIOperator(r, k).apply(dense)
    assert_array_equal(out_dense[where], out)
    assert_array_equal(state_dense.play, state.play)


@PROPERTY
@given(bank=banks(), points=turning_points(), data=st.data())
def test_minor_loop_closes_on_its_starting_point(bank, points, data):
    """Return-point memory: from a, reverse to b (not beyond the previous turning
    point p) and come back: the state at a is restored exactly, and the path
    continues as if the minor loop had not happened."""
    k, r = bank
    p, a = points[-2], points[-1]
    b = float(np.clip(p + data.draw(st.floats(0, 1)) * (a - p), min(a, p), max(a, p)))
    beyond = a + data.draw(st.floats(0.01, 2.0)) * np.sign(a - p)
    history = sample_between(points, 0.05)
    op = PIOperator(r, k)
    out_a, state_a = op.apply(history)
    tail = sample_between([a, beyond], 0.05)[1:]
    loop = np.concatenate([sample_between([a, b, a], 0.05)[1:], tail])
    out_loop, state_loop = op.apply(loop, state_a)
    n_loop = loop.size - tail.size
    back_at_a = play(history, r)[-1]
    assert_array_equal(
        play(np.concatenate([history, loop]), r)[history.size + n_loop - 1], back_at_a
    )
    assert out_loop[n_loop - 1] == out_a[-1]
    out_direct, state_direct = op.apply(tail, state_a)
    assert_array_equal(out_loop[n_loop:], out_direct)
    assert_array_equal(state_loop.play, state_direct.play)


@PROPERTY
@given(bank=banks(), points=turning_points(max_size=14))
def test_larger_excursions_wipe_out_smaller_ones(bank, points):
    """The final state depends only on the turning points that survive the
    wiping-out rule (each excursion erases the smaller loops it encloses)."""
    _, r = bank
    memory = reduce_memory(points)
    assume(len(memory) < len(points))
    full = play(sample_between(points, 0.07), r, initial=points[0] + r)
    reduced = play(sample_between(memory, 0.07), r, initial=memory[0] + r)
    assert_array_equal(full[-1], reduced[-1])


@PROPERTY
@given(bank=banks(), y=paths(), data=st.data())
def test_monotone_input_gives_monotone_output(bank, y, data):
    k, r = bank
    u = np.array(data.draw(st.lists(st.floats(-1, 1), min_size=r.size, max_size=r.size)))
    up = np.sort(y)
    op = PIOperator(r, k)
    out_up, _ = op.apply(up, PIState(up[0], up[0] - u * r))
    out_down, _ = op.apply(up[::-1], PIState(up[-1], up[-1] - u * r))
    tol = 4 * float(np.sum(k)) * np.spacing(np.max(np.abs(y)) + np.max(r))
    assert np.all(np.diff(out_up) >= -tol)
    assert np.all(np.diff(out_down) <= tol)


@PROPERTY
@given(bank=banks(), y=paths(min_size=2, max_size=80), data=st.data())
def test_chunked_equals_whole_bit_for_bit(bank, y, data):
    k, r = bank
    cuts = sorted(set(data.draw(st.lists(st.integers(1, y.size - 1), max_size=5))))
    op = PIOperator(r, k)
    whole, final = op.apply(y)
    parts, state = [], None
    for chunk in np.split(y, cuts):
        out, state = op.apply(chunk, state)
        parts.append(out)
    assert_array_equal(np.concatenate(parts), whole)
    assert_array_equal(state.play, final.play)
    assert state.last_input == final.last_input
    assert state.direction == final.direction
    # play(): the state passed on is the play state at the first sample of the next
    # chunk's input, so the chunks overlap by one sample
    x_whole = play(y, r)
    x_parts, start, x_last = [], 0, None
    for end in [*cuts, y.size]:
        lo = max(start - 1, 0)
        x = play(y[lo:end], r, initial=x_last)
        x_parts.append(x[start - lo :])
        x_last, start = x[-1], end
    assert_array_equal(np.concatenate(x_parts), x_whole)


@PROPERTY
@given(bank=banks(), loop=paths(min_size=2), data=st.data())
def test_no_energy_is_created_around_a_closed_cycle(bank, loop, data):
    """∮ F dy >= 0 for positive stiffnesses, from any starting state."""
    k, r = bank
    y = np.append(loop, loop[0])  # closed input cycle
    u = np.array(data.draw(st.lists(st.floats(-1, 1), min_size=r.size, max_size=r.size)))
    start = PIState(y[0], y[0] - u * r)
    f = np.vstack([start.deformation, stop(y, r, start.play)])  # deformation before each move
    moves = np.diff(np.concatenate([[y[0]], y]))
    work = sum(float(segment_work(f[t], moves[t], r) @ k) for t in range(y.size))
    assert work >= -1e-12 * float(k @ r) * (np.sum(np.abs(moves)) + np.max(r))


@pytest.mark.parametrize(
    ("path", "prior", "expected"),
    [
        ([0.0, 1.0, 1.0, 1.0], None, 1.0),  # a flat tail keeps the last direction
        ([0.0, -1.0, 0.5, 0.5], None, 1.0),
        ([2.0, 1.0, 1.0], None, -1.0),
        ([3.0, 3.0, 3.0], None, 0.0),  # no motion yet
        ([3.0, 3.0], PIState(3.0, [3.0], -1.0), -1.0),  # carried over from the state
        ([3.0, 3.0], PIState(2.5, [2.5], 0.0), 1.0),  # the increment into the first sample
    ],
)
def test_final_direction_is_the_sign_of_the_last_nonzero_increment(path, prior, expected):
    op = PIOperator([1.0], [1.0])
    _, state = op.apply(np.array(path), prior)
    assert state.direction == expected
    _, per_sample = PIFriction(0.5, [1.0], threshold=[1.0]).force(np.array(path), prior)
    assert per_sample.direction == expected
