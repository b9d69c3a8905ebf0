"""Least-squares machinery shared by the ``fit_*`` functions, and their `FitResult`.

Every identification in presliding minimises a sum of squared residuals over
named parameters with scipy.optimize.least_squares (trust-region reflective,
bounds respected). Parameters may be held *fixed* at a value or *tied* to
another one (p = factor·q); only the remaining *free* parameters are varied.

Uncertainty follows the usual linearisation at the optimum: with the Jacobian
J of the residuals with respect to the free parameters, n residuals and p free
parameters, the covariance is s²·(JᵀJ)⁻¹ with s² = ‖r‖²/(n − p); tied
parameters inherit it through their factor, fixed ones have zero error. The
confidence interval is value ± t_{n−p}·SE (Student t at the chosen level). It
is exact for parameters that enter linearly and Gaussian independent noise, a
first-order approximation otherwise. A direction of parameter space that the
data do not determine (a singular JᵀJ) makes the affected errors infinite and
the status ``"not_identifiable"``.

The solver (`solve_least_squares`, its `Solution`, the fixed/tied parameter map
and the covariance) lives in `_least_squares` and is re-exported here; this
module holds the fit statistics and the public result, `FitResult`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding.friction.pi_friction import PIFriction
from presliding.identification._least_squares import STATUSES as STATUSES
from presliding.identification._least_squares import Solution, solve_least_squares
from presliding.identification._least_squares import Tie as Tie
from presliding.identification._status import judge
from presliding.identification._units import parameter_units

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["FitResult", "fit_statistics", "solve_least_squares"]

FloatArray = NDArray[np.float64]


# ---------------------------------------------------------------------- statistics
def fit_statistics(measured: ArrayLike, fitted: ArrayLike) -> tuple[float, float, float]:
    """Residual RMS, NRMSE and the relative residual of a fit.

    NRMSE = RMS(measured − fitted) / (max(measured) − min(measured)), the RMS
    normalised by the range of the measured signal. The relative residual
    ‖measured − fitted‖ / ‖measured − mean(measured)‖ is 0 for a perfect fit and
    1 for a fit no better than the mean (1 − FIT/100 of the "fit percentage").
    Both are inf for a constant measured signal.

    Parameters
    ----------
    measured, fitted : array_like, shape (T,)
        The measured signal and the model's fit to it.

    Returns
    -------
    residual_rms, nrmse, relative_residual : float
    """
    m = np.asarray(measured, dtype=float)
    r = m - np.asarray(fitted, dtype=float)
    rms = float(np.sqrt(np.mean(r * r)))
    span = float(np.ptp(m))
    spread = float(np.linalg.norm(m - np.mean(m)))
    nrmse = rms / span if span > 0 else float("inf")
    return rms, nrmse, (float(np.linalg.norm(r)) / spread if spread > 0 else float("inf"))


# ---------------------------------------------------------------------- result
@dataclass(frozen=True, eq=False)
class FitResult:
    """Outcome of a ``fit_*`` function.

    Attributes
    ----------
    model : PIFriction or None
        The identified friction model, ready to simulate (None if the fit failed
        or the parameters do not form a valid model).
    parameters, standard_error : dict name -> float
        Every parameter (free, fixed and tied) and its standard error (0 for
        fixed parameters, inf where the data do not determine it).
    confidence_interval : dict name -> (lower, upper)
        At `confidence_level`.
    fixed, tied : tuple of str
    abscissa, measured, fitted : ndarray
        What was fitted (only the samples used in the fit), against `abscissa`.
    residual_rms, nrmse, relative_residual : float
        RMS of measured − fitted, that RMS over the range of the measured
        signal, and ‖measured − fitted‖/‖measured − mean‖ (see `fit_statistics`).
    status : str
        One of `STATUSES`: ``"converged"`` (the only success),
        ``"not_identifiable"`` (the data do not determine some parameters),
        ``"at_bound"`` (a parameter sits on a bound, where the linearised
        interval does not hold), ``"poor_fit"`` (the model explains less than
        half of the variance, or every parameter sits on a bound: check units,
        window and sign), ``"max_evaluations"`` or ``"failed"``.
    message : str
    n_evaluations : int
    derived : dict name -> float
        Quantities computed from the parameters (e.g. the Coulomb level F_c, eq. 9).
    at_bounds : tuple of str
        Free parameters the optimiser left on a bound (reported exactly at it).
    units : dict name -> str
        SI unit of each parameter and derived quantity (rotary units for an
        angle and a torque).
    """

    model: PIFriction | None
    parameters: dict[str, float]
    standard_error: dict[str, float]
    confidence_interval: dict[str, tuple[float, float]]
    confidence_level: float
    fixed: tuple[str, ...]
    tied: tuple[str, ...]
    abscissa: FloatArray
    measured: FloatArray
    fitted: FloatArray
    residual_rms: float
    nrmse: float
    relative_residual: float
    status: str
    message: str
    n_evaluations: int
    kind: str = "least-squares"
    abscissa_label: str = "sample"
    signal_label: str = "signal"
    signal_unit: str = ""
    derived: dict[str, float] = field(default_factory=dict)
    at_bounds: tuple[str, ...] = ()
    units: dict[str, str] = field(default_factory=dict)

    @classmethod
    def from_solution(
        cls, sol: Solution, model: PIFriction | None, abscissa: Any, measured: Any, fitted: Any,
        hint: str = "", rotary: bool = False, **labels: Any,
    ) -> FitResult:  # fmt: skip
        """Assemble a result from a `Solution` and the fitted signal.

        The status passes the poor-fit test of `_status.judge` (`hint` adds a
        likely cause to its message); `rotary` selects rotary parameter units.
        """
        rms, nrmse, relative = fit_statistics(measured, fitted)
        status, message = judge(
            sol.status, sol.message, np.asarray(measured, dtype=float),
            np.asarray(fitted, dtype=float), sol.free, sol.at_bounds,
            labels.get("signal_label", "signal"), hint,
        )  # fmt: skip
        units = parameter_units([*sol.values, *labels.get("derived", {})], rotary)
        units.update(labels.pop("units", {}))
        return cls(
            model=model, parameters=sol.values, standard_error=sol.standard_error,
            confidence_interval=sol.confidence_interval, confidence_level=sol.level,
            fixed=sol.fixed, tied=sol.tied, abscissa=np.asarray(abscissa, dtype=float),
            measured=np.asarray(measured, dtype=float), fitted=np.asarray(fitted, dtype=float),
            residual_rms=rms, nrmse=nrmse, relative_residual=relative, status=status,
            message=message, n_evaluations=sol.n_evaluations, at_bounds=sol.at_bounds,
            units=units, **labels,
        )  # fmt: skip

    @property
    def success(self) -> bool:
        """True when the fit converged and every parameter is determined."""
        return self.status == "converged"

    @property
    def residual(self) -> FloatArray:
        """measured − fitted."""
        return self.measured - self.fitted

    @property
    def mass(self) -> float | None:
        """The identified mass m (eq. 17), or None if the fit has none."""
        return self.parameters.get("mass")

    def report(self) -> str:
        """A readable summary: status, parameters with units, errors and intervals, fit quality."""
        pct = f"{100 * self.confidence_level:g} %"
        lines = [
            f"{self.kind} fit: {self.status} — {self.message}",
            f"{self.measured.shape[0]} samples, {self.n_evaluations} evaluations",
            "",
            f"{'parameter':<16}{'value':>14} {'unit':<10}{'std. error':>11}   "
            f"{pct + ' interval':<30}",
        ]
        for n, v in self.parameters.items():
            se = self.standard_error[n]
            lo, hi = self.confidence_interval[n]
            note = " (fixed)" if n in self.fixed else (" (tied)" if n in self.tied else "")
            note += " (at bound)" if n in self.at_bounds else ""
            unit = self.units.get(n, "")
            lines.append(f"{n:<16}{v:>14.6g} {unit:<10}{se:>11.3g}   [{lo:.6g}, {hi:.6g}]{note}")
        if self.derived:
            lines.append("")
            lines += [
                f"{n:<16}{v:>14.6g} {self.units.get(n, '')}".rstrip()
                for n, v in self.derived.items()
            ]
        lines += [
            "",
            f"residual RMS: {self.residual_rms:.6g} {self.signal_unit} ({self.signal_label})",
            f"NRMSE (RMS / range): {100 * self.nrmse:.3f} %; "
            f"relative residual ‖r‖/‖y − ȳ‖: {100 * self.relative_residual:.3f} %; "
            f"explained variance {100 * (1 - self.relative_residual**2):.3f} %",
            f"model: {self.model!r}",
        ]
        return "\n".join(lines)

    def _signal_text(self) -> str:
        return (
            f"{self.signal_label} [{self.signal_unit}]" if self.signal_unit else self.signal_label
        )

    def plot(self, ax: Axes | None = None) -> Axes:
        """Measured and fitted signal, with the residual in a panel below; returns the axes."""
        from presliding.plotting import plot_fit

        return plot_fit(
            self.abscissa, self.measured, self.fitted, ax=ax,
            xlabel=self.abscissa_label, ylabel=self._signal_text(),
            title=f"{self.kind} fit (NRMSE {100 * self.nrmse:.2f} %)",
        )  # fmt: skip
