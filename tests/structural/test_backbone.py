"""Quasi-static modal analysis: ω(a), ζ(a), D(a) of a mode, exact for the model."""

import math

import numpy as np
import pytest

import presliding as ps
from presliding import PIFriction, SegalmanIwan, amplitude_response
from presliding.structural import JointedStructure, modal_backbone

AMPLITUDES = np.geomspace(1e-4, 10.0, 41)


def _closed_form(mass, spring, joint, a):
    """ω(a), ζ(a) of m·ẍ + k·x + F(x) from the joint's closed-form amplitude quantities."""
    x = a / math.sqrt(mass)  # the mass-normalised mode is 1/√m
    ar = amplitude_response(joint, x)
    force = spring * x + ar.force
    return np.sqrt(force / (mass * x)), ar.dissipation / (2 * math.pi * force * x), ar.dissipation


JOINTS = {
    "jenkins": PIFriction(0.0, [20.0], breakaway=[1.0]),
    "iwan elements": PIFriction(0.0, [5.0, 4.0, 3.0, 2.0], threshold=[0.01, 0.02, 0.05, 0.1]),
    "segalman density": PIFriction(0.0, density=SegalmanIwan(20.0, 1.0, -0.3, 0.2)),
    "mindlin density": PIFriction(0.0, density=ps.MindlinContact(1.0, 0.05)),
}


@pytest.mark.parametrize("spring", [3.0, 0.0])
@pytest.mark.parametrize("name", sorted(JOINTS))
def test_one_mass_one_joint_matches_the_closed_forms(name, spring):
    """The issue's check: 1e-12 against `amplitude_response` (a Jenkins or Iwan joint)."""
    mass, joint = 2.5, JOINTS[name]
    bb = modal_backbone(JointedStructure(mass, spring, [[1.0]], [joint]), 0, AMPLITUDES)
    w, zeta, d = _closed_form(mass, spring, joint, AMPLITUDES)
    np.testing.assert_allclose(bb.frequency, w, rtol=1e-12)
    np.testing.assert_allclose(bb.damping_ratio, zeta, rtol=1e-12, atol=0)
    np.testing.assert_allclose(bb.dissipation, d, rtol=1e-12, atol=0)
    assert bb.linear_frequency == pytest.approx(
        math.sqrt((spring + joint.initial_stiffness) / mass)
    )
    np.testing.assert_allclose(bb.joint_amplitude[:, 0], AMPLITUDES / math.sqrt(mass), rtol=1e-12)
    assert bb.success and (bb.operator is None) == (not joint.is_discrete)


def test_what_a_slow_decay_shows_for_a_jenkins_joint():
    """ζ_d = D/(2π·a·E'(a)) with E = ½k·a² + ½k_t·r² (the stop at its limit), and ω₁ the
    describing function of the stop: in closed form for one mass (m = 1)."""
    k, kt, r = 10.0, 2.0, 0.05
    st = JointedStructure(1.0, k, [[1.0]], [PIFriction(0.0, [kt], threshold=[r])])
    a = np.geomspace(0.06, 5.0, 12)
    bb = modal_backbone(st, 0, a)
    expected = 4 * kt * r * (a - r) / (2 * math.pi * k * a * a)
    np.testing.assert_allclose(bb.decay_damping_ratio, expected, rtol=1e-13)
    theta = np.arccos(1 - 2 * r / a)
    first = k + kt * (theta - np.sin(2 * theta) / 2) / math.pi
    np.testing.assert_allclose(bb.harmonic_frequency**2, first, rtol=1e-13)
    # below the threshold every definition gives the stuck oscillator
    small = modal_backbone(st, 0, [0.01])
    assert small.harmonic_frequency[0] == pytest.approx(math.sqrt(k + kt), rel=1e-15)
    assert small.decay_damping_ratio[0] == 0.0
    # nothing but the joint: beyond its threshold no stiffness holds the mode
    alone = modal_backbone(JointedStructure(1.0, 0.0, [[1.0]], [PIFriction(0.0, [kt], [r])]), 0,
                           [0.01, 1.0])  # fmt: skip
    assert alone.status == "macroslip" and np.isinf(alone.decay_damping_ratio[1])


def test_the_element_path_and_the_closed_form_path_agree_on_two_masses():
    """One joint with elements on a 2-DOF structure: the compiled operator and the one-joint
    closed form are two independent exact computations."""
    joint = PIFriction(0.0, [30.0, 10.0], threshold=[0.02, 0.08])
    st = JointedStructure([1.0, 2.0], [[5.0, -2.0], [-2.0, 3.0]], [[1.0], [-0.5]], [joint])
    a = np.geomspace(1e-3, 3.0, 25)
    compiled = modal_backbone(st, 0, a)
    from presliding.structural._single_joint import single_joint_curve

    p, d, q, tangent, first = single_joint_curve(
        st.stiffness, st.contacts[:, 0], st.mass @ compiled.mode_shape, joint, a
    )
    np.testing.assert_allclose(compiled.modal_force, p, rtol=1e-12)
    np.testing.assert_allclose(compiled.dissipation, d, rtol=1e-11)
    np.testing.assert_allclose(compiled.deflection, q, rtol=1e-11, atol=1e-14)
    # the slow-flow quantities: closed forms of the elements against the curve's quadrature
    np.testing.assert_allclose(compiled.harmonic_frequency**2, first, rtol=2e-6)
    np.testing.assert_allclose(compiled.decay_damping_ratio, d / (2 * np.pi * a * a * tangent),
                               rtol=1e-11)  # fmt: skip


def test_the_nlvib_chain_softens_and_damps_by_masing():
    """Three masses, two Jenkins joints (k = 20, μN = 1): ω falls from the stuck ω0 to the
    free structure's, D(a) is the loop area 8∫P − 4aP of the backbone."""
    k = np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 2]])
    w = np.array([[1.0, -1.0], [0.0, 1.0], [0.0, 0.0]])
    jenkins = PIFriction(0.0, [20.0], breakaway=[1.0])
    st = JointedStructure(np.eye(3), k, w, [jenkins, jenkins])
    a = np.geomspace(1e-3, 1e3, 60)
    bb = modal_backbone(st, 0, a)
    assert np.all(np.diff(bb.frequency) <= 1e-12)
    assert bb.frequency[0] == pytest.approx(np.sqrt(np.linalg.eigvalsh(k + 20 * w @ w.T)[0]))
    # once both joints slide, the load along φ meets the structure without joints (K⁻¹)
    phi = bb.mode_shape
    assert bb.operator.linear_stiffness == pytest.approx(1 / (phi @ np.linalg.solve(k, phi)))
    # the loop area from the backbone alone (trapezoids are exact on a piecewise-linear P)
    grid = np.unique(np.r_[0.0, bb.operator.friction.threshold, a])
    pg = bb.operator.virgin_curve(grid)
    area = np.r_[0.0, np.cumsum(np.diff(grid) * (pg[1:] + pg[:-1]) / 2)]
    i = np.searchsorted(grid, a)
    np.testing.assert_allclose(bb.dissipation, 8 * area[i] - 4 * a * bb.modal_force,
                               rtol=1e-9, atol=1e-12 * bb.dissipation.max())  # fmt: skip


def test_a_network_structure_with_a_coulomb_contact_is_taken():
    """A rigid joint (c1 > 0) between two masses: the stuck mode moves them together; both
    exact paths agree, the joint stuck below its Coulomb level."""
    model = PIFriction(0.4, [50.0], threshold=[0.01])
    net = ps.NetworkStructure([1.0, 2.0], [[20.0, -10.0], [-10.0, 10.0]], [[-1.0], [1.0]], [model])
    a = np.geomspace(1e-3, 10.0, 30)
    bb = modal_backbone(net, 0, a)
    assert bb.linear_frequency == pytest.approx(math.sqrt(10.0 / 3.0), rel=1e-14)
    assert bb.frequency[0] == pytest.approx(bb.linear_frequency, rel=1e-14)
    assert bb.status == "no_dissipation" and "no joint slides" in bb.message
    from presliding.structural._single_joint import single_joint_curve

    st = JointedStructure.from_network(net)
    p, d = single_joint_curve(st.stiffness, st.contacts[:, 0], st.mass @ bb.mode_shape, model, a)[
        :2
    ]
    np.testing.assert_allclose(bb.modal_force, p, rtol=1e-12)
    np.testing.assert_allclose(bb.dissipation, d, rtol=1e-11)


def test_result_and_errors():
    st = JointedStructure(1.0, 3.0, [[1.0]], [JOINTS["jenkins"]])
    bb = modal_backbone(st, 0, [0.01, 0.1, 1.0])
    assert "ModalBackbone(mode=0" in repr(bb) and "omega" in bb.report()
    frame = bb.to_pandas()
    assert list(frame.columns) == ["modal_force", "frequency", "damping_ratio", "dissipation",
                                   "harmonic_frequency", "decay_damping_ratio"]  # fmt: skip
    assert frame.attrs["units"]["frequency"] == "rad/s"
    with pytest.raises(ValueError, match="`mode` must be"):
        modal_backbone(st, 1, [0.1])
    with pytest.raises(ValueError, match="`amplitudes` must be positive"):
        modal_backbone(st, 0, [0.0, 1.0])
    two = JointedStructure(np.eye(2), np.eye(2), np.eye(2), [SegalmanIwan(1, 1, 0, 0)] * 2)
    with pytest.raises(ValueError, match="a density is exact only for one joint"):
        modal_backbone(two, 0, [0.1])
    with pytest.raises(ValueError, match="`quantity` must be one of"):
        bb.plot(quantity="phase")
