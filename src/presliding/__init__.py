"""presliding: dry friction with presliding hysteresis on Prandtl–Ishlinskii operators.

Equation numbers in the documentation refer to the paper "Use of
Prandtl–Ishlinskii hysteresis operators for Coulomb friction modeling with
presliding" (Ruderman, Rachinskii et al.).
"""

from ._version import __version__
from .friction import PIFriction
from .operators import PIOperator, PIState, play, stop

__all__ = [
    "PIFriction",
    "PIOperator",
    "PIState",
    "__version__",
    "play",
    "stop",
]
