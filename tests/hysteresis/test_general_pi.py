"""The exact general PI operator (eqs. 10, 11) and PIFriction with a density."""

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from presliding import (
    Density,
    Discrete,
    Exponential,
    GeneralPIOperator,
    MemoryState,
    PiecewiseConstant,
    PIFriction,
    PIOperator,
    PIState,
    Uniform,
)
from presliding.hysteresis import _general_pi as gk

DENSITIES = [
    Uniform(2.0, 1.0),
    Exponential(3.0, 0.4),
    Exponential(3.0, 0.4, 1.0),
    PiecewiseConstant([0.1, 0.4, 1.2], [3.0, 0.5]),
    Density.from_function(lambda r: 1.0 + math.sin(3.0 * r) ** 2, 1.0),
    Discrete([1.0, 2.0, 3.0], [0.2, 0.5, 0.9]),
]
IDS = ["uniform", "exp", "exp-trunc", "piecewise", "tabulated", "discrete"]

paths = st.lists(
    st.floats(-3.0, 3.0, allow_nan=False, allow_subnormal=False), min_size=1, max_size=60
).map(np.array)
banks = st.integers(1, 6).flatmap(
    lambda n: st.tuples(
        st.lists(st.floats(0.1, 10.0), min_size=n, max_size=n),
        st.lists(st.floats(0.01, 1.0), min_size=n, max_size=n),
    )
)


def _walk(seed: int, n: int = 400) -> np.ndarray:
    rng = np.random.default_rng(seed)
    y = np.cumsum(rng.normal(size=n)) * 0.2
    tail = 0.6 * np.sin(np.linspace(0.0, 40.0, 300)) * np.exp(-np.linspace(0.0, 4.0, 300))
    return np.concatenate([y, y[-1] + tail])


@settings(max_examples=60, deadline=None)
@given(bank=banks, y=paths)
def test_discrete_density_equals_the_discrete_operator(bank, y):
    k, r = np.array(bank[0]), np.array(bank[1])
    exact, state = GeneralPIOperator(Discrete(k, r)).apply(y)
    ref, ref_state = PIOperator(r, k).apply(y)
    fm = float(np.sum(k * r))
    assert np.max(np.abs(exact - ref)) <= 1e-12 * fm
    np.testing.assert_allclose(state.play(r), ref_state.play, rtol=0, atol=1e-12)


@pytest.mark.parametrize("density", DENSITIES, ids=IDS)
def test_chunked_equals_whole_and_deformation_is_bounded(density):
    op = GeneralPIOperator(density)
    y = _walk(1)
    whole, final = op.apply(y)
    a, s1 = op.apply(y[:137])
    b, s2 = op.apply(y[137:], s1)
    assert np.array_equal(np.concatenate([a, b]), whole)
    np.testing.assert_array_equal(s2.turning, final.turning)
    r = np.linspace(0.0, 3.0, 301)
    assert np.all(np.abs(final.deformation(r)) <= r * (1 + 1e-12) + 1e-12)
    fm = density.max_elastic_force
    assert np.all(np.abs(whole) <= fm * (1 + 1e-12))


@settings(max_examples=40, deadline=None)
@given(y=paths, seed=st.integers(0, 2**16))
def test_property_chunks_states_rate_independence(y, seed):
    op = GeneralPIOperator(Exponential(2.0, 0.3, 1.5))
    whole, final = op.apply(y)
    cut = seed % len(y)
    if cut:
        a, s1 = op.apply(y[:cut])
        b, _ = op.apply(y[cut:], s1)
        assert np.array_equal(np.concatenate([a, b]), whole)
    # Rate independence: extra samples on the monotone pieces change nothing at the old ones.
    fine = np.concatenate([[y[0]], *[np.linspace(p, q, 4)[1:] for p, q in itertools.pairwise(y)]])
    dense, _ = op.apply(fine)
    np.testing.assert_allclose(dense[::3], whole, rtol=0, atol=1e-13)
    r = np.linspace(0.0, 2.0, 101)
    assert np.all(np.abs(final.deformation(r)) <= r + 1e-12)


@pytest.mark.parametrize("density", DENSITIES[:4], ids=IDS[:4])
def test_return_point_memory(density):
    """A minor loop that closes leaves no trace (wiping-out property)."""
    op = GeneralPIOperator(density)
    direct, _ = op.apply(np.array([0.0, 1.3, -0.4, 0.9]))
    looped, _ = op.apply(np.array([0.0, 1.3, -0.4, 0.5, 0.1, 0.4, 0.2, 0.9]))
    assert looped[-1] == pytest.approx(direct[-1], abs=1e-14)


@pytest.mark.parametrize("density", DENSITIES[:5], ids=IDS[:5])
def test_midpoint_discretisation_converges_with_order_two(density):
    op = GeneralPIOperator(density)
    y = _walk(2)
    exact, _ = op.apply(y)
    ns = np.array([50, 100, 200, 400, 800, 1600, 3200])
    big_r = density.max_threshold if math.isfinite(density.max_threshold) else 30 * 0.4
    err = []
    for n in ns:
        disc = density.discretize(int(n), big_r)
        approx, _ = PIOperator(disc.threshold, disc.stiffness).apply(y)
        err.append(np.sqrt(np.mean((approx - exact) ** 2)) / density.max_elastic_force)
    order = -np.polyfit(np.log(ns), np.log(err), 1)[0]
    assert 1.8 <= order <= 2.4, (order, err)
    assert err[-1] < 2e-5


@settings(max_examples=40, deadline=None)
@given(y=paths, trial=st.floats(-4.0, 4.0), k=st.integers(0, 5))
def test_force_at_is_pure_and_matches_one_more_sample(y, trial, k):
    density = DENSITIES[k]
    d = density
    op = GeneralPIOperator(d)
    _, state = op.apply(y)
    head, stack = state.working_memory(d)
    n = int(head[3])
    head0, stack0 = head.copy(), stack[:n].copy()
    f, slope = gk.force_at(trial, head, stack, d._kind, d._par, d._tab)
    assert np.array_equal(head, head0) and np.array_equal(stack[:n], stack0)
    ref, _ = op.apply(np.array([trial]), state)
    assert f == pytest.approx(ref[0], abs=1e-13 * d.max_elastic_force)
    assert 0.0 <= slope <= d.total_stiffness * (1 + 1e-12)
    # continuous μ: the slope is continuous away from the memory's turning points
    # (every turning point is a sample of y; the difference quotient must not cross one)
    if k < 5 and np.min(np.abs(y - trial)) > 1e-6:
        nxt = trial + 1e-7 * np.sign(trial - state.last_input)
        f2, _ = op.force_at(nxt, state)
        # One-sided derivative dF/dy = μ((ρ, R]), the stiffness still sticking (eq. 7 at ρ = 0).
        assert (f2 - f) / (nxt - trial) == pytest.approx(slope, rel=1e-3, abs=1e-5)


def test_saturated_and_relaxed_memories():
    for d in DENSITIES:
        op = GeneralPIOperator(d)
        f, _ = op.apply([0.0, -0.01], op.saturated_state(0.0, 1.0))
        assert f[0] == pytest.approx(d.max_elastic_force, rel=1e-14)
        # right after the reversal the stiffness is μ([0, R]) (eq. 7)
        assert (f[1] - f[0]) / -0.01 == pytest.approx(d.total_stiffness, rel=0.05)
        y = np.linspace(0.0, 2.5, 26)
        virgin, _ = op.apply(y, op.relaxed_state(0.0))
        np.testing.assert_allclose(virgin, d.virgin_curve(y), rtol=1e-13, atol=1e-15)
    assert gk.saturated_memory(1.0, -1.0, math.inf, 4)[0][2] == math.inf


def test_memory_state_validation_and_roundtrip():
    s = MemoryState(0.5, [1.0, 0.2], 0.0, 1.0)
    assert s.front == pytest.approx(0.15)
    with pytest.raises(ValueError, match="alternate"):
        MemoryState(0.5, [1.0, 1.2], 0.0, 1.0)
    with pytest.raises(ValueError, match="nested"):
        MemoryState(0.5, [1.0, -1.5], 0.0, 1.0)
    with pytest.raises(ValueError, match="direction"):
        MemoryState(0.5, [1.0, 0.2], 0.0, -1.0)
    with pytest.raises(ValueError, match="direction"):
        MemoryState.saturated(0.0, 0.0)
    op = GeneralPIOperator(Uniform(1.0, 1.0))
    with pytest.raises(TypeError, match="MemoryState"):
        op.apply([0.0, 1.0], PIState.relaxed(0.0, 2))
    head, stack = s.working_memory(op.density)
    assert MemoryState.from_working_memory(head, stack).turning.tolist() == [1.0, 0.2]


@pytest.mark.parametrize("density", DENSITIES[:5], ids=IDS[:5])
def test_pifriction_with_a_density(density):
    model = PIFriction(0.3, density=density)
    assert not model.is_discrete
    assert model.max_elastic_force == density.max_elastic_force
    assert model.coulomb_level == pytest.approx(0.3 + density.max_elastic_force)
    assert model.initial_stiffness == density.total_stiffness
    y = _walk(3, 200)
    force, _state = model.force(y)
    elastic, _state2 = model.elastic_force(y)
    exact, _ = GeneralPIOperator(density).apply(y)
    np.testing.assert_array_equal(elastic, exact)
    direction = np.sign(np.diff(y, prepend=y[0]))
    moved = direction != 0
    np.testing.assert_allclose(force[moved], (exact + 0.3 * direction)[moved], atol=1e-15)
    a, sa = model.force(y[:50])
    b, _ = model.force(y[50:], sa)
    assert np.array_equal(np.concatenate([a, b]), force)
    assert model.virgin_curve(0.2) == pytest.approx(0.3 + density.virgin_curve(0.2))
    assert isinstance(model.saturated_state(0.0, -1.0), MemoryState)
    with pytest.raises(TypeError, match="continuous density"):
        _ = model.n_elements
    assert model == PIFriction(0.3, density=density) and "density=" in repr(model)


def test_pifriction_discrete_density_is_the_finite_model():
    k, r = [10.0, 4.0], [0.1, 0.25]
    finite = PIFriction(0.5, k, threshold=r)
    via = PIFriction(0.5, density=Discrete(k, r))
    assert via == finite and via.is_discrete and finite.density == Discrete(k, r)
    y = _walk(4, 300)
    assert np.array_equal(via.force(y)[0], finite.force(y)[0])
    with pytest.raises(TypeError, match="not both"):
        PIFriction(0.5, k, threshold=r, density=Uniform(1.0, 1.0))
    with pytest.raises(TypeError, match="Density"):
        PIFriction(0.5, density="uniform")
