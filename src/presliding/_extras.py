"""Optional dependencies: imported on use, with an ImportError naming the extra to install.

`require` imports an optional module or raises ``ImportError`` whose message says
what needed it and the extra that installs it (``pip install "presliding[dask]"``).
`missing_extra` turns any ImportError (also a bare ``No module named 'pandas'``
from deeper code) into that one sentence, for the command line's one-line errors.
"""

from __future__ import annotations

import importlib
from typing import Any

__all__ = ["EXTRA_OF", "install_hint", "missing_extra", "require"]

#: The extra of pyproject.toml that installs each optional top-level module.
EXTRA_OF: dict[str, str] = {
    "dask": "dask",
    "distributed": "dask",
    "cloudpickle": "dask",
    "pandas": "pandas",
    "xarray": "xarray",
    "lmfit": "lmfit",
    "h5py": "h5py",
    # a core dependency; its extra is kept so that old install lines keep working
    "control": "control",
}


def install_hint(extra: str) -> str:
    """The install command of an extra, quoted so that every shell takes the brackets."""
    return f'pip install "presliding[{extra}]"'


def require(module: str, what: str, extra: str | None = None) -> Any:
    """Import `module`, or raise ImportError naming `what` needs it and the extra to install.

    >>> require("numpy", "this").__name__
    'numpy'
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        top = module.split(".", 1)[0]
        name = extra or EXTRA_OF.get(top, top)
        raise ImportError(
            f"{what} needs the optional package `{top}`; install it with `{install_hint(name)}`."
        ) from exc


def missing_extra(exc: ImportError) -> str:
    """One sentence for an ImportError: the message of `require`, or which extra to install."""
    text = " ".join(str(exc).split())
    if "pip install" in text:
        return text
    top = (getattr(exc, "name", None) or "").split(".", 1)[0]
    if top in EXTRA_OF:
        return (
            f"this needs the optional package `{top}`, which is not installed; install it "
            f"with `{install_hint(EXTRA_OF[top])}`."
        )
    return text or type(exc).__name__
