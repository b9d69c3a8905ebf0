"""Hysteresis operators: the lowest layer (eqs. 3–6, 10, 11).

Rate-independent maps from a displacement path to stop outputs, with explicit
memory. Everything above builds on these operators.

Files
-----
operators.py            `play`, `stop` (eqs. 3, 5, 11), `PIOperator` (eq. 4) and its `PIState`
batch.py                `PIBatch`, `PIBatchState`: B operators on one input, output F[T, B]
general_pi.py           `GeneralPIOperator` and `MemoryState`: the exact operator of a density μ
densities.py            the distributions μ of section 3: `Discrete`, `Uniform`, `Exponential`, …
iwan.py                 the Iwan family: `SegalmanIwan`, `MindlinContact`, `MicroslipBar`
inverse.py              `pi_inverse`, `inverse_state`, `PIInverse`: inverse operators (compensation)
_inversion.py           the inverse's parameters from the loading-curve slopes (and on the range)
_kernels.py, _fused.py  compiled play/stop loops, time-blocked and batched
_batch_kernels.py       the compiled loop of `PIBatch` (batch as the SIMD axis, full output)
_general_pi.py          compiled kernels of the general operator (closed-form pieces)
_density_base.py, _density_primitives.py, _tabulated.py   the density classes and their primitives
_jit.py                 the typed `njit` decorator every compiled kernel uses (cache=True)
_sorting.py             a stable argsort for kernels (numba's own costs 0.9 s to compile)
_results.py             the result convention shared by every layer: string `Status`, `ResultMixin`

May import: numpy, scipy, numba and the package root's shared modules only.
"""

from presliding.hysteresis.batch import PIBatch, PIBatchState
from presliding.hysteresis.densities import (
    Density,
    Discrete,
    Exponential,
    PiecewiseConstant,
    Tabulated,
    Uniform,
)
from presliding.hysteresis.general_pi import GeneralPIOperator, MemoryState
from presliding.hysteresis.inverse import PIInverse, inverse_state, pi_inverse
from presliding.hysteresis.iwan import MicroslipBar, MindlinContact, SegalmanIwan
from presliding.hysteresis.operators import PIOperator, PIState, play, stop

__all__ = [
    "Density",
    "Discrete",
    "Exponential",
    "GeneralPIOperator",
    "MemoryState",
    "MicroslipBar",
    "MindlinContact",
    "PIBatch",
    "PIBatchState",
    "PIInverse",
    "PIOperator",
    "PIState",
    "PiecewiseConstant",
    "SegalmanIwan",
    "Tabulated",
    "Uniform",
    "inverse_state",
    "pi_inverse",
    "play",
    "stop",
]
