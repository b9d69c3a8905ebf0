"""HAC covariance: the Bartlett sum, the bandwidth, calibration on autocorrelated noise."""

from __future__ import annotations

import numpy as np
import pytest

from presliding.identification.uncertainty import (
    _bartlett_meat,
    andrews_bandwidth,
    correlation_matrix,
    hac_covariance,
    ols_covariance,
)


@pytest.mark.parametrize("lag", [0, 1, 5, 40])
def test_window_sums_equal_the_bartlett_weighted_autocovariances(lag):
    rng = np.random.default_rng(lag)
    g = rng.standard_normal((120, 3))
    brute = g.T @ g
    for ell in range(1, lag + 1):
        gamma = g[ell:].T @ g[:-ell]
        brute += (1 - ell / (lag + 1)) * (gamma + gamma.T)
    np.testing.assert_allclose(_bartlett_meat(g, lag), brute, rtol=1e-12, atol=1e-12)


def test_bandwidth_grows_with_the_autocorrelation():
    rng = np.random.default_rng(0)
    white = rng.standard_normal(2000)
    ar = np.zeros(2000)
    for t in range(1, 2000):
        ar[t] = 0.9 * ar[t - 1] + white[t]
    assert andrews_bandwidth(white) <= 3
    assert andrews_bandwidth(ar) > 20
    assert andrews_bandwidth(np.zeros(10)) == 0


def test_independent_residuals_give_about_the_textbook_covariance():
    rng = np.random.default_rng(1)
    x = np.column_stack([np.ones(4000), rng.standard_normal(4000)])
    r = rng.standard_normal(4000)
    hac, undetermined, _ = hac_covariance(x, r, bandwidth=0)
    ols, _ = ols_covariance(x, r)
    assert not undetermined
    np.testing.assert_allclose(np.diag(hac), np.diag(ols), rtol=0.15)


def test_intervals_cover_a_mean_under_ar1_noise_where_the_textbook_ones_do_not():
    """AR(1) noise, ρ = 0.9: the HAC 95 % interval of a mean covers it about 95 % of the time."""
    rng = np.random.default_rng(2)
    hits_hac = hits_ols = 0
    n_runs, n = 200, 1000
    for _ in range(n_runs):
        e = np.zeros(n)
        w = rng.standard_normal(n)
        for t in range(1, n):
            e[t] = 0.9 * e[t - 1] + w[t]
        jac = np.ones((n, 1))
        r = e - e.mean()  # residual at the least-squares estimate (the mean)
        se_hac = np.sqrt(hac_covariance(jac, r)[0][0, 0])
        se_ols = np.sqrt(ols_covariance(jac, r)[0][0, 0])
        hits_hac += abs(e.mean()) <= 1.96 * se_hac
        hits_ols += abs(e.mean()) <= 1.96 * se_ols
    assert hits_hac / n_runs >= 0.85
    assert hits_ols / n_runs < 0.6


def test_blocks_are_independent_and_singular_directions_reported():
    rng = np.random.default_rng(3)
    jac = np.zeros((200, 3))
    jac[:100, 0] = 1.0
    jac[100:, 1] = 1.0  # column 2 stays zero: undetermined
    r = rng.standard_normal(200)
    cov, undetermined, widths = hac_covariance(jac, r, [slice(0, 100), slice(100, 200)])
    assert undetermined == [2] and len(widths) == 2
    assert cov[0, 1] == 0.0  # no cross-block lags


def test_correlation_matrix():
    cov = np.array([[4.0, 2.0, 0.0], [2.0, 9.0, 0.0], [0.0, 0.0, np.inf]])
    corr = correlation_matrix(cov)
    assert corr[0, 1] == pytest.approx(2.0 / 6.0)
    assert corr[2, 2] == 0.0 and corr[0, 2] == 0.0 and corr[0, 0] == 1.0


def test_a_record_fitted_exactly_gets_a_nonzero_standard_error_for_its_own_parameter():
    """Pooled blocks: the second record's residuals are all 0 (reproduced exactly), so the
    HAC meat of its own offset vanishes; its variance falls back to s²·(JᵀJ)⁻¹, never 0."""
    from presliding.identification.uncertainty import hac_covariance

    rng = np.random.default_rng(1)
    n = 200
    jac = np.zeros((2 * n, 3))
    jac[:n, 0] = rng.standard_normal(n)  # shared, seen by record 1 only
    jac[:n, 1] = 1.0  # record 1's offset
    jac[n:, 2] = 1.0  # record 2's offset
    r = np.concatenate([rng.standard_normal(n), np.zeros(n)])
    r[:n] -= r[:n].mean()
    blocks = [np.arange(n), np.arange(n, 2 * n)]
    for clusters in (None, [0, 1]):
        cov, undetermined, _ = hac_covariance(jac, r, blocks, clusters=clusters)
        assert not undetermined
        assert np.all(np.diag(cov) > 0)
        s2 = float(r @ r) / (2 * n - 3)
        expected = s2 * np.linalg.inv(jac.T @ jac)[2, 2]
        assert cov[2, 2] == pytest.approx(expected, rel=1e-9)
