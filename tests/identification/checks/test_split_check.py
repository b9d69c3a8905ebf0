"""The element split the data do not determine (`_split_check`) and relabelling
interchangeable elements with their covariance (`_response_checks.relabelled`)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from presliding.identification.checks._response_checks import stiffest_first
from presliding.identification.checks._split_check import undetermined_split
from presliding.identification.solve._least_squares import solve_least_squares

X = np.linspace(0.0, 1.0, 60)
K = ("stiffness_1", "stiffness_2")
BOUNDS = {"stiffness_1": (0.0, np.inf), "stiffness_2": (0.0, np.inf)}
SIGMA = 1e-3


def _model(threshold: float, weight: float):
    """y = (k1 + k2)·x + z, and a kink: the stiffer element shows only past `threshold`
    (an element that slides only where a swing crosses its threshold), at one sample."""

    def model(p: np.ndarray) -> np.ndarray:
        out = (p[0] + p[1]) * X + p[2]
        out[-1] += weight * max(max(p[0], p[1]) - threshold, 0.0)
        return out

    return model


def _data(model, truth, pull: float) -> np.ndarray:
    noise = SIGMA * np.random.default_rng(3).standard_normal(X.size)
    noise[-1] = pull * SIGMA  # what the kink can take up
    return model(np.array(truth)) + noise


def _fit(model, data, begin):
    def solve(start, extra=None, max_evaluations=None):
        return solve_least_squares(lambda p: model(p) - data, start, bounds=BOUNDS,
                                   fixed=extra or {}, max_evaluations=max_evaluations,
                                   tolerance=1e-12)  # fmt: skip

    names = ("stiffness_1", "stiffness_2", "offset")
    return solve(dict(zip(names, begin, strict=True))), solve


def test_a_split_on_a_plateau_is_not_identifiable_with_the_plateau_in_its_intervals():
    """Truth 5 + 3 on the plateau (neither element past the threshold 6): the optimum sits
    at its edge, where the kink takes up one sample's noise; its linearised error is tiny
    and misses the truth by thousands of errors. The check says what the data say."""
    model = _model(6.0, 50.0)
    data = _data(model, (5.0, 3.0, 0.5), 1.0)
    sol, solve = _fit(model, data, (6.5, 1.5, 0.5))
    assert sol.status == "converged"
    assert 6.0 < sol.values["stiffness_1"] < 6.001  # the edge of the plateau
    se = sol.standard_error["stiffness_1"]
    assert abs(sol.values["stiffness_1"] - 5.0) > 100 * se  # the lie the check removes
    out = undetermined_split(sol, solve, K)
    assert out.status == "not_identifiable"
    assert "split" in out.message and "stiffness_1 + stiffness_2" in out.message
    assert np.isinf(out.standard_error["stiffness_1"])
    assert np.isinf(out.standard_error["stiffness_2"])
    names = list(out.values)
    assert all(np.isinf(out.covariance[names.index(x), names.index(x)]) for x in K)
    lo, hi = out.confidence_interval["stiffness_1"]
    assert lo <= 5.0 <= hi and abs(lo - 0.5 * (sol.values["stiffness_1"]
                                               + sol.values["stiffness_2"])) < 1e-6  # fmt: skip
    lo, hi = out.confidence_interval["stiffness_2"]
    assert lo <= 3.0 <= hi
    assert out.standard_error["offset"] == sol.standard_error["offset"]


def test_a_split_the_data_determine_is_left_as_it_is():
    """Truth 7 + 1: the stiffer element is past its threshold, the kink's sample fixes it."""
    model = _model(6.0, 50.0)
    data = _data(model, (7.0, 1.0, 0.5), 0.0)
    sol, solve = _fit(model, data, (6.5, 1.5, 0.5))
    assert sol.status == "converged"
    out = undetermined_split(sol, solve, K)
    assert out is sol or (out.status == sol.status and out.standard_error == sol.standard_error)


def test_relabelling_carries_the_covariance_with_the_names():
    model = _model(100.0, 0.0)
    rng = np.random.default_rng(1)

    def split(p: np.ndarray) -> np.ndarray:  # k1 and k2 told apart by small x², x³ terms
        return model(p) + 0.02 * (p[0] - p[1]) * X**2 + 0.05 * p[1] * X**3

    data = split(np.array([3.0, 5.0, 0.5])) + SIGMA * rng.standard_normal(X.size)
    sol, _ = _fit(split, data, (2.0, 6.0, 0.4))
    assert sol.values["stiffness_1"] < sol.values["stiffness_2"]
    out = stiffest_first(sol, list(K))
    names = list(out.values)
    assert out.values["stiffness_1"] == sol.values["stiffness_2"]
    for x in names:
        assert np.isclose(np.sqrt(out.covariance[names.index(x), names.index(x)]),
                          out.standard_error[x], rtol=1e-9)  # fmt: skip
    i, j, o = (names.index(x) for x in ("stiffness_1", "stiffness_2", "offset"))
    assert out.covariance[i, o] == sol.covariance[j, o] != sol.covariance[i, o]
    assert out.standard_error["stiffness_1"] != sol.standard_error["stiffness_1"]


def test_a_pair_whose_intervals_hold_the_merged_point_is_not_refitted():
    """Elements nearly equal within their errors: the merged point says nothing new."""
    model = _model(6.0, 50.0)
    data = _data(model, (5.0, 3.0, 0.5), 1.0)
    sol, _ = _fit(model, data, (6.5, 1.5, 0.5))
    half = 0.5 * (sol.values["stiffness_1"] + sol.values["stiffness_2"])
    ci = {**sol.confidence_interval, "stiffness_1": (half - 1.0, sol.values["stiffness_1"] + 1)}

    def never(*args, **kwargs):
        raise AssertionError("no refit expected")

    out = undetermined_split(replace(sol, confidence_interval=ci), never, K)
    assert out.status == sol.status and out.standard_error == sol.standard_error
