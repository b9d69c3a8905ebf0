"""Motion of a mass with PI friction, exact stiction and optional viscous damping (eqs. 12, 17).

Files
-----
simulation.py         `simulate`: one motion, by the exact event method or an implicit step
batch.py              `simulate_batch` and `free_response`: many motions at once
quasi_static.py       `quasi_static_response`, `friction_inverse`: position under a slow force
results.py            `MotionResult`, `MotionEnergy`, `MotionBatch`, `FreeResponse`
_run.py               set-up and runners behind `simulate` (validation, steps, continuation)
_batch_setup.py       set-up of batches: parameters, broadcasting, the parallel kernel call
_event.py             the exact event kernel: closed-form pieces between events
_damped.py            closed-form damped pieces (viscous term σ > 0), their events and energy
_batch_events.py      compiled batches of exact motions (parallel)
_implicit.py          the implicit step with exact stiction (finite elements), its grid loop
_implicit_loop.py     the implicit time loop of `simulate`: uniform steps, samples off the steps
_implicit_density.py  the implicit stepper for a density μ: set-up and runner
_density_loop.py      its fused loop: Newton and commit with the memory in local variables
_forcing.py           the applied force u(t): constant, callable or samples
_rate_run.py          `simulate` of GMS, LuGre and Dahl friction: packing, initial state, run
_rate_loop.py         their implicit time loop: uniform steps, samples off the steps
_rate_step.py         their implicit step: the friction state advanced exactly, Brent's root

May import: `presliding.friction`, `presliding.hysteresis` and the root's shared modules.
It does not import `presliding.analysis` (a sibling layer).
"""

from presliding.motion.batch import free_response, simulate_batch
from presliding.motion.quasi_static import (
    QuasiStaticResponse,
    friction_inverse,
    quasi_static_response,
)
from presliding.motion.results import FreeResponse, MotionBatch, MotionEnergy, MotionResult
from presliding.motion.simulation import simulate

__all__ = [
    "FreeResponse",
    "MotionBatch",
    "MotionEnergy",
    "MotionResult",
    "QuasiStaticResponse",
    "free_response",
    "friction_inverse",
    "quasi_static_response",
    "simulate",
    "simulate_batch",
]
