"""How a `FitResult` shows itself: the text report, the notebook table, the table of
parameters for pandas, a short repr and the figure (`FitResult` inherits `FitReport`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from presliding._display import fill_attrs, fit_html, short_repr
from presliding._interop import require
from presliding.identification.result._fit_names import bound_text, bounds_lines, interval_text

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["FitReport"]

FloatArray = NDArray[np.float64]


class FitReport:
    """The display methods of a `FitResult`, from its fields."""

    kind: str
    status: str
    message: str
    parameters: dict[str, float]
    standard_error: dict[str, float]
    confidence_interval: dict[str, tuple[float, float]]
    confidence_level: float
    units: dict[str, str]
    fixed: tuple[str, ...]
    tied: tuple[str, ...]
    at_bounds: tuple[str, ...]
    bounds: dict[str, tuple[float, float]]
    derived: dict[str, float]
    bootstrap: Any
    records: Any
    notes: Any
    cross_validation: Any
    measured: FloatArray
    fitted: FloatArray
    abscissa: FloatArray
    abscissa_label: str
    signal_label: str
    signal_unit: str
    residual_rms: float
    nrmse: float
    relative_residual: float
    n_evaluations: int
    model: Any
    correlation: Any
    search: Any
    interval_method: dict[str, str]
    alternatives: Any
    asymmetry: Any
    adequacy: Any

    @property
    def intervals_calibrated(self) -> bool:  # pragma: no cover - `FitResult` decides
        return True

    def to_pandas(self) -> Any:
        """A pandas DataFrame of the parameters: value, unit, standard error, interval,
        fixed/tied; ``df.attrs`` holds the status, message, parameter ``units``, the
        model, its ``parameters``, the fit's kind, NRMSE and confidence level."""
        pd = require("pandas", "`to_pandas()`")

        rows = []
        for n, v in self.parameters.items():
            lo, hi = self.confidence_interval[n]
            rows.append({"parameter": n, "value": v, "unit": self.units.get(n, ""),
                         "standard_error": self.standard_error[n], "lower": lo, "upper": hi,
                         "fixed": n in self.fixed, "tied": n in self.tied})  # fmt: skip
        frame = fill_attrs(pd.DataFrame(rows).set_index("parameter"), self, units=self.units)
        frame.attrs.update(kind=self.kind, nrmse=self.nrmse, derived=dict(self.derived),
                           confidence_level=self.confidence_level)  # fmt: skip
        return frame

    def __repr__(self) -> str:
        names = ("kind", "parameters", "standard_error", "nrmse", "relative_residual",
                 "n_evaluations", "model", "measured")  # fmt: skip
        return short_repr(self, names)

    def _repr_html_(self) -> str:
        """The status, the fit quality and the parameter table with units, for notebooks."""
        return fit_html(self)

    def report(self) -> str:
        """A readable summary: status, parameters with units, errors and intervals, fit quality.

        Also, when present: the record-level bootstrap, strong correlations
        (|ρ| >= 0.9), the notes, the test of an asymmetric fit against the
        symmetric one and the cross-validation table.
        """
        pct = f"{100 * self.confidence_level:g} %"
        width = max([16, *(len(n) + 2 for n in self.parameters)])
        boot = self.bootstrap or {}
        pct_note = "" if self.intervals_calibrated else " (not calibrated: see below)"
        lines = [
            f"{self.kind} fit: {self.status} — {self.message}",
            f"{self.measured.shape[0]} samples"
            + (f" in {len(self.records)} records" if self.records else "")
            + f", {self.n_evaluations} evaluations",
            "",
            f"{'parameter':<{width}}{'value':>14} {'unit':<10}{'std. error':>11}   "
            f"{pct + ' interval' + pct_note:<30}"
            + ("   bootstrap std. error and interval" if boot else ""),
        ]
        for n, v in self.parameters.items():
            se = self.standard_error[n]
            lo, hi = self.confidence_interval[n]
            note = " (fixed)" if n in self.fixed else (" (tied)" if n in self.tied else "")
            if n in self.at_bounds:
                note += f" (at its bound {bound_text(self.bounds.get(n), v)})"
            if self.interval_method.get(n) == "union":
                note += " (interval widened to hold another optimum)"
            elif self.interval_method.get(n) == "partner":
                note += " (interval along a saturated parameter's profile)"
            unit = self.units.get(n, "")
            line = f"{n:<{width}}{v:>14.6g} {unit:<10}{se:>11.3g}   {interval_text(lo, hi)}{note}"
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
        lines += bounds_lines(self.bounds, list(self.parameters))
        lines += self._correlation_lines()
        lines += [
            "",
            f"residual RMS: {self.residual_rms:.6g} {self.signal_unit} ({self.signal_label})",
            f"NRMSE (RMS / range): {100 * self.nrmse:.3g} %; "
            f"relative residual ‖r‖/‖y − ȳ‖: {100 * self.relative_residual:.3g} %; "
            f"explained variance {100 * (1 - self.relative_residual**2):.3f} %",
            f"model: {self.model!r}",
        ]
        lines += self.search.lines() if self.search is not None else []
        lines += self._adequacy_lines()
        for alt in self.alternatives:
            lines.append(
                f"another optimum (cost {alt.cost:.6g}, {alt.rise:+.3g} over the best): "
                + alt.text(self.parameters, tuple(self.parameters))
            )
        lines += [f"note: {n}" for n in self.notes]
        lines += self.asymmetry.lines() if self.asymmetry is not None else []
        if self.cross_validation is not None:
            lines += ["", self.cross_validation.report()]
        return "\n".join(lines)

    def _adequacy_lines(self) -> list[str]:
        """The residual tests' verdict and whether the intervals may be read as calibrated."""
        out = []
        if self.adequacy is not None:
            levels = ", ".join(f"{x:.3g}" for x in self.adequacy.levels[:8])
            more = " ..." if len(self.adequacy.levels) > 8 else ""
            out.append(f"residual tests: {'passed' if self.adequacy.passed else 'failed'}; "
                       f"residual RMS over the noise per record: {levels}{more}")  # fmt: skip
            if not self.adequacy.passed:
                out.append(f"  {self.adequacy.text()}")
        if not self.intervals_calibrated:
            out.append("intervals: not calibrated (the fit is not at an optimum of a model that "
                       "describes the data); the numbers are the local ones")  # fmt: skip
        return out

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

    def plot(self, ax: Axes | None = None, *, labels: Any = None) -> Axes:
        """Measured and fitted signal, with the residual in a panel below; returns the axes.

        The records of a pooled fit are drawn apart, one colour and one label each
        (`labels`, e.g. the file names; default "record 1", ...).
        """
        from presliding.plotting import plot_fit

        xlabel = self.abscissa_label
        if "[" not in xlabel:  # the unit of the abscissa, where the label has none
            unit = ("index" if xlabel == "sample" else
                    self.units.get("coulomb", "N") if "force" in xlabel else
                    self.units.get("threshold_1", "m"))  # fmt: skip
            xlabel = f"{xlabel} [{unit}]"
        return plot_fit(
            self.abscissa, self.measured, self.fitted, ax=ax,
            xlabel=xlabel, ylabel=self._signal_text(),
            title=f"{self.kind} fit (NRMSE {100 * self.nrmse:.3g} %)",
            records=self.records, labels=labels,
        )  # fmt: skip
