"""fit_quasi_static(creep=True): torque loops of a PI contact in series with a Kelvin–Voigt
element."""

import numpy as np
import pytest

from presliding import (
    CreepingFriction,
    Measurement,
    PIFriction,
    fit_quasi_static,
    masing_check,
    quasi_static_response,
)

PI = PIFriction(0.1, [2e4, 5e3], breakaway=[0.3, 0.3])
CREEP = CreepingFriction(PI, 3e-5, 0.15)


def creeping_loops(seed: int, n_records: int = 3, samples: int = 250, noise: float = 0.0):
    """Decaying sines below break-away from a relaxed start, Gaussian position noise."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n_records):
        duration = rng.uniform(1.5, 3.0)
        t = np.linspace(0.0, duration, samples)
        u = rng.uniform(0.5, 0.8) * PI.coulomb_level * np.exp(-t / duration) * np.sin(
            2 * np.pi * rng.uniform(0.5, 1.5) * t + rng.uniform(0, 2 * np.pi))  # fmt: skip
        y = quasi_static_response(CREEP, u, time=t).position
        out.append(Measurement(t, position=y + noise * rng.standard_normal(samples),
                               applied_force=u))  # fmt: skip
    return out


def test_a_creep_fit_recovers_creeping_loops_that_the_pi_model_cannot_follow():
    records = creeping_loops(0)
    fit = fit_quasi_static(records, n_elements=2, creep=True, initial_state="relaxed")
    truth = {"coulomb": 0.1, "creep_compliance": 3e-5, "creep_time": 0.15}
    np.testing.assert_allclose([fit.parameters[x] for x in truth], list(truth.values()),
                               rtol=1e-6)  # fmt: skip
    # the loops' swings leave the split of the elements (and so F_c) to the intervals; the
    # stiffness after a reversal (eq. 7) is determined
    total = fit.parameters["stiffness_1"] + fit.parameters["stiffness_2"]
    np.testing.assert_allclose(total, 2.5e4, rtol=1e-6)
    assert isinstance(fit.model, CreepingFriction) and fit.model.has_creep
    assert fit.units["creep_compliance"] == "m/N" and fit.units["creep_time"] == "s"
    plain = fit_quasi_static(records, n_elements=2, initial_state="relaxed")
    # the PI model cannot creep: its residuals fail the tests on every record (the model, not
    # the search, is what cannot fit)
    assert plain.status == "model_inadequate" and fit.bic < plain.bic
    assert fit.status != "model_inadequate"
    assert plain.search.residual_over_floor > 10.0 * fit.search.residual_over_floor
    loops = [(r.position, r.applied_force) for r in records]
    assert not masing_check(PI, loops).passed  # the creep breaks Masing's rule


def test_a_creep_fit_predicts_a_held_out_loop_and_holds_the_truth_in_its_intervals():
    records = creeping_loops(1, n_records=4, noise=3e-8)
    fit = fit_quasi_static(records[:3], n_elements=2, creep=True, initial_state="relaxed")
    for name, value in (("creep_compliance", 3e-5), ("creep_time", 0.15)):
        lo, hi = fit.confidence_interval[name]
        assert lo <= value <= hi and hi - lo < 0.2 * value, (name, lo, hi)
    held = fit.predict(records[3])
    assert held.status == "success" and held.nrmse < 0.01


def test_without_creep_the_quasi_static_fit_is_unchanged():
    records = creeping_loops(2, n_records=2, samples=120)
    default = fit_quasi_static(records, n_elements=2)
    named = fit_quasi_static(records, n_elements=2, creep=False)
    assert default.to_dict() == named.to_dict()
    with pytest.raises(TypeError, match=r"`creep` must be True or False"):
        fit_quasi_static(records, n_elements=2, creep="yes")
