"""`PIBatch` against the straightforward kernel, member by member (eq. 4, eq. 8).

Play states must be bit-identical to `_kernels._stop_sum_short`, forces within
1e-12 of F_m, chunked runs equal whole runs bit for bit, and a whole-array call
must neither copy its input nor allocate more than its output and O(N).
"""

from __future__ import annotations

import itertools
import tracemalloc

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from presliding import PIBatch, PIBatchState, PIFriction, PIOperator, PIState, friction_batch
from presliding.hysteresis import _batch_kernels, _kernels
from tests.hysteresis.test_kernels import assert_bit_identical, plateaued_input, walk


def reference(y, r, w, x0, linear=0.0, coulomb=0.0):
    """Member by member: the straightforward kernel, then a·y + c·sign(ẏ) added."""
    x = x0.copy()
    out = np.empty(y.shape[0])
    _kernels._stop_sum_short(y, r, w, x, out)
    direction = np.empty(y.shape[0])
    _kernels.motion_direction(y, y[0], 0.0, direction)
    return out + linear * y + coulomb * direction, x


def random_batch(n_batch, n, rng, *, coulomb=True):
    r = 10 ** rng.uniform(-2.0, 0.0, (n_batch, n))
    w = 10 ** rng.uniform(-1.0, 2.0, (n_batch, n)) * rng.choice([-1.0, 1.0, 1.0], (n_batch, n))
    lin = rng.normal(0.0, 1.0, n_batch)
    c = rng.uniform(0.0, 2.0, n_batch) if coulomb else np.zeros(n_batch)
    return PIBatch(r, w, linear=lin, coulomb=c)


def check_members(batch, y, state, force, final):
    x0 = np.full(batch.threshold.shape, y[0]) if state is None else state.play
    for b in range(batch.n_members):
        ref, x_ref = reference(
            y, batch.threshold[b], batch.weight[b], x0[b], batch.linear[b], batch.coulomb[b]
        )
        assert_bit_identical(final.play[b], x_ref)
        f_m = np.abs(batch.weight[b]) @ batch.threshold[b] + batch.coulomb[b]
        bound = 1e-12 * max(f_m, 1.0) + abs(batch.linear[b]) * np.spacing(np.abs(y).max())
        assert np.max(np.abs(force[:, b] - ref)) <= bound


@pytest.mark.parametrize("n_batch", [1, 3, 31, 32, 33, 64, 70])
@pytest.mark.parametrize("n", [0, 1, 5, 9])
def test_members_match_the_straightforward_kernel(n_batch, n):
    rng = np.random.default_rng(100 * n_batch + n)
    batch = random_batch(n_batch, n, rng)
    y = walk(301, rng)
    force, final = batch.apply(y)
    assert force.shape == (301, n_batch)
    assert final.play.shape == (n_batch, n)
    check_members(batch, y, None, force, final)
    assert final.direction == np.sign(y[-1] - y[-2])


@settings(max_examples=40, deadline=None)
@given(
    n_batch=st.integers(1, 40),
    n=st.integers(0, 9),
    n_time=st.integers(1, 200),
    offset=st.sampled_from([0.0, 1.0, 1e3, -1e8]),
    seed=st.integers(0, 2**32 - 1),
)
def test_play_states_bit_identical_and_sums_within_tolerance(n_batch, n, n_time, offset, seed):
    # plateaus (repeated samples), reversals of every length and rounding bands,
    # from a state that is not relaxed
    rng = np.random.default_rng(seed)
    batch = random_batch(n_batch, n, rng)
    y = plateaued_input(n_time, rng, offset)
    play = y[0] - rng.uniform(-1.0, 1.0, (n_batch, n)) * batch.threshold
    state = PIBatchState(y[0], play, 0.0)
    force, final = batch.apply(y, state)
    x0 = state.play
    for b in range(n_batch):
        ref, x_ref = reference(
            y, batch.threshold[b], batch.weight[b], x0[b], batch.linear[b], batch.coulomb[b]
        )
        assert_bit_identical(final.play[b], x_ref)
        f_m = np.abs(batch.weight[b]) @ batch.threshold[b] + batch.coulomb[b]
        # at an offset the terms w_j·y and linear·y are large: the kernel and the
        # reference each round them within about an ulp of that size, so the two
        # may differ by a few ulps (a difference of two approximations)
        bound = 1e-12 * max(f_m, 1.0) + 4.0 * (
            np.abs(batch.weight[b]).sum() + abs(batch.linear[b])
        ) * np.spacing(abs(offset) + 1)
        assert np.max(np.abs(force[:, b] - ref)) <= bound


@settings(max_examples=30, deadline=None)
@given(
    n_batch=st.sampled_from([1, 5, 32, 37]),
    n=st.sampled_from([1, 5, 8]),
    cuts=st.lists(st.integers(1, 299), max_size=6),
    seed=st.integers(0, 2**32 - 1),
)
def test_chunked_equals_whole_bit_for_bit(n_batch, n, cuts, seed):
    rng = np.random.default_rng(seed)
    batch = random_batch(n_batch, n, rng)
    y = walk(300, rng)
    whole, final = batch.apply(y)
    edges = [0, *sorted(set(cuts)), 300]
    state, parts = None, []
    for a, b in itertools.pairwise(edges):
        part, state = batch.apply(y[a:b], state)
        parts.append(part)
    assert_bit_identical(np.concatenate(parts), whole)
    assert_bit_identical(state.play, final.play)
    assert state.direction == final.direction
    assert state.last_input == final.last_input


def test_members_equal_their_operators_and_friction_models():
    rng = np.random.default_rng(7)
    ops = [PIOperator(10 ** rng.uniform(-2, 0, 4), rng.uniform(1, 9, 4), linear=a) for a in (0, 2)]
    batch = PIBatch.stack(ops)
    y = walk(500, rng)
    force, final = batch.apply(y)
    for b, op in enumerate(ops):
        f, s = op.apply(y)
        assert_bit_identical(final.member(b).play, s.play)
        assert np.max(np.abs(force[:, b] - f)) <= 1e-12 * (op.weight @ op.threshold) + 1e-15
        assert batch.member(b).linear == op.linear
    k, c = [500.0, 10.0, 4.0], [1.0, 1.0, 1.0]
    models = [PIFriction(c1, stiffness=k, breakaway=c) for c1 in (0, 1)]
    fb = friction_batch(models)
    force, final = fb.apply(y)
    for b, m in enumerate(models):
        f, s = m.force(y)
        assert_bit_identical(final.member(b).play, s.play)
        assert final.member(b).direction == s.direction
        assert np.max(np.abs(force[:, b] - f)) <= 1e-12 * m.coulomb_level


def test_a_stacked_state_continues_the_members():
    rng = np.random.default_rng(3)
    ops = [PIOperator(10 ** rng.uniform(-2, 0, 3), rng.uniform(1, 9, 3)) for _ in range(3)]
    y = walk(200, rng)
    states = [op.apply(y[:120])[1] for op in ops]
    force, _ = PIBatch.stack(ops).apply(y[120:], PIBatchState.stack(states))
    for b, (op, s) in enumerate(zip(ops, states, strict=True)):
        assert np.max(np.abs(force[:, b] - op.apply(y[120:], s)[0])) <= 1e-12 * 30


def test_the_input_is_not_copied_and_out_is_written_in_place(monkeypatch):
    seen = []
    kernel = _batch_kernels.batch_apply

    def spy(y, *args):
        seen.append(y)
        return kernel(y, *args)

    monkeypatch.setattr(_batch_kernels, "batch_apply", spy)
    rng = np.random.default_rng(1)
    batch = random_batch(4, 5, rng)
    y = walk(100, rng)
    out = np.empty((100, 4))
    force, _ = batch.apply(y, out=out)
    assert force is out
    assert seen[0] is y
    # a non-float64 or non-contiguous input is converted, never modified
    y32 = y.astype(np.float32)
    batch.apply(y32)
    assert seen[1] is not y32 and seen[1].dtype == np.float64


def test_apply_leaves_the_state_it_was_given_unchanged():
    rng = np.random.default_rng(4)
    batch = random_batch(1, 3, rng)  # (1, 3): the transposed state is contiguous too
    y = walk(50, rng)
    state = PIBatchState(y[0], y[0] - 0.5 * batch.threshold)
    before = state.play.copy()
    batch.apply(y, state)
    assert_bit_identical(state.play, before)
    assert not state.play.flags.writeable


def test_a_single_operator_and_a_friction_model_read_their_input_in_place(monkeypatch):
    seen = []
    kernel = _kernels.stop_sum

    def spy(y, *args):
        seen.append(y)
        return kernel(y, *args)

    monkeypatch.setattr(_kernels, "stop_sum", spy)
    y = walk(100, np.random.default_rng(2))
    PIOperator([0.1, 0.2], [1.0, 2.0]).apply(y)
    PIFriction(0.5, stiffness=[1.0, 2.0], breakaway=[0.1, 0.4]).force(y)
    assert len(seen) == 2 and all(s is y for s in seen)


@pytest.mark.parametrize(
    "call",
    [
        lambda y: PIOperator(np.full(5, 0.1), np.ones(5)).apply(y),
        lambda y: PIFriction(0.5, stiffness=np.ones(5), breakaway=np.full(5, 0.1)).force(y),
        lambda y: random_batch(8, 5, np.random.default_rng(0)).apply(y),
    ],
)
def test_a_whole_array_call_allocates_only_its_output(call):
    y = walk(200_000, np.random.default_rng(5))
    call(y[:10])  # compile first
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        force, _ = call(y)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak - force.nbytes <= 64 * 1024  # O(N) beyond the output, no O(T) temporary


def test_bad_arguments_are_reported():
    with pytest.raises(ValueError, match="`weight` must have the shape of `threshold`"):
        PIBatch([[0.1, 0.2]], [[1.0]])
    with pytest.raises(ValueError, match=r"must be nonnegative; got -0\.2 at index \(0, 1\)"):
        PIBatch([[0.1, -0.2]], [[1.0, 1.0]])
    with pytest.raises(ValueError, match=r"`linear` must be a scalar or have shape \(2,\)"):
        PIBatch([[0.1], [0.2]], [[1.0], [1.0]], linear=[1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match=r"`coulomb` must be nonnegative; got -1\.0 at index 1"):
        PIBatch([[0.1], [0.2]], [[1.0], [1.0]], coulomb=[0.0, -1.0])
    batch = PIBatch([[0.1], [0.2]], [[1.0], [1.0]])
    with pytest.raises(TypeError, match="`state` must be a PIBatchState or None; got PIState"):
        batch.apply([0.0, 1.0], PIState(0.0, [0.0]))
    with pytest.raises(ValueError, match=r"`state` must hold play states of shape \(2, 1\)"):
        batch.apply([0.0, 1.0], PIBatchState(0.0, np.zeros((3, 1))))
    with pytest.raises(ValueError, match=r"got \|0.0 − 0.5\| > 0.2 at index \(1, 0\)"):
        batch.apply([0.0, 1.0], PIBatchState(0.0, [[0.0], [0.5]]))
    with pytest.raises(ValueError, match=r"`out` must be a writeable C-contiguous float64 array"):
        batch.apply([0.0, 1.0], out=np.empty((2, 3)))
    with pytest.raises(ValueError, match="`y` must be finite; got nan at index 1"):
        batch.apply([0.0, np.nan])
    with pytest.raises(ValueError, match="must all have 2 elements"):
        PIBatch.stack([PIOperator([0.1, 0.2], [1, 1]), PIOperator([0.1], [1])])
    with pytest.raises(ValueError, match="must share `last_input` and `direction`"):
        PIBatchState.stack([PIState(0.0, [0.0]), PIState(1.0, [1.0])])
    with pytest.raises(TypeError, match="`models` must hold PIFriction models; got PIOperator"):
        friction_batch([PIOperator([0.1], [1.0])])


def test_docstring_examples_run():
    import doctest

    import presliding.friction.batch
    import presliding.hysteresis.batch

    for module in (presliding.hysteresis.batch, presliding.friction.batch):
        assert doctest.testmod(module).failed == 0


def test_out_arguments_of_apply_and_force():
    y = walk(64, np.random.default_rng(8))
    op = PIOperator([0.1, 0.2], [1.0, 2.0])
    model = PIFriction(0.5, stiffness=[1.0, 2.0], threshold=[0.1, 0.2])
    buf = np.empty(64)
    force, _ = op.apply(y, out=buf)
    assert force is buf and np.array_equal(buf, op.apply(y)[0])
    force, _ = model.force(y, out=buf)
    assert force is buf and np.array_equal(buf, model.force(y)[0])
    with pytest.raises(ValueError, match=r"`out` must be .* of shape \(64,\); got a read-only"):
        ro = np.empty(64)
        ro.setflags(write=False)
        op.apply(y, out=ro)
    with pytest.raises(ValueError, match=r"`out` must be .*; got a non-contiguous float64"):
        model.force(y, out=np.empty(128)[::2])


def test_a_zero_threshold_is_the_identity_as_for_pi_operator():
    y = walk(200, np.random.default_rng(9))
    ops = [PIOperator([0.0, 0.1], [2.0, 1.0]), PIOperator([0.2, 0.0], [1.0, 3.0])]
    force, final = PIBatch.stack(ops).apply(y)
    for b, op in enumerate(ops):
        f, s = op.apply(y)
        assert_bit_identical(final.member(b).play, s.play)
        assert np.max(np.abs(force[:, b] - f)) <= 1e-12 * 4


@pytest.mark.parametrize("n_members", [1, 3])
def test_out_may_be_a_view_of_the_input(n_members):
    """`out` sharing memory with `y` (y a column of out) gives the values of a fresh output."""
    t = np.linspace(0.0, 20.0, 700)
    batch = PIBatch(np.tile([0.1, 0.3, 0.05], (n_members, 1)), np.ones((n_members, 3)))
    buffer = np.empty((t.size, n_members))
    buffer[:, 0] = np.sin(t) + 0.2 * np.sin(7 * t)
    y = buffer[:, 0]
    expected, state = batch.apply(y.copy())
    got, got_state = batch.apply(y, out=buffer)  # B = 1: y is contiguous, read in place
    assert got is buffer
    np.testing.assert_array_equal(got, expected)
    np.testing.assert_array_equal(got_state.play, state.play)


def test_the_output_size_is_checked_before_allocation(monkeypatch):
    monkeypatch.setattr("presliding._validation.MAX_ALLOCATION_BYTES", 8 * 10**4)
    batch = PIBatch(np.full((4, 2), 0.1), np.ones((4, 2)))
    with pytest.raises(ValueError, match=r"^`y` must ask for at most 10000 forces \(T × B\)"):
        batch.apply(np.zeros(3000))
    out = np.empty((3000, 4))  # a buffer the caller made is used as it is
    assert batch.apply(np.zeros(3000), out=out)[0] is out
