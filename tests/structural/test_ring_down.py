"""Ring-downs: exact free decays, and ω(A), ζ(A) read back by the analytic signal or peaks."""

import math

import numpy as np
import pytest

import presliding as ps
from presliding import PIFriction
from presliding.structural import JointedStructure, modal_backbone
from presliding.structural.motion import simulate_ring_down, simulate_structure
from presliding.structural.ring_down import BIAS, analyze_ring_down

W, ZETA = 3.4641, 0.0072
DT = 2 * math.pi / W / 64
T = np.arange(int(150 / DT)) * DT


@pytest.mark.parametrize("method", ["hilbert", "peaks"])
@pytest.mark.parametrize("zeta", [0.001, 0.0072, 0.05])
@pytest.mark.parametrize("phase", [0.0, 1.9])
def test_a_linear_decay_is_read_back_within_the_stated_bias(method, zeta, phase):
    """The bias the module states for linear decays (its constants come from this)."""
    t = T[min(150.0, 8 / (zeta * W) + 60) > T]
    x = np.exp(-zeta * W * t) * np.sin(W * math.sqrt(1 - zeta**2) * t + phase)
    rd = analyze_ring_down((t, x), method=method)
    assert rd.success and rd.time.shape[0] >= 6
    z0, z2, w0, w2 = BIAS[method]
    assert np.max(np.abs(rd.damping_ratio / zeta - 1)) < max(z0, z2 * zeta**2)
    assert np.max(np.abs(rd.frequency / W - 1)) < max(w0, w2 * zeta**2)
    assert np.all(np.abs(rd.damping_ratio - zeta) <= rd.damping_ratio_error)
    # the amplitude of x at the windows' centres (the filter's gain divided out)
    np.testing.assert_allclose(rd.amplitude, np.exp(-zeta * W * rd.time), rtol=1e-2)
    assert "trimmed" in rd.message


def test_velocity_and_acceleration_give_the_displacement_amplitude():
    wd = W * math.sqrt(1 - ZETA**2)
    s = -ZETA * W + 1j * wd
    z = np.exp(s * T)
    meas = ps.Measurement(T, position=z.imag, velocity=(s * z).imag, acceleration=(s * s * z).imag)
    ref = analyze_ring_down(meas)
    assert ref.signal == "position"
    for sig in ("velocity", "acceleration"):
        other = analyze_ring_down(meas, signal=sig)
        np.testing.assert_allclose(other.amplitude, ref.amplitude, rtol=3e-3)
        np.testing.assert_allclose(other.damping_ratio, ref.damping_ratio, rtol=3e-3)


#: a mass on a spring of 10 N/m with a Jenkins joint (2 N/m, r = 0.05 m) and c = 0.01 N s/m
JENKINS = JointedStructure(1.0, 10.0, [[1.0]], [PIFriction(0.0, [2.0], threshold=[0.05])],
                           damping=0.01)  # fmt: skip


@pytest.mark.parametrize("method", ["hilbert", "peaks"])
def test_the_ring_down_of_one_mass_with_a_jenkins_joint_matches_the_backbone(method):
    """The issue's check: ζ(A) of the exact ring-down against the backbone, within the
    estimator's stated error; what a decay shows is ζ_d, not the secant's ζ."""
    motion = simulate_ring_down(JENKINS, 0, 1.0, 150.0)
    assert motion.success and motion.solver == "joints" and motion.n_events > 50
    rd = analyze_ring_down(motion, method=method)
    bb = modal_backbone(JENKINS, 0, np.geomspace(1e-3, 3.0, 800))
    cmp = rd.compare(bb)
    assert cmp["damping_within"].all() and cmp["frequency_within"].all()
    sliding = rd.amplitude > 0.2  # where the joint slides over most of each cycle
    assert sliding.sum() >= 10 and np.max(np.abs(cmp["damping"][sliding])) < 3e-4
    # the secant (quasi-static) quantities are not what a decay shows: 8 and 40 times off
    for key in ("damping", "frequency"):
        slow = np.mean(np.abs(cmp[key][sliding]))
        assert slow < 0.2 * np.mean(np.abs(cmp[f"quasi_static_{key}"][sliding]))


def test_an_impulse_and_a_deflection_decay_alike():
    a = analyze_ring_down(simulate_ring_down(JENKINS, 0, 0.8, 120.0, start="impulse"))
    b = analyze_ring_down(simulate_ring_down(JENKINS, 0, 0.8, 120.0, start="deflection"))
    common = np.geomspace(0.1, 0.35, 5)
    za = np.interp(np.log(common), np.log(a.amplitude[::-1]), a.damping_ratio[::-1])
    zb = np.interp(np.log(common), np.log(b.amplitude[::-1]), b.damping_ratio[::-1])
    np.testing.assert_allclose(za, zb, rtol=0.02)


def test_a_structure_with_a_coulomb_contact_decays_on_simulate_network():
    model = PIFriction(0.05, [50.0], threshold=[0.002])
    net = ps.NetworkStructure([1.0, 2.0], [[20.0, -10.0], [-10.0, 10.0]], [[-1.0], [1.0]],
                              [model], damping=[[0.02, 0.0], [0.0, 0.02]])  # fmt: skip
    w0 = JointedStructure.from_network(net).mode(0)[0]
    for start in ("impulse", "deflection"):
        motion = simulate_ring_down(net, 0, 2.0, 200.0, start=start)
        assert motion.success and motion.solver == "network"
        rd = analyze_ring_down(motion, coordinate=1, floor=1e-2)
        # the contact slides: more damping and a lower frequency than the stuck mode's
        assert np.all(rd.damping_ratio > 0.01) and np.all(rd.frequency < w0)


def test_a_periodic_orbit_is_periodic_for_simulate_structure():
    orbit = ps.periodic_orbit(JENKINS, [0.5], 2.0)
    z = orbit.initial_state
    motion = simulate_structure(
        JENKINS,
        orbit.period,
        z[:1],
        z[1:2],
        force=[0.5],
        frequency=2.0,
        plastic=z[2:],
        t_eval=[0.0, orbit.period],
    )
    assert motion.success and motion.solver == "joints" and motion.n_events == 4
    assert abs(motion.position[-1, 0] - z[0]) < 1e-12 and abs(motion.velocity[-1, 0] - z[1]) < 1e-12
    with pytest.raises(ValueError, match="`force` and `frequency` must be given together"):
        simulate_structure(JENKINS, 1.0, force=[0.5])


def test_bad_inputs_are_refused():
    with pytest.raises(ValueError, match="sampled uniformly"):
        analyze_ring_down((np.r_[T[:100], T[100:] * 1.01], np.sin(W * T)))
    with pytest.raises(ValueError, match="must keep at least"):
        analyze_ring_down((T[:300], np.sin(W * T[:300])))
    with pytest.raises(ValueError, match="`band` must satisfy"):
        analyze_ring_down((T, np.sin(W * T)), band=(2.0, 1.0))
    with pytest.raises(TypeError, match="`data` must be a Measurement"):
        analyze_ring_down(np.sin(W * T))
    with pytest.raises(ValueError, match="`start` must be one of"):
        simulate_ring_down(JENKINS, 0, 1.0, 10.0, start="push")
    bb = modal_backbone(JENKINS, 0, [0.5, 0.6])
    rd = analyze_ring_down(simulate_ring_down(JENKINS, 0, 1.0, 100.0))
    with pytest.raises(ValueError, match="`backbone` must span"):
        rd.compare(bb)
