"""Exact periodic orbits: shooting on the event solver, continuation, Floquet multipliers."""

import math

import numpy as np
import pytest

from presliding import PIFriction
from presliding.structural import JointedStructure
from presliding.structural._joint_run import run
from presliding.structural._pieces import Model
from presliding.structural.periodic import force_response, frequency_response, periodic_orbit
from tests.structural._harmonic_balance import HarmonicBalance

JENKINS = PIFriction(0.0, [20.0], breakaway=[1.0])  # k = 20, μN = 1


def _chain():
    """NLvib's chain: three unit masses, four unit springs and dampers 0.02, Jenkins joints
    on q1 and on q2 − q1, the force on q2."""
    k = np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 2]])
    w = np.array([[1.0, -1.0], [0.0, 1.0], [0.0, 0.0]])
    return JointedStructure(np.eye(3), k, w, [JENKINS, JENKINS], damping=0.02 * k)


#: a 1-DOF Jenkins oscillator: m = k = 1, a Jenkins joint kt = 3, μN = 0.5, c = 0.1
ONE_DOF = JointedStructure(1.0, 1.0, [[1.0]], [PIFriction(0.0, [3.0], breakaway=[0.5])],
                           damping=0.1)  # fmt: skip


def test_a_periodic_orbit_closes_to_1e_10_and_its_monodromy_is_exact():
    st = _chain()
    orbit = periodic_orbit(st, [0.0, 1.0, 0.0], 1.1)
    assert orbit.success and orbit.residual <= 1e-10
    assert orbit.stable and np.max(np.abs(orbit.multipliers)) < 1.0
    np.testing.assert_allclose(orbit.position[-1], orbit.position[0], rtol=0, atol=1e-10)


@pytest.mark.parametrize("d_omega", [0.0, 1.0])
def test_the_state_transition_and_the_parameter_derivative_are_exact(d_omega):
    """Against central differences of the flow over a period with ten events (from a state
    with every stop inside its thresholds: the flow is smooth there)."""
    st = _chain()
    force = np.array([0.0, 1.0, 0.0], dtype=complex)
    md = Model(st, force, 1.2)
    z0 = np.array([0.3, 0.5, 0.2, 0.1, -0.2, 0.3, 0.27, 0.18])

    def flow(z, om=1.2, s=1.0):
        r = run(md.with_forcing(s * force, om), 0.0, z[:3], z[3:6], z[6:], 5.0)
        return np.r_[r.q, r.v, r.x]

    r = run(md, 0.0, z0[:3], z0[3:6], z0[6:], 5.0, transition=True, d_omega=d_omega,
            d_force=None if d_omega else force)  # fmt: skip
    assert r.n_events >= 5
    fd = np.zeros_like(r.transition)
    for i in range(z0.shape[0]):
        dz = np.zeros_like(z0)
        dz[i] = 1e-7
        fd[:, i] = (flow(z0 + dz) - flow(z0 - dz)) / 2e-7
    assert np.max(np.abs(fd - r.transition)) < 1e-7 * np.max(np.abs(r.transition))
    h = 1e-7
    if d_omega:
        dp = (flow(z0, om=1.2 + h) - flow(z0, om=1.2 - h)) / (2 * h)
    else:
        dp = (flow(z0, s=1 + h) - flow(z0, s=1 - h)) / (2 * h)
    assert np.max(np.abs(dp - r.derivative)) < 1e-7 * np.max(np.abs(dp))


def test_below_the_thresholds_the_orbit_is_the_stuck_linear_response():
    """Floquet multipliers exp(λT) of the stuck system, amplitude |Ẑ| (to rounding)."""
    st = _chain()
    om, force = 0.7, np.array([0.0, 0.05, 0.0])
    orbit = periodic_orbit(st, force, om)
    ks = st.stuck_stiffness()
    amp = np.linalg.solve(ks - om**2 * st.mass + 1j * om * st.damping, force)
    np.testing.assert_allclose(orbit.amplitude, np.abs(amp), rtol=1e-12)
    np.testing.assert_allclose(orbit.harmonics[1], amp, rtol=1e-12)
    a = np.block([[np.zeros((3, 3)), np.eye(3)], [-ks, -st.damping]])
    expected = np.sort(np.abs(np.exp(np.linalg.eigvals(a) * 2 * math.pi / om)))
    got = np.abs(orbit.multipliers)
    np.testing.assert_allclose(np.sort(got[got > 1e-12]), expected, rtol=1e-9)


def _fine_period(st, force, om, z0, periods, steps=20000):
    """Velocity Verlet with the stop's play operator at every step: an independent fine
    time integration of the 1-DOF oscillator (second order away from the events)."""
    m, c, k = float(st.mass[0, 0]), float(st.damping[0, 0]), float(st.stiffness[0, 0])
    kt, r = float(st.joints[0].stiffness[0]), float(st.joints[0].threshold[0])
    dt = 2 * math.pi / om / steps
    q, v, x = float(z0[0]), float(z0[1]), float(z0[2])
    qs = np.empty(steps * periods + 1)
    qs[0] = q

    def acc(t, q, v, x):
        return (force * math.cos(om * t) - c * v - k * q - kt * (q - x)) / m

    a = acc(0.0, q, v, x)
    for i in range(steps * periods):
        t = i * dt
        vh = v + 0.5 * dt * a
        q = q + dt * vh
        x = min(max(x, q - r), q + r)
        a = acc(t + dt, q, vh, x)
        v = vh + 0.5 * dt * a
        a = acc(t + dt, q, v, x)
        qs[i + 1] = q
    return np.array([q, v, x]), qs


def test_one_dof_jenkins_frequency_response_against_a_fine_time_integration():
    fr = frequency_response(ONE_DOF, [0.4], (0.8, 2.6), step=0.05)
    assert fr.success and np.all(fr.residual <= 1e-10) and fr.stable.all()
    assert fr.frequency.shape[0] > 15 and fr.n_events.max() == 4  # stick, slide, both ways
    for k in np.linspace(0, fr.frequency.shape[0] - 1, 4).astype(int):
        om, z0 = float(fr.frequency[k]), fr.initial_state[k]
        z1, qs = _fine_period(ONE_DOF, 0.4, om, z0, 1)
        assert np.max(np.abs(z1 - z0)) < 5e-5 * np.max(np.abs(z0))  # periodic for it too
        assert abs(0.5 * (qs.max() - qs.min()) / fr.amplitude[k, 0] - 1) < 1e-5
    # from rest, the fine integration settles on the orbit at the peak (stable)
    k = int(np.argmax(fr.amplitude[:, 0]))
    _, qs = _fine_period(ONE_DOF, 0.4, float(fr.frequency[k]), np.zeros(3), 40, steps=2000)
    last = qs[-2001:]
    assert abs(0.5 * (last.max() - last.min()) / fr.amplitude[k, 0] - 1) < 2e-3


def test_harmonic_balance_converges_to_the_exact_orbit():
    """The HB truncation error on the 1-DOF Jenkins oscillator falls with the harmonics."""
    om = 1.35
    exact = periodic_orbit(ONE_DOF, [0.4], om, harmonics=9)
    errors = {}
    for h in (1, 3, 5, 9):
        hb = HarmonicBalance(1.0, 0.1, 1.0, [[1.0]], [(3.0, 0.5 / 3.0)], [0.4], h, samples=512)
        coef, ok = hb.solve(om)
        assert ok
        errors[h] = abs(hb.amplitude(coef)[0] / exact.amplitude[0] - 1)
        first = math.hypot(coef[1, 0], coef[h + 1, 0])
        errors[f"Q1_{h}"] = abs(first / abs(exact.harmonics[1, 0]) - 1)
    assert errors[1] > 1e-3  # one harmonic misses the peak by a visible amount
    assert errors[9] < errors[5] < errors[1] and errors[9] < 0.2 * errors[1]
    assert errors["Q1_9"] < 2e-3


def test_force_response_is_linear_below_the_threshold():
    fo = force_response(ONE_DOF, [1.0], 1.2, (0.01, 0.8), step=0.05)
    assert fo.success and fo.parameter == "scale"
    ks = 4.0  # k + kt
    lin = 1 / abs(ks - 1.2**2 + 1j * 1.2 * 0.1)
    small = fo.amplitude[:, 0] < 0.5 / 3.0 * 0.999  # the joint stays stuck
    np.testing.assert_allclose(fo.amplitude[small, 0], lin * fo.scale[small], rtol=1e-11)
    assert fo.amplitude[-1, 0] > lin * fo.scale[-1]  # softening once it slips
    ax = fo.plot()
    assert ax.get_xlabel().startswith("force scale")


def test_bad_inputs_are_refused():
    with pytest.raises(ValueError, match="joints of stops only"):
        periodic_orbit(JointedStructure(1.0, 1.0, [[1.0]], [PIFriction(0.5)]), [1.0], 1.0)
    with pytest.raises(ValueError, match="`force` must be a nonzero vector of shape"):
        periodic_orbit(ONE_DOF, [1.0, 2.0], 1.0)
    with pytest.raises(ValueError, match="`frequencies` must be two different positive"):
        frequency_response(ONE_DOF, [1.0], (1.0, 1.0))
    with pytest.raises(ValueError, match="positive definite stiffness"):
        periodic_orbit(JointedStructure(1.0, 0.0, [[1.0]], [JENKINS]), [1.0], 1.0)
