"""Virgin-curve fits from pooled, quantised ramps; the Masing check of loops."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import PIFriction, fit_virgin_curve, masing_check

MODEL = PIFriction(0.1, [1e4, 3e3, 1e3], breakaway=[0.2, 0.2, 0.2])


def _ramps(seed, quantum=1e-6):
    rng = np.random.default_rng(seed)
    ys, fs = [], []
    for sign in (1.0, -1.0, 1.0):
        y = sign * np.linspace(0.0, 8e-4, 400)
        y = quantum * np.round((y + 0.2 * quantum * rng.standard_normal(400)) / quantum)
        ys.append(y)
        fs.append(MODEL.force(y)[0] + 0.002 * rng.standard_normal(400))
    return ys, fs


def test_quantised_ramps_of_both_signs_are_pooled():
    ys, fs = _ramps(0)
    fit = fit_virgin_curve(ys, fs, 3, loops=False, reversal_tolerance=None)
    assert fit.success, fit.message
    assert fit.parameters["coulomb"] == pytest.approx(0.1, abs=0.01)
    np.testing.assert_allclose(sorted(fit.model.stiffness), [1e3, 3e3, 1e4], rtol=0.1)
    assert np.all(np.diff(fit.abscissa) >= 0)


def test_a_ramp_that_reverses_is_refused():
    # ramp 1 runs to -8e-4, then back by 2e-4 (a quarter of its travel): a reversal
    ys, fs = _ramps(1)
    ys[1] = np.concatenate([ys[1], ys[1][-1] + np.linspace(0, 2e-4, 20)])
    fs[1] = np.concatenate([fs[1], np.full(20, fs[1][-1])])
    with pytest.raises(ValueError, match=r"`displacement\[1\]` must be a loading ramp"):
        fit_virgin_curve(ys, fs, 3, loops=False)


@pytest.mark.parametrize("retreat", [3.7, 6.0])
def test_quantised_ramps_retreating_by_several_quanta_fit_by_default(retreat):
    # a drive that settles back by several encoder counts now and then, as real ramps do
    ys, fs = _ramps(2)
    rng = np.random.default_rng(3)
    for y in ys:
        sign = np.sign(y[-1])
        at = rng.choice(np.arange(50, 390), 4, replace=False)
        for i in at:
            y[i : i + 3] -= sign * np.round(retreat) * 1e-6
    fit = fit_virgin_curve(ys, fs, 3, loops=False)
    assert fit.success, fit.message
    assert fit.parameters["coulomb"] == pytest.approx(0.1, abs=0.01)
    np.testing.assert_allclose(sorted(fit.model.stiffness), [1e3, 3e3, 1e4], rtol=0.15)


def test_envelope_is_monotone_and_matches_the_raw_fit_on_clean_data():
    y = np.linspace(0.0, 8e-4, 300)
    f = MODEL.force(y)[0]
    a = fit_virgin_curve(y, f, 3, loops=False)
    b = fit_virgin_curve(y, f, 3, loops=False, envelope=False)
    assert a.parameters["coulomb"] == pytest.approx(b.parameters["coulomb"], rel=1e-6)


def test_masing_check_passes_model_loops_and_flags_creep():
    t = np.linspace(0.0, 1.0, 3000)
    y = 6e-4 * np.sin(6 * np.pi * t) * np.exp(-0.5 * t)
    f = MODEL.force(y)[0]
    ok = masing_check(MODEL, (y, f))
    assert ok.passed and ok.discrepancy < 1e-9 and "passed" in ok.report()
    # a Maxwell element in parallel (stiffness 3e3 N/m, relaxation time 0.05 s): creep
    decay, maxwell = np.exp(-(t[1] - t[0]) / 0.05), np.zeros_like(y)
    for i in range(1, len(t)):
        maxwell[i] = maxwell[i - 1] * decay + 3e3 * (y[i] - y[i - 1])
    bad = masing_check(MODEL, (y, f + maxwell))
    assert not bad.passed and "break Masing's rule" in bad.message
    assert bad.branch_discrepancy.shape[0] >= 4
    with pytest.raises(TypeError, match="`virgin_model` must be a PIFriction"):
        masing_check("model", (y, f))
    with pytest.raises(ValueError, match="at least one branch"):
        masing_check(MODEL, (np.linspace(0, 1, 50), np.linspace(0, 1, 50)))


def test_asymmetric_ramps_give_both_branches():
    """Ramps from rest in +y and −y of a model with its own c1⁻ and r_j⁻: both branches
    recovered (the stiffnesses shared), the asymmetry supported; loops and ramps of one
    direction refused."""
    model = PIFriction(0.1, [500.0, 100.0], threshold=[0.001, 0.01], coulomb_negative=0.08,
                       threshold_negative=[0.0008, 0.007])  # fmt: skip
    ys = [s * np.linspace(0.0, 0.03, 200) for s in (1.0, -1.0)]
    fs = [model.force(y)[0] for y in ys]
    fit = fit_virgin_curve(ys, fs, 2, loops=False, asymmetric=True)
    assert fit.success, fit.message
    truth = {"coulomb": 0.1, "coulomb_negative": 0.08, "stiffness_1": 500.0,
             "stiffness_2": 100.0, "threshold_1": 0.001, "threshold_2": 0.01,
             "threshold_negative_1": 0.0008, "threshold_negative_2": 0.007}  # fmt: skip
    for name, value in truth.items():
        assert fit.parameters[name] == pytest.approx(value, rel=1e-6), name
    assert fit.model.coulomb_levels == pytest.approx(model.coulomb_levels, rel=1e-6)
    assert fit.asymmetry.verdict == "supported" and fit.asymmetry.degrees_of_freedom[0] == 3
    assert len(fit.records) == 2 and np.all(np.diff(fit.abscissa[: fit.records[0][1]]) >= 0)
    with pytest.raises(ValueError, match="needs loops=False"):
        fit_virgin_curve(ys, fs, 2, asymmetric=True)
    with pytest.raises(ValueError, match="ramps in both directions"):
        fit_virgin_curve(ys[:1], fs[:1], 2, loops=False, asymmetric=True)
