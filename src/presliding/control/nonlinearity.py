"""`FrictionNonlinearity`: PI friction as a python-control describing-function nonlinearity.

A subclass of ``control.DescribingFunctionNonlinearity`` (when python-control is
installed), so that ``control.describing_function`` and
``control.describing_function_plot`` use the exact `describing_function`, and
calling it with one input sample at a time gives the friction force along the
path (``model.force`` with the memory carried from call to call): the stateful
form python-control's numerical route evaluates. This module imports
python-control; `presliding.control` loads it only when the name is used.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from presliding._validation import as_positive_scalar, as_real_scalar
from presliding.control.describing import describing_function, friction_model
from presliding.hysteresis.general_pi import MemoryState
from presliding.hysteresis.operators import PIState

try:  # the base class when python-control is there; a plain object otherwise
    from control import DescribingFunctionNonlinearity as _Base
except ImportError:  # pragma: no cover - the control extra is missing
    _Base = object

__all__ = ["FrictionNonlinearity"]


class FrictionNonlinearity(_Base):
    """The friction force of a model as a stateful nonlinearity with an exact describing function.

    Parameters
    ----------
    model : PIFriction or CoulombFriction
    state : PIState or MemoryState, optional
        Memory before the first call; default relaxed at 0.

    Examples
    --------
    >>> import control
    >>> model = PIFriction(coulomb=0.2, stiffness=[400.0, 60.0], breakaway=[0.3, 0.4])
    >>> F = FrictionNonlinearity(model)
    >>> complex(control.describing_function(F, 0.01)) == describing_function(model, 0.01)
    True
    """

    def __init__(self, model: Any, state: Any = None) -> None:
        self.model = friction_model(model)
        self.state = self._checked(state)

    def _checked(self, state: Any) -> Any:
        """`state`, checked on entry by the model itself (type and size: a PIState for
        elements, a MemoryState for a density), or the relaxed memory at 0 for None."""
        if state is None:
            return self.model.relaxed_state(0.0)
        if not isinstance(state, (PIState, MemoryState)):
            raise TypeError(
                f"`state` must be a PIState, a MemoryState or None; got {type(state).__name__}."
            )
        self.model.force(np.array([float(state.last_input)]), state)  # raises naming `state`
        return state

    def __call__(self, position: float) -> float:
        """The friction force at the next input sample (the memory moves on)."""
        y = as_real_scalar("position", np.squeeze(position))
        force, self.state = self.model.force(np.array([y]), self.state)
        return float(force[0])

    def reset(self, state: Any = None) -> None:
        """Start again from `state` (default relaxed at 0)."""
        self.state = self._checked(state)

    def describing_function(self, amplitude: float) -> complex:
        """N(A), exact (`presliding.control.describing_function`), for one amplitude A > 0
        (``control.describing_function`` passes them one at a time)."""
        return complex(describing_function(self.model, as_positive_scalar("amplitude", amplitude)))

    def _isstatic(self) -> bool:
        return False

    def __repr__(self) -> str:
        return f"FrictionNonlinearity({self.model!r})"
