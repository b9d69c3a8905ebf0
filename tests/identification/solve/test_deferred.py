"""A solve whose covariance is deferred (`identification._deferred`): what the search reads
(values, residual, status, message) must be the full solve's, and `complete` must give
exactly the full solution."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import fit_response
from presliding.identification.intervals._covariance import undetermined_columns
from presliding.identification.problem._model_spec import ModelSpec
from presliding.identification.records import _pooled_problem as pp
from presliding.identification.records._pooled_record import as_record
from presliding.identification.solve._deferred import complete
from presliding.identification.solve._least_squares import solve_least_squares
from presliding.identification.uncertainty import hac_covariance
from tests.helpers import stop_records
from tests.identification.test_pooled_fit import MODEL, SHARED


def _solve(problem, start, **kw):
    """The pooled solve as `FitProblem.solve` makes it (blocks, records, links)."""
    return solve_least_squares(
        problem.residual(), start, free_jacobian=problem.free_jacobian(),
        blocks=[rows for _, rows in problem.rows], clusters=[i for i, _ in problem.rows],
        links=problem.links, residual_size=problem.n_res, step_limit=problem.step_limit,
        method="lm", max_evaluations=60, **kw,
    )  # fmt: skip


@pytest.mark.parametrize("fixed", [{}, {"stiffness_4": 500.0}])
def test_deferred_solve_completes_to_the_full_one(fixed):
    records, truth = stop_records(5, 3, MODEL, quantum=1e-6, noise=2e-7)
    recs = [as_record(m) for m in records]
    problem = pp.PooledProblem(recs, ModelSpec(4, True, None, 32), (1.0, 50.0), "preload",
                               offset=False, suffix=True)  # fmt: skip
    start = {x: v * 1.05 for x, v in SHARED.items()}
    for i, n in enumerate(truth):
        for k in problem.kinds:
            start[problem.nuisance(k, i)] = n[k]
    problem.set_typical(start)
    full = _solve(problem, start, fixed=fixed)
    deferred = _solve(problem, start, fixed=fixed, errors=False)
    assert full.pending is None and deferred.pending is not None
    for what in ("values", "status", "message", "n_evaluations", "at_bounds", "free"):
        assert getattr(deferred, what) == getattr(full, what), what
    np.testing.assert_array_equal(deferred.residual, full.residual)
    assert all(np.isnan(v) for v in deferred.standard_error.values())
    done = complete(deferred)
    assert done.pending is None and complete(done) is done
    assert done.standard_error == full.standard_error
    assert done.confidence_interval == full.confidence_interval
    np.testing.assert_array_equal(done.covariance, full.covariance)
    assert not any(np.isnan(full.standard_error[x]) for x in full.free)


def test_undetermined_columns_are_the_covariances():
    """A column that repeats another (scaled) and a dead one: the same undetermined columns
    as the HAC covariance, which the status rule reads."""
    rng = np.random.default_rng(1)
    jac = rng.standard_normal((200, 5))
    jac[:, 3] = 2.5 * jac[:, 1]
    jac[:, 4] = 0.0
    r = rng.standard_normal(200)
    blocks = [slice(0, 100), slice(100, 200)]
    assert undetermined_columns(jac, blocks) == hac_covariance(jac, r, blocks)[1] == [1, 3, 4]
    assert undetermined_columns(jac, None) is None  # no blocks: computed at once
    assert undetermined_columns(jac[:4], [slice(0, 4)]) is None  # no more rows than columns


def test_the_searchs_best_comes_with_its_errors():
    """The search defers every start's errors (each solve with ``errors=False``); the fit it
    returns has them (none NaN, the mark of a deferred solve), the profile intervals too."""
    records, _ = stop_records(6, 3, MODEL, quantum=1e-6, noise=2e-7)
    fit = fit_response(records, signal="both", initial_state="preload")
    assert fit.search is not None and fit.search.n_starts >= 1
    for x in fit.parameters:
        assert not np.isnan(fit.standard_error[x]), x
        assert not np.any(np.isnan(fit.confidence_interval[x])), x
