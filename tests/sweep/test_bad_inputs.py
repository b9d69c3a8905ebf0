"""Bad input to the sweep layer's entry points (the review's table)."""

from __future__ import annotations

import importlib

import pytest

from presliding import sweep
from tests.helpers import Entry, bad_input_cases, check_bad_input, check_good_call

check_address = importlib.import_module("presliding.sweep").check_address


def _square(x):
    return x * x


RESULT = sweep(_square, {"x": [1.0, 2.0, 3.0]}, n_workers=1)
ENTRIES = {
    "sweep": Entry(
        lambda **a: sweep(**a),
        {"fn": _square, "grid": {"x": [1.0, 2.0, 3.0]}, "n_workers": 1},
        {
            "fn": "callable",
            "grid": "mapping",
            "chunk_size": "count?!",
            "n_workers": "count?!",
            "retries": "count0!",
        },
        [
            ("grid-empty", {"grid": {}}, "grid", False),
            ("grid-axis-empty", {"grid": {"x": []}}, "grid", False),
            ("grid-axis-nan", {"grid": {"x": [1.0, float("nan")]}}, "grid", False),
            ("grid-axis-str", {"grid": {"x": ["a"]}}, "grid", False),
            ("grid-1e10-points", {"grid": {"x": range(100000), "y": range(100000)}}, "grid", False),
            ("n_workers-1e12", {"n_workers": 10**12}, "n_workers", False),
            ("scheduler-bad", {"scheduler": 3.0}, "scheduler", False),
        ],
    ),
    "SweepResult.to_pandas": Entry(
        lambda **a: RESULT.to_pandas(**a),
        {"names": None},
        {},
        [
            ("names-int", {"names": 3}, "names", False),
            ("names-length", {"names": ["a", "b", "c"]}, "names", False),
        ],
    ),
    "SweepResult.plot": Entry(lambda **a: RESULT.plot(**a), {}, {"ax": "object?"}),
    "check_address": Entry(
        lambda **a: check_address(**a),
        {"address": "tcp://127.0.0.1:8786"},
        {"address": "object"},
        [("malformed", {"address": "tcp://::::"}, "address|scheduler", False)],
        needles={"address": "address|scheduler"},
    ),
}


@pytest.mark.parametrize("name", list(ENTRIES))
def test_the_table_starts_from_good_calls(name, tmp_path):
    check_good_call(ENTRIES[name], tmp_path)


@pytest.mark.parametrize(("entry", "overrides", "needle", "legal"), bad_input_cases(ENTRIES))
def test_bad_input_is_a_clear_error(entry, overrides, needle, legal, tmp_path):
    check_bad_input(entry, overrides, needle, legal, tmp_path)
