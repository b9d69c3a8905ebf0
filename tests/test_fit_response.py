"""fit_response: the paper's output-error fit with the exact simulator."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import PIFriction
from presliding.fit_response import fit_response
from presliding.measurement import Measurement
from presliding.motion import simulate

DT, N = 2.5e-4, 3000
T = np.arange(N) * DT
U = np.select([T < 0.15, T < 0.35, T < 0.5], [2.0, -2.0, 2.0], 0.0)


def _paper_model(k=(4000.0, 2000.0, 1000.0, 500.0), c1=0.3, fc=1.0) -> PIFriction:
    """Four elements of equal break-away force c_j = (F_c − c1)/4, as in the paper."""
    return PIFriction(c1, list(k), breakaway=[(fc - c1) / len(k)] * len(k))


def _data(model, mass=2.0, u=U, v0=0.05):
    res = simulate(model, mass, applied_force=(T, u) if np.ndim(u) else u, initial_velocity=v0,
                   initial_state="saturated", t_eval=T)  # fmt: skip
    assert res.success
    return res


def test_paper_seven_parameter_fit_recovers_noise_free_data():
    res = _data(_paper_model())
    meas = Measurement(T, position=res.position, velocity=res.velocity, applied_force=U)
    fit = fit_response(meas)
    assert fit.success, fit.message
    truth = {"mass": 2.0, "coulomb_level": 1.0, "coulomb": 0.3, "stiffness_1": 4000.0,
             "stiffness_2": 2000.0, "stiffness_3": 1000.0, "stiffness_4": 500.0,
             "initial_velocity": 0.05}  # fmt: skip
    for name, value in truth.items():
        assert fit.parameters[name] == pytest.approx(value, rel=1e-8), name
    assert fit.model.coulomb_level == pytest.approx(1.0, rel=1e-8)
    assert fit.residual_rms < 1e-10


def test_free_motion_is_reported_per_unit_mass_unless_scaled():
    model = PIFriction(0.05, [3000.0, 600.0], breakaway=[0.3, 0.3])
    res = _data(model, mass=2.0, u=0.0, v0=0.1)
    assert res.n_reversals >= 2
    meas = Measurement(T, position=res.position, velocity=res.velocity)
    per_mass = fit_response(meas, n_elements=2)
    assert "per unit mass" in per_mass.message
    assert per_mass.parameters["mass"] == 1.0 and "mass" in per_mass.fixed
    assert per_mass.parameters["coulomb_level"] == pytest.approx(0.65 / 2.0, rel=1e-7)
    assert per_mass.parameters["stiffness_1"] == pytest.approx(1500.0, rel=1e-7)
    with_mass = fit_response(meas, n_elements=2, mass=2.0)
    assert with_mass.parameters["coulomb"] == pytest.approx(0.05, rel=1e-7)
    with_level = fit_response(meas, n_elements=2, coulomb_level=0.65)
    assert with_level.parameters["mass"] == pytest.approx(2.0, rel=1e-7)
    assert "per unit mass" not in with_level.message


def test_fixed_parameters_and_free_breakaways():
    model = PIFriction(0.3, [4000.0, 800.0], breakaway=[0.5, 0.2])
    res = _data(model)
    meas = Measurement(T, velocity=res.velocity, applied_force=U)
    fit = fit_response(meas, n_elements=2, equal_breakaway=False, fixed={"coulomb": 0.3})
    assert fit.parameters["coulomb"] == 0.3
    assert fit.parameters["breakaway_1"] == pytest.approx(0.5, rel=1e-7)
    assert fit.parameters["breakaway_2"] == pytest.approx(0.2, rel=1e-7)
    assert fit.derived["coulomb_level"] == pytest.approx(1.0, rel=1e-7)


def test_position_signal_and_report():
    res = _data(_paper_model(k=(5000.0, 800.0)))
    meas = Measurement(T, position=res.position + 0.01, applied_force=U)
    fit = fit_response(meas, n_elements=2, signal="position")
    assert fit.parameters["initial_position"] == pytest.approx(0.01, abs=1e-10)
    assert fit.parameters["mass"] == pytest.approx(2.0, rel=1e-6)
    assert "output-error" in fit.report()


def test_bad_input():
    meas = Measurement(T, applied_force=U)
    with pytest.raises(ValueError, match="must hold `velocity`"):
        fit_response(meas)
    with pytest.raises(ValueError, match="`signal`"):
        fit_response(Measurement(T, velocity=np.sin(T)), signal="force")
    with pytest.raises(ValueError, match="`velocity` must vary"):
        fit_response(Measurement(T, velocity=np.zeros_like(T)))
    with pytest.raises(ValueError, match="equal_breakaway"):
        fit_response(Measurement(T, velocity=np.sin(T)), equal_breakaway=False, coulomb_level=1.0)
    with pytest.raises(TypeError, match="Measurement"):
        fit_response(np.zeros(4))
