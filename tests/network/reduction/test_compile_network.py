"""A slider network driven through one input is one exact PI operator (Krejčí et al. 2014)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import presliding as ps
from presliding import MicroslipBar, PIFriction, amplitude_response
from presliding.network import GROUND, SliderNetwork, compile_network, network_virgin_curve
from presliding.network.reduction.compile import network_force

HISTORY = np.array([0.0, 1.0, -0.7, 0.45, -0.2, 0.3, -0.05, 0.6, -1.1, 0.35, 0.1, -0.4, 1.3])


def _chain4(seed):
    rng = np.random.default_rng(seed)
    springs = [(i, i + 1, rng.uniform(5, 200)) for i in range(3)]
    sliders = [(i, GROUND, rng.uniform(0.1, 2.0)) for i in (1, 2, 3)]
    stops = [(0, GROUND, rng.uniform(5, 200), rng.uniform(0.1, 2.0))]
    return SliderNetwork(4, springs, sliders, stops)


def _graph6(seed):
    rng = np.random.default_rng(seed)
    pairs = [(0, 1), (1, 2), (2, 3), (3, 4), (4, 5), (5, 1), (1, 3), (2, 4), (0, 5)]
    springs = [(a, b, rng.uniform(5, 200)) for a, b in pairs]
    sliders = [(i, GROUND, rng.uniform(0.1, 2.0)) for i in range(1, 6)]
    stops = [(i, GROUND, rng.uniform(5, 200), rng.uniform(0.1, 2.0)) for i in (0, 2, 4)]
    return SliderNetwork(6, springs, sliders, stops)


def _compare(net, load, model, scale):
    nodes = np.array(sorted(load))
    coef = np.array([load[i] for i in sorted(load)])
    coef = -coef if np.all(coef < 0) else coef
    u = scale * HISTORY
    f_net = network_force(net, nodes, coef, u)
    f_pi, _ = model.force(u)
    return float(np.max(np.abs(f_net - f_pi)) / np.max(np.abs(f_net)))


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("build", [_chain4, _graph6])
def test_network_equals_its_compiled_operator(build, seed):
    net = build(seed)
    model = compile_network(net, 0)
    assert isinstance(model, PIFriction) and model.n_elements >= 3
    assert _compare(net, {0: 1.0}, model, 1.4 * np.max(model.threshold)) <= 1e-12


def _two_inputs(seed):
    """Nodes 0 and 4 driven; they reach the rest through stops (no spring path between them)."""
    rng = np.random.default_rng(seed)
    springs = [(1, 2, rng.uniform(5, 200)), (2, 3, rng.uniform(5, 200)), (1, 3, 40.0),
               (2, GROUND, rng.uniform(5, 200))]  # fmt: skip
    sliders = [(i, GROUND, rng.uniform(0.1, 2.0)) for i in (1, 2, 3)]
    stops = [(0, 1, rng.uniform(5, 200), rng.uniform(0.1, 2.0)),
             (4, 3, rng.uniform(5, 200), rng.uniform(0.1, 2.0)),
             (0, 2, rng.uniform(5, 200), rng.uniform(0.1, 2.0))]  # fmt: skip
    return SliderNetwork(5, springs, sliders, stops)


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize(
    "build, load", [(_graph6, {0: 1.0, 3: 1.0}), (_two_inputs, {0: 1.0, 4: 0.4})]
)
def test_two_inputs_of_one_sign_compile(build, load, seed):
    net = build(seed)
    model = compile_network(net, load)
    assert _compare(net, load, model, 1.4 * np.max(model.threshold)) <= 1e-12
    # the negative load vector gives the same operator
    same = compile_network(net, {node: -a for node, a in load.items()})
    assert same == model


def test_mixed_sign_loads_are_refused_and_would_be_wrong():
    """With loads (u, −u) the PI operator of the virgin curve can fail; compile refuses them all."""
    deviations = []
    for seed in range(12):
        net = _two_inputs(seed)
        load = {0: 1.0, 4: -1.0}
        with pytest.raises(ValueError, match="one sign"):
            compile_network(net, load)
        c1, breaks, _, slopes = network_virgin_curve(net, load)
        drops = slopes[:-1] - slopes[1:]
        keep = drops > 1e-13 * slopes.max()
        if slopes[-1] > 1e-12 * slopes.max() or np.any(drops < -1e-12 * slopes.max()):
            deviations.append(np.inf)  # not even a PI operator's virgin curve
            continue
        naive = PIFriction(c1, drops[keep], threshold=breaks[keep])
        deviations.append(_compare(net, load, naive, 1.4 * np.max(breaks)))
    # the refusal is needed: some networks deviate from the naive reduction
    assert max(deviations) > 1e-6


def test_coulomb_element_and_a_known_network():
    net = SliderNetwork(2, springs=[(0, 1, 50.0)], sliders=[(1, GROUND, 1.0), (0, GROUND, 0.3)],
                        stops=[(0, GROUND, 100.0, 0.5)])  # fmt: skip
    model = compile_network(net, 0)
    assert model == PIFriction(0.3, [100.0, 50.0], threshold=[0.005, 0.02])
    # every tool takes it
    tp = ps.turning_points(model, 1.0, 0.05)
    assert tp.success
    assert ps.amplitude_response(model, [0.01]).dissipation[0] > 0


def test_an_elastic_path_to_ground_is_refused():
    net = SliderNetwork(2, springs=[(0, 1, 50.0), (1, GROUND, 10.0)], sliders=[(1, GROUND, 1.0)])
    with pytest.raises(ValueError, match="grows without bound"):
        compile_network(net, 0)


@pytest.mark.parametrize(
    "load, match",
    [
        ({}, "load"),
        ({7: 1.0}, "load"),
        ({0: 0.0}, "nonzero"),
        ("0", "load"),
        ({0: math.inf}, "finite"),
    ],
)
def test_bad_loads_are_named(load, match):
    with pytest.raises((ValueError, TypeError), match=match):
        compile_network(_chain4(0), load)


@st.composite
def _chains(draw):
    n = draw(st.integers(2, 5))
    k = draw(st.lists(st.floats(1.0, 1e3), min_size=n, max_size=n))
    c = draw(st.lists(st.floats(0.05, 5.0), min_size=n, max_size=n))
    springs = [(i, i + 1, k[i]) for i in range(n - 1)]
    sliders = [(i + 1, GROUND, c[i]) for i in range(n - 1)]
    stops = [(0, GROUND, k[-1], c[-1])]
    return SliderNetwork(n, springs, sliders, stops)


@settings(max_examples=25, deadline=None)
@given(_chains(), st.floats(0.1, 0.9), st.floats(0.1, 0.9))
def test_masing_and_wiping_out_hold(net, frac1, frac2):
    model = compile_network(net, 0)
    big = 1.3 * np.max(model.threshold)
    a, b = big, -big * frac1
    # Masing: the branch after a reversal at a is the virgin curve doubled
    y = np.linspace(a, b, 30)
    f, _ = model.force(np.concatenate([[0.0], y]))
    fa = model.virgin_curve(a)
    np.testing.assert_allclose(f[1:], fa - 2 * model.virgin_curve((a - y) / 2),
                               rtol=1e-12, atol=1e-12 * fa)  # fmt: skip
    # wiping-out: a closed minor loop inside (b, a) is forgotten once the input passes it
    m = b + (a - b) * frac2
    with_loop = np.array([0.0, a, b, m, b, 1.5 * big])
    without = np.array([0.0, a, b, 1.5 * big])
    f1 = network_force(net, np.array([0]), np.array([1.0]), with_loop)
    f2 = network_force(net, np.array([0]), np.array([1.0]), without)
    # to rounding: the loop's events add a few ulps per event (1.1e-12 seen)
    assert f1[-1] == pytest.approx(f2[-1], rel=1e-11)
    assert model.force(with_loop)[0][-1] == pytest.approx(f2[-1], rel=1e-11)


def _bar_chain(n, ea, tau, length):
    c = np.full(n + 1, tau * length / n)
    c[[0, -1]] /= 2
    return SliderNetwork.chain(np.full(n, ea * n / length), c)


def test_a_chain_converges_to_the_microslip_bar_as_n_to_the_minus_two():
    ea, tau, length = 2e6, 5e3, 0.4
    force = 0.6 * tau * length  # F/(τL/N) is an integer for N a multiple of 5
    exact = MicroslipBar(ea, tau, length).loop_energy_at_force(force)
    assert exact == pytest.approx(2 * force**3 / (3 * ea * tau), rel=1e-15)
    errors = []
    for n in (10, 20, 40, 80):
        model = compile_network(_bar_chain(n, ea, tau, length), 0)
        # displacement amplitude of the force amplitude: invert the piecewise-linear backbone
        grid = np.concatenate([[0.0], model.threshold, [2 * model.threshold[-1]]])
        backbone = model.virgin_curve(grid[1:])
        a = np.interp(force, backbone, grid[1:])
        res = amplitude_response(model, [a])
        assert res.force[0] == pytest.approx(force, rel=1e-12)
        errors.append(abs(res.dissipation[0] / exact - 1.0))
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    np.testing.assert_allclose(ratios, 4.0, rtol=1e-6)  # second order
    assert errors[-1] < 3e-4


def test_the_replay_check_catches_a_wrong_operator():
    from presliding.network.reduction.compile import _verify

    net = _chain4(1)
    model = compile_network(net, 0, verify=True)
    _verify(net, np.array([0]), np.array([1.0]), model)  # passes
    wrong = PIFriction(0.0, model.stiffness * (1 + 1e-6), threshold=model.threshold)
    with pytest.raises(ValueError, match="not reproduced"):
        _verify(net, np.array([0]), np.array([1.0]), wrong)


@pytest.mark.parametrize("verify", ["yes", 1, "no"])
def test_verify_must_be_a_bool(verify):
    """`verify="yes"` (or "no", which is truthy too) was taken as True."""
    net = SliderNetwork(2, springs=[(0, 1, 50.0)], sliders=[(1, -1, 1.0)],
                        stops=[(0, -1, 100.0, 0.5)])  # fmt: skip
    with pytest.raises(TypeError, match="`verify` must be a bool"):
        compile_network(net, 0, verify=verify)
    assert compile_network(net, 0, verify=np.False_).coulomb == 0.0
