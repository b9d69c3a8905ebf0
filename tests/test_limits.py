"""The shared mechanisms of `_validation` for overflow, sizes and types, and their use
in the shared ground (signals, model files)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from presliding import PIFriction
from presliding._validation import (
    as_count,
    check_finite_derived,
    check_size,
    check_type,
    size_limit,
)
from presliding.model_io import MotionSettings, save_model
from presliding.signals import piecewise_linear
from tests.test_validation import assert_rejects


def test_check_finite_derived_names_every_source_and_the_index():
    check_finite_derived("sum", 1e308, "a")
    message = assert_rejects(
        lambda: check_finite_derived("sum Σ a_j", np.array([1.0, np.inf]), ("a", "b", "c")),
        ValueError,
        "a",
    )
    assert message.startswith("`a`, `b` and `c` must give a finite sum Σ a_j; got inf at index 1")


def test_check_size_reports_the_size_with_the_limit(monkeypatch):
    assert size_limit() > 2**20
    monkeypatch.setattr("presliding._validation.MAX_ALLOCATION_BYTES", 8000)
    assert size_limit() == 8000
    assert check_size("n", 1000, 1000) == 1000
    message = assert_rejects(lambda: check_size("n", 1001, 1001), ValueError, "n")
    assert message == (
        "`n` must ask for at most 1000 values (7.81 KiB); got 1001, which asks for 1001 values "
        "(7.82 KiB)."
    )
    message = assert_rejects(
        lambda: check_size("step", 1e-300, math.inf, what="samples"), ValueError, "step"
    )
    assert "more than 1.8e308 samples (beyond any memory)" in message
    assert_rejects(lambda: check_size("n", 3, math.nan), ValueError, "n")
    monkeypatch.setattr("presliding._validation.MAX_ALLOCATION_BYTES", None)
    message = assert_rejects(lambda: check_size("n", 10**12, 10**12), ValueError, "n")
    assert "half of this machine's memory" in message


def test_as_count_maximum_and_check_type():
    assert as_count("k", 5, maximum=5) == 5
    assert assert_rejects(lambda: as_count("k", 6, maximum=5), ValueError, "k") == (
        "`k` must be at most 5; got 6."
    )
    assert check_type("x", 1.0, float) == 1.0
    message = assert_rejects(lambda: check_type("x", "1", (int, float)), TypeError, "x")
    assert message == "`x` must be an int or float; got str."


@pytest.mark.parametrize(
    ("points", "step", "name"),
    [
        ([0.0, 1.0], 1e-12, "step"),
        ([0.0, 1e308], 1e-300, "step"),
        ([-1e308, 1e308], 1.0, "turning_points"),
    ],
)
def test_piecewise_linear_checks_its_size_first(points, step, name):
    assert_rejects(lambda: piecewise_linear(points, step), ValueError, name)


def test_piecewise_linear_is_unchanged():
    y = piecewise_linear([0.0, 1.0, -1.0, 0.5], 0.3)
    assert y.tolist()[:5] == [0.0, 0.25, 0.5, 0.75, 1.0] and y[-1] == 0.5 and y.shape == (17,)


def test_save_model_names_a_model_of_the_wrong_type(tmp_path):
    path = tmp_path / "m.toml"
    message = assert_rejects(lambda: save_model(path, "notamodel"), TypeError, "model")
    assert message == "`model` must be a PIFriction; got str."
    assert_rejects(
        lambda: save_model(path, PIFriction(1.0), motion={"mass": 1.0}), TypeError, "motion"
    )
    assert not path.exists()
    save_model(path, PIFriction(1.0), MotionSettings())
    assert path.exists()
