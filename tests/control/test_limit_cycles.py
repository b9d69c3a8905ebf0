"""predict_limit_cycles: a closed form for Coulomb friction, agreement with the exact closed
loop where the describing function's assumptions hold, and the result object."""

import numpy as np
import pytest

control = pytest.importorskip("control")

from presliding import Exponential, PIFriction  # noqa: E402
from presliding.control import PID, predict_limit_cycles, simulate_loop  # noqa: E402

#: no Coulomb element: the motion never rests, the hunting cycle is near-sinusoidal
BANK = PIFriction(0.0, [2e4, 5e3, 1.5e3, 500.0], [0.2, 0.2, 0.2, 0.2])


def test_coulomb_friction_closed_form():
    """N = j·4c1/(πA) meets G = 1/(ms² + C(s)) at ω0 = sqrt(kp/m) (PID with an ideal D):
    A = 4c1·ω0/(π·(ki − kd·ω0²)); the cycle is unstable (it separates rest and growth)."""
    m, c1, kp, ki, kd = 2.0, 0.3, 800.0, 2e4, 10.0
    s = control.tf("s")
    cycles = predict_limit_cycles(m, PIFriction(c1), kp + ki / s + kd * s)
    w0 = np.sqrt(kp / m)
    assert cycles.n_cycles == 1 and cycles.status == "predicted"
    assert cycles.frequency[0] == pytest.approx(w0, rel=1e-9)
    assert cycles.amplitude[0] == pytest.approx(4 * c1 * w0 / (np.pi * (ki - kd * w0**2)),
                                                rel=1e-9)  # fmt: skip
    assert not cycles.stable[0]
    # the same loop given as its linear part G = P/(1 + PC)
    loop = control.feedback(1 / (m * s**2), kp + ki / s + kd * s)
    again = predict_limit_cycles(loop, PIFriction(c1))
    np.testing.assert_allclose(again.amplitude, cycles.amplitude, rtol=1e-9)


@pytest.mark.parametrize(
    ("kp", "ki", "kd"), [(400.0, 4e4, 0.0), (1000.0, 2e5, 1.0), (2000.0, 1e5, 0.0)]
)
def test_hunting_cycle_matches_the_exact_loop(kp, ki, kd):
    """A stable cycle predicted for a PI(D) loop whose linear part is unstable: the exact
    sampled-data loop, started near rest, settles on it (amplitude within 15 %,
    frequency within 10 %; in fact within 1 %)."""
    pid = PID(kp, ki, kd, dt=1e-4)
    cycles = predict_limit_cycles(1.0, BANK, pid)
    stable = np.flatnonzero(cycles.stable)
    assert stable.size == 1
    a, w = cycles.amplitude[stable[0]], cycles.frequency[stable[0]]
    res = simulate_loop(BANK, 1.0, pid, 0.0, t_end=6.0, initial_velocity=1e-3)
    sim = res.limit_cycle(4.0)
    assert sim.steady
    assert sim.amplitude == pytest.approx(a, rel=0.15)
    assert sim.frequency == pytest.approx(w, rel=0.10)
    # the larger, unstable cycle separates the hunting from growth
    assert np.all(cycles.amplitude[~cycles.stable] > a)


def test_density_and_stable_loop():
    s = control.tf("s")
    model = PIFriction(0.0, density=Exponential(height=7e7, length=1e-4))
    assert predict_limit_cycles(1.0, model, 400.0 + 4e4 / s).n_cycles >= 1
    # a stable linear loop (kd·kp > m·ki): friction only dissipates, no cycle
    none = predict_limit_cycles(1.0, BANK, PID(400.0, 1000.0, 40.0, dt=1e-4))
    assert none.n_cycles == 0 and none.status == "none" and none.success
    assert "no limit cycle predicted" in none.message


def test_result_object():
    cycles = predict_limit_cycles(1.0, BANK, PID(400.0, 4e4, 0.0, dt=1e-4))
    assert cycles.success and cycles.n_cycles == 2
    np.testing.assert_allclose(cycles.period, 2 * np.pi / cycles.frequency)
    text = cycles.report()
    assert "amplitude [m]" in text and "True" in text and "False" in text
    d = cycles.to_dict()
    assert d["status"] == "predicted" and d["amplitude"] is cycles.amplitude
    from matplotlib.figure import Figure

    ax = Figure().subplots()
    assert cycles.plot(ax=ax) is ax
    assert len(ax.lines) >= 5


def test_errors():
    with pytest.raises(TypeError, match=r"^`plant_or_loop` must be a python-control LTI"):
        predict_limit_cycles("plant", BANK)
    with pytest.raises(ValueError, match=r"^`plant_or_loop` must be positive"):
        predict_limit_cycles(-1.0, BANK, PID(1.0))
    with pytest.raises(ValueError, match=r"^`points` must be an integer >= 20"):
        predict_limit_cycles(1.0, BANK, PID(1.0), points=3)
    with pytest.raises(ValueError, match=r"^`amplitudes` must be a range"):
        predict_limit_cycles(1.0, BANK, PID(1.0), amplitudes=(1.0, 0.1))
    with pytest.raises(TypeError, match=r"^`model` must be a PIFriction"):
        predict_limit_cycles(1.0, "friction", PID(1.0))


def test_viscous_term_goes_to_the_linear_part():
    """N(A) leaves σ·ẏ out; the prediction folds it into G = P/(1 + P·(C + σs))."""
    from presliding.control import describing_function

    s = control.tf("s")
    sigma, m = 0.5, 1.0
    viscous = PIFriction(0.0, BANK.stiffness, BANK.breakaway, viscous=sigma)
    assert describing_function(viscous, 3e-5) == describing_function(BANK, 3e-5)
    pid = PID(400.0, 4e4, 0.0, dt=1e-4)
    with_sigma = predict_limit_cycles(m, viscous, pid)
    folded = predict_limit_cycles(1 / (m * s**2 + sigma * s), BANK, pid)
    np.testing.assert_allclose(with_sigma.amplitude, folded.amplitude, rtol=1e-8)
    np.testing.assert_allclose(with_sigma.frequency, folded.frequency, rtol=1e-8)
