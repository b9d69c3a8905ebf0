"""The test of an asymmetric fit against its symmetric one (`judge._asymmetry`)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from scipy import stats

from presliding.identification.judge._asymmetry import asymmetry_test

ROW = {"coulomb_level_negative": 1.0, "coulomb_level": -1.0}


def _fit(rss: float, p: int, status: str = "converged", n: int = 1000, se: float = 0.01,
         levels: tuple[float, float] = (1.0, 0.8)) -> SimpleNamespace:  # fmt: skip
    """What the test reads of a FitResult: RSS, size, free parameters, AIC/BIC, status, the
    levels and their covariance."""
    aic = n * np.log(rss / n) + 2 * p
    bic = n * np.log(rss / n) + p * np.log(n)
    return SimpleNamespace(chisqr=rss, ndata=n, nvarys=p, aic=aic, bic=bic, status=status,
                           message="", parameters={"coulomb_level": levels[0],
                                                   "coulomb_level_negative": levels[1]},
                           covariance=np.diag([se**2, se**2]), to_dict=dict)  # fmt: skip


def test_the_statistic_is_the_f_test_of_the_nested_fits():
    sym, asym = _fit(1.05, 5), _fit(1.0, 6)
    test = asymmetry_test(sym, asym, [ROW], 1.0, 0.95)
    f = (1.05 - 1.0) / (1.0 / (1000 - 6))
    assert test.statistic == pytest.approx(f)
    assert test.p_value == pytest.approx(stats.f.sf(f, 1, 994))
    assert test.likelihood_ratio == pytest.approx(1000 * np.log(1.05))
    assert test.delta_aic == pytest.approx(asym.aic - sym.aic)
    assert test.degrees_of_freedom == (1, 994) and test.verdict == "supported"
    assert test.to_dict()["verdict"] == "supported" and "F = " in test.report()


def test_the_scale_divides_the_statistic():
    """κ > 1 (a residual correlated in time): the statistic shrinks by κ, the verdict can
    change where the classical test would reject."""
    sym, asym = _fit(1.005, 5), _fit(1.0, 6)
    plain = asymmetry_test(sym, asym, [ROW], 1.0, 0.95)
    scaled = asymmetry_test(sym, asym, [ROW], 2.5, 0.95)
    assert scaled.statistic == pytest.approx(plain.statistic / 2.5)
    assert plain.verdict == "supported" and scaled.verdict == "not supported"
    assert scaled.likelihood_ratio_p_value == plain.likelihood_ratio_p_value


def test_undetermined_when_a_fit_failed_or_the_difference_is_loose():
    assert asymmetry_test(_fit(1.05, 5, "failed"), _fit(1.0, 6), [ROW], 1.0, 0.95).verdict \
        == "undetermined"  # fmt: skip
    loose = asymmetry_test(_fit(1.05, 5), _fit(1.0, 6, se=2.0), [ROW], 1.0, 0.95)
    assert loose.verdict == "undetermined" and "slide both ways" in loose.message
    assert asymmetry_test(_fit(1.05, 5), _fit(1.0, 6), [ROW], np.nan, 0.95).verdict \
        == "undetermined"  # fmt: skip


def test_an_asymmetric_fit_above_the_symmetric_one_counts_as_no_drop():
    test = asymmetry_test(_fit(1.0, 5), _fit(1.0 + 1e-12, 6), [ROW], 1.0, 0.95)
    assert test.statistic == 0.0 and test.p_value == 1.0 and test.verdict == "not supported"


def test_no_free_constraint_is_undetermined():
    """Every negative side fixed or tied: nothing to test."""
    test = asymmetry_test(_fit(1.0, 5), _fit(1.0, 5), [], np.nan, 0.95)
    assert test.verdict == "undetermined" and "fixed or tied" in test.message
