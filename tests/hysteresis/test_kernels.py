"""Fast kernels against the straightforward ones (eqs. 3, 4, 17).

Play states and deformations must be bit-identical; sums (the PI output, the
fused identification loss) agree within 1e-12 of the force scale; chunked runs
equal whole runs bit for bit.
"""

from __future__ import annotations

import itertools

import numba as nb
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from presliding import PIFriction
from presliding.hysteresis import _fused, _kernels
from presliding.identification.problem._pi_regression import batch_stop_loss
from presliding.motion import _implicit
from presliding.motion._run import implicit_grid

SIZES = [0, 1, 2, 3, 5, 7, 8, 9, 15, 16, 17, 100, 1000]


def bits(a: np.ndarray) -> np.ndarray:
    """The bit patterns of a float array (+0.0 for either signed zero)."""
    return (np.asarray(a, dtype=np.float64) + 0.0).view(np.int64)


def assert_bit_identical(a: np.ndarray, b: np.ndarray) -> None:
    assert a.shape == b.shape
    assert np.array_equal(bits(a), bits(b))


def bank(n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Thresholds over two decades, weights of both signs (eq. 4 allows any real weight)."""
    r = 10 ** rng.uniform(-2.0, 0.0, n)
    w = 10 ** rng.uniform(-1.0, 2.0, n) * rng.choice([-1.0, 1.0, 1.0], n)
    return r, w


def walk(n_time: int, rng: np.random.Generator, offset: float = 0.0) -> np.ndarray:
    return offset + np.cumsum(rng.normal(0.0, 0.05, n_time))


def reference(y, r, w, x0):
    """The straightforward kernel: one time step per pass, sum in element order."""
    x = x0.copy()
    out = np.empty(y.shape[0])
    _kernels._stop_sum_short(y, r, w, x, out)
    return out, x


def blocked(y, r, w, x, out):
    """The two-sided time-blocked kernel, with no linear or Coulomb term."""
    return _fused.stop_sum_blocked(y, r, w, x, out, 0.0, 0.0, y[0], 0.0)


def one_sided(y, r, w, x, out):
    """The one-sided time-blocked kernel, with no linear or Coulomb term."""
    return _fused.stop_sum_one_sided(y, r, w, x, out, 0.0, 0.0, y[0], 0.0)


def scale(r, w) -> float:
    """F_m = Σ |w_j| r_j, the force scale of the 1e-12 criterion."""
    return float(np.abs(w) @ r) if r.size else 1.0


# ----------------------------------------------------------------------------- stop sum


@pytest.mark.parametrize("n", SIZES)
@pytest.mark.parametrize("n_time", [1, 2, 3, 4, 5, 11, 997])
def test_stop_sum_matches_the_straightforward_kernel(n, n_time):
    rng = np.random.default_rng(1000 * n + n_time)
    r, w = bank(n, rng)
    y = walk(n_time, rng)
    x0 = y[0] - rng.uniform(-1.0, 1.0, n) * r  # a non-relaxed start
    ref, x_ref = reference(y, r, w, x0)
    for kernel in (_kernels.stop_sum, blocked, one_sided):
        x = x0.copy()
        out = np.empty(n_time)
        kernel(y, r, w, x, out)
        assert_bit_identical(x, x_ref)
        assert np.max(np.abs(out - ref)) <= 1e-12 * scale(r, w)


def plateaued_input(n_time: int, rng: np.random.Generator, offset: float) -> np.ndarray:
    """A walk on a coarse grid around ``offset``: plateaus (equal samples), reversals of every
    length and, with a large offset, bands y ± r that round."""
    steps = rng.choice([-2.0, -1.0, 0.0, 0.0, 1.0, 3.0], n_time) * 0.003
    return offset + np.cumsum(steps)


@settings(max_examples=60, deadline=None)
@given(
    n=st.sampled_from([1, 8, 64, 200]),
    n_time=st.integers(1, 300),
    offset=st.sampled_from([0.0, 1.0, 1e3, -1e8]),
    seed=st.integers(0, 2**32 - 1),
)
def test_one_sided_updates_are_bit_identical_to_the_two_sided_clamp(n, n_time, offset, seed):
    # the one-sided update relies on each state lying in its band for the previous
    # sample; the state handed in does not (some lie far outside), so the first
    # sample must take the full clamp
    rng = np.random.default_rng(seed)
    r, w = bank(n, rng)
    y = plateaued_input(n_time, rng, offset)
    x0 = y[0] + rng.uniform(-3.0, 3.0, n) * r
    ref, x_ref = reference(y, r, w, x0)
    x_play = x0.copy()
    states = np.empty((n_time, n))
    _kernels.play_outputs(y, r, x_play, states)
    x = x0.copy()
    out = np.empty(n_time)
    one_sided(y, r, w, x, out)
    assert_bit_identical(x, x_ref)
    assert_bit_identical(x, x_play)
    # every intermediate state: the state after each prefix of the input
    for t in range(n_time):
        x_prefix = x0.copy()
        one_sided(y[: t + 1], r, w, x_prefix, np.empty(t + 1))
        assert_bit_identical(x_prefix, states[t])
    bound = 1e-12 * scale(r, w) + np.abs(w).sum() * np.spacing(abs(offset) + 1.0)
    assert np.max(np.abs(out - ref)) <= bound


def test_one_sided_kernel_clamps_an_outside_start_on_both_sides_first():
    # a test that can fail: dropping the first full clamp gives other states here
    r = np.array([0.1, 0.2] * 32)
    w = np.ones(64)
    y = np.array([0.0, 0.05, 0.1])
    x0 = np.full(64, 5.0)  # far above every band
    x = x0.copy()
    out = np.empty(3)
    one_sided(y, r, w, x, out)
    np.testing.assert_array_equal(x, r)  # clamped to y + r at y = 0, then inside the band
    assert out[0] == pytest.approx(-(0.1 * 32 + 0.2 * 32))


def test_stop_sum_play_states_are_those_of_play_outputs():
    rng = np.random.default_rng(5)
    r, w = bank(13, rng)
    y = walk(3001, rng, offset=1e3)  # large offset: rounding of y ± r matters
    x = np.full(13, y[0])
    out = np.empty(y.size)
    _kernels.stop_sum(y, r, w, x, out)
    x_play = np.full(13, y[0])
    states = np.empty((y.size, 13))
    _kernels.play_outputs(y, r, x_play, states)
    assert_bit_identical(x, x_play)
    # the sum of the stored play states, in element order, agrees within 1e-12·F_m
    direct = (y[:, None] - states) @ w
    assert np.max(np.abs(out - direct)) <= 1e-12 * scale(r, w) + np.abs(w).sum() * np.spacing(1e3)


@settings(max_examples=40, deadline=None)
@given(
    n=st.sampled_from([1, 3, 5, 8, 12, 40, 64, 130]),
    cuts=st.lists(st.integers(0, 400), min_size=1, max_size=6),
    seed=st.integers(0, 2**32 - 1),
)
def test_stop_sum_chunked_equals_whole(n, cuts, seed):
    rng = np.random.default_rng(seed)
    r, w = bank(n, rng)
    y = walk(400, rng)
    whole = np.empty(y.size)
    x_whole = np.full(n, y[0])
    _kernels.stop_sum(y, r, w, x_whole, whole)
    edges = [0, *sorted(set(cuts)), y.size]
    x = np.full(n, y[0])
    parts = []
    for a, b in itertools.pairwise(edges):
        if b > a:
            out = np.empty(b - a)
            _kernels.stop_sum(y[a:b], r, w, x, out)
            parts.append(out)
    assert_bit_identical(np.concatenate(parts), whole)
    assert_bit_identical(x, x_whole)


# ----------------------------------------------------------------------------- fused loss


def straightforward_loss(y, target, r, w, a):
    """Loss of each batch member from the straightforward kernel's full output."""
    n_batch, n = r.shape
    loss = np.empty(n_batch)
    states = np.empty((n, n_batch))
    for b in range(n_batch):
        out, x = reference(y, r[b].copy(), w[b].copy(), np.full(n, y[0]))
        e = out + a[b] * y - target
        loss[b] = e @ e
        states[:, b] = x
    return loss, states


@pytest.mark.parametrize("plateaus", [False, True], ids=["walk", "plateaus"])
@pytest.mark.parametrize(
    ("n", "n_batch", "n_time"), [(5, 64, 1001), (3, 37, 6), (1, 1, 1), (9, 70, 97)]
)
def test_fused_loss_matches_the_straightforward_kernel(n, n_batch, n_time, plateaus):
    rng = np.random.default_rng(n * n_batch + n_time)
    r = 10 ** rng.uniform(-2.0, 0.0, (n_batch, n))
    w = 10 ** rng.uniform(-1.0, 2.0, (n_batch, n))
    a = rng.normal(0.0, 1.0, n_batch)
    # equal samples and a large offset exercise the one-sided updates' rounding argument
    y = plateaued_input(n_time, rng, 1e3) if plateaus else walk(n_time, rng)
    target = rng.normal(0.0, 1.0, n_time) + 0.5 * y
    ref, x_ref = straightforward_loss(y, target, r, w, a)
    # residual e = F − target: a rounding δ <= 1e-12·F_m in F moves e² by at most 2|e|δ + δ²
    fm = np.abs(w * r).sum(axis=1)
    resid_scale = np.sqrt(ref * n_time) + n_time * fm
    losses = []
    for kernel in (_fused.batch_loss, _fused.batch_loss_parallel):
        x = np.full((n, n_batch), y[0])
        loss = np.zeros(n_batch)
        r_t, w_t = np.ascontiguousarray(r.T), np.ascontiguousarray(w.T)
        kernel(y, y, target, r_t, w_t, a, np.zeros(n_batch), x, loss)
        assert_bit_identical(x, x_ref)
        assert np.all(np.abs(loss - ref) <= 2e-12 * fm * resid_scale)
        losses.append(loss)
    # each member is computed by the same code whatever the thread split
    assert_bit_identical(losses[0], losses[1])
    wrapped = batch_stop_loss(y, target, r, w, a, parallel=True)
    assert_bit_identical(wrapped, losses[0])


def test_fused_loss_with_a_design_signal_an_offset_and_a_burn_in():
    # the loss of the friction model of eq. 8 (c1·direction + offset + elastic force)
    model = PIFriction(0.3, [50.0, 20.0, 5.0], threshold=[0.01, 0.03, 0.1])
    y = walk(701, np.random.default_rng(8))
    elastic, _ = model.elastic_force(y)
    direction = np.empty(y.size)
    _kernels.motion_direction(y, y[0], 0.0, direction)
    target = model.force(y)[0] + 0.05 * np.sin(np.arange(y.size))
    skip = 37
    e = 0.3 * direction + 0.2 + elastic - target
    loss = batch_stop_loss(
        y, target, model.threshold[None, :], model.stiffness[None, :], np.array([0.3]),
        design=direction, offset=np.array([0.2]), skip=skip,
    )  # fmt: skip
    assert loss[0] == pytest.approx(float(e[skip:] @ e[skip:]), rel=1e-12)
    whole = batch_stop_loss(y, target, model.threshold[None, :], model.stiffness[None, :])
    assert whole[0] == pytest.approx(float((elastic - target) @ (elastic - target)), rel=1e-12)


def test_fused_loss_is_zero_on_its_own_output():
    rng = np.random.default_rng(11)
    r, w = bank(5, rng)
    y = walk(501, rng)
    out, _ = reference(y, r, np.abs(w), np.full(5, y[0]))
    loss = batch_stop_loss(y, out, r[None, :], np.abs(w)[None, :])
    assert loss[0] <= (1e-12 * scale(r, w)) ** 2 * y.size
    shifted = batch_stop_loss(y, out + 0.5, r[None, :], np.abs(w)[None, :])
    assert shifted[0] == pytest.approx(0.25 * y.size, rel=1e-12)


# ----------------------------------------------------------------------------- stepper


@nb.njit(**{**_implicit._JIT, "cache": False})  # the same arithmetic flags
def reference_stepper(m, c1, k, r, f, y, v, t_grid, u_mid):
    """The implicit step of `presliding.motion._implicit` with the straightforward `_commit`.

    Returns the trajectory (y, v, dissipated) after every step and the final state.
    """
    n_steps = t_grid.shape[0] - 1
    ktot = 0.0
    for j in range(k.shape[0]):
        ktot += k[j]
    fel, kpos, kneg, _, dpos, dneg = _implicit._commit(k, r, f, 0.0)
    dis = 0.0
    o_y = np.empty(n_steps)
    o_v = np.empty(n_steps)
    o_dis = np.empty(n_steps)
    for i in range(n_steps):
        h = t_grid[i + 1] - t_grid[i]
        inv_h = 1.0 / h
        m_h = m * inv_h
        mh2 = m_h * inv_h
        u = u_mid[i]
        g = m_h * v + u - fel
        if abs(g) <= c1:
            v_new = 0.0
        else:
            if g > 0.0:
                s, b, slope, dist = 1.0, g - c1, mh2 + ktot - kpos, dpos
            else:
                s, b, slope, dist = -1.0, -g - c1, mh2 + ktot - kneg, dneg
            d = b / slope
            if d >= dist:
                d = _implicit._newton_walk(mh2, k, r, f, s, b, slope, d)
            delta = s * d
            fel, kpos, kneg, dplastic, dpos, dneg = _implicit._commit(k, r, f, delta)
            y += delta
            v_new = delta * inv_h
            dis += c1 * d + dplastic
        v = v_new
        o_y[i] = y
        o_v[i] = v
        o_dis[i] = dis
    return o_y, o_v, o_dis


@pytest.mark.parametrize("n", [0, 1, 5])
@pytest.mark.parametrize("amplitude", [3.0, 1.0, 0.35])
def test_stepper_is_bit_identical_to_the_straightforward_step(n, amplitude):
    """Gross sliding (all elements saturated: the short cut), presliding stick-slip,
    and sticking, sampled at every step."""
    m, c1 = 1.0, 0.3
    k = np.array([400.0, 200.0, 100.0, 50.0, 25.0])[:n]
    r = np.array([0.001, 0.002, 0.004, 0.008, 0.016])[:n]
    grid, _ = implicit_grid(0.0, 4.0, np.array([0.0, 4.0]), 1e-4)
    u = amplitude * np.sin(np.pi * 0.5 * (grid[1:] + grid[:-1]))
    n_steps = grid.size - 1
    out_idx = np.arange(n_steps + 1)
    o = [np.empty(n_steps + 1) for _ in range(8)]
    rev = [np.empty(256) for _ in range(2)]
    f = np.zeros(n)
    _implicit.run_implicit(m, c1, k, r, f, 0.0, 0.0, 0.0, grid, u, out_idx, *o, *rev)
    f_ref = np.zeros(n)
    y_ref, v_ref, dis_ref = reference_stepper(m, c1, k, r, f_ref, 0.0, 0.0, grid, u)
    assert_bit_identical(f, f_ref)
    assert_bit_identical(o[0][1:], y_ref)
    assert_bit_identical(o[1][1:], v_ref)
    assert np.max(np.abs(o[6][1:] - dis_ref)) <= 1e-12 * max(dis_ref[-1], 1e-300)
    if amplitude == 3.0 and n:
        assert np.any(np.abs(f) == r)  # the gross-sliding short cut was exercised


@pytest.mark.parametrize("n", [0, 1, 7, 8, 9, 17, 1000])
def test_peak_is_the_largest_magnitude(n):
    """`peak` (one pass, eight partial maxima) equals max |y|, wherever the extreme sits."""
    rng = np.random.default_rng(n)
    y = rng.normal(0.0, 1.0, n)
    assert _kernels.peak(y) == (float(np.abs(y).max()) if n else 0.0)
    for i in range(n):  # the extreme in every lane and in the remainder
        z = y.copy()
        z[i] = -1e3 if i % 2 else 1e3
        assert _kernels.peak(z) == 1e3
