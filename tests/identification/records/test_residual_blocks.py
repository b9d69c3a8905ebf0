"""The pooled residual as the adequacy tests read it (`records._residual_blocks`)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from presliding import Measurement, PIFriction
from presliding.identification.problem._model_spec import ModelSpec
from presliding.identification.records._pooled_problem import PooledProblem
from presliding.identification.records._pooled_record import as_record, difference_matrix
from presliding.identification.records._residual_blocks import (
    position_sensitivity,
    residual_blocks,
)
from tests.helpers import stop_records

MODEL = PIFriction(0.3, [4000.0, 1000.0], breakaway=[0.35, 0.35])


def test_a_quotient_velocity_s_path_carries_the_position_sensitivity():
    """A velocity compared as the central difference quotient of an uncompared position:
    its whiteness is read on the position residual, which the parameters' error moves by
    J_y·Δθ. The path sensitivity is that J_y: its difference quotient is the velocity's
    sensitivity (found by differences of the simulated velocities, another step)."""
    measured, truth = stop_records(3, 2, MODEL, samples=300, noise=2e-7)
    records = [as_record(Measurement(m.time, position=m.position,
                                     velocity=np.gradient(m.position, m.time),
                                     applied_force=m.applied_force)) for m in measured]  # fmt: skip
    assert all(r.difference for r in records)
    problem = PooledProblem(records, ModelSpec(2, True, None, 32), (1.0, 0.0), "preload",
                            offset=False, suffix=True)  # fmt: skip
    values = {"mass": 2.0, "coulomb_level": 1.0, "coulomb": 0.3, "stiffness_1": 4000.0,
              "stiffness_2": 1000.0}  # fmt: skip
    for i, n in enumerate(truth):
        for k in problem.kinds:
            values[problem.nuisance(k, i)] = n[k]
    problem.set_typical(values)
    free = ["mass", "coulomb", "stiffness_1", problem.nuisance("initial_velocity", 0),
            *[problem.nuisance(k, 1) for k in problem.kinds]]  # fmt: skip
    paths = position_sensitivity(SimpleNamespace(records=problem, bounds={}), values, free)
    assert paths is not None and paths.shape == (problem.t_all.shape[0], len(free))
    base = np.array([values[x] for x in problem.names])
    n1 = problem.t_off[1]
    for j, name in enumerate(free):
        if name.startswith("initial_position"):  # y shifts the second record alone, as it is
            np.testing.assert_allclose(paths[:n1, j], 0.0, atol=1e-9)
            np.testing.assert_allclose(paths[n1:, j], 1.0, rtol=1e-6)
            continue
        h = 1e-5 * abs(values[name]) or 1e-9
        sets = np.repeat(base[None], 2, axis=0)
        sets[0, problem.names.index(name)] += h
        sets[1, problem.names.index(name)] -= h
        _, o_v, status, _ = problem.simulate(sets)
        assert np.all(status == 0)
        jv = (o_v[0] - o_v[1]) / (2 * h)
        scale = float(np.max(np.abs(jv)))
        assert scale > 0
        for i, rec in enumerate(records):
            a, b = problem.t_off[i], problem.t_off[i + 1]
            quotient = difference_matrix(rec.time, rec.difference) @ paths[a:b, j]
            np.testing.assert_allclose(quotient, jv[a:b], atol=1e-4 * scale)
    blocks = residual_blocks(problem, values, None, np.eye(len(free)), paths)
    assert [b.signal for b in blocks] == ["velocity", "velocity"]
    for b in blocks:
        assert b.whiteness and b.path is not None
        a = problem.t_off[b.record]
        np.testing.assert_array_equal(b.path_sensitivity, paths[a : a + b.residual.shape[0]])
