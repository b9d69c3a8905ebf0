"""`TurningPoints`: the result of `presliding.analysis.stops.turning_points`."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis._results import ResultMixin
from presliding.hysteresis.general_pi import MemoryState
from presliding.hysteresis.operators import PIState

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["TurningPoints"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False, repr=False)
class TurningPoints(ResultMixin):
    """Turning points of a free motion (eq. 12), from the work-energy balance.

    Attributes
    ----------
    positions : ndarray, shape (P,)
        Every position where the velocity vanished, in order; the last one is
        the rest position when the mass stopped.
    elastic_forces : ndarray, shape (P,)
        F_el at those positions.
    n_reversals : int
        Turning points at which the motion reversed (the final stop not counted):
        sign changes of the velocity, as in `presliding.simulate`; a start from
        rest is not a reversal, whatever direction the memory remembers.
    rest_position : float or None
        Where the mass came to rest; None if it never stops.
    status : str
        'stopped'; 'oscillating' (c1 = 0 and a swing without any sliding: an
        undamped oscillation inside presliding between the last two positions,
        forever); 'never_stops' (c1 = 0 and stops with arbitrarily small
        thresholds: infinitely many reversals of vanishing amplitude; the first
        ``max_reversals`` are listed); 'max_reversals' (c1 > 0: it stops later).
    message : str
    final_state : PIState or MemoryState
        Memory at the last position.
    initial_position, initial_velocity, mass : float
    model : PIFriction
    initial_state : PIState or MemoryState
        Memory at the initial position.
    """

    positions: FloatArray
    elastic_forces: FloatArray
    n_reversals: int
    rest_position: float | None
    status: str
    message: str
    final_state: PIState | MemoryState = field(repr=False)
    initial_position: float = 0.0
    initial_velocity: float = 0.0
    mass: float = 1.0
    model: PIFriction | None = field(default=None, repr=False)
    initial_state: PIState | MemoryState | None = field(default=None, repr=False)
    _rows, _rows_are_index = "positions", False  # to_pandas: a row per turning point

    @property
    def success(self) -> bool:
        """True when the mass came to rest."""
        return self.status == "stopped"

    def plot(self, ax: Axes | None = None, *, samples_per_swing: int = 200) -> Axes:
        """Elastic force along the swings: the Masing branches spiralling into the stick band.

        Each swing from one turning point to the next is sampled with
        `samples_per_swing` points and run through the model from the initial
        memory; the band |F_el| <= c1 where the mass sticks (eq. 16) is shaded.
        """
        from presliding.plotting import plot_turning_points

        return plot_turning_points(self, ax=ax, samples_per_swing=samples_per_swing)

    def report(self) -> str:
        """A readable summary."""
        lines = [
            f"free motion from y0 = {self.initial_position:.6g} m with v0 = "
            f"{self.initial_velocity:.6g} m/s (mass {self.mass:.6g} kg): {self.status}",
            self.message,
            f"reversals: {self.n_reversals}",
        ]
        for i, (y, f) in enumerate(zip(self.positions, self.elastic_forces, strict=True)):
            lines.append(f"  turning point {i + 1}: y = {y:.10g} m, F_el = {f:.6g} N")
        if self.rest_position is not None:
            lines.append(f"rest position: {self.rest_position:.10g} m")
        return "\n".join(lines)
