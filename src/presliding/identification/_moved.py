"""Old paths of the modules that moved to `presliding.measurement`.

``presliding.identification.measurement``, ``presliding.identification._units``
and the others keep resolving (imports, attribute access, pickles): each is the
moved module itself, registered in `sys.modules` when the package is imported,
before any fit imports it.
"""

from __future__ import annotations

import importlib
import sys

MOVED = (
    "measurement",
    "_measurement_readers",
    "_readers",
    "_mat",
    "_frames",
    "_join",
    "_units",
    "_source",
    "_filters",
)

_package = sys.modules["presliding.identification"]
for _name in MOVED:
    _module = importlib.import_module(f"presliding.measurement.{_name}")
    sys.modules[f"presliding.identification.{_name}"] = _module
    setattr(_package, _name, _module)
