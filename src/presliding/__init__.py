"""presliding: dry friction with presliding hysteresis on Prandtl–Ishlinskii operators.

Equation numbers in the documentation refer to the paper "Use of
Prandtl–Ishlinskii hysteresis operators for Coulomb friction modeling with
presliding" (M. Ruderman and D. Rachinskii, Journal of Physics: Conference
Series 811, 2017).
"""

import importlib as _importlib
import sys as _sys

# `_numba_cache` comes first: importing it finds a folder numba can cache the
# compiled kernels in, before any kernel module is imported.
from presliding import _numba_cache, signals  # noqa: F401  (_numba_cache: for that effect)
from presliding._version import __version__
from presliding.analysis import (
    AmplitudeResponse,
    TurningPoints,
    amplitude_response,
    dissipated_energy,
    elastic_energy,
    phi,
    stops_at_turning_point,
    total_energy,
    turning_point,
    turning_points,
    viscous_dissipation,
)
from presliding.control import (
    PID,
    DiscreteController,
    LimitCycles,
    LoopBatch,
    LoopResult,
    MeasuredCycle,
    describing_function,
    iosys_state,
    measure_limit_cycle,
    predict_limit_cycles,
    simulate_loop,
    simulate_loop_batch,
    to_iosys,
)
from presliding.friction import (
    Comparison,
    CoulombFriction,
    CreepingFriction,
    DahlFriction,
    DahlState,
    GMSFriction,
    GMSState,
    LuGreFriction,
    LuGreState,
    PIFriction,
    compare,
    friction_batch,
    preloaded_state,
)
from presliding.hysteresis import (
    Density,
    Discrete,
    Exponential,
    GeneralPIOperator,
    MemoryState,
    MicroslipBar,
    MindlinContact,
    PIBatch,
    PIBatchState,
    PiecewiseConstant,
    PIInverse,
    PIOperator,
    PIState,
    SegalmanIwan,
    Tabulated,
    Uniform,
    inverse_state,
    pi_inverse,
    play,
    stop,
)
from presliding.identification import (
    CrossValidation,
    FitResult,
    MasingCheck,
    Measurement,
    Prediction,
    correlation_matrix,
    count_reversals,
    cross_validate,
    fit_motion,
    fit_presliding,
    fit_quasi_static,
    fit_response,
    fit_virgin_curve,
    hac_covariance,
    masing_check,
    predict_motion_force,
    reversal_tolerance,
)
from presliding.motion import (
    FreeResponse,
    MotionBatch,
    MotionEnergy,
    MotionResult,
    QuasiStaticResponse,
    free_response,
    friction_inverse,
    quasi_static_response,
    simulate,
    simulate_batch,
)
from presliding.network import (
    NetworkEnergy,
    NetworkResult,
    NetworkState,
    NetworkStructure,
    QuasiStaticNetworkResult,
    SliderNetwork,
    chain_structure,
    compile_network,
    modal_structure,
    multi_contact_structure,
    network_virgin_curve,
    quasi_static_network,
    simulate_network,
    simulate_network_moreau,
)
from presliding.sweep import SweepResult, sweep

#: Module paths from before the package was split into layers, and their homes.
#: ``presliding.operators`` and the others keep resolving (imports, attribute
#: access and pickles of `PIState` and `MemoryState`).
_MOVED = {
    "operators": "presliding.hysteresis.operators",
    "general_pi": "presliding.hysteresis.general_pi",
    "densities": "presliding.hysteresis.densities",
    "inverse": "presliding.hysteresis.inverse",
    "baselines": "presliding.friction.baselines",
    "comparison": "presliding.friction.comparison",
    "energy": "presliding.analysis.energy",
    "fitting": "presliding.identification.fit_result",
    "fit_presliding": "presliding.identification.fit_presliding",
    "fit_motion": "presliding.identification.fit_motion",
    "fit_response": "presliding.identification.fit_response",
}
for _old, _new in _MOVED.items():
    _module = _importlib.import_module(_new)
    _sys.modules[f"{__name__}.{_old}"] = _module
    # ``presliding.fit_presliding`` and its like stay the functions they always were.
    globals().setdefault(_old, _module)
del _old, _new, _module


def __getattr__(name: str) -> object:
    """Names loaded on first access (`presliding.control.LAZY`: they import python-control)."""
    from presliding import control as _control

    if name in _control.LAZY:
        value = getattr(_control, name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'presliding' has no attribute {name!r}")


__all__ = [
    "PID",
    "AmplitudeResponse",
    "Comparison",
    "CoulombFriction",
    "CreepingFriction",
    "CrossValidation",
    "DahlFriction",
    "DahlState",
    "Density",
    "Discrete",
    "DiscreteController",
    "Exponential",
    "FitResult",
    "FreeResponse",
    "FrictionNonlinearity",
    "GMSFriction",
    "GMSState",
    "GeneralPIOperator",
    "LimitCycles",
    "LoopBatch",
    "LoopResult",
    "LuGreFriction",
    "LuGreState",
    "MasingCheck",
    "MeasuredCycle",
    "Measurement",
    "MemoryState",
    "MicroslipBar",
    "MindlinContact",
    "MotionBatch",
    "MotionEnergy",
    "MotionResult",
    "NetworkEnergy",
    "NetworkResult",
    "NetworkState",
    "NetworkStructure",
    "PIBatch",
    "PIBatchState",
    "PIFriction",
    "PIInverse",
    "PIOperator",
    "PIState",
    "PiecewiseConstant",
    "Prediction",
    "QuasiStaticNetworkResult",
    "QuasiStaticResponse",
    "SegalmanIwan",
    "SliderNetwork",
    "SweepResult",
    "Tabulated",
    "TurningPoints",
    "Uniform",
    "__version__",
    "amplitude_response",
    "chain_structure",
    "compare",
    "compile_network",
    "correlation_matrix",
    "count_reversals",
    "cross_validate",
    "describing_function",
    "dissipated_energy",
    "elastic_energy",
    "fit_motion",
    "fit_presliding",
    "fit_quasi_static",
    "fit_response",
    "fit_virgin_curve",
    "free_response",
    "friction_batch",
    "friction_inverse",
    "hac_covariance",
    "inverse_state",
    "iosys_state",
    "masing_check",
    "measure_limit_cycle",
    "modal_structure",
    "multi_contact_structure",
    "network_virgin_curve",
    "phi",
    "pi_inverse",
    "play",
    "predict_limit_cycles",
    "predict_motion_force",
    "preloaded_state",
    "quasi_static_network",
    "quasi_static_response",
    "reversal_tolerance",
    "signals",
    "simulate",
    "simulate_batch",
    "simulate_loop",
    "simulate_loop_batch",
    "simulate_network",
    "simulate_network_moreau",
    "stop",
    "stops_at_turning_point",
    "sweep",
    "to_iosys",
    "total_energy",
    "turning_point",
    "turning_points",
    "viscous_dissipation",
]
