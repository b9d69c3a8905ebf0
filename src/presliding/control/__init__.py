"""Control engineering: python-control systems, exact sampled-data loops, describing
functions and limit cycles of loops with PI friction.

Files
-----
iosys.py              `to_iosys`, `iosys_state`: friction, the friction-loaded mass, controllers
_controller_iosys.py  controllers as python-control systems (the kernels' arithmetic)
controllers.py        `PID` and `DiscreteController`: discrete controllers with saturation
loop.py               `simulate_loop`, `simulate_loop_batch`: exact compiled closed loops
_loop.py              the compiled loop kernels (one exact event-driven period per sample)
results.py            `LoopResult`, `LoopBatch`, `measure_limit_cycle`

May import: `presliding.identification` and everything below it, and the root's
shared modules. python-control is imported only when used (the ``control`` extra).
"""

from presliding.control.controllers import PID, DiscreteController
from presliding.control.iosys import iosys_state, to_iosys
from presliding.control.loop import simulate_loop, simulate_loop_batch
from presliding.control.results import LoopBatch, LoopResult, measure_limit_cycle

__all__ = [
    "PID",
    "DiscreteController",
    "LoopBatch",
    "LoopResult",
    "iosys_state",
    "measure_limit_cycle",
    "simulate_loop",
    "simulate_loop_batch",
    "to_iosys",
]
