"""Analysis of free motion without time stepping: eqs. 14–16 and energy.

Files
-----
amplitude.py  D(a), secant stiffness, damping ratio, loss factor, backbone and their slopes
stops.py      Φ (eq. 14), y_e (eq. 15), the stop test (eq. 16) and `turning_points`
energy.py     stored, kinetic and dissipated energy (the energy after eq. 12), viscous loss
_turning_result.py  `TurningPoints`, the result of `turning_points`
_walks.py     exact half swings by the work-energy balance (finite elements, densities)

May import: `presliding.friction`, `presliding.hysteresis` and the root's shared modules.
It does not import `presliding.motion` (a sibling layer).
"""

from presliding.analysis.amplitude import AmplitudeResponse, amplitude_response
from presliding.analysis.energy import (
    dissipated_energy,
    elastic_energy,
    total_energy,
    viscous_dissipation,
)
from presliding.analysis.stops import (
    TurningPoints,
    phi,
    stops_at_turning_point,
    turning_point,
    turning_points,
)

__all__ = [
    "AmplitudeResponse",
    "TurningPoints",
    "amplitude_response",
    "dissipated_energy",
    "elastic_energy",
    "phi",
    "stops_at_turning_point",
    "total_energy",
    "turning_point",
    "turning_points",
    "viscous_dissipation",
]
