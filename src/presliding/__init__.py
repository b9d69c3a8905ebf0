"""presliding: dry friction with presliding hysteresis on Prandtl–Ishlinskii operators.

Equation numbers in the documentation refer to the paper "Use of
Prandtl–Ishlinskii hysteresis operators for Coulomb friction modeling with
presliding" (Ruderman, Rachinskii et al.).
"""

from . import signals
from ._version import __version__
from .analysis import TurningPoints, phi, stops_at_turning_point, turning_point, turning_points
from .baselines import (
    CoulombFriction,
    DahlFriction,
    DahlState,
    LuGreFriction,
    LuGreState,
)
from .comparison import Comparison, compare
from .control import iosys_state, to_iosys
from .densities import Density, Discrete, Exponential, PiecewiseConstant, Tabulated, Uniform
from .energy import dissipated_energy, elastic_energy, total_energy
from .fit_motion import fit_motion, predict_motion_force
from .fit_presliding import fit_presliding, fit_virgin_curve
from .fit_response import fit_response
from .fitting import FitResult
from .friction import PIFriction
from .general_pi import GeneralPIOperator, MemoryState
from .inverse import inverse_state, pi_inverse
from .measurement import Measurement
from .motion import (
    FreeResponse,
    MotionBatch,
    MotionEnergy,
    MotionResult,
    free_response,
    simulate,
    simulate_batch,
)
from .operators import PIOperator, PIState, play, stop
from .sweep import SweepResult, sweep

__all__ = [
    "Comparison",
    "CoulombFriction",
    "DahlFriction",
    "DahlState",
    "Density",
    "Discrete",
    "Exponential",
    "FitResult",
    "FreeResponse",
    "GeneralPIOperator",
    "LuGreFriction",
    "LuGreState",
    "Measurement",
    "MemoryState",
    "MotionBatch",
    "MotionEnergy",
    "MotionResult",
    "PIFriction",
    "PIOperator",
    "PIState",
    "PiecewiseConstant",
    "SweepResult",
    "Tabulated",
    "TurningPoints",
    "Uniform",
    "__version__",
    "compare",
    "dissipated_energy",
    "elastic_energy",
    "fit_motion",
    "fit_presliding",
    "fit_response",
    "fit_virgin_curve",
    "free_response",
    "inverse_state",
    "iosys_state",
    "phi",
    "pi_inverse",
    "play",
    "predict_motion_force",
    "signals",
    "simulate",
    "simulate_batch",
    "stop",
    "stops_at_turning_point",
    "sweep",
    "to_iosys",
    "total_energy",
    "turning_point",
    "turning_points",
]
