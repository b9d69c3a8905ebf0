"""The compiled difference quotient of the pooled fit (`identification._pooled_kernel`): the
model's velocity compared where a record's velocity is the quotient of its position must
be numpy.gradient's to the last bit (the fits' results must not depend on the route)."""

from __future__ import annotations

import numpy as np
import pytest

from presliding.identification.problem._model_spec import ModelSpec
from presliding.identification.records import _pooled_kernel as pk
from presliding.identification.records import _pooled_problem as pp
from presliding.identification.records._pooled_record import as_record
from tests.helpers import stop_records
from tests.identification.test_pooled_fit import MODEL


def _plan(n: int) -> tuple:
    return (np.full(n, -1, dtype=np.int64), *(np.zeros(n, dtype=np.int64) for _ in range(3)),
            *(np.zeros(n) for _ in range(3)))  # fmt: skip


@pytest.mark.parametrize("uniform", [True, False])
@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("n", [2, 3, 4, 57])
def test_quotient_is_numpy_gradient_to_the_last_bit(uniform, order, n):
    if n < order + 1:
        pytest.skip("numpy needs edge_order + 1 samples")
    rng = np.random.default_rng(n + 10 * order)
    t = (0.37 + np.arange(n) * 1e-3) if uniform else np.cumsum(rng.uniform(5e-4, 2e-3, n))
    y = rng.standard_normal((3, n)) * 1e-3
    offset = 4  # the record sits after other samples, which keep their velocity
    plan = _plan(n + offset)
    pk.quotient_plan(t, offset, order, plan)
    positions = np.zeros((3, n + offset))
    positions[:, offset:] = y
    velocity = np.full((3, n + offset), 7.0)
    pk.quotients(positions, velocity, *plan)
    np.testing.assert_array_equal(velocity[:, offset:], np.gradient(y, t, axis=1, edge_order=order))
    assert np.all(velocity[:, :offset] == 7.0)


def test_pooled_velocities_are_each_records_gradient():
    """Records of different lengths and sampling: the problem's velocity rows are the
    gradient of its position rows, record by record."""
    records, _ = stop_records(3, 3, MODEL, quantum=1e-6, noise=2e-7)
    t2 = np.concatenate([[0.0], np.cumsum(np.full(records[1].time.shape[0] - 1, 1e-3)
                                          * (1 + 0.1 * np.sin(np.arange(599))))])  # fmt: skip
    from presliding import Measurement

    m = records[1]
    records[1] = Measurement(t2, position=m.position, velocity=np.gradient(m.position, t2),
                             applied_force=m.applied_force)  # fmt: skip
    recs = [as_record(m) for m in records]
    assert all(r.difference for r in recs)
    problem = pp.PooledProblem(recs, ModelSpec(4, True, None, 32), (1.0, 50.0), "preload",
                               offset=False, suffix=True)  # fmt: skip
    rng = np.random.default_rng(0)
    o_y = rng.standard_normal((2, problem.t_all.shape[0]))
    o_v = np.zeros_like(o_y)
    problem.as_measured(o_y, o_v)
    for i, rec in enumerate(recs):
        a, b = problem.t_off[i], problem.t_off[i + 1]
        ref = np.gradient(o_y[:, a:b], rec.time, axis=1, edge_order=rec.difference)
        np.testing.assert_array_equal(o_v[:, a:b], ref)
