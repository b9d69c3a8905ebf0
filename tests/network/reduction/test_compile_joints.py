"""A structure with joints loaded along one vector: an exact linear spring plus PI operator."""

import numpy as np
import pytest

from presliding import PIFriction, SegalmanIwan
from presliding.network import GROUND, SliderNetwork, compile_network, compile_structure
from presliding.network.reduction.compile import network_force
from presliding.network.reduction.compile_joints import _structure, replay

HISTORY = np.array([0.0, 1.0, -0.7, 0.45, -0.2, 0.3, -0.05, 0.6, -1.1, 0.35, 0.1, -0.4, 1.3])


def _as_structure(net):
    """The network's springs as K, its sliders and stops as joints on node differences."""
    k = np.zeros((net.n_nodes, net.n_nodes))

    def column(a, b):
        w = np.zeros(net.n_nodes)
        for node, sign in ((int(a), 1.0), (int(b), -1.0)):
            if node != GROUND:
                w[node] = sign
        return w

    for a, b, s in net.springs:
        w = column(a, b)
        k += s * np.outer(w, w)
    cols, joints = [], []
    for a, b, c in net.sliders:
        cols.append(column(a, b))
        joints.append(PIFriction(c))
    for a, b, s, c in net.stops:
        cols.append(column(a, b))
        joints.append(PIFriction(0.0, [s], breakaway=[c]))
    return k, np.array(cols).T, joints


def _graph6(seed):
    rng = np.random.default_rng(seed)
    pairs = [(0, 1), (1, 2), (2, 3), (3, 4), (4, 5), (5, 1), (1, 3), (2, 4), (0, 5)]
    springs = [(a, b, rng.uniform(5, 200)) for a, b in pairs]
    sliders = [(i, GROUND, rng.uniform(0.1, 2.0)) for i in range(1, 6)]
    stops = [(i, GROUND, rng.uniform(5, 200), rng.uniform(0.1, 2.0)) for i in (0, 2, 4)]
    return SliderNetwork(6, springs, sliders, stops)


@pytest.mark.parametrize("seed", range(4))
def test_a_slider_network_driven_at_a_node_compiles_as_compile_network_does(seed):
    """An independent solver: the network's own event-driven sweeping process."""
    net = _graph6(seed)
    model = compile_network(net, 0)
    k, w, joints = _as_structure(net)
    load = np.eye(net.n_nodes)[0]
    op = compile_structure(k, w, joints, load, verify=True)
    assert op.linear_stiffness == 0.0  # the node reaches the ground through sliders only
    np.testing.assert_allclose(op.friction.threshold, model.threshold, rtol=1e-12)
    np.testing.assert_allclose(op.friction.stiffness, model.stiffness, rtol=1e-10)
    u = 1.4 * np.max(model.threshold) * HISTORY
    f_net = network_force(net, np.array([0]), np.array([1.0]), u)
    assert np.max(np.abs(op.force(u) - f_net)) <= 1e-12 * np.max(np.abs(f_net))


def _jenkins_chain():
    """NLvib's chain of three unit masses and four unit springs, Jenkins joints k = 20, μN = 1
    on q1 and on q2 − q1."""
    k = np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 2]])
    w = np.array([[1.0, -1.0], [0.0, 1.0], [0.0, 0.0]])
    jenkins = PIFriction(0.0, [20.0], breakaway=[1.0])
    return k, w, [jenkins, jenkins]


@pytest.mark.parametrize("mode", range(3))
def test_every_mode_of_the_jenkins_chain_replays_as_its_operator(mode):
    k, w, joints = _jenkins_chain()
    stuck = k + 20.0 * w @ w.T
    lam, phi = np.linalg.eigh(stuck)
    op = compile_structure(k, w, joints, phi[:, mode], verify=True)
    assert op.initial_stiffness == pytest.approx(lam[mode], rel=1e-13)  # φᵀK_stuck φ
    net = _structure(k, w, joints, phi[:, mode])
    rng = np.random.default_rng(mode)
    history = np.r_[0.0, np.cumsum(rng.normal(size=12))] * np.max(op.friction.threshold)
    u, p = replay(net, history)
    np.testing.assert_allclose(op.force(np.r_[0.0, u])[1:], p, rtol=0, atol=1e-12 * np.abs(p).max())
    # the deflection on the virgin curve is the stuck mode's at small amplitudes
    small = 0.5 * op.friction.threshold.min()
    np.testing.assert_allclose(op.deflection([small])[0], small * phi[:, mode] / 1.0, rtol=1e-12)


def test_a_load_that_reverses_a_joint_is_refused():
    k = np.array([[0.193, 0.211], [0.211, 5.822]])
    w = np.array([[-0.378, 2.043], [0.647, 0.663]])
    joints = [
        PIFriction(0.0, [1.561], breakaway=[1.057]),
        PIFriction(0.0, [8.674], breakaway=[5.496]),
    ]
    with pytest.raises(ValueError, match="order-preserving"):
        compile_structure(k, w, joints, [-0.514, -1.648])


def test_mixed_sign_node_loads_either_raise_or_replay_exactly():
    """Loads that compile_network refuses (no order preservation promised) never give a wrong
    operator: the joints' directions are watched and the replay checks the rest."""
    outcomes = []
    for seed in range(8):
        net = _graph6(seed)
        k, w, joints = _as_structure(net)
        load = np.zeros(net.n_nodes)
        load[[0, 3]] = [1.0, -1.0]
        try:
            op = compile_structure(k, w, joints, load, verify=True)
        except ValueError as err:
            outcomes.append(str(err).split(":")[0])
            continue
        history = np.max(op.friction.threshold) * HISTORY
        u, p = replay(_structure(k, w, joints, load), history)
        assert np.max(np.abs(op.force(np.r_[0.0, u])[1:] - p)) <= 1e-9 * np.abs(p).max()
        outcomes.append("ok")
    assert any("order-preserving" in o for o in outcomes)


def test_bad_inputs_are_refused():
    k, w, joints = _jenkins_chain()
    with pytest.raises(ValueError, match="`load` must be a nonzero vector of shape"):
        compile_structure(k, w, joints, [1.0, 0.0])
    with pytest.raises(ValueError, match="one model per contact"):
        compile_structure(k, w, joints[:1], [1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="not a density"):
        compile_structure(k, w, [PIFriction(0.0, density=SegalmanIwan(1, 1, 0, 0))] * 2, [1, 0, 0])
    with pytest.raises(ValueError, match="must be symmetric"):
        compile_structure([[1.0, 2.0], [0.0, 1.0]], np.eye(2), joints, [1.0, 0.0])
    with pytest.raises(ValueError, match="hold the structure"):
        compile_structure([[0.0]], [[1.0]], [PIFriction(1.0)], [1.0])  # rigid: u cannot move


def test_a_load_that_no_joint_feels_is_a_linear_spring():
    op = compile_structure(np.diag([2.0, 3.0]), [[1.0], [0.0]], [PIFriction(0.0, [5.0], [1.0])],
                           [0.0, 1.0])  # fmt: skip
    assert op.friction is None and op.linear_stiffness == pytest.approx(3.0, rel=1e-15)
    np.testing.assert_allclose(op.force([0.0, 2.0, -1.0]), [0.0, 6.0, -3.0], rtol=1e-14)
