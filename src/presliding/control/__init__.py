"""Control engineering: friction models as python-control systems.

Files
-----
iosys.py     `to_iosys`, `iosys_state`: friction blocks and the friction-loaded mass

May import: `presliding.identification` and everything below it, and the root's
shared modules. python-control is imported only when used (the ``control`` extra).
"""

from presliding.control.iosys import iosys_state, to_iosys

__all__ = ["iosys_state", "to_iosys"]
