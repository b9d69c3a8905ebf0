"""python-control, imported only when used (the ``control`` extra)."""

from __future__ import annotations

from typing import Any


def python_control() -> Any:
    """The ``control`` module, or an ImportError naming the extra to install."""
    try:
        import control
    except ImportError as exc:
        raise ImportError(
            "this needs the optional `control` package (python-control); "
            "install it with `pip install presliding[control]`."
        ) from exc
    return control
