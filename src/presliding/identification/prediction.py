"""Predictions of a fitted model on a record: signal, NRMSE, reversal counts, rest positions.

`FitResult.predict(measurement)` returns a `Prediction`; `cross_validate`
collects one per held-out record. Reversals are counted the same way on the
measured and on the predicted position (`count_reversals`): a turning point
counts when the path leaves it by more than a tolerance, by default three
times the larger of the position's quantum (its smallest nonzero step, an
encoder's resolution) and its noise (the RMS of second differences over √6),
so that a quantised or noisy record is not credited with reversals it only
seems to make.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._display import fill_attrs, result_html, short_repr, unit_of
from presliding._interop import require
from presliding._validation import as_nonnegative_scalar, as_signal
from presliding.identification.fit_result import fit_statistics
from presliding.identification.problem._pi_regression import reversal_indices

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = [
    "Prediction",
    "count_reversals",
    "counted",
    "position_quantum",
    "reversal_tolerance",
]

FloatArray = NDArray[np.float64]


def reversal_tolerance(position: ArrayLike) -> float:
    """Three times the larger of the quantum and the noise of a position record [m].

    Parameters
    ----------
    position : array_like, shape (T,)

    Returns
    -------
    float
        3·max(smallest nonzero |Δy|, RMS(Δ²y)/√6); 0 for a constant record.
    """
    y = as_signal("position", position)
    steps = np.abs(np.diff(y))
    steps = steps[steps > 0]
    if not steps.size:
        return 0.0
    quantum = float(np.min(steps))
    noise = float(np.sqrt(np.mean(np.diff(y, 2) ** 2)) / np.sqrt(6)) if y.shape[0] > 2 else 0.0
    return 3.0 * max(quantum, min(noise, 0.05 * float(np.ptp(y))))


def position_quantum(position: ArrayLike) -> float | None:
    """The quantum of a quantised position record (an encoder count) [m], None if not quantised.

    The smallest nonzero step, when every step is a whole multiple of it.
    """
    y = np.asarray(position, dtype=float)
    steps = np.abs(np.diff(y))
    steps = steps[steps > 0]
    if not steps.size:
        return None
    q = float(np.min(steps))
    ratio = steps / q
    return q if np.allclose(ratio, np.round(ratio), rtol=0.0, atol=1e-6) else None


def counted(initial: str, tolerance: float, position: ArrayLike) -> dict[str, Any]:
    """The `Prediction` fields stating how it started and at which tolerance it counted."""
    return {"initial": initial, "reversal_tolerance": float(tolerance),
            "quantum": position_quantum(position)}  # fmt: skip


def tolerance_text(tolerance: float | None, quantum: float | None, unit: str = "m") -> str:
    """``"3e-06 m (3 encoder counts of 1e-06 m)"``, or the tolerance alone."""
    if tolerance is None:
        return "—"
    text = f"{tolerance:.3g} {unit}"
    if quantum:
        text += f" ({tolerance / quantum:.3g} encoder counts of {quantum:.3g} {unit})"
    return text


def count_reversals(position: ArrayLike, tolerance: float | None = None) -> int:
    """Number of turning points of a position record, left by more than `tolerance`.

    Parameters
    ----------
    position : array_like, shape (T,)
        y [m].
    tolerance : float, optional
        Travel [m] by which the path must leave a turning point (>= 0); default
        `reversal_tolerance` of the record.

    Returns
    -------
    int
        The motion reversals (the first motion is not one).
    """
    y = as_signal("position", position)
    tol = reversal_tolerance(y) if tolerance is None else as_nonnegative_scalar(
        "tolerance", tolerance, kind="position")  # fmt: skip
    return int(reversal_indices(np.ascontiguousarray(y), tol).shape[0])


@dataclass(frozen=True, eq=False)
class Prediction:
    """A fitted model's prediction of one record.

    Attributes
    ----------
    abscissa, measured, predicted : ndarray, shape (T,)
        Against time (or force for a quasi-static fit): the compared signal.
    signal_label, abscissa_label : str
    nrmse : float
        RMS(measured − predicted) over the range of the measured signal.
    measured_reversals, predicted_reversals : int or None
        `count_reversals` of the measured and the predicted position (same
        tolerance); None where the record has no time course (virgin curves).
    measured_rest, predicted_rest : float or None
        Position at the end of the record, when it is at rest there (a response).
    parameters : dict
        The record's own parameters used (initial conditions, preload).
    status : str
        "success", or "failed" when the record's initial conditions could not be
        estimated or its simulation failed.
    message : str
    initial : {"fit", "measured"}
        How the record's own start was set: fitted to the record with every
        shared parameter held, or taken from its first samples.
    reversal_tolerance : float or None
        The travel [m or rad] by which reversals were counted (both counts).
    quantum : float or None
        The position's quantum (an encoder count) when it is quantised.
    """

    abscissa: FloatArray
    measured: FloatArray
    predicted: FloatArray
    signal_label: str
    abscissa_label: str
    nrmse: float
    measured_reversals: int | None
    predicted_reversals: int | None
    measured_rest: float | None
    predicted_rest: float | None
    parameters: dict[str, float]
    status: str = "success"
    message: str = ""
    initial: str = "fit"
    reversal_tolerance: float | None = None
    quantum: float | None = None

    @property
    def from_record(self) -> dict[str, str]:
        """Every parameter taken from the predicted record itself, and how it was taken."""
        how = "fitted to the record" if self.initial == "fit" else "its first samples"
        return {name: how for name in self.parameters}

    @property
    def success(self) -> bool:
        """True when the prediction could be computed."""
        return self.status == "success"

    @property
    def reversals_match(self) -> bool | None:
        """Whether the predicted reversal count equals the measured one."""
        if self.measured_reversals is None or self.predicted_reversals is None:
            return None
        return self.measured_reversals == self.predicted_reversals

    @property
    def rest_error(self) -> float | None:
        """predicted_rest − measured_rest (None unless both are at rest)."""
        if self.measured_rest is None or self.predicted_rest is None:
            return None
        return self.predicted_rest - self.measured_rest

    @classmethod
    def build(
        cls, abscissa: Any, measured: Any, predicted: Any, labels: tuple[str, str], **extra: Any
    ) -> Prediction:
        """A prediction with its NRMSE computed."""
        _, nrmse, _ = fit_statistics(measured, predicted)
        defaults: dict[str, Any] = {"measured_reversals": None, "predicted_reversals": None,
                    "measured_rest": None, "predicted_rest": None, "parameters": {}}  # fmt: skip
        return cls(np.asarray(abscissa, float), np.asarray(measured, float),
                   np.asarray(predicted, float), labels[0], labels[1], nrmse,
                   **{**defaults, **extra})  # fmt: skip

    def to_dict(self) -> dict[str, Any]:
        """The summary figures (not the arrays) as plain values."""
        return {
            "nrmse": self.nrmse, "measured_reversals": self.measured_reversals,
            "predicted_reversals": self.predicted_reversals, "measured_rest": self.measured_rest,
            "predicted_rest": self.predicted_rest, "parameters": dict(self.parameters),
            "status": self.status, "success": self.success, "message": self.message,
            "initial": self.initial, "reversal_tolerance": self.reversal_tolerance,
            "quantum": self.quantum,
        }  # fmt: skip

    def to_pandas(self) -> Any:
        """A DataFrame of the abscissa, measured and predicted signal."""
        pd = require("pandas", "`to_pandas()`")

        frame = pd.DataFrame({self.abscissa_label: self.abscissa, "measured": self.measured,
                              "predicted": self.predicted})  # fmt: skip
        frame.attrs.update(signal=self.signal_label, nrmse=self.nrmse,
                           parameters=dict(self.parameters))  # fmt: skip
        return fill_attrs(frame, self, units=_units(self.abscissa_label, self.signal_label))

    def __repr__(self) -> str:
        return short_repr(self)

    def _repr_html_(self) -> str:
        """The status, NRMSE, reversal counts, rest positions and parameters, for notebooks."""
        figures = [("signal", self.signal_label, ""), ("samples", str(self.measured.shape[0]), ""),
                   ("NRMSE", f"{100 * self.nrmse:.3f}", "%")]  # fmt: skip
        for name in ("measured_reversals", "predicted_reversals"):
            if getattr(self, name) is not None:
                figures.append((name.replace("_", " "), str(getattr(self, name)), ""))
        for name in ("measured_rest", "predicted_rest"):
            if getattr(self, name) is not None:
                figures.append((name.replace("_", " "), f"{getattr(self, name):.6g}", "m"))
        rows = [(n, f"{v:.6g}") for n, v in self.parameters.items()]
        return result_html(self, figures, (("parameter", "value"), rows) if rows else None)

    def report(self) -> str:
        """A one-paragraph summary."""
        lines = [f"prediction: {self.status}{' — ' + self.message if self.message else ''}",
                 f"  NRMSE {100 * self.nrmse:.3f} % ({self.signal_label})"]  # fmt: skip
        start = "fitted to the record" if self.initial == "fit" else "measured (first samples)"
        lines.append(f"  start: {start}")
        if self.parameters:
            lines.append("  taken from the record: " + ", ".join(
                f"{k} = {v:.6g}" for k, v in self.parameters.items()))  # fmt: skip
        if self.measured_reversals is not None:
            lines.append(f"  reversals: measured {self.measured_reversals}, predicted "
                         f"{self.predicted_reversals} (tolerance "
                         f"{tolerance_text(self.reversal_tolerance, self.quantum)})")  # fmt: skip
        if self.rest_error is not None:
            lines.append(f"  rest position: measured {self.measured_rest:.6g}, predicted "
                         f"{self.predicted_rest:.6g}")  # fmt: skip
        return "\n".join(lines)

    def plot(self, ax: Axes | None = None) -> Axes:
        """Measured and predicted signal with the residual below; returns the axes."""
        from presliding.plotting import plot_fit

        ylabel, xlabel = self.signal_label, self.abscissa_label
        ylabel += "" if "[" in ylabel else f" [{unit_of(ylabel.split()[-1]) or '-'}]"
        xlabel += "" if "[" in xlabel else f" [{unit_of(xlabel.split()[-1]) or 'index'}]"
        return plot_fit(self.abscissa, self.measured, self.predicted, ax=ax,
                        xlabel=xlabel, ylabel=ylabel, fitted_label="predicted",
                        title=f"prediction (NRMSE {100 * self.nrmse:.3g} %)")  # fmt: skip


def _units(abscissa_label: str, signal_label: str) -> dict[str, str]:
    """Units of the columns, read from labels such as ``time [s]`` (none where not given)."""
    import re

    out = {}
    for column, label in ((abscissa_label, abscissa_label), ("measured", signal_label),
                          ("predicted", signal_label)):  # fmt: skip
        found = re.search(r"\[([^\]]+)\]", label)
        if found:
            out[column] = found.group(1)
    return out
