"""Leave-one-record-out cross-validation of the pooled fits.

`cross_validate(records, fit=fit_response, **options)` fits all records once,
then, for each record i, fits the others and predicts record i with
`FitResult.predict` twice: from its measured start (first samples) and from
a start fitted to it with every shared parameter held. The table lists, per
held-out record, the NRMSE of both predictions, the measured and predicted
reversal counts (counted alike, `count_reversals`, at a stated tolerance),
rest positions, and which parameters were taken from the held-out record.
The result of the fit on all records carries the table, so its report shows
it.

A record left out is never seen by the fit that predicts it: the figures
measure how well the identified physics carries over to a record the fit did
not see, not how well the fit reproduces its own data.
"""

from __future__ import annotations

import textwrap
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from presliding._display import fill_attrs, result_html, short_repr
from presliding._interop import require
from presliding._validation import as_choice, as_nonnegative_scalar
from presliding.identification.fit_result import FitResult
from presliding.identification.prediction import Prediction, tolerance_text
from presliding.identification.result._fit_progress import reporting

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["CrossValidation", "cross_validate"]


@dataclass(frozen=True, eq=False)
class CrossValidation:
    """Leave-one-record-out predictions (module notes).

    Attributes
    ----------
    predictions : tuple of Prediction
        One per held-out record, in order (a failed fold: status "failed"),
        from the start chosen by `initial`.
    alternatives : tuple of Prediction
        The same records predicted from the other start (measured or fitted),
        so that both figures are reported.
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
    alternatives: tuple[Prediction, ...] = ()

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

    def _by_start(self) -> list[tuple[Prediction | None, Prediction | None]]:
        """(measured-start, fitted-start) predictions of each record (None where absent)."""
        alts = self.alternatives or (None,) * len(self.predictions)
        out: list[tuple[Prediction | None, Prediction | None]] = []
        for p, a in zip(self.predictions, alts, strict=True):
            out.append((p, a) if p.initial == "measured" else (a, p))
        return out

    def table(self) -> list[list[str]]:
        """Rows: record, fit status, NRMSE and reversals (measured and fitted start), rest."""
        unit = _position_unit(self.result)
        rows = [["record", "fit status", "NRMSE % (measured start)", "NRMSE % (fitted start)",
                 "reversals meas. / pred. (measured start)",
                 "reversals meas. / pred. (fitted start)", f"rest error [{unit}] (measured / "
                 "fitted start)", "fitted to the held-out record"]]  # fmt: skip
        for label, fit, (m, f) in zip(self.labels, self.fits, self._by_start(), strict=True):
            own = ", ".join(f.parameters) if f is not None and f.parameters else "—"
            rows.append([label, fit.status, _nrmse(m), _nrmse(f), _rev(m), _rev(f),
                         f"{_err(m)} / {_err(f)}", own])  # fmt: skip
        return rows

    @property
    def reversal_tolerances(self) -> str:
        """The tolerances the reversals were counted at, as text (encoder counts if quantised)."""
        unit = _position_unit(self.result)
        texts = sorted({tolerance_text(p.reversal_tolerance, p.quantum, unit)
                        for p in self.predictions})  # fmt: skip
        return texts[0] if len(texts) == 1 else f"each record's own ({', '.join(texts[:3])}, ...)"

    def report(self) -> str:
        """The table as text (headers wrapped to the columns, about 100 characters wide), the
        median NRMSE, the share of exact reversal counts and why a left-out fit did not
        converge."""
        head, *rows = self.table()
        own = {r[-1] for r in rows}
        if len(own) == 1:  # the same parameters fitted to every held-out record: said below
            head, rows = head[:-1], [r[:-1] for r in rows]
        widths = [max([len(r[i]) for r in rows] + [len(w) for w in head[i].split()])
                  for i in range(len(head))]  # fmt: skip
        wrapped = [textwrap.wrap(h, max(w, 10)) for h, w in zip(head, widths, strict=True)]
        widths = [max(w, *(len(x) for x in h)) for w, h in zip(widths, wrapped, strict=True)]
        lines = ["leave-one-record-out cross-validation:"]
        for k in range(max(len(h) for h in wrapped)):
            cells = [h[k] if k < len(h) else "" for h in wrapped]
            lines.append(
                "  " + "  ".join(c.ljust(w) for c, w in zip(cells, widths, strict=True)).rstrip()
            )
        lines += ["  " + "  ".join(c.ljust(w) for c, w in zip(r, widths, strict=True)).rstrip()
                  for r in rows]  # fmt: skip
        if len(own) == 1:
            lines.append(f"  fitted to each held-out record: {own.pop()}")
        for label, fit in zip(self.labels, self.fits, strict=True):
            if fit.status != "converged":
                lead = f"  {label}: fit {fit.status}: "
                lines.append(lead + textwrap.shorten(fit.message, max(40, 100 - len(lead))))
        lines.append(
            f"  median NRMSE {100 * float(np.median(self.nrmse)):.3g} % (start "
            f"{self.predictions[0].initial if self.predictions else 'fit'}); reversal counts "
            f"exact in {_pct(self.reversals_exact)} of the records"
        )
        pairs = self._by_start()
        if all(m is not None and f is not None for m, f in pairs):
            meas = float(np.median([m.nrmse for m, _ in pairs if m is not None]))
            fitted = float(np.median([f.nrmse for _, f in pairs if f is not None]))
            lines.append(f"  median NRMSE from the measured start {100 * meas:.3g} %, from a "
                         f"start fitted to the held-out record {100 * fitted:.3g} %")  # fmt: skip
        lines.append(f"  reversals counted at a tolerance of {self.reversal_tolerances}")
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
        pd = require("pandas", "`to_pandas()`")

        rows = [
            {"record": label, "fit_status": f.status, **p.to_dict()}
            for label, f, p in zip(self.labels, self.fits, self.predictions, strict=True)
        ]
        frame = pd.DataFrame(rows).drop(columns=["parameters"]).set_index("record")
        frame.attrs.update(median_nrmse=float(np.median(self.nrmse)))
        unit = _position_unit(self.result)
        return fill_attrs(frame, self, units={"measured_rest": unit, "predicted_rest": unit},
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


def _position_unit(result: FitResult | None) -> str:
    """The unit of positions on the axis of the records (m, or rad on a rotary axis)."""
    from presliding._axes import axis_unit

    return axis_unit("position", getattr(result, "axis", None) or "linear")


def _num(x: float | None) -> str:
    return "moving" if x is None else f"{x:.6g}"


def _nrmse(p: Prediction | None) -> str:
    return "—" if p is None else f"{100 * p.nrmse:.3g}"


def _rev(p: Prediction | None) -> str:
    if p is None or p.measured_reversals is None:
        return "—"
    return f"{p.measured_reversals} / {p.predicted_reversals}"


def _err(p: Prediction | None) -> str:
    if p is None or (p.measured_rest is None and p.predicted_rest is None):
        return "—"
    return "moving" if p.rest_error is None else f"{p.rest_error:.3g}"


def _pct(x: float) -> str:
    return "—" if not np.isfinite(x) else f"{100 * x:.3g} %"


def cross_validate(
    records: Sequence[Any],
    fit: Callable[..., FitResult] | str = "response",
    *,
    labels: Sequence[str] | None = None,
    initial: str = "fit",
    reversal_tolerance: float | None = None,
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
        The start of `CrossValidation.predictions`: fitted to the held-out
        record with every shared parameter held, or its measured first samples
        (see `FitResult.predict`); the other start's predictions are in
        `CrossValidation.alternatives`, and the table shows both.
    reversal_tolerance : float, optional
        Travel [m or rad] by which reversals are counted, measured and
        predicted alike (default: each record's `reversal_tolerance`, three
        times its quantum or noise; the report states it).
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
        by_name: dict[str, Callable[..., FitResult]] = {
            "response": fit_response,
            "quasi-static": fit_quasi_static,
        }
        fit = by_name[as_choice("fit", fit, ("response", "quasi-static"))]
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
    tol_value = None
    if reversal_tolerance is not None:
        tol_value = as_nonnegative_scalar("reversal_tolerance", reversal_tolerance)
    given = options.pop("progress", None)  # passed on only when given (any fit works)
    with reporting(False if given is None else given, "cross_validate") as shown:
        extra: dict[str, Any] = {} if given is None else {"progress": shown}
        shown.stage(f"fit of all {len(recs)} records")
        full = fit(recs, **options, **extra)
        fits, predictions, alternatives = [], [], []
        for i, held in enumerate(recs):
            shown.stage(f"cross-validation: {names[i]} left out ({i + 1} of {len(recs)})")
            others = recs[:i] + recs[i + 1 :]
            part = fit(others, **options, **extra)
            fits.append(part)
            if part.model is None or part.status == "failed":
                predictions.append(_failed(held, part))
                alternatives.append(_failed(held, part))
                continue
            other = "measured" if initial == "fit" else "fit"
            tol = {} if reversal_tolerance is None else {"reversal_tolerance": tol_value}
            predictions.append(part.predict(held, initial=initial, **tol))
            alternatives.append(part.predict(held, initial=other, **tol))
    cv = CrossValidation(tuple(predictions), tuple(fits), full, names, tuple(alternatives))
    result = replace(full, cross_validation=cv)
    return replace(cv, result=result)


def _failed(held: Any, part: FitResult) -> Prediction:
    t = np.asarray(held.time, dtype=float)
    nan = np.full(t.shape, np.nan)
    return Prediction(t, nan, nan, part.signal_label, part.abscissa_label, float("nan"),
                      None, None, None, None, {}, "failed",
                      f"the fit without this record failed: {part.message}")  # fmt: skip
