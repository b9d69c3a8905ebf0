"""The covariance of a fit (`identification._covariance`): leverage-adjusted HAC sandwich."""

from __future__ import annotations

import numpy as np
import pytest

from presliding.identification.intervals._covariance import fit_covariance, leverage
from presliding.identification.uncertainty import hac_covariance, ols_covariance

N, RECORDS = 200, 4


def _design(tau: float = 2.0) -> tuple[np.ndarray, list[slice]]:
    """Two shared columns over every sample; per record one column its first samples carry
    (like a record's initial velocity: it decays within a few samples)."""
    t = np.arange(N) / N
    jac = np.zeros((RECORDS * N, 2 + RECORDS))
    blocks = [slice(i * N, (i + 1) * N) for i in range(RECORDS)]
    for i, rows in enumerate(blocks):
        jac[rows, 0] = t
        jac[rows, 1] = np.exp(-5 * t)
        jac[rows, 2 + i] = np.exp(-np.arange(N) / tau)
    return jac, blocks


def test_leverage_is_the_diagonal_of_the_hat_matrix():
    jac, _ = _design()
    jac[:, 0] *= 1e6  # column scaling must not matter
    hat = jac @ np.linalg.solve(jac.T @ jac, jac.T)
    h = leverage(jac)
    np.testing.assert_allclose(h, np.diag(hat), atol=1e-10)
    assert h.sum() == pytest.approx(jac.shape[1], rel=1e-9)


def test_without_blocks_it_is_the_ordinary_covariance():
    rng = np.random.default_rng(0)
    jac, _ = _design()
    r = rng.standard_normal(jac.shape[0])
    cov, undetermined, widths = fit_covariance(jac, r)
    np.testing.assert_array_equal(cov, ols_covariance(jac, r)[0])
    assert undetermined == [] and widths == []


def test_a_parameter_few_samples_determine_gets_its_variance_back():
    """White noise, exact variance σ²(JᵀJ)⁻¹ known: the plain sandwich sees the residuals the
    fit pulled to zero at the high-leverage samples and gives about a third of the variance of
    the per-record parameters (95 % intervals holding the truth in about 68 % of the draws);
    the leverage-adjusted one restores it (HC3: on average a little above the exact value)
    while the shared parameters, which no sample dominates, keep their variance."""
    rng = np.random.default_rng(1)
    jac, blocks = _design()
    clusters = list(range(RECORDS))
    exact = np.diag(np.linalg.inv(jac.T @ jac))
    draws = 200
    ratio = {"plain": np.zeros(jac.shape[1]), "adjusted": np.zeros(jac.shape[1])}
    inside = {"plain": 0.0, "adjusted": 0.0}
    for _ in range(draws):
        e = rng.standard_normal(jac.shape[0])
        theta = np.linalg.lstsq(jac, e, rcond=None)[0]  # the truth is 0
        r = jac @ theta - e
        for label, cov in (
            ("plain", hac_covariance(jac, r, blocks, clusters=clusters)[0]),
            ("adjusted", fit_covariance(jac, r, blocks, clusters)[0]),
        ):
            v = np.diag(cov)
            ratio[label] += v / exact / draws
            inside[label] += np.mean(np.abs(theta[2:]) <= 1.96 * np.sqrt(v[2:])) / draws
    assert np.all(ratio["plain"][2:] < 0.5)
    assert np.all((ratio["adjusted"][2:] > 0.9) & (ratio["adjusted"][2:] < 2.0))
    np.testing.assert_allclose(ratio["adjusted"][:2], ratio["plain"][:2], rtol=0.1)
    assert inside["plain"] < 0.75 < 0.8 < inside["adjusted"]


def test_autocorrelated_noise_shared_parameters_stay_calibrated():
    """AR(1) noise (φ = 0.5) over long records: the shared parameters' 95 % intervals hold the
    truth in 95 ± 3 % of the draws with the adjustment (no sample has a large leverage)."""
    rng = np.random.default_rng(2)
    jac, blocks = _design()
    draws, hits = 200, np.zeros(2)
    for _ in range(draws):
        w = rng.standard_normal(jac.shape[0])
        e = np.empty_like(w)
        for rows in blocks:  # AR(1) per record, stationary start (a short loop over samples)
            x = w[rows].copy()
            x[0] /= np.sqrt(0.75)
            for k in range(1, x.size):
                x[k] += 0.5 * x[k - 1]
            e[rows] = x
        theta = np.linalg.lstsq(jac, e, rcond=None)[0]
        cov = fit_covariance(jac, jac @ theta - e, blocks, list(range(RECORDS)))[0]
        hits += np.abs(theta[:2]) <= 1.96 * np.sqrt(np.diag(cov)[:2])
    assert np.all(np.abs(hits / draws - 0.95) <= 0.035), hits / draws


def _linked_design(ratio: float, dt: float = 1e-3, n: int = 300):
    """Records of position rows J and velocity rows ratio·D·J (D = numpy.gradient): two
    shared columns, and per record a start-like column (its velocity sensitivity dies out
    within a few samples, its position one stays) and a transient one."""
    from presliding.identification.intervals._covariance import Link
    from presliding.identification.records._pooled_record import difference_matrix

    t = np.arange(n) * dt
    k = np.arange(n)
    d = difference_matrix(t, 1)
    p = 2 + 2 * RECORDS
    position = np.zeros((RECORDS * n, p))
    for i in range(RECORDS):
        rows = slice(i * n, (i + 1) * n)
        position[rows, 0] = t
        position[rows, 1] = 1 - np.exp(-k / 150)
        position[rows, 2 + 2 * i] = 1 - np.exp(-k / 3)
        position[rows, 3 + 2 * i] = k * np.exp(-k / 4)
    jac = np.zeros((2 * RECORDS * n, p))
    blocks, links, to_rows = [], [], []
    for i in range(RECORDS):
        vel, pos = slice(2 * i * n, (2 * i + 1) * n), slice((2 * i + 1) * n, (2 * i + 2) * n)
        jac[vel] = ratio * (d @ position[i * n : (i + 1) * n])
        jac[pos] = position[i * n : (i + 1) * n]
        blocks += [vel, pos]
        links.append(Link(vel, pos, d, ratio))
        to_rows.append((vel, pos))
    return jac, blocks, links, to_rows, d


def test_velocity_from_the_position_links_the_noise_of_the_two_signals():
    """Position noise e white, the velocity its difference quotient: the velocity residuals
    are ratio·D·e. The exact covariance is s²·B·J̃ᵀJ̃·B (J̃ = J_y + ratio·DᵀJ_v): its 95 %
    intervals hold the truth in 95 ± 3 % of the draws for every parameter. The sandwich
    alone (velocity and position blocks apart) leaves the transient per-record parameters
    short (about 88 %: few samples fix them, and the velocity noise is negatively
    correlated at lag 2) and the shared ones too wide (100 %); with the links (the moved
    scores' sandwich, C_white as a floor) every parameter reaches 95 % − 2 % and the shared
    intervals narrow."""
    from presliding.identification.intervals._covariance import white_floor

    rng = np.random.default_rng(3)
    jac, blocks, links, to_rows, d = _linked_design(ratio=0.03)
    clusters = [i for i in range(RECORDS) for _ in range(2)]
    draws = 300
    hits = {x: np.zeros(jac.shape[1]) for x in ("sandwich", "linked", "white")}
    for _ in range(draws):
        e = np.zeros(jac.shape[0])
        for vel, pos in to_rows:
            noise = rng.standard_normal(pos.stop - pos.start)
            e[pos], e[vel] = noise, 0.03 * (d @ noise)
        theta = np.linalg.lstsq(jac, e, rcond=None)[0]  # the truth is 0
        r = jac @ theta - e
        for label, var in (
            ("sandwich", np.diag(fit_covariance(jac, r, blocks, clusters)[0])),
            ("linked", np.diag(fit_covariance(jac, r, blocks, clusters, links)[0])),
            ("white", white_floor(jac, r, links)),
        ):
            hits[label] += np.abs(theta) <= 1.96 * np.sqrt(var)
    share = {x: v / draws for x, v in hits.items()}
    transient = slice(3, None, 2)
    assert np.all(np.abs(share["white"] - 0.95) <= 0.03), share["white"]
    assert np.all(share["sandwich"][transient] < 0.92), share["sandwich"]
    assert np.all(share["linked"] >= 0.93), share["linked"]
    assert np.all(share["sandwich"][:2] == 1.0) and np.all(share["linked"][:2] < 0.995)
    # the floor is the variance of a white position noise: without links, or with rows
    # outside every link, there is none
    assert white_floor(jac, np.ones(jac.shape[0]), links[:-1]) is None
