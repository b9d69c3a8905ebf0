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

from presliding._axes import as_axis, on_axis
from presliding.identification.intervals._alternatives import Alternative, hidden_optima
from presliding.identification.intervals._profile import profile_solution
from presliding.identification.judge._status import judge
from presliding.identification.result._fit_names import LmfitNames
from presliding.identification.result._fit_report import FitReport
from presliding.identification.solve._least_squares import STATUSES as STATUSES
from presliding.identification.solve._least_squares import Solution, solve_least_squares
from presliding.identification.solve._least_squares import Tie as Tie
from presliding.measurement._units import parameter_units

if TYPE_CHECKING:  # pragma: no cover
    pass

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
@dataclass(frozen=True, eq=False, repr=False)
class FitResult(FitReport, LmfitNames):
    """Outcome of a ``fit_*`` function.

    Attributes
    ----------
    model : PIFriction, GMSFriction, LuGreFriction, DahlFriction, CreepingFriction or None
        The identified friction model, ready to simulate (None if the fit failed
        or the parameters do not form a valid model): a `PIFriction`, or the family
        `fit_response(family=...)` fits, or with ``fit_quasi_static(creep=True)`` a
        `CreepingFriction`.
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
        ``"local_minimum"`` (the search found a better optimum than the one
        returned, or the residual stays far above the noise floor),
        ``"model_inadequate"`` (the residuals are not what the noise model
        says: the model does not describe the data; `adequacy` says which test
        failed where, and the likely cause), ``"not_identifiable"`` (the data
        do not determine some parameters:
        |ρ| >= 0.999, a standard error that is not finite, an interval that
        is unbounded or spans orders of magnitude, a flat profile),
        ``"at_bound"`` (a model parameter sits on a bound, where the linearised
        interval does not hold), ``"poor_fit"`` (the model explains less than
        half of the variance, or every parameter sits on a bound),
        ``"max_evaluations"`` or ``"failed"``. The rules and their order are
        those of `presliding.identification.judge._status`; the message names the
        rule that fired.
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
    axis : {'linear', 'rotary'}
        The axis of the data fitted (`presliding.measurement.Measurement.axis`);
        `units` and `signal_unit` are in its units.
    chisqr, ndata, var_names : float, int, tuple of str
        The minimised sum of squared residuals χ² (of the residual the solver
        saw, weights included), the number of residuals and the free
        parameters (lmfit's names; ``nvarys = len(var_names)``).
    nvarys, nfree, redchi, aic, bic, x, nfev : properties
        lmfit's and scipy's names: the number of free parameters, ndata − nvarys,
        χ²/(ndata − nvarys), n·ln(χ²/n) + 2·nvarys, n·ln(χ²/n) + ln(n)·nvarys,
        the free parameter vector (order of `var_names`) and the evaluations.
    interval_method : dict name -> str
        How each free parameter's interval was formed: ``"profile"`` (profile
        likelihood, `presliding.identification.intervals._profile`), ``"wald"``
        (value ± t·SE, on a log scale from a bound it would cross; also where
        the profile was not resolved on the scale of its threshold: the
        optimum is not a minimum on that scale, or the profile depends on
        where its inner optimisations stop), ``"partner"`` (widened to the
        values it takes along the profile of a parameter whose column vanishes
        on its bound, such as a preload saturated in the motion's direction,
        `presliding.identification.intervals._profile_bound`; its standard error raised
        to match) or ``"union"`` (widened to hold another local optimum,
        `alternatives`).
    asymmetry : AsymmetryTest or None
        A fit with ``asymmetric=True``: the test of the asymmetry against the
        symmetric fit of the same data (``verdict`` "supported", "not
        supported" or "undetermined", ``statistic``, ``p_value``, ``delta_aic``,
        ``delta_bic``, the ``symmetric`` fit;
        `presliding.identification.judge._asymmetry`).
    adequacy : Adequacy or None
        The residual tests of the fit (`presliding.identification.judge._adequacy`):
        ``passed``, ``findings`` (test, record, signal, lag), ``levels`` (each
        record's residual RMS over its noise) and ``cause`` (the likely mechanism
        the model lacks, when one is found); None where they did not run (a fit
        that is not at an optimum).
    intervals_calibrated : bool (property)
        False when the intervals cannot be read as calibrated confidence
        intervals: the residual tests failed (the model does not describe the
        data), the fit is not at an optimum of its model, or a linearised
        interval is too wide to hold and its profile was not resolved (rule
        ``profile``). The numbers stay.
    alternatives : tuple of Alternative
        Other local optima the search reached whose cost rise over the best is
        within the profile's likelihood-ratio threshold while they put a
        parameter outside its interval (`presliding.identification.intervals._alternatives`):
        each with ``parameters``, ``cost``, ``rise`` and ``differs`` (the
        parameters whose intervals were widened to hold it; the fit is then
        ``"not_identifiable"``).
    """

    model: Any  # PIFriction | GMSFriction | LuGreFriction | DahlFriction | CreepingFriction | None
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
    axis: str = "linear"
    chisqr: float = float("nan")
    ndata: int = 0
    var_names: tuple[str, ...] = ()
    interval_method: dict[str, str] = field(default_factory=dict)
    ties: dict[str, tuple[str, float, float]] = field(default_factory=dict)
    search: Any = None  # the pooled fits' `_search.SearchSummary` (starts, noise floor, order)
    alternatives: tuple[Alternative, ...] = ()
    asymmetry: Any = None  # an `AsymmetryTest` (fits with asymmetric=True)
    adequacy: Any = None
    unresolved: tuple[str, ...] = ()  # parameters whose profile stopped unresolved

    @classmethod
    def from_solution(
        cls, sol: Solution, model: Any, abscissa: Any, measured: Any, fitted: Any,
        hint: str = "", rotary: bool = False, **labels: Any,
    ) -> FitResult:  # fmt: skip
        """Assemble a result from a `Solution` and the fitted signal.

        The status passes the poor-fit test of `_status.judge` (`hint` adds a
        likely cause to its message); `rotary` selects rotary parameter units.
        """
        rms, nrmse, relative = fit_statistics(measured, fitted)
        if not sol.interval_method:
            sol = profile_solution(sol, labels.pop("profile", "auto"))
        sol, alternatives = hidden_optima(sol)
        status, message = judge(
            sol.status, sol.message, np.asarray(measured, dtype=float),
            np.asarray(fitted, dtype=float), sol.free, sol.at_bounds,
            labels.get("signal_label", "signal"), hint, values=sol.values,
            standard_error=sol.standard_error, intervals=sol.confidence_interval,
            covariance=sol.covariance, bounds=sol.bounds,
            model_hint=labels.pop("model_hint", ""),
            interval_method={x: sol.interval_method.get(x, "") for x in sol.unresolved},
        )  # fmt: skip
        chisqr = float(sol.residual @ sol.residual) if sol.residual.size else float("nan")
        units = parameter_units([*sol.values, *labels.get("derived", {})], rotary)
        units.update(labels.pop("units", {}))
        if rotary:
            units = {k: on_axis(v, "rotary") for k, v in units.items()}
            labels["signal_unit"] = on_axis(labels.get("signal_unit", ""), "rotary")
            labels["abscissa_label"] = on_axis(labels.get("abscissa_label", "sample"), "rotary")
            labels["axis"] = "rotary"
        return cls(
            model=model, parameters=sol.values, standard_error=sol.standard_error,
            confidence_interval=sol.confidence_interval, confidence_level=sol.level,
            fixed=sol.fixed, tied=sol.tied, abscissa=np.asarray(abscissa, dtype=float),
            measured=np.asarray(measured, dtype=float), fitted=np.asarray(fitted, dtype=float),
            residual_rms=rms, nrmse=nrmse, relative_residual=relative, status=status,
            message=message, n_evaluations=sol.n_evaluations, at_bounds=sol.at_bounds,
            units=units, covariance=sol.covariance, bounds=sol.bounds, chisqr=chisqr,
            ndata=int(sol.residual.size), var_names=sol.free,
            interval_method=dict(sol.interval_method), ties=dict(sol.ties),
            alternatives=alternatives, adequacy=sol.adequacy, unresolved=sol.unresolved,
            **labels,
        )  # fmt: skip

    def on_axis(self, axis: str) -> FitResult:
        """The same result with its units labelled for `axis` (from a fit of bare arrays)."""
        from dataclasses import replace

        if as_axis(axis) == self.axis:
            return self
        if self.axis == "rotary":
            raise ValueError(f"`axis` {axis!r}: this result is already labelled rotary.")
        return replace(
            self, axis=axis, units={k: on_axis(v, axis) for k, v in self.units.items()},
            signal_unit=on_axis(self.signal_unit, axis),
            abscissa_label=on_axis(self.abscissa_label, axis),
        )  # fmt: skip

    @property
    def intervals_calibrated(self) -> bool:
        """Whether the intervals may be read as calibrated: the fit is at an optimum of its
        model and its residuals pass the tests of `adequacy` (where they ran)."""
        from presliding.identification.judge._status import loose_wald

        at_optimum = self.status in ("converged", "not_identifiable", "at_bound")
        if loose_wald(self.parameters, self.confidence_interval, self.interval_method,
                      self.unresolved):  # fmt: skip
            return False  # a linearised interval too wide to hold, its profile not resolved
        return at_optimum and (self.adequacy is None or bool(self.adequacy.passed))

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
            Passed to the fit's predictor: ``initial="fit"`` (default: the
            record's own initial conditions estimated with every shared
            parameter held) or ``initial="measured"`` (its first samples), and
            ``reversal_tolerance`` (the travel [m or rad] by which reversals are
            counted; default the record's own; its old name ``tolerance`` works
            with a DeprecationWarning).

        Returns
        -------
        Prediction
            Measured against predicted signal, NRMSE, reversal counts and rest
            positions (`presliding.identification.cross_validation`).
        """
        from presliding._validation import renamed_keyword

        if self.predictor is None:
            raise ValueError(
                f"a {self.kind} fit cannot predict other records; got kind {self.kind!r}."
            )
        given = renamed_keyword(options, "tolerance", "reversal_tolerance",
                                options.pop("reversal_tolerance", None), "predict")  # fmt: skip
        if given is not None:
            options["tolerance"] = given  # the predictors' own name
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
            "chisqr": self.chisqr,
            "redchi": self.redchi,
            "aic": self.aic,
            "bic": self.bic,
            "ndata": self.ndata,
            "nvarys": self.nvarys,
            "var_names": list(self.var_names),
            "interval_method": dict(self.interval_method),
            "intervals_calibrated": self.intervals_calibrated,
            "adequacy": None if self.adequacy is None else self.adequacy.to_dict(),
            "alternatives": [a.to_dict() for a in self.alternatives],
            "covariance": None if self.covariance is None else self.covariance.tolist(),
            "bootstrap": None if self.bootstrap is None else {
                k: list(v) for k, v in self.bootstrap.items()},
            "notes": list(self.notes),
            "asymmetry": None if self.asymmetry is None else self.asymmetry.to_dict(),
            "model": repr(self.model),
        }  # fmt: skip

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
