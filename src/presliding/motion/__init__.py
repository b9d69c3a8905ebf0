"""Motion of a mass with PI friction, exact stiction and optional viscous damping (eqs. 12, 17).

Files
-----
simulation.py         `simulate`: one motion, by the exact event method or an implicit step
batch.py              `simulate_batch` and `free_response`: many motions at once
results.py            `MotionResult`, `MotionEnergy`, `MotionBatch`, `FreeResponse`
_run.py               set-up and runners behind `simulate` (validation, grids, kernel calls)
_event.py             the exact event kernel: closed-form pieces between events
_damped.py            closed-form damped pieces (viscous term σ > 0), their events and energy
_batch_events.py      compiled batches of exact motions (parallel)
_implicit.py          the implicit stepper with exact stiction (finite elements)
_implicit_density.py  the implicit stepper for a density μ
_forcing.py           the applied force u(t): constant, callable or samples

May import: `presliding.friction`, `presliding.hysteresis` and the root's shared modules.
It does not import `presliding.analysis` (a sibling layer).
"""

from presliding.motion.batch import free_response, simulate_batch
from presliding.motion.results import FreeResponse, MotionBatch, MotionEnergy, MotionResult
from presliding.motion.simulation import simulate

__all__ = [
    "FreeResponse",
    "MotionBatch",
    "MotionEnergy",
    "MotionResult",
    "free_response",
    "simulate",
    "simulate_batch",
]
