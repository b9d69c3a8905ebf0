"""Leave-one-record-out cross-validation of the pooled fits.

`cross_validate(records, fit=fit_response, **options)` fits all records once,
then, for each record i, fits the others and predicts record i with
`FitResult.predict` (its own initial conditions estimated with every shared
parameter held, by default). The table lists, per held-out record, the NRMSE
of the prediction, the measured and predicted reversal counts (counted alike,
`count_reversals`) and rest positions. The result of the fit on all records
carries the table, so its report shows it.

A record left out is never seen by the fit that predicts it: the figures
measure how well the identified physics carries over to a record the fit did
not see, not how well the fit reproduces its own data.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from presliding._display import fill_attrs, result_html, short_repr
from presliding._validation import as_choice
from presliding.identification._fit_progress import reporting
from presliding.identification.fit_result import FitResult
from presliding.identification.prediction import Prediction

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["CrossValidation", "cross_validate"]


@dataclass(frozen=True, eq=False)
class CrossValidation:
    """Leave-one-record-out predictions (module notes).

    Attributes
    ----------
    predictions : tuple of Prediction
        One per held-out record, in order (a failed fold: status "failed").
    fits : tuple of FitResult
        The fit without each record.
    result : FitResult
        The fit on every record, with this table attached.
    labels : tuple of str
        A name per record (``record 1``, ... unless given).
    success : bool
        True when every fold was fitted and predicted.
    status : str
        "success", or "failed" when a fold's fit or prediction failed.
    message : str
        How many folds failed, and the first failure's message.
    """

    predictions: tuple[Prediction, ...]
    fits: tuple[FitResult, ...]
    result: FitResult
    labels: tuple[str, ...]

    @property
    def nrmse(self) -> np.ndarray:
        """NRMSE of each held-out record."""
        return np.array([p.nrmse for p in self.predictions])

    @property
    def reversals_exact(self) -> float:
        """Share of held-out records whose reversal count is predicted exactly (nan if none)."""
        hits = [p.reversals_match for p in self.predictions if p.reversals_match is not None]
        return float(np.mean(hits)) if hits else float("nan")

    @property
    def success(self) -> bool:
        """True when every fold was fitted and predicted."""
        return all(p.success for p in self.predictions) and all(
            f.status != "failed" for f in self.fits
        )

    @property
    def status(self) -> str:
        """Either "success" or "failed" (a fold's fit or prediction failed)."""
        return "success" if self.success else "failed"

    @property
    def message(self) -> str:
        """How many folds failed, with the first failure's message."""
        bad = [p.message for p in self.predictions if not p.success]
        bad += [f.message for f in self.fits if f.status == "failed"]
        if not bad:
            return f"{len(self.predictions)} held-out records predicted"
        return f"{len(bad)} of {len(self.predictions)} folds failed; first: {bad[0]}"

    def table(self) -> list[list[str]]:
        """Rows: record, fit status, NRMSE, reversals measured/predicted, rest positions."""
        rows = [["record", "fit status", "NRMSE [%]", "reversals (meas./pred.)",
                 "rest position [m] (meas./pred.)"]]  # fmt: skip
        for label, fit, p in zip(self.labels, self.fits, self.predictions, strict=True):
            rev = (
                "—" if p.measured_reversals is None
                else f"{p.measured_reversals} / {p.predicted_reversals}"
            )  # fmt: skip
            rest = "—"
            if p.measured_rest is not None or p.predicted_rest is not None:
                rest = f"{_num(p.measured_rest)} / {_num(p.predicted_rest)}"
            rows.append([label, fit.status, f"{100 * p.nrmse:.3g}", rev, rest])
        return rows

    def report(self) -> str:
        """The table as text, with the median NRMSE and the share of exact reversal counts."""
        rows = self.table()
        widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
        lines = ["leave-one-record-out cross-validation:"]
        lines += [
            "  " + "  ".join(c.ljust(w) for c, w in zip(r, widths, strict=True)) for r in rows
        ]
        lines.append(
            f"  median NRMSE {100 * float(np.median(self.nrmse)):.3g} %; reversal counts exact "
            f"in {_pct(self.reversals_exact)} of the records"
        )
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """The per-record figures as plain values."""
        return {
            "labels": list(self.labels),
            "fit_status": [f.status for f in self.fits],
            "predictions": [p.to_dict() for p in self.predictions],
            "median_nrmse": float(np.median(self.nrmse)),
            "reversals_exact": self.reversals_exact,
            "nrmse": self.nrmse,
            "status": self.status,
            "success": self.success,
            "message": self.message,
        }

    def to_pandas(self) -> Any:
        """A DataFrame with a row per held-out record."""
        import pandas as pd

        rows = [
            {"record": label, "fit_status": f.status, **p.to_dict()}
            for label, f, p in zip(self.labels, self.fits, self.predictions, strict=True)
        ]
        frame = pd.DataFrame(rows).drop(columns=["parameters"]).set_index("record")
        frame.attrs.update(median_nrmse=float(np.median(self.nrmse)))
        return fill_attrs(frame, self, units={"measured_rest": "m", "predicted_rest": "m"},
                          model=self.result.model)  # fmt: skip

    def __repr__(self) -> str:
        return short_repr(self, ("labels", "nrmse", "reversals_exact"))

    def _repr_html_(self) -> str:
        """The status, the median NRMSE and the per-record table, for notebooks."""
        figures = [("held-out records", str(len(self.predictions)), ""),
                   ("median NRMSE", f"{100 * float(np.median(self.nrmse)):.3g}", "%"),
                   ("reversal counts exact", _pct(self.reversals_exact), "")]  # fmt: skip
        rows = self.table()
        return result_html(self, figures, (rows[0], rows[1:]))

    def plot(self, ax: Axes | None = None) -> Axes:
        """NRMSE of each held-out record (bars); returns the axes."""
        from presliding.plotting import new_axes

        ax = new_axes(ax)
        ax.bar(np.arange(len(self.labels)), 100 * self.nrmse)
        ax.set_xticks(np.arange(len(self.labels)), self.labels, rotation=45, ha="right")
        ax.set_ylabel("NRMSE of the prediction [%]")
        ax.set_title("leave-one-record-out cross-validation")
        return ax


def _num(x: float | None) -> str:
    return "moving" if x is None else f"{x:.6g}"


def _pct(x: float) -> str:
    return "—" if not np.isfinite(x) else f"{100 * x:.3g} %"


def cross_validate(
    records: Sequence[Any],
    fit: Callable[..., FitResult] | str = "response",
    *,
    labels: Sequence[str] | None = None,
    initial: str = "fit",
    **options: Any,
) -> CrossValidation:
    """Leave-one-record-out cross-validation of a pooled fit (module notes).

    Parameters
    ----------
    records : sequence of Measurement
        At least two records.
    fit : callable or {"response", "quasi-static"}
        The fit: `fit_response`, `fit_quasi_static` or any function taking a
        list of records and `options` and returning a `FitResult` that can
        `predict`.
    labels : sequence of str, optional
        A name per record for the table.
    initial : {"fit", "measured"}
        How the held-out record's own initial conditions are set (see
        `FitResult.predict`).
    **options
        Passed to every fit. ``progress`` (as in `fit_response`) also names
        each left-out record as its fit begins.

    Returns
    -------
    CrossValidation
    """
    from presliding.identification.fit_quasi_static import fit_quasi_static
    from presliding.identification.fit_response import fit_response

    if isinstance(fit, str):
        fit = {"response": fit_response, "quasi-static": fit_quasi_static}[
            as_choice("fit", fit, ("response", "quasi-static"))
        ]
    if not callable(fit):
        raise TypeError(f"`fit` must be a fit function or its name; got {type(fit).__name__}.")
    recs = list(records) if isinstance(records, Sequence) else None
    if recs is None or len(recs) < 2:
        raise ValueError(
            "`records` must be a sequence of at least two records to leave one out; got "
            + (f"{len(recs)}." if recs is not None else f"{type(records).__name__}.")
        )
    names = (
        tuple(labels) if labels is not None else tuple(f"record {i + 1}" for i in range(len(recs)))
    )
    if len(names) != len(recs):
        raise ValueError(f"`labels` must name each of the {len(recs)} records; got {len(names)}.")
    initial = as_choice("initial", initial, ("fit", "measured"))
    given = options.pop("progress", None)  # passed on only when given (any fit works)
    with reporting(False if given is None else given, "cross_validate") as shown:
        extra: dict[str, Any] = {} if given is None else {"progress": shown}
        shown.stage(f"fit of all {len(recs)} records")
        full = fit(recs, **options, **extra)
        fits, predictions = [], []
        for i, held in enumerate(recs):
            shown.stage(f"cross-validation: {names[i]} left out ({i + 1} of {len(recs)})")
            others = recs[:i] + recs[i + 1 :]
            part = fit(others, **options, **extra)
            fits.append(part)
            if part.model is None or part.status == "failed":
                predictions.append(_failed(held, part))
                continue
            predictions.append(part.predict(held, initial=initial))
    cv = CrossValidation(tuple(predictions), tuple(fits), full, names)
    result = replace(full, cross_validation=cv)
    return replace(cv, result=result)


def _failed(held: Any, part: FitResult) -> Prediction:
    t = np.asarray(held.time, dtype=float)
    nan = np.full(t.shape, np.nan)
    return Prediction(t, nan, nan, part.signal_label, part.abscissa_label, float("nan"),
                      None, None, None, None, {}, "failed",
                      f"the fit without this record failed: {part.message}")  # fmt: skip
