"""The regression start of the pooled fits (`_pooled_start`)."""

from __future__ import annotations

import numpy as np

from presliding import PIFriction
from presliding.identification._model_spec import ModelSpec
from presliding.identification._pooled_record import as_record
from presliding.identification._pooled_start import DEAD_SHARE, pooled_start
from tests.helpers import stop_records

#: break-away forces 0.05/0.1/0.2/0.35 N (the study's unequal design)
UNEQUAL = PIFriction(0.3, [4000.0, 2000.0, 1000.0, 500.0], breakaway=[0.05, 0.1, 0.2, 0.35])


def test_every_element_of_free_breakaway_force_starts_alive():
    """Before: the grid weights the bounded regression leaves at rounding merged into
    elements of stiffness ~1e-13 N/m and break-away force ~1e-16 N, which carry no force
    and have no gradient: the fit ended with one element carrying F_m, off the floor."""
    spec = ModelSpec(4, False, None, 32)
    for seed in range(3):
        records, _ = stop_records(seed, 8, UNEQUAL, samples=1000, quantum=2e-6, noise=4e-7)
        start = pooled_start([as_record(m) for m in records], spec, None, False)
        c = np.array([start[x] for x in spec.c_names])
        k = np.array([start[x] for x in spec.k_names])
        assert np.all(c >= DEAD_SHARE * c.sum()), (seed, start)
        assert np.all(k > 1e-3 * k.max()), (seed, start)
        assert start["coulomb"] + c.sum() > 0  # F_c = c1 + Σ c_j of the regression
