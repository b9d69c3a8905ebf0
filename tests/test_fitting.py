"""Shared least-squares machinery: estimates, standard errors, fixed and tied parameters."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest
from scipy import stats

from presliding.fitting import FitResult, fit_statistics, solve_least_squares


def _linear_problem(seed: int, n: int = 40, noise: float = 0.1):
    rng = np.random.default_rng(seed)
    x = np.column_stack([np.ones(n), np.linspace(-1, 1, n), rng.normal(size=n)])
    beta = np.array([1.0, -2.0, 0.5])
    y = x @ beta + noise * rng.normal(size=n)
    return x, y, beta


def test_linear_estimates_and_errors_equal_ordinary_least_squares():
    x, y, _ = _linear_problem(0)
    sol = solve_least_squares(lambda p: x @ p - y, {"a": 0.0, "b": 0.0, "c": 0.0},
                              jacobian=lambda p: x)  # fmt: skip
    beta, *_ = np.linalg.lstsq(x, y, rcond=None)
    r = y - x @ beta
    cov = r @ r / (len(y) - 3) * np.linalg.inv(x.T @ x)
    np.testing.assert_allclose(list(sol.values.values()), beta, rtol=1e-10)
    np.testing.assert_allclose(list(sol.standard_error.values()), np.sqrt(np.diag(cov)), rtol=1e-8)
    q = stats.t.ppf(0.975, len(y) - 3)
    lo, hi = sol.confidence_interval["b"]
    assert lo == pytest.approx(beta[1] - q * np.sqrt(cov[1, 1])) and hi > lo
    assert sol.status == "converged"


def test_confidence_intervals_cover_at_their_level():
    hits = 0
    for seed in range(200):
        x, y, beta = _linear_problem(seed, n=15, noise=0.5)
        sol = solve_least_squares(lambda p, x=x, y=y: x @ p - y, dict.fromkeys("abc", 0.0),
                                  jacobian=lambda p, x=x: x, level=0.9)  # fmt: skip
        lo, hi = sol.confidence_interval["c"]
        hits += lo <= beta[2] <= hi
    assert 0.84 <= hits / 200 <= 0.96  # binomial(200, 0.9): ± 2.4 sd


def test_fixed_and_tied_parameters_are_respected():
    x, y, _ = _linear_problem(1)
    sol = solve_least_squares(lambda p: x @ p - y, {"a": 0.0, "b": 0.0, "c": 0.0},
                              fixed={"a": 1.5}, tied={"c": ("b", -0.25)})  # fmt: skip
    assert sol.values["a"] == 1.5 and sol.standard_error["a"] == 0.0
    assert sol.values["c"] == -0.25 * sol.values["b"]
    assert sol.standard_error["c"] == pytest.approx(0.25 * sol.standard_error["b"])
    # the tied fit is the least-squares solution of the reduced problem
    xr = x[:, 1] - 0.25 * x[:, 2]
    b = xr @ (y - 1.5 * x[:, 0]) / (xr @ xr)
    assert sol.values["b"] == pytest.approx(b, rel=1e-8)
    assert sol.fixed == ("a",) and sol.tied == ("c",)


def test_bounds_are_respected():
    x, y, _ = _linear_problem(2)
    sol = solve_least_squares(lambda p: x @ p - y, dict.fromkeys("abc", 0.0),
                              bounds={"b": (-1.0, 5.0)})  # fmt: skip
    assert sol.values["b"] == pytest.approx(-1.0)


def test_unidentifiable_parameters_are_reported():
    x, y, _ = _linear_problem(3)
    x = np.column_stack([x, x[:, 1]])  # d duplicates b
    sol = solve_least_squares(lambda p: x @ p - y, dict.fromkeys("abcd", 0.0))
    assert sol.status == "not_identifiable"
    assert np.isinf(sol.standard_error["b"]) and np.isinf(sol.standard_error["d"])
    assert np.isfinite(sol.standard_error["a"])
    assert "b" in sol.message and "d" in sol.message


def test_insensitive_model_is_a_failure():
    sol = solve_least_squares(lambda p: np.ones(5), {"a": 1.0})
    assert sol.status == "failed" and "does not change" in sol.message


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"fixed": {"z": 1.0}}, "unknown parameter 'z'"),
        ({"tied": {"a": "z"}}, "target of 'a'"),
        ({"tied": {"a": "b", "b": "a"}}, "cycle"),
        ({"fixed": {"a": 1.0}, "tied": {"a": "b"}}, "both fixed and tied"),
        ({"fixed": {"a": 5.0}, "bounds": {"a": (0.0, 1.0)}}, "must lie in"),
        ({"level": 1.5}, "`level`"),
    ],
)
def test_bad_specifications_raise(kwargs, message):
    with pytest.raises(ValueError, match=message):
        solve_least_squares(lambda p: p - 1.0, {"a": 0.0, "b": 0.0}, **kwargs)


def test_statistics():
    rms, nrmse, rel = fit_statistics(np.array([0.0, 2.0, 4.0]), np.array([1.0, 2.0, 3.0]))
    assert rms == pytest.approx(np.sqrt(2 / 3))
    assert nrmse == pytest.approx(np.sqrt(2 / 3) / 4)
    assert rel == pytest.approx(np.sqrt(2) / np.sqrt(8))
    assert fit_statistics(np.ones(3), np.zeros(3))[1] == np.inf


def test_fit_result_report_and_plot():
    x, y, _ = _linear_problem(4)
    sol = solve_least_squares(lambda p: x @ p - y, dict.fromkeys("abc", 0.0), fixed={"a": 1.0})
    res = FitResult.from_solution(sol, None, np.arange(len(y)), y, x @ list(sol.values.values()))
    text = res.report()
    assert "converged" in text and "(fixed)" in text and "NRMSE" in text
    assert res.success and res.residual.shape == y.shape
    ax = res.plot()
    assert ax.get_ylabel() == "signal"
    assert len(ax.figure.axes) == 2  # the residual panel
    import matplotlib.pyplot as plt

    plt.close(ax.figure)
