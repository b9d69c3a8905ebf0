"""Least-squares machinery shared by the ``fit_*`` functions, and their `FitResult`.

Every identification in presliding minimises a sum of squared residuals over
named parameters with scipy.optimize.least_squares (trust-region reflective,
bounds respected). Parameters may be held *fixed* at a value or *tied* to
another one (p = factor·q); only the remaining *free* parameters are varied.

Uncertainty follows the usual linearisation at the optimum: with the Jacobian
J of the residuals with respect to the free parameters, n residuals and p free
parameters, the covariance is s²·(JᵀJ)⁻¹ with s² = ‖r‖²/(n − p); tied
parameters inherit it through their factor, fixed ones have zero error. The
confidence interval is value ± t_{n−p}·SE (Student t at the chosen level); where it would
cross a bound of the parameter (a nonnegative one below 0), the data do not exclude the
bound: the interval reaches it, and its far end is taken on a log scale from the bound, so it
never leaves the parameter's range. It
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
    covariance : ndarray, shape (P, P) or None
        Covariance of every parameter, in the order of `parameters` (0 for fixed
        ones, inf variance where the data do not determine one). The pooled fits
        give the HAC covariance of `presliding.identification.uncertainty`.
    records : tuple of (start, stop)
        Sample ranges of each record in `abscissa`, `measured` and `fitted`
        (empty for a fit of one record).
    bootstrap : dict name -> (standard error, lower, upper), or None
        The record-level bootstrap of a pooled fit (percentile interval at
        `confidence_level`), when it ran.
    notes : tuple of str
        Remarks the report lists (per unit mass, pruned elements, ...).
    cross_validation : object or None
        A `presliding.identification.CrossValidation` whose table the report shows.
    at_bounds : tuple of str
        Free parameters the optimiser left on a bound (reported exactly at it).
    bounds : dict name -> (lower, upper)
        The bounds of the parameters that have a finite one (the fit's own,
        such as stiffness >= 0, and the caller's).
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
    covariance: FloatArray | None = None
    records: tuple[tuple[int, int], ...] = ()
    bootstrap: dict[str, tuple[float, float, float]] | None = None
    notes: tuple[str, ...] = ()
    cross_validation: Any = None
    predictor: Any = field(default=None, repr=False)
    at_bounds: tuple[str, ...] = ()
    units: dict[str, str] = field(default_factory=dict)
    bounds: dict[str, tuple[float, float]] = field(default_factory=dict)
    search: Any = None  # the pooled fits' `_search.SearchSummary` (starts, noise floor, order)

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
            units=units, covariance=sol.covariance, bounds=sol.bounds, **labels,
        )  # fmt: skip

    @property
    def n_starts(self) -> int | None:
        """Starts of the shared parameters the search ran (pooled fits; None otherwise)."""
        return None if self.search is None else self.search.n_starts

    @property
    def n_starts_at_best(self) -> int | None:
        """How many of those starts reached the best optimum (pooled fits; None otherwise)."""
        return None if self.search is None else self.search.n_starts_at_best

    @property
    def nfev(self) -> int:
        """Residual evaluations over every start and check (scipy's name for `n_evaluations`)."""
        return self.n_evaluations

    @property
    def correlation(self) -> FloatArray | None:
        """Correlations of the parameters (order of `parameters`), from `covariance`."""
        if self.covariance is None:
            return None
        from presliding.identification.uncertainty import correlation_matrix

        return correlation_matrix(self.covariance)

    def predict(self, measurement: Any, **options: Any) -> Any:
        """The fitted model's prediction of another record (a `Prediction`).

        Parameters
        ----------
        measurement : Measurement
            A record of the kind fitted (same signals).
        **options
            Passed to the fit's predictor, e.g. ``initial="fit"`` (default: the
            record's own initial conditions estimated with every shared
            parameter held) or ``initial="measured"`` (its first samples).

        Returns
        -------
        Prediction
            Measured against predicted signal, NRMSE, reversal counts and rest
            positions (`presliding.identification.cross_validation`).
        """
        if self.predictor is None:
            raise ValueError(
                f"a {self.kind} fit cannot predict other records; got kind {self.kind!r}."
            )
        return self.predictor.predict(self, measurement, **options)

    def to_dict(self) -> dict[str, Any]:
        """Parameters, errors, intervals, fit quality and status as plain Python values."""
        return {
            "kind": self.kind,
            "status": self.status,
            "message": self.message,
            "success": self.success,
            "parameters": dict(self.parameters),
            "standard_error": dict(self.standard_error),
            "confidence_interval": {k: list(v) for k, v in self.confidence_interval.items()},
            "confidence_level": self.confidence_level,
            "fixed": list(self.fixed),
            "tied": list(self.tied),
            "bounds": {k: list(v) for k, v in self.bounds.items()},
            "derived": dict(self.derived),
            "residual_rms": self.residual_rms,
            "nrmse": self.nrmse,
            "relative_residual": self.relative_residual,
            "nfev": self.n_evaluations,
            "covariance": None if self.covariance is None else self.covariance.tolist(),
            "bootstrap": None if self.bootstrap is None else {
                k: list(v) for k, v in self.bootstrap.items()},
            "notes": list(self.notes),
            "model": repr(self.model),
        }  # fmt: skip

    def to_pandas(self) -> Any:
        """A pandas DataFrame of the parameters: value, standard error, interval, fixed/tied."""
        import pandas as pd

        rows = []
        for n, v in self.parameters.items():
            lo, hi = self.confidence_interval[n]
            rows.append({"parameter": n, "value": v, "standard_error": self.standard_error[n],
                         "lower": lo, "upper": hi, "fixed": n in self.fixed,
                         "tied": n in self.tied})  # fmt: skip
        return pd.DataFrame(rows).set_index("parameter")

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
        """A readable summary: status, parameters with units, errors and intervals, fit quality.

        Also, when present: the record-level bootstrap, strong correlations
        (|ρ| >= 0.9), the notes and the cross-validation table.
        """
        pct = f"{100 * self.confidence_level:g} %"
        width = max([16, *(len(n) + 2 for n in self.parameters)])
        boot = self.bootstrap or {}
        lines = [
            f"{self.kind} fit: {self.status} — {self.message}",
            f"{self.measured.shape[0]} samples"
            + (f" in {len(self.records)} records" if self.records else "")
            + f", {self.n_evaluations} evaluations",
            "",
            f"{'parameter':<{width}}{'value':>14} {'unit':<10}{'std. error':>11}   "
            f"{pct + ' interval':<30}" + ("   bootstrap std. error and interval" if boot else ""),
        ]
        for n, v in self.parameters.items():
            se = self.standard_error[n]
            lo, hi = self.confidence_interval[n]
            note = " (fixed)" if n in self.fixed else (" (tied)" if n in self.tied else "")
            if n in self.at_bounds:
                note += f" (at its bound {_bound_text(self.bounds.get(n), v)})"
            unit = self.units.get(n, "")
            line = f"{n:<{width}}{v:>14.6g} {unit:<10}{se:>11.3g}   [{lo:.6g}, {hi:.6g}]{note}"
            if n in boot:
                b_se, b_lo, b_hi = boot[n]
                line = f"{line:<{width + 70}}   {b_se:.3g}  [{b_lo:.6g}, {b_hi:.6g}]"
            lines.append(line)
        if self.derived:
            lines.append("")
            lines += [
                f"{n:<{width}}{v:>14.6g} {self.units.get(n, '')}".rstrip()
                for n, v in self.derived.items()
            ]
        lines += _bounds_lines(self.bounds, list(self.parameters))
        lines += self._correlation_lines()
        lines += [
            "",
            f"residual RMS: {self.residual_rms:.6g} {self.signal_unit} ({self.signal_label})",
            f"NRMSE (RMS / range): {100 * self.nrmse:.3f} %; "
            f"relative residual ‖r‖/‖y − ȳ‖: {100 * self.relative_residual:.3f} %; "
            f"explained variance {100 * (1 - self.relative_residual**2):.3f} %",
            f"model: {self.model!r}",
        ]
        lines += self.search.lines() if self.search is not None else []
        lines += [f"note: {n}" for n in self.notes]
        if self.cross_validation is not None:
            lines += ["", self.cross_validation.report()]
        return "\n".join(lines)

    def _correlation_lines(self) -> list[str]:
        corr = self.correlation
        if corr is None:
            return []
        names = list(self.parameters)
        pairs = [
            f"  {names[i]} ~ {names[j]}: {corr[i, j]:+.3f}"
            for i in range(len(names))
            for j in range(i + 1, len(names))
            if abs(corr[i, j]) >= 0.9
        ]
        if not pairs:
            return []
        return ["", "strong correlations (|ρ| >= 0.9):", *pairs[:20]] + (
            [f"  ... {len(pairs) - 20} more"] if len(pairs) > 20 else []
        )

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


def _bound_text(bounds: tuple[float, float] | None, value: float) -> str:
    if bounds is None:
        return f"{value:.6g}"
    return f"{bounds[0]:.6g}" if value == bounds[0] else f"{bounds[1]:.6g}"


def _bounds_lines(bounds: dict[str, tuple[float, float]], order: list[str]) -> list[str]:
    """Bounds grouped by range, parameters in their order (at most 8 named per range)."""
    groups: dict[tuple[float, float], list[str]] = {}
    for n in order:
        if n in bounds:
            groups.setdefault(bounds[n], []).append(n)
    lines = []
    for (lo, hi), names in groups.items():
        rng = f"[{lo:.6g}, {hi:.6g}]".replace("[-inf", "(-inf").replace("inf]", "inf)")
        more = f" and {len(names) - 8} more" if len(names) > 8 else ""
        lines.append(f"  {rng}: {', '.join(names[:8])}{more}")
    return ["", "bounds:", *lines] if lines else []
