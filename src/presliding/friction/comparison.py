"""Several friction models on one displacement path: forces, dissipation, a plot.

`compare` runs each model (PIFriction, or the classical models of
`presliding.friction.baselines`) from its default state along the same path and
returns a `Comparison`: the force of every model, the work each dissipates
along the path, ∫ F dy (for closed loops, the area of the hysteresis loop),
and how far each lies from the first model.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_list,
    as_signal,
    check_increasing,
    check_same_length,
    check_type,
)
from presliding.friction.baselines import CoulombFriction, DahlFriction, LuGreFriction
from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis._results import ResultMixin

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["Comparison", "compare"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False, repr=False)
class Comparison(ResultMixin):
    """Forces of several friction models along one displacement path.

    Attributes
    ----------
    displacement : ndarray, shape (T,)
    time : ndarray, shape (T,), or None
    forces : dict of str to ndarray, shape (T,)
        The friction force of each model, by label, in the order given.
    work : dict of str to float
        ∫ F dy along the path [J] (trapezoidal rule), by label: the energy the
        friction takes from the motion (dissipated over closed loops).
    rms_difference : dict of str to float
        Root mean square of F − F_first, by label (0 for the first model).
    status, message : str
        Always "ok" (a model that cannot run raises on entry).

    ``to_pandas()`` has a row per sample: displacement, time (if given) and
    ``forces_<label>`` for each model.
    """

    _rows, _rows_are_index = "displacement", False

    displacement: FloatArray
    time: FloatArray | None
    forces: dict[str, FloatArray]
    work: dict[str, float]
    rms_difference: dict[str, float]
    status: str = "ok"
    message: str = ""

    @property
    def success(self) -> bool:
        """True: every model ran."""
        return self.status == "ok"

    def plot(self, ax: Axes | None = None) -> Axes:
        """Every model's force against the displacement (hysteresis loops) on one axes."""
        from presliding.plotting import plot_hysteresis

        return plot_hysteresis(
            self.displacement, list(self.forces.values()), labels=list(self.forces), ax=ax
        )

    def report(self) -> str:
        """A table of the models: force range, work along the path, distance to the first."""
        first = next(iter(self.forces))
        lines = [
            f"{len(self.forces)} models on {self.displacement.shape[0]} samples: {self.message}"
        ]
        width = max(len(label) for label in self.forces)
        for label, f in self.forces.items():
            lines.append(
                f"  {label:<{width}}  F in [{np.min(f):.6g}, {np.max(f):.6g}] N, "
                f"∫F dy = {self.work[label]:.6g} J, RMS difference to {first}: "
                f"{self.rms_difference[label]:.6g} N"
            )
        return "\n".join(lines)


def compare(
    models: Mapping[str, Any] | Sequence[Any],
    displacement: ArrayLike,
    *,
    time: ArrayLike | None = None,
) -> Comparison:
    """Run several friction models along one displacement path.

    Parameters
    ----------
    models : mapping of label to model, or sequence of models
        Any of PIFriction, CoulombFriction, DahlFriction, LuGreFriction (each
        started from its default state at the first sample); a sequence is
        labelled by class name.
    displacement : array_like, shape (T,)
        The path y [m], monotone between samples.
    time : array_like, shape (T,), optional
        Sample times [s], strictly increasing; required when a LuGre model
        (rate dependent) is included.

    Returns
    -------
    Comparison
        Forces, work along the path and differences; ``.plot()`` draws the loops.
    """
    if isinstance(models, Mapping):
        labels, items = [str(k) for k in models], list(models.values())
    else:
        items = as_list("models", models)
        labels = [type(m).__name__ for m in items]
    if not items:
        raise ValueError("`models` must not be empty; got no models.")
    if len(set(labels)) != len(labels):
        raise ValueError(f"`models` must have distinct labels; got {labels}.")
    y = as_signal("displacement", displacement)
    t = None
    if time is not None:
        t = as_signal("time", time)
        check_same_length(displacement=y, time=t)
        check_increasing("time", t)
    kinds = (PIFriction, CoulombFriction, DahlFriction, LuGreFriction)
    for i, (label, model) in enumerate(zip(labels, items, strict=True)):
        where = f" at {label!r}" if isinstance(models, Mapping) else f" at index {i}"
        check_type("models", model, kinds, where=where)
    forces: dict[str, FloatArray] = {}
    for label, model in zip(labels, items, strict=True):
        if isinstance(model, LuGreFriction):
            if t is None:
                raise ValueError(f"`time` must be given for the LuGre model {label!r}; got None.")
            forces[label] = np.asarray(model.force(y, t)[0], dtype=np.float64)
        else:
            forces[label] = np.asarray(model.force(y)[0], dtype=np.float64)
    dy = np.diff(y)
    work = {k: float(0.5 * (f[1:] + f[:-1]) @ dy) for k, f in forces.items()}
    ref = forces[labels[0]]
    rms = {k: float(np.sqrt(np.mean((f - ref) ** 2))) for k, f in forces.items()}
    return Comparison(y, t, forces, work, rms, "ok", "every model ran along the path")
