"""The residual tests of model adequacy (`_adequacy`): their statistics against closed forms
and their calibration on noise alone (white, difference quotients, rounding)."""

from __future__ import annotations

import numpy as np
import pytest

from presliding.identification.judge import _adequacy as ad
from presliding.identification.judge._adequacy import Block, Candidate, assess, score_causes
from presliding.identification.records._pooled_record import difference_matrix


def _semivariogram(e: np.ndarray, k: int) -> float:
    return 0.5 * float(np.mean((e[k:] - e[:-k]) ** 2))


def test_the_semivariogram_of_white_gaussian_noise_has_its_closed_form_mean_and_variance():
    """For white Gaussian noise of variance σ², ½·mean (e_{t+k} − e_t)² / σ² is a mean of
    n − k χ²₁ whose neighbours k apart correlate at ρ = −1/2: mean 1 and variance
    (2(n − k) + (n − 2k)) / (n − k)²."""
    rng = np.random.default_rng(0)
    n, k, sigma = 400, 7, 0.3
    draws = np.array([_semivariogram(sigma * rng.standard_normal(n), k) / sigma**2
                      for _ in range(2000)])  # fmt: skip
    var = (2 * (n - k) + (n - 2 * k)) / (n - k) ** 2
    assert np.mean(draws) == pytest.approx(1.0, abs=4 * np.sqrt(var / 2000))
    assert np.var(draws) == pytest.approx(var, rel=0.12)


def test_noise_alone_passes_the_tests_at_the_designed_false_alarm_rate():
    """White Gaussian residuals of the noise model's variance, with a smooth input, a
    velocity and its sign as regressors: the three tests fail in at most a few % of draws
    (level 1.5, whiteness 5 null spreads, independence at a family-wise 10⁻³)."""
    rng = np.random.default_rng(1)
    n = 600
    t = np.arange(n) * 1e-3
    u = np.sin(2 * np.pi * 3 * t)
    v = np.cos(2 * np.pi * 3 * t)
    fails = 0
    for _ in range(200):
        r = 0.2 * rng.standard_normal(n)
        block = Block(0, "position", r, 0.04, regressors={"u": u, "v": v, "sign": np.sign(v)})
        fails += not assess([block], 1).passed
    assert fails <= 4


def test_a_difference_quotient_of_white_noise_is_judged_with_its_own_noise_model():
    """The velocity as the central difference quotient D·e of a white position noise e is
    not white (ρ₂ = −1/2); its independence statistic is standardised by σ·‖Dᵀx‖, exact:
    the standardised cross-correlation with any regressor has unit variance."""
    rng = np.random.default_rng(2)
    n, dt, sigma = 500, 1e-3, 1e-6
    t = np.arange(n) * dt
    d = difference_matrix(t, 1)
    x = np.sin(2 * np.pi * 2 * t) + 0.3 * np.sign(np.sin(2 * np.pi * 5 * t))
    shifted = ad.lagged(x, 3)[:, 3 + 2]  # x_{t−2}
    a = d.T @ shifted
    z = [float((d @ (sigma * rng.standard_normal(n))) @ shifted) / (sigma * np.linalg.norm(a))
         for _ in range(3000)]  # fmt: skip
    assert np.var(z) == pytest.approx(1.0, rel=0.08)
    block = Block(0, "velocity", d @ (sigma * rng.standard_normal(n)), sigma**2, d,
                  regressors={"x": x})  # fmt: skip
    assert ad.level(block) == pytest.approx(1.0, abs=0.1)
    assert ad.independence(block, 4.0) is None


def test_the_rounding_of_a_record_at_rest_is_not_taken_for_structure():
    """A position at rest reads one quantum value for long stretches: its rounding error is a
    constant there (not white), which lifts the semivariogram by up to q²/12 over the still
    samples; the allowance keeps a correctly specified residual passing."""
    rng = np.random.default_rng(3)
    q, n = 1e-6, 800
    true = np.concatenate([np.linspace(0.0, 4e-4, 100), np.full(n - 100, 4e-4 + 0.37 * q)])
    meas = q * np.round((true + 0.1 * q * rng.standard_normal(n)) / q)
    still = np.zeros(n, dtype=bool)
    same = np.diff(meas) == 0
    still[1:] |= same
    still[:-1] |= same
    block = Block(0, "position", true - meas, q * q / 12, None, q, still)
    g, _, limit = ad.whiteness(block)
    assert g <= limit
    block = Block(0, "position", true - meas, q * q / 12, None, q, None)  # no allowance
    _, _, limit2 = ad.whiteness(block)
    assert limit2 < limit


def test_slow_structure_fails_whiteness_and_names_its_lag():
    rng = np.random.default_rng(4)
    n = 600
    r = 0.1 * rng.standard_normal(n) + 0.1 * np.sin(np.arange(n) / 6.0)
    found = assess([Block(2, "position", r, 0.01)], 3)
    tests = {f.test for f in found.findings}
    assert "whiteness" in tests and not found.passed
    assert found.failing_records == (2,)
    assert "record 3 (position)" in found.text() and "lag" in found.text()


def test_a_residual_following_the_input_fails_independence_at_its_lag():
    rng = np.random.default_rng(5)
    n = 800
    u = rng.standard_normal(n).cumsum()
    u -= u.mean()
    lagged_u = np.concatenate([np.zeros(4), u[:-4]])
    r = rng.standard_normal(n) + 0.05 * lagged_u
    found = ad.independence(Block(0, "force", r, 1.0, regressors={"the input": u}), 4.5)
    assert found is not None and found.regressor == "the input" and found.lag == 4


def test_the_score_test_names_the_mechanism_the_residual_asks_for():
    """r = noise + 0.3·j₂: of three candidate directions, the one in r is named, its estimate
    −0.3 (r = fitted − measured), its statistic far above χ²₁; noise alone names none."""
    rng = np.random.default_rng(6)
    n = 500
    jac = rng.standard_normal((n, 3))
    js = [rng.standard_normal(n) for _ in range(3)]
    r = 0.1 * rng.standard_normal(n) + 0.3 * js[1]
    r -= jac @ np.linalg.lstsq(jac, r, rcond=None)[0]  # at the optimum: r ⟂ J
    cands = [Candidate(f"c{i}", j, lambda e, i=i: f"c{i} {e:.3f}") for i, j in enumerate(js)]
    cause = score_causes(r, jac, cands, floor_cost=0.01 * n)
    assert cause is not None and cause.name == "c1"
    assert cause.estimate == pytest.approx(-0.3, abs=0.03)
    assert cause.statistic > 100
    noise = 0.1 * rng.standard_normal(n)
    noise -= jac @ np.linalg.lstsq(jac, noise, rcond=None)[0]
    assert score_causes(noise, jac, cands, floor_cost=0.01 * n) is None
