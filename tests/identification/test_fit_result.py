"""Shared least-squares machinery: estimates, standard errors, fixed and tied parameters."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import re

import numpy as np
import pytest
from scipy import stats

from presliding.identification.fit_result import FitResult, fit_statistics, solve_least_squares


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
        ({"fixed": {"z": 1.0}}, "`fixed` must name parameters of the fit"),
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


PAIR = "must be a parameter name, a (name, factor) pair or a (name, factor, offset) triple"
BAD_OPTIONS = [
    ({"max_evaluations": 2.5}, TypeError, "`max_evaluations` must be an integer; got 2.5."),
    ({"max_evaluations": True}, TypeError, "`max_evaluations` must be an integer; got True."),
    ({"max_evaluations": -5}, ValueError, "`max_evaluations` must be a positive integer; got -5."),
    ({"max_evaluations": 0}, ValueError, "`max_evaluations` must be a positive integer; got 0."),
    ({"tolerance": "x"}, TypeError, "`tolerance` must be a real number; got 'x'."),
    ({"tolerance": np.nan}, ValueError, "`tolerance` must be finite; got nan."),
    ({"tolerance": -1.0}, ValueError, "`tolerance` must be positive; got -1.0."),
    ({"gradient_tolerance": 0.0}, ValueError, "`gradient_tolerance` must be positive; got 0.0."),
    ({"level": "0.9"}, TypeError, "`level` must be a real number; got '0.9'."),
    ({"level": np.nan}, ValueError, "`level` must be finite; got nan."),
    ({"level": 1.0}, ValueError, "`level` must be between 0 and 1 (exclusive); got 1.0."),
    (
        {"difference": "central"},
        ValueError,
        "`difference` must be one of '3-point', '2-point'; got 'central'.",
    ),
    ({"fixed": {"a": "abc"}}, TypeError, "`fixed['a']` must be a real number; got 'abc'."),
    ({"fixed": {"a": np.inf}}, ValueError, "`fixed['a']` must be finite; got inf."),
    ({"fixed": {"a": True}}, TypeError, "`fixed['a']` must be a real number; got True."),
    (
        {"fixed": [("a", 1.0)]},
        TypeError,
        "`fixed` must be a mapping of parameter names to values; got list.",
    ),
    ({"tied": {"a": 5}}, TypeError, f"`tied['a']` {PAIR}; got 5."),
    ({"tied": {"a": ("b",)}}, TypeError, f"`tied['a']` {PAIR}; got ('b',)."),
    ({"tied": {"a": (2.0, "b")}}, TypeError, f"`tied['a']` {PAIR}; got (2.0, 'b')."),
    ({"tied": {"a": ("b", "x")}}, TypeError, "`tied['a'][1]` must be a real number; got 'x'."),
    ({"tied": {"a": ("b", np.nan)}}, ValueError, "`tied['a'][1]` must be finite; got nan."),
    (
        {"fixed": {"a": 5.0}, "bounds": {"a": (0.0, 1.0)}},
        ValueError,
        "`fixed['a']` must lie in [0.0, 1.0] (its bounds); got 5.0.",
    ),
]


@pytest.mark.parametrize(("kwargs", "error", "message"), BAD_OPTIONS)
def test_bad_options_raise_on_entry_in_one_sentence(kwargs, error, message):
    calls = []

    def residual(p):
        calls.append(p)
        return p - 1.0

    with pytest.raises(error, match=f"^{re.escape(message)}$"):
        solve_least_squares(residual, {"a": 0.0, "b": 0.0}, **kwargs)
    assert not calls  # rejected before the residual is ever evaluated


def test_checked_options_reach_the_solver():
    x, y, _ = _linear_problem(5)
    z = np.random.default_rng(99).normal(size=y.shape)

    def residual(p):  # nonlinear in c: needs several evaluations
        return x @ p[:3] + np.exp(p[3]) * z - y

    capped = solve_least_squares(residual, dict.fromkeys("abcd", 0.0), max_evaluations=np.int64(2))
    assert capped.status == "max_evaluations" and capped.n_evaluations <= 2
    full = solve_least_squares(residual, dict.fromkeys("abcd", 0.0), level=np.float64(0.9))
    assert full.status == "converged" and full.level == 0.9
    # a tie given as a list pair with a numpy factor is the same tie as a tuple
    as_list = solve_least_squares(lambda p: p - [1.0, 2.0], {"a": 0.0, "b": 0.0},
                                  tied={"b": ["a", np.float64(2.0)]})  # fmt: skip
    as_tuple = solve_least_squares(lambda p: p - [1.0, 2.0], {"a": 0.0, "b": 0.0},
                                   tied={"b": ("a", 2.0)})  # fmt: skip
    assert as_list.values == pytest.approx(as_tuple.values)
    assert as_list.values["b"] == pytest.approx(2.0 * as_list.values["a"])


@pytest.mark.parametrize("start", ["abc", True, [1.0], None])
def test_start_value_must_be_a_real_number(start):
    message = f"`initial['a']` must be a real number; got {start!r}."
    with pytest.raises(TypeError, match=f"^{re.escape(message)}$"):
        solve_least_squares(lambda p: p - 1.0, {"a": start})
