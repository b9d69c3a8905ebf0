"""Old paths of the modules that moved into network's rooms.

``presliding.network.exact``, ``.moreau``, ``.slider_network``, ``.quasi_static``,
``.compile`` and ``.compile_joints`` keep resolving (imports, attribute access,
pickles): each is the moved module itself, registered in `sys.modules` when the
package is imported. ``structure`` and ``results`` did not move.
"""

from __future__ import annotations

import importlib
import sys

MOVED = {
    "exact": "events",
    "moreau": "stepping",
    "slider_network": "sliders",
    "quasi_static": "sliders",
    "compile": "reduction",
    "compile_joints": "reduction",
}

_package = sys.modules["presliding.network"]
for _name, _room in MOVED.items():
    _module = importlib.import_module(f"presliding.network.{_room}.{_name}")
    sys.modules[f"presliding.network.{_name}"] = _module
    setattr(_package, _name, _module)
