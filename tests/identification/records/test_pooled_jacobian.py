"""The pooled problem's finite differences (`identification._pooled_jacobian`): forward steps
away from zero, so a record and its mirror image give the same parameters also where the
solver uses forward differences (problems over 5,000 residuals)."""

from __future__ import annotations

import time

import numpy as np
import pytest

from presliding import Measurement, PIFriction, fit_response
from presliding.identification.records._pooled_jacobian import difference_steps
from tests.helpers import pooled_problem_at, stop_records

MODEL2 = PIFriction(0.3, [4000.0, 1000.0], breakaway=[0.35, 0.35])
SHARED = ("mass", "coulomb_level", "coulomb", "stiffness_1", "stiffness_2")


def _mirror(m: Measurement) -> Measurement:
    neg = lambda a: None if a is None else -a  # noqa: E731
    return Measurement(m.time, position=neg(m.position), velocity=neg(m.velocity),
                       applied_force=neg(m.applied_force))  # fmt: skip


def test_forward_steps_go_away_from_zero_and_mirror():
    x = np.array([2.0, -2.0, 0.0, -0.0, 1.0, -1.0, 0.5])
    lo = np.array([-np.inf, -np.inf, -1.0, -1.0, -1.0, -1.0, 0.5])
    hi = np.array([np.inf, np.inf, 1.0, 1.0, 1.0, 1.0, 0.5])
    typical = np.full(7, 1e-3)
    up, down = difference_steps(x, lo, hi, typical, central=False)
    assert np.all(up[[0, 2]] > 0) and np.all(down[[0, 2]] == 0)  # ≥ +0: up
    assert np.all(down[[1, 3]] > 0) and np.all(up[[1, 3]] == 0)  # ≤ −0: down
    assert up[4] == 0 and down[4] > 0  # at the upper bound: down
    assert down[5] == 0 and up[5] > 0  # at the lower bound: up
    assert up[6] == down[6] == 0  # pinned by its bounds
    # the mirror image (the records' own parameters negated, bounds mirrored) steps the
    # mirrored way by the same amount
    up_m, down_m = difference_steps(-x[:6], -hi[:6], -lo[:6], typical[:6], central=False)
    np.testing.assert_array_equal(up_m, down[:6])
    np.testing.assert_array_equal(down_m, up[:6])
    # central steps are untouched: both sides within the bounds
    up_c, down_c = difference_steps(x, lo, hi, typical, central=True)
    assert np.all(up_c[:4] > 0) and np.all(down_c[:4] > 0)


def test_a_large_record_and_its_mirror_image_give_the_same_parameters():
    """Five stops × 600 samples, positions and velocities compared: 6,000 residuals, so the
    structured solver with forward differences runs (the small problems of
    `test_fit_engine` use central ones). A 1 µm encoder with 0.2 µm noise keeps the optimum
    off the truth, where the step directions would show (stepping +h everywhere, the mirror
    image's records came out up to 20 % apart). The nuisance grid is symmetric to the last
    bit too, so the search's further starts see mirrored candidates: bit-identical here."""
    records, _ = stop_records(0, 5, MODEL2, quantum=1e-6, noise=2e-7)
    assert sum(2 * r.n_samples for r in records) > 5000
    t0 = time.perf_counter()
    a = fit_response(records, 2, signal="both", initial_state="preload")
    b = fit_response([_mirror(r) for r in records], 2, signal="both", initial_state="preload")
    assert time.perf_counter() - t0 < 60.0  # a guard against a runaway search, not a timing
    assert a.status == b.status
    assert a.ndata > 5000
    for name, value in a.parameters.items():
        mirrored = value if name in SHARED else -value
        assert b.parameters[name] == pytest.approx(mirrored, rel=1e-9, abs=1e-15), name
    assert a.status == "converged", a.message  # and the fit is a fit: its intervals cover
    truth = {"mass": 2.0, "coulomb_level": 1.0, "coulomb": 0.3, "stiffness_1": 4000.0,
             "stiffness_2": 1000.0}  # fmt: skip
    for name in SHARED:
        lo, hi = a.confidence_interval[name]
        assert lo < truth[name] < hi, name


def test_gathered_forward_jacobian_equals_its_columns_one_by_one():
    """`forward_jacobian` (one compiled gather into CSC) against `difference_columns` and
    `assemble` (each column divided on its own rows), including a column stepping down at a
    bound and one pinned by its bounds: the same matrix to the last bit."""
    from presliding.identification.records import _pooled_jacobian as pj
    from presliding.identification.solve._least_squares import _parameter_map

    records, truth = stop_records(4, 3, MODEL2, quantum=1e-6, noise=2e-7)
    problem, values = pooled_problem_at(records, truth, {
        "mass": 2.0, "coulomb_level": 0.7, "coulomb": 0.3, "stiffness_1": 4000.0,
        "stiffness_2": 1000.0})  # fmt: skip
    pm = _parameter_map(tuple(problem.names), {"stiffness_2": 1000.0}, {})
    x = np.array([values[n] for n in pm.free])
    lo, hi = np.full(x.shape, -np.inf), np.full(x.shape, np.inf)
    up_at = pm.free.index(problem.nuisance("preload_fraction", 1))
    hi[up_at] = x[up_at]  # on its upper bound: steps down
    pinned = pm.free.index(problem.nuisance("initial_velocity", 2))
    lo[pinned] = hi[pinned] = x[pinned]
    base = problem.residual()(pm.full(x))  # the solver's last evaluation
    got = problem.free_jacobian(sparse_output=True)(pm, x, lo, hi)
    groups = problem.column_groups(pm)
    rows = [problem.rows_of_column(pm, j) for j in range(len(pm.free))]
    up, down = pj.difference_steps(x, lo, hi, problem.typical(pm), central=False)
    assert down[up_at] > 0 and up[up_at] == 0 and up[pinned] == down[pinned] == 0
    values_ = pj.difference_columns(problem, pm, x, up, down, groups, rows, False, base)
    want = pj.assemble(values_, rows, problem.n_res, x.shape[0], True)
    np.testing.assert_array_equal(got.indptr, want.indptr)
    np.testing.assert_array_equal(got.indices, want.indices)
    np.testing.assert_array_equal(got.data, want.data)
    assert not np.any(got[:, pinned].toarray()) and np.any(got[:, up_at].toarray())
