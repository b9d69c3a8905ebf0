"""The network tests run the compiled event loop deterministically: on a cold cache it is
compiled in process (not by a second process while the general loop runs)."""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True)
def _compile_in_process(monkeypatch: pytest.MonkeyPatch) -> None:
    from presliding.network.events import _warm

    monkeypatch.setattr(_warm, "BACKGROUND", False)
