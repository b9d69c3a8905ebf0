"""Control engineering: python-control systems, exact sampled-data loops, describing
functions and limit cycles of loops with PI friction.

Files
-----
iosys.py              `to_iosys`, `iosys_state`: friction, the friction-loaded mass, controllers
_controller_iosys.py  controllers as python-control systems (the kernels' arithmetic)
controllers.py        `PID` and `DiscreteController`: discrete controllers with saturation
loop.py               `simulate_loop`, `simulate_loop_batch`: exact compiled closed loops
_loop.py              the compiled loop kernels (one exact event-driven period per sample)
_optional.py          python-control, imported on use with a clear error when missing
results.py            `LoopResult`, `LoopBatch`, `measure_limit_cycle`
describing.py         `describing_function`: N(A) exact for elements and densities
nonlinearity.py       `FrictionNonlinearity`: python-control's DescribingFunctionNonlinearity
limit_cycles.py       `predict_limit_cycles`: harmonic balance G(jω)·N(A) = −1, Loeb's criterion
cycles.py             `LimitCycles`: predicted cycles, Nyquist plot with −1/N(A), report

May import: `presliding.identification` and everything below it, and the root's
shared modules. python-control is imported only when used (the ``control`` extra):
`FrictionNonlinearity` is loaded on first access.
"""

import importlib as _importlib
from typing import Any as _Any

from presliding.control.controllers import PID, DiscreteController
from presliding.control.cycles import LimitCycles
from presliding.control.describing import describing_function
from presliding.control.iosys import iosys_state, to_iosys
from presliding.control.limit_cycles import predict_limit_cycles
from presliding.control.loop import simulate_loop, simulate_loop_batch
from presliding.control.results import LoopBatch, LoopResult, MeasuredCycle, measure_limit_cycle

__all__ = [
    "PID",
    "DiscreteController",
    "FrictionNonlinearity",
    "LimitCycles",
    "LoopBatch",
    "LoopResult",
    "MeasuredCycle",
    "describing_function",
    "iosys_state",
    "measure_limit_cycle",
    "predict_limit_cycles",
    "simulate_loop",
    "simulate_loop_batch",
    "to_iosys",
]


#: Names loaded on first access (their modules import python-control).
LAZY = {"FrictionNonlinearity": "presliding.control.nonlinearity"}


def __getattr__(name: str) -> _Any:
    if name in LAZY:
        value = getattr(_importlib.import_module(LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'presliding.control' has no attribute {name!r}")
