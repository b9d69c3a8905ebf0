"""The fit as one design: `FitProblem` (what is minimised) and `run_fit` (the steps)."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import PIFriction
from presliding.identification._fit_engine import FitPlan, Found, run_fit
from presliding.identification.fit_presliding import _direction, fit_presliding
from presliding.identification.problem import _pi_regression as pr
from presliding.identification.problem._fit_problem import FitOptions, FitProblem
from presliding.identification.problem._model_spec import ModelSpec
from presliding.identification.problem._separable_problem import (
    Separable,
    separable_problem,
    solve_separable,
)
from presliding.identification.solve._least_squares import solve_least_squares
from presliding.signals import piecewise_linear
from tests.helpers import pooled_problem_at, stop_records

TRUE = PIFriction(0.3, [50.0, 20.0], threshold=[0.01, 0.05])
PATH = piecewise_linear([0.0, 0.3, -0.3, 0.2, -0.1, 0.25], 2e-3)


def _force():
    return TRUE.force(PATH)[0]


def _path_problem(force):
    used = np.ones(PATH.shape[0], dtype=bool)
    sep = Separable(force, _direction(PATH)[:, None], ("coulomb",), pr.stop_basis(PATH), 2, used)
    problem = separable_problem(sep, {"coulomb": (0.0, np.inf)},
                                grid=pr.threshold_grid(PATH, 48))  # fmt: skip
    return sep, problem


def test_a_direct_problem_is_what_fit_presliding_minimises():
    """The problem's start, residual and Jacobian; one solve of it reaches the public fit."""
    force = _force()
    sep, problem = _path_problem(force)
    assert tuple(problem.start()) == problem.names == (
        "coulomb", "stiffness_1", "stiffness_2", "threshold_1", "threshold_2")  # fmt: skip
    assert problem.free == problem.names
    x = np.array(list(problem.start().values())) * 1.1
    jac = problem.jacobian(x)
    for j in range(x.shape[0]):
        h = 1e-7 * abs(x[j])
        xp, xm = x.copy(), x.copy()
        xp[j] += h
        xm[j] -= h
        col = (problem.residual(xp) - problem.residual(xm)) / (2 * h)
        np.testing.assert_allclose(jac[:, j], col, rtol=1e-5, atol=1e-6 * np.abs(col).max())
    fit = solve_separable(sep, problem, FitOptions(0.95, None, 1e-8))
    public = fit_presliding(PATH, force, 2)
    # the public fit keeps the best of this solve and those from the threshold search's
    # starts (`_threshold_search`): on noise-free data all reach the truth, to rounding
    for name, value in fit.solution.values.items():
        assert public.parameters[name] == pytest.approx(value, rel=1e-9, abs=1e-15), name
    np.testing.assert_allclose(public.fitted, fit.fitted, rtol=1e-9, atol=1e-12)
    assert public.parameters["stiffness_1"] == pytest.approx(50.0, rel=1e-8)


def test_the_pipeline_runs_its_steps_in_order_and_a_refit_ends_it():
    force = _force()
    _, problem = _path_problem(force)
    options = FitOptions(0.95, None, 1e-8)
    seen = []

    def search(run):
        seen.append("search")
        return Found(run.solve(), note="one start")

    def check(run, sol):
        seen.append("checks")
        return sol

    def result(run, sol, boot, summary):
        seen.append("result")
        return sol, boot, summary, run.evaluations

    sol, boot, summary, spent = run_fit(problem, options, FitPlan(search, result, (check,)))
    assert seen == ["search", "checks", "result"]
    assert boot is None and summary.note == "one start"  # a direct problem: its Found
    assert sol.n_evaluations == spent > 0
    reference = solve_least_squares(
        problem.residual_function, problem.start(), jacobian=problem.jacobian_function,
        bounds=problem.bounds,
    )  # fmt: skip
    assert sol.values == reference.values
    ended = run_fit(problem, options, FitPlan(search, result, (check,),
                                              refit=lambda run, sol: "refitted"))  # fmt: skip
    assert ended == "refitted"
    assert seen[3:] == ["search", "checks"]  # no judge, intervals or result after a refit


def test_a_pooled_problem_carries_its_records_and_structured_jacobian():
    """The records' layout and Jacobian structure: the problem's Jacobian over every
    parameter equals central differences of its residual; a solve from the truth stays."""
    model = PIFriction(0.3, [4000.0, 1000.0], breakaway=[0.35] * 2)
    records, nuisance = stop_records(2, 2, model, samples=300)
    spec = ModelSpec(2, True, None, 32)
    rec, truth = pooled_problem_at(records, nuisance, {
        "mass": 2.0, "coulomb_level": 1.0, "coulomb": 0.3, "stiffness_1": 4000.0,
        "stiffness_2": 1000.0})  # fmt: skip
    problem = FitProblem(tuple(rec.names), truth, {}, {}, {}, records=rec, spec=spec,
                         method="lm")  # fmt: skip
    x = np.array([truth[n] for n in problem.names])
    assert np.max(np.abs(problem.residual(x))) < 1e-9  # noise-free records at the truth
    jac = problem.jacobian(x)
    for j in range(x.shape[0]):
        h = 1e-6 * max(abs(x[j]), 1e-3)
        xp, xm = x.copy(), x.copy()
        xp[j] += h
        xm[j] -= h
        col = (problem.residual(xp) - problem.residual(xm)) / (2 * h)
        scale = np.linalg.norm(col) + 1e-300
        assert np.linalg.norm(jac[:, j] - col) <= 1e-4 * scale, problem.names[j]
    sol = problem.solve(FitOptions(0.95, 200, 1e-10, 1e-15))
    assert sol.status in ("converged", "not_identifiable")
    for name, value in truth.items():
        assert sol.values[name] == pytest.approx(value, rel=1e-6, abs=1e-9), name
