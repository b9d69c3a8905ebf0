"""python-control, imported only when used (it is heavy: about a second to import)."""

from __future__ import annotations

from typing import Any

from presliding._interop import require


def python_control() -> Any:
    """The ``control`` module, or an ImportError naming the package to install.

    python-control is a core dependency; it is missing only from a partial install.
    """
    return require("control", "this part of presliding.control (python-control systems)")
