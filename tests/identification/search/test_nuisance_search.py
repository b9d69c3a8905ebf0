"""The records' own parameters searched on a grid (`identification._nuisance_search`)."""

from __future__ import annotations

import numpy as np

from presliding import Measurement, PIFriction
from presliding.identification.problem._model_spec import ModelSpec
from presliding.identification.records import _pooled_problem as pp
from presliding.identification.records._pooled_record import as_record
from presliding.identification.search import _nuisance_search as ns
from tests.helpers import random_preload_stops

MODEL = PIFriction(0.3, [4000.0, 1000.0], breakaway=[0.35, 0.35])
SHARED = {"mass": 2.0, "coulomb_level": 1.0, "coulomb": 0.3, "stiffness_1": 4000.0,
          "stiffness_2": 1000.0}  # fmt: skip


def _mirror(m: Measurement) -> Measurement:
    return Measurement(m.time, position=-m.position, velocity=-m.velocity,
                       applied_force=-m.applied_force)  # fmt: skip


def _problem(records: list[Measurement]) -> pp.PooledProblem:
    spec = ModelSpec(2, True, None, 32)
    return pp.PooledProblem([as_record(m) for m in records], spec, (1.0, 50.0), "preload",
                            offset=False, suffix=True)  # fmt: skip


def test_a_record_and_its_mirror_image_get_mirrored_grid_candidates_to_the_sign_of_zero():
    records = random_preload_stops(5, MODEL, n_records=3, samples=200)
    a, b = _problem(records), _problem([_mirror(m) for m in records])
    values = dict(SHARED)
    for i in range(3):
        values |= {a.nuisance("initial_position", i): 1e-4, a.nuisance("initial_velocity", i): 0.03,
                   a.nuisance("preload_fraction", i): 0.1}  # fmt: skip
    mirrored = {x: (v if a.record_of[x] is None else -v) for x, v in values.items()}
    free = {x for x in a.names if a.record_of[x] is not None}
    ca, cb = ns._candidates(a, values, free), ns._candidates(b, mirrored, free)
    own = [a.index[x] for x in sorted(free)]

    def key(row: np.ndarray) -> tuple:  # values and signs: +0 and −0 told apart
        return tuple((float(v), bool(np.signbit(v))) for v in row)

    # the grid is the mirror image of the other's, the zero preload included: +0 for one,
    # −0 for the other (a forward difference step goes away from zero, so the two then
    # step the mirrored way)
    assert sorted(key(-row) for row in ca[:, own]) == sorted(key(row) for row in cb[:, own])
    fractions = [a.index[a.nuisance("preload_fraction", i)] for i in range(3)]
    assert np.any(ca[:, fractions] == 0.0)
