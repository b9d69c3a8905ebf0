"""Frictional networks: quasi-static slider networks and their reduction to one PI operator.

Files
-----
slider_network.py     `SliderNetwork`: springs, Coulomb sliders and stops between nodes
quasi_static.py       `quasi_static_network`: the exact piecewise-linear quasi-static response
_qs_solver.py         the event-driven active-set solution of the sweeping process
compile.py            `compile_network`: a network driven through one input as a `PIFriction`

May import: `presliding.friction`, `presliding.hysteresis` and the root's shared modules.
It does not import `presliding.motion` or `presliding.analysis` (sibling layers).
"""

from presliding.network.compile import compile_network, network_virgin_curve
from presliding.network.quasi_static import QuasiStaticNetworkResult, quasi_static_network
from presliding.network.slider_network import GROUND, SliderNetwork

__all__ = [
    "GROUND",
    "QuasiStaticNetworkResult",
    "SliderNetwork",
    "compile_network",
    "network_virgin_curve",
    "quasi_static_network",
]
