"""Shared fixtures of the presliding tests, and the hypothesis profile.

Strategies and helpers are in ``tests/helpers.py`` (``from tests.helpers import ...``).
The tests are a package that mirrors ``src/presliding``: ``tests/hysteresis``,
``tests/friction``, ``tests/motion`` and so on.
"""

from __future__ import annotations

import os

import pytest
from hypothesis import settings

from presliding import PIFriction
from tests.helpers import FIGURE3_FIRST_STIFFNESS, figure3_model

# In CI (CI=true) the property tests draw a fixed sequence of examples, so a
# run is reproducible; locally every run explores new ones.
settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True)
if os.environ.get("CI", "").lower() in ("1", "true", "yes"):
    settings.load_profile("ci")


@pytest.fixture(params=FIGURE3_FIRST_STIFFNESS, ids=lambda k: f"k1={k:g}")
def figure3(request: pytest.FixtureRequest) -> PIFriction:
    """One of the three Figure 3 models (coulomb 0, eq. 4)."""
    return figure3_model(request.param)
