"""The pooled fits in any consistent units: the same relative start values and estimates.

A user's rig may log millimetres and milliseconds, or grams: lengths × L, times × T,
masses × M scale forces by M·L/T² and stiffnesses by M/T². Every step of the fit
must then give the same relative values (rounding and the solvers' tolerances aside).
"""

from __future__ import annotations

import numpy as np
import pytest

from presliding import Measurement, PIFriction
from presliding.identification.problem._model_spec import ModelSpec
from presliding.identification.records._pooled_record import as_record
from presliding.identification.records._pooled_start import pooled_start
from tests.helpers import stop_records

MODEL = PIFriction(0.3, [4000.0, 2000.0, 1000.0, 500.0], breakaway=[0.175] * 4)
#: (length, time, mass) factors: mm and ms; mm, s and g
UNITS = [(1e3, 1e3, 1.0), (1e3, 1.0, 1e3)]
#: exponents of (length, time, mass) of the shared parameters
DIMENSION = {"mass": (0, 0, 1), "coulomb_level": (1, -2, 1), "coulomb": (1, -2, 1),
             "stiffness": (0, -2, 1)}  # fmt: skip


def rescaled(m: Measurement, units: tuple[float, float, float]) -> Measurement:
    length, time, mass = units
    return Measurement(m.time * time, position=m.position * length,
                       velocity=m.velocity * length / time,
                       applied_force=m.applied_force * mass * length / time**2)  # fmt: skip


def factor(name: str, units: tuple[float, float, float]) -> float:
    e = DIMENSION[name.split("_")[0] if name.startswith("stiffness") else name]
    return float(np.prod([u**p for u, p in zip(units, e, strict=True)]))


@pytest.mark.parametrize("units", UNITS)
def test_the_regression_start_is_the_same_in_other_consistent_units(units):
    """Before: the bounded regression's right-hand side (force × time) kept its units, so
    its solver stopped elsewhere: c1 came out 85 % lower in mm, s and g, the stiffnesses
    5e-4 apart in mm and ms (the equal-break-away solve took finite-difference steps relative
    to log k_j, whose value shifts with the units). The regression's right-hand side is
    scaled, its bounded solve is BVLS (exact, not stopped on a tolerance) and the stiffness
    solve has its exact Jacobian in log k relative to its start: every value to rounding."""
    records, _ = stop_records(0, 4, MODEL, samples=500, quantum=1e-6, noise=2e-7)
    spec = ModelSpec(4, True, None, 32)
    si = pooled_start([as_record(m) for m in records], spec, None, False)
    other = pooled_start([as_record(rescaled(m, units)) for m in records], spec, None, False)
    for name, value in si.items():
        rel = 1e-9
        assert other[name] / factor(name, units) == pytest.approx(value, rel=rel), name
