"""Write the intersphinx inventories the documentation links through, offline.

The build never downloads: ``conf.py`` maps numpy, scipy, matplotlib, Python,
python-control, pandas, lmfit and pint to the inventories in ``docs/_inventories/``,
which this script
writes from the names of the installed packages (their public functions and
classes, each at the address its project documents it under). Run it again
after a major release of one of them::

    python docs/_ext/make_inventories.py

The files follow Sphinx's inventory format (version 2: a four-line header, then
zlib-compressed lines ``name domain:role priority uri display``).
"""

from __future__ import annotations

import builtins
import importlib
import inspect
import zlib
from pathlib import Path

OUT = Path(__file__).resolve().parents[1] / "_inventories"


def _public(module: str) -> list[tuple[str, str]]:
    """(name, role) of a module's public functions and classes."""
    mod = importlib.import_module(module)
    names = getattr(mod, "__all__", None) or [n for n in dir(mod) if not n.startswith("_")]
    out = []
    for name in sorted(set(names)):
        obj = getattr(mod, name, None)
        if inspect.isclass(obj):
            out.append((name, "class"))
        elif callable(obj):
            out.append((name, "function"))
    return out


def _write(project: str, version: str, entries: list[tuple[str, str, str]]) -> None:
    """entries: (name, domain:role, uri); ``$`` in a uri stands for the name."""
    head = (
        "# Sphinx inventory version 2\n"
        f"# Project: {project}\n# Version: {version}\n"
        "# The remainder of this file is compressed using zlib.\n"
    )
    # Sphinx expands a ``$`` only at the end of a uri: the others are written out here
    lines = {(n, r, uri[:-1].replace("$", n) + "$" if uri.endswith("$") else uri.replace("$", n))
             for n, r, uri in entries}  # fmt: skip
    body = "".join(f"{name} {role} 1 {uri} -\n" for name, role, uri in sorted(lines))
    OUT.mkdir(exist_ok=True)
    (OUT / f"{project.lower()}.inv").write_bytes(head.encode() + zlib.compress(body.encode(), 9))


def numpy_inventory() -> None:
    import numpy as np

    entries = [(f"numpy.{n}", f"py:{r}", "reference/generated/$.html#$")
               for n, r in _public("numpy")]  # fmt: skip
    entries += [("numpy.typing.ArrayLike", "py:data", "reference/typing.html#$"),
                ("numpy.typing.NDArray", "py:data", "reference/typing.html#$")]  # fmt: skip
    _write("numpy", np.__version__, entries)


def scipy_inventory() -> None:
    import scipy

    entries = []
    for sub in ("optimize", "signal", "interpolate", "integrate", "stats", "linalg"):
        entries += [(f"scipy.{sub}.{n}", f"py:{r}", "reference/generated/$.html#$")
                    for n, r in _public(f"scipy.{sub}")]  # fmt: skip
    _write("scipy", scipy.__version__, entries)


def matplotlib_inventory() -> None:
    import matplotlib
    from matplotlib.axes import Axes

    entries = [("matplotlib.axes.Axes", "py:class", "api/_as_gen/$.html#$"),
               ("matplotlib.figure.Figure", "py:class", "api/_as_gen/$.html#$")]  # fmt: skip
    methods = [n for n in dir(Axes) if not n.startswith("_") and callable(getattr(Axes, n))]
    entries += [(f"matplotlib.axes.Axes.{n}", "py:method", "api/_as_gen/$.html#$")
                for n in methods]  # fmt: skip
    entries += [(f"matplotlib.pyplot.{n}", f"py:{r}", "api/_as_gen/$.html#$")
                for n, r in _public("matplotlib.pyplot")]  # fmt: skip
    _write("matplotlib", matplotlib.__version__, entries)


def python_inventory() -> None:
    import sys

    entries = []
    for name in dir(builtins):
        obj = getattr(builtins, name)
        if inspect.isclass(obj) and issubclass(obj, BaseException):
            entries.append((name, "py:exception", "library/exceptions.html#$"))
        elif inspect.isclass(obj):
            entries.append((name, "py:class", "library/functions.html#$"))
        elif callable(obj) and not name.startswith("_"):
            entries.append((name, "py:function", "library/functions.html#$"))
    entries += [("None", "py:data", "library/constants.html#$")]
    for module, page in (("pathlib", "pathlib"), ("concurrent.futures", "concurrent.futures"),
                         ("functools", "functools"), ("pickle", "pickle")):  # fmt: skip
        entries += [(f"{module}.{n}", f"py:{r}", f"library/{page}.html#$")
                    for n, r in _public(module)]  # fmt: skip
        entries.append((module, "py:module", f"library/{page}.html#module-$"))
    _write("Python", f"{sys.version_info.major}.{sys.version_info.minor}", entries)


def control_inventory() -> None:
    import control

    entries = [(f"control.{n}", f"py:{r}", "generated/$.html#$") for n, r in _public("control")]
    _write("python-control", control.__version__, entries)


def _members(cls: type, prefix: str, uri: str) -> list[tuple[str, str, str]]:
    """A class's public methods and attributes, each on the page `uri` names."""
    out = []
    for name in dir(cls):
        if name.startswith("_"):
            continue
        role = "py:method" if callable(getattr(cls, name, None)) else "py:attribute"
        out.append((f"{prefix}.{name}", role, uri))
    return out


def pandas_inventory() -> None:
    import pandas as pd

    entries = [(f"pandas.{n}", f"py:{r}", "reference/api/$.html#$") for n, r in _public("pandas")]
    for cls in (pd.DataFrame, pd.Series):
        entries += _members(cls, f"pandas.{cls.__name__}", "reference/api/$.html#$")
    _write("pandas", pd.__version__, entries)


def lmfit_inventory() -> None:
    import lmfit

    pages = {"Parameters": ("parameters", "parameter"), "Parameter": ("parameters", "parameter"),
             "Minimizer": ("fitting", "minimizer"), "MinimizerResult": ("fitting", "minimizer"),
             "minimize": ("fitting", "minimizer"), "Model": ("model", "model"),
             "ModelResult": ("model", "model")}  # fmt: skip
    entries = []
    for name, (page, module) in pages.items():
        role = "py:function" if name.islower() else "py:class"
        # documented as lmfit.<module>.<name>; lmfit.<name> is how users import it
        entries += [(f"lmfit.{module}.{name}", role, f"{page}.html#$"),
                    (f"lmfit.{name}", role, f"{page}.html#lmfit.{module}.{name}")]  # fmt: skip
    entries += _members(lmfit.Parameters, "lmfit.parameter.Parameters",
                        "parameters.html#$")  # fmt: skip
    _write("lmfit", lmfit.__version__, entries)


def pint_inventory() -> None:
    import pint

    entries = [(f"pint.{n}", f"py:{r}", "api/base.html#$")
               for n in ("Quantity", "Unit", "UnitRegistry", "Measurement", "Context")
               for r in ("class",)]  # fmt: skip
    entries += [(f"pint.{n}", "py:exception", "api/base.html#$")
                for n in ("DimensionalityError", "UndefinedUnitError", "PintError")]  # fmt: skip
    entries += _members(pint.Quantity, "pint.Quantity", "api/base.html#$")
    _write("pint", pint.__version__, entries)


if __name__ == "__main__":
    numpy_inventory()
    scipy_inventory()
    matplotlib_inventory()
    python_inventory()
    control_inventory()
    pandas_inventory()
    lmfit_inventory()
    pint_inventory()
    for path in sorted(OUT.glob("*.inv")):
        print(f"{path.name}: {path.stat().st_size} bytes")
