"""Hardening of the friction layer: derived quantities that overflow, models of the wrong type."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import (
    CoulombFriction,
    DahlFriction,
    DahlState,
    PIFriction,
    Uniform,
    compare,
)
from tests.test_validation import assert_rejects


@pytest.mark.parametrize(
    ("kwargs", "names", "quantity"),
    [
        (dict(coulomb=0.5, stiffness=[1e308] * 2, breakaway=[1e308] * 2), ("stiffness",),
         "initial stiffness"),
        (dict(coulomb=1e308, stiffness=[1.0], breakaway=[1e308]), ("coulomb", "breakaway"),
         "Coulomb level"),
        (dict(coulomb=0.0, stiffness=[1e10] * 2, threshold=[1e298] * 2),
         ("coulomb", "stiffness", "threshold"), "Coulomb level"),
        (dict(coulomb=0.0, stiffness=[1e-10], breakaway=[1e200]), ("stiffness", "breakaway"),
         "stored energy"),
        (dict(coulomb=1.5e308, density=Uniform(1e308, 1.0)), ("coulomb", "density"),
         "Coulomb level"),
    ],
)  # fmt: skip
def test_pi_friction_derived_quantities_must_be_finite(kwargs, names, quantity):
    message = assert_rejects(lambda: PIFriction(**kwargs), ValueError, names[0])
    assert all(f"`{n}`" in message for n in names) and quantity in message, message


def test_pi_friction_at_the_edge_of_the_range_is_accepted():
    model = PIFriction(0.5, [1e300, 1e300], [1e300, 1e300])
    assert model.coulomb_level == 0.5 + 2e300 and np.isfinite(model.initial_stiffness)


def test_compare_names_models_that_are_not_friction_models():
    y = np.linspace(0.0, 1.0, 5)
    message = assert_rejects(lambda: compare([DahlState(0.0, 0.0)], y), TypeError, "models")
    assert message.endswith("got DahlState at index 0.")
    message = assert_rejects(
        lambda: compare({"ok": CoulombFriction(1.0), "bad": "dahl"}, y), TypeError, "models"
    )
    assert message.endswith("got str at 'bad'.")
    res = compare([CoulombFriction(1.0), DahlFriction(1.0, 100.0)], y)
    assert res.success and set(res.forces) == {"CoulombFriction", "DahlFriction"}
