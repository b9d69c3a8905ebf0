"""Other packages at the boundary: optional dependencies and pint Quantities.

`require` imports an optional module or raises ``ImportError`` whose message says
what needed it and the extra that installs it (``pip install "presliding[dask]"``).
`missing_extra` turns any ImportError (also a bare ``No module named 'pandas'``
from deeper code) into that one sentence, for the command line's one-line errors.
`as_si` converts a pint Quantity to SI after checking its dimension (pint is not
imported for the test); `presliding._validation` calls it where numbers enter.
"""

from __future__ import annotations

import importlib
from typing import Any

__all__ = [
    "EXTRA_OF",
    "SI_UNITS",
    "as_si",
    "install_hint",
    "is_quantity",
    "missing_extra",
    "require",
]

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


#: The SI units a pint Quantity of each kind is converted to (the first that fits its
#: dimension; the second is the rotary axis).
SI_UNITS: dict[str, tuple[str, ...]] = {
    "position": ("m", "rad"),
    "velocity": ("m/s", "rad/s"),
    "force": ("N", "N*m"),
    "time": ("s",),
    "mass": ("kg", "kg*m**2"),
}


def is_quantity(value: Any) -> bool:
    """A pint Quantity (found by its type's module: pint is not imported for the test)."""
    return type(value).__module__.split(".", 1)[0] == "pint" and hasattr(value, "to")


def as_si(name: str, value: Any, kind: str | None) -> Any:
    """The magnitude in SI of a pint Quantity of `kind` (see `SI_UNITS`); others unchanged.

    A Quantity of another dimension is refused naming the argument and its unit; with
    `kind` None (an argument whose unit is not known here) any Quantity is refused.
    """
    if not is_quantity(value):
        return value
    if kind is None:
        raise TypeError(
            f"`{name}` must be a plain number or array in SI units here; got a pint Quantity "
            f"in {value.units} (convert it with `.to(...).magnitude`)."
        )
    units = SI_UNITS[kind]
    for unit in units:
        try:
            return value.to(unit).magnitude
        except Exception as exc:  # pint's DimensionalityError: try the next unit
            if type(exc).__name__ != "DimensionalityError":
                raise
    raise ValueError(
        f"`{name}` must be a {kind} (a Quantity in {' or '.join(units)} or any unit of the same "
        f"dimension); got a Quantity in {value.units}."
    )
