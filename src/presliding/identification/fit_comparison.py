"""Model families side by side: each fitted by the same engine to the same records.

`compare_fits(records, candidates=("pi", "pi-asymmetric", "coulomb"), hold_out=...)` fits
every candidate family to the same records, predicts the held-out records from their
measured starts with each fit, and tabulates per family its status, free parameters, residual
sum of squares, AIC and BIC (Gaussian least squares: n·ln(RSS/n) + 2p and n·ln(RSS/n) +
p·ln n, as `FitResult.aic` and `FitResult.bic`) and the held-out NRMSE and reversal counts.
The family the data support is the one of least BIC (or AIC, or held-out NRMSE: `criterion`)
among those whose fit did not fail; `FitComparison.status` is that fit's status.
(`presliding.compare` is another thing: given models along one displacement path.)

The families are those of the registry `presliding.identification.families` (``FAMILIES``,
whose notes give a fitter's contract; `register_family` adds one).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from presliding._display import fill_attrs, result_html, short_repr
from presliding._validation import as_choice, fmt
from presliding.identification.families import CARRIES, FAMILIES
from presliding.identification.fit_result import FitResult
from presliding.identification.prediction import Prediction
from presliding.measurement.measurement import Measurement

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["FitComparison", "compare_fits"]

CRITERIA = ("bic", "aic", "held_out")
INITIAL = ("measured", "fit")


@dataclass(frozen=True, eq=False)
class FitComparison:
    """Model families fitted to the same records, side by side (module notes).

    Attributes
    ----------
    families : tuple of str
        The candidates, in the order given.
    fits : tuple of FitResult
        Each family's fit.
    predictions : tuple of tuple of Prediction
        Per family, its predictions of the held-out records (empty without them).
    held_out : tuple of str
        Labels of the held-out records.
    criterion : {"bic", "aic", "held_out"}
        What chose the family the data support.
    best : str or None
        That family (None when every fit failed).
    status : str
        The best family's fit status: "converged", "local_minimum",
        "not_identifiable", "at_bound", "poor_fit", "max_evaluations", or
        "failed" (also when every fit failed).
    message : str
        Which family the data support and by how much, and whether the
        held-out records agree.
    """

    families: tuple[str, ...]
    fits: tuple[FitResult, ...]
    predictions: tuple[tuple[Prediction, ...], ...]
    held_out: tuple[str, ...]
    criterion: str
    best: str | None
    message: str

    @property
    def status(self) -> str:
        """The best family's fit status ("failed" when there is none)."""
        return "failed" if self.best is None else self.fits[self.families.index(self.best)].status

    @property
    def success(self) -> bool:
        """True when the family the data support converged."""
        return self.status == "converged"

    @property
    def model(self) -> Any:
        """The best family's model (None when there is none)."""
        return None if self.best is None else self.fits[self.families.index(self.best)].model

    @property
    def rss(self) -> np.ndarray:
        """Each family's residual sum of squares (its fit's ``chisqr``)."""
        return np.array([f.chisqr for f in self.fits])

    @property
    def n_parameters(self) -> np.ndarray:
        """Each family's free parameters (the records' own included)."""
        return np.array([f.nvarys for f in self.fits])

    @property
    def aic(self) -> np.ndarray:
        return np.array([f.aic for f in self.fits])

    @property
    def bic(self) -> np.ndarray:
        return np.array([f.bic for f in self.fits])

    @property
    def held_out_best(self) -> str | None:
        """The family whose held-out predictions are best (median NRMSE; errors within 0.1 %
        of the least are ties, won by fewer free parameters); None without held-out records."""
        held = self.held_out_nrmse
        ok = [i for i, f in enumerate(self.fits) if f.status != "failed" and np.isfinite(held[i])]
        if not ok:
            return None
        return self.families[_ranked(ok, held, [f.nvarys for f in self.fits], True)[0]]

    @property
    def held_out_nrmse(self) -> np.ndarray:
        """Each family's median NRMSE over the held-out records (nan without them)."""
        return np.array([_median([p.nrmse for p in ps]) for ps in self.predictions])

    @property
    def reversals_exact(self) -> np.ndarray:
        """Each family's share of held-out records whose reversal count it predicts."""
        out = []
        for ps in self.predictions:
            hits = [p.reversals_match for p in ps if p.reversals_match is not None]
            out.append(float(np.mean(hits)) if hits else float("nan"))
        return np.array(out)

    def table(self) -> list[list[str]]:
        """Rows: family, status, free parameters, RSS, AIC, ΔAIC, BIC, ΔBIC, held-out NRMSE
        and exact reversal counts; the family the data support marked."""
        rows = [["family", "status", "free parameters", "RSS", "AIC", "ΔAIC", "BIC", "ΔBIC",
                 "held-out NRMSE % (median)", "held-out reversals exact"]]  # fmt: skip
        aic, bic = self.aic, self.bic
        a0, b0 = np.nanmin(_finite(aic)), np.nanmin(_finite(bic))
        for i, name in enumerate(self.families):
            f = self.fits[i]
            mark = " (supported)" if name == self.best else ""
            rows.append([name + mark, f.status, str(f.nvarys), f"{f.chisqr:.6g}",
                         f"{aic[i]:.6g}", f"{aic[i] - a0:+.4g}", f"{bic[i]:.6g}",
                         f"{bic[i] - b0:+.4g}", _pct(self.held_out_nrmse[i]),
                         _pct(self.reversals_exact[i], 0)])  # fmt: skip
        return rows

    def report(self) -> str:
        """The table as text, the verdict and each fit's message."""
        rows = self.table()
        widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
        lines = [f"comparison of model families ({self.criterion}): {self.status} — "
                 f"{self.message}"]  # fmt: skip
        lines += ["  " + "  ".join(c.ljust(w) for c, w in zip(r, widths, strict=True))
                  for r in rows]  # fmt: skip
        if self.held_out:
            lines.append(f"  held out (predicted from their measured starts): "
                         f"{', '.join(self.held_out)}")  # fmt: skip
        for name, f in zip(self.families, self.fits, strict=True):
            lines.append(f"  {name}: {f.message}")
            if f.asymmetry is not None:
                lines.append(f"  {name}: asymmetry {f.asymmetry.verdict} — {f.asymmetry.message}")
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """The table's figures as plain values (each fit as its own dict)."""
        return {
            "families": list(self.families), "status": self.status, "success": self.success,
            "message": self.message, "criterion": self.criterion, "best": self.best,
            "rss": self.rss, "aic": self.aic, "bic": self.bic,
            "n_parameters": self.n_parameters, "held_out": list(self.held_out),
            "held_out_nrmse": self.held_out_nrmse, "held_out_best": self.held_out_best,
            "reversals_exact": self.reversals_exact,
            "fits": [f.to_dict() for f in self.fits],
        }  # fmt: skip

    def to_pandas(self) -> Any:
        """A DataFrame with a row per family."""
        import pandas as pd

        frame = pd.DataFrame({
            "family": list(self.families), "status": [f.status for f in self.fits],
            "free_parameters": self.n_parameters, "rss": self.rss, "aic": self.aic,
            "bic": self.bic, "held_out_nrmse": self.held_out_nrmse,
            "reversals_exact": self.reversals_exact,
            "supported": [n == self.best for n in self.families],
        }).set_index("family")  # fmt: skip
        frame.attrs.update(criterion=self.criterion, best=self.best)
        return fill_attrs(frame, self, units={"held_out_nrmse": "1", "reversals_exact": "1"})

    def __repr__(self) -> str:
        return short_repr(self, ("families", "best", "criterion", "bic", "held_out_nrmse"))

    def _repr_html_(self) -> str:
        """The verdict and the table, for notebooks."""
        rows = self.table()
        figures = [("families", str(len(self.families)), ""), ("supported", str(self.best), ""),
                   ("criterion", self.criterion, "")]  # fmt: skip
        return result_html(self, figures, (rows[0], rows[1:]))

    def plot(self, ax: Axes | None = None) -> Axes:
        """ΔBIC of each family (bars; the supported one at 0), held-out NRMSE above each bar
        when there are held-out records; returns the axes."""
        from presliding.plotting import new_axes

        ax = new_axes(ax)
        bic = self.bic
        delta = np.where(np.isfinite(bic), bic - np.nanmin(_finite(bic)), np.nan)
        x = np.arange(len(self.families))
        colours = ["C2" if n == self.best else "C0" for n in self.families]
        ax.bar(x, np.nan_to_num(delta), color=colours)
        ax.set_xticks(x, self.families)
        ax.set_ylabel("ΔBIC [-]")
        ax.set_title("model families: BIC over the least (lower is better)")
        for i, e in enumerate(self.held_out_nrmse):
            if np.isfinite(e):
                ax.annotate(f"held out {100 * e:.3g} %", (x[i], np.nan_to_num(delta[i])),
                            ha="center", va="bottom", fontsize="small")  # fmt: skip
        return ax


def _finite(a: np.ndarray) -> np.ndarray:
    return a[np.isfinite(a)] if np.any(np.isfinite(a)) else np.array([np.nan])


def _median(values: Sequence[float]) -> float:
    ok = [v for v in values if np.isfinite(v)]
    return float(np.median(ok)) if ok else float("nan")


def _pct(x: float, digits: int = 3) -> str:
    if not np.isfinite(x):
        return "—"
    return f"{100 * x:.{digits}g}" if digits else f"{100 * x:.0f} %"


def _as_list(name: str, value: Any, allow_none: bool = False) -> list[Measurement]:
    """A Measurement or a sequence of them, as a list (None → empty where allowed)."""
    if value is None and allow_none:
        return []
    found = [value] if isinstance(value, Measurement) else value
    if not isinstance(found, Sequence) or isinstance(found, (str, bytes)):
        raise TypeError(f"`{name}` must be a Measurement or a sequence of them; got "
                        f"{type(value).__name__}.")  # fmt: skip
    for i, m in enumerate(found):
        if not isinstance(m, Measurement):
            raise TypeError(f"`{name}[{i}]` must be a Measurement; got {type(m).__name__}.")
    if not found and not allow_none:
        raise ValueError(f"`{name}` must hold at least one Measurement; got none.")
    return list(found)


def _candidates(candidates: Any) -> dict[str, dict[str, Any]]:
    """Names (a string, a sequence, or a mapping name → own options) checked against
    `FAMILIES`."""
    if isinstance(candidates, str):
        candidates = [c.strip() for c in candidates.split(",")]
    if isinstance(candidates, Mapping):
        pairs = list(candidates.items())
    elif isinstance(candidates, Sequence):
        pairs = [(c, {}) for c in candidates]
    else:
        raise TypeError(f"`candidates` must be family names or a mapping of them; got "
                        f"{type(candidates).__name__}.")  # fmt: skip
    if not pairs:
        raise ValueError("`candidates` must name at least one family; got none.")
    out: dict[str, dict[str, Any]] = {}
    for name, own in pairs:
        if name not in FAMILIES:
            raise ValueError(f"`candidates` must name families of {sorted(FAMILIES)}; got "
                             f"{fmt(name)}.")  # fmt: skip
        if name in out:
            raise ValueError(f"`candidates` must name each family once; got {name!r} twice.")
        if not isinstance(own, Mapping):
            raise TypeError(f"`candidates[{name!r}]` must be a mapping of options; got "
                            f"{type(own).__name__}.")  # fmt: skip
        out[name] = dict(own)
    return out


def compare_fits(
    records: Measurement | Sequence[Measurement],
    candidates: Sequence[str] | Mapping[str, Mapping[str, Any]] | str = (
        "pi",
        "pi-asymmetric",
        "coulomb",
    ),
    *,
    hold_out: Measurement | Sequence[Measurement] | None = None,
    labels: Sequence[str] | None = None,
    criterion: str = "bic",
    initial: str = "measured",
    **options: Any,
) -> FitComparison:
    """Fit several model families to the same records and tabulate them (module notes).

    Parameters
    ----------
    records : Measurement or sequence of Measurement
        The records every family fits (as `fit_response` takes them).
    candidates : sequence of str, mapping or str
        Family names of `FAMILIES` (a comma-separated string works too), or a
        mapping name → that family's own options, e.g. ``{"pi": {"n_elements":
        "auto"}, "coulomb": {}}``.
    hold_out : Measurement or sequence of Measurement, optional, keyword only
        Records no family fits, predicted by each fit (`FitResult.predict`).
    labels : sequence of str, optional, keyword only
        Names of the held-out records (default ``held-out 1``, ...).
    criterion : {"bic", "aic", "held_out"}, keyword only
        What chooses the family the data support: the least BIC (default), AIC,
        or held-out median NRMSE (needs `hold_out`).
    initial : {"measured", "fit"}, keyword only
        The held-out records' starts: their first samples (default), or fitted
        to each with the shared parameters held.
    **options
        Passed to every family's fitter (e.g. ``signal``, ``initial_state``,
        ``mass``, ``viscous``, ``progress``); a family that does not take one
        refuses it.

    Returns
    -------
    FitComparison
    """
    recs = _as_list("records", records)
    held = _as_list("hold_out", hold_out, allow_none=True)
    chosen = _candidates(candidates)
    criterion = as_choice("criterion", criterion, CRITERIA)
    initial = as_choice("initial", initial, INITIAL)
    if criterion == "held_out" and not held:
        raise ValueError("`criterion='held_out'` needs held-out records; got hold_out=None.")
    names = tuple(labels) if labels is not None else tuple(
        f"held-out {i + 1}" for i in range(len(held)))  # fmt: skip
    if len(names) != len(held):
        raise ValueError(f"`labels` must name each of the {len(held)} held-out records; got "
                         f"{len(names)}.")  # fmt: skip
    found = _fit_all(chosen, recs, options)
    fits, predictions = [found[name] for name in chosen], []
    for fit in fits:
        usable = fit.status != "failed" and fit.predictor is not None
        predictions.append(tuple(fit.predict(m, initial=initial) for m in held) if usable
                             else ())  # fmt: skip
    best, message = _verdict(tuple(chosen), fits, predictions, criterion)
    return FitComparison(tuple(chosen), tuple(fits), tuple(predictions), names, criterion, best,
                         message)  # fmt: skip


def _fit_all(chosen: dict[str, dict[str, Any]], recs: list[Measurement],
             options: dict[str, Any]) -> dict[str, FitResult]:  # fmt: skip
    """Every family's fit; one another carries (`CARRIES`, same options) taken from it."""
    found: dict[str, FitResult] = {}
    carried = {CARRIES[n]: n for n in chosen if n in CARRIES and CARRIES[n] in chosen
               and chosen[CARRIES[n]] == chosen[n]}  # fmt: skip
    order = sorted(chosen, key=lambda n: n in carried)  # the carriers first
    for name in order:
        if name in carried:
            test = getattr(found[carried[name]], "asymmetry", None)
            if test is not None and isinstance(test.symmetric, FitResult):
                found[name] = test.symmetric
                continue
        fit = FAMILIES[name](recs, **{**options, **chosen[name]})
        if not isinstance(fit, FitResult):
            raise TypeError(f"the fitter of {name!r} must return a FitResult; got "
                            f"{type(fit).__name__}.")  # fmt: skip
        found[name] = fit
    return found


#: Held-out errors within this share of the least are ties, won by fewer free parameters.
HELD_OUT_TIE = 1e-3


def _ranked(ok: list[int], score: np.ndarray, sizes: list[int], relative: bool) -> list[int]:
    """The families `ok` from the best score (a held-out error: ties within `HELD_OUT_TIE`
    won by the fewer free parameters, as equal predictions favour the simpler model)."""
    if not relative:
        return sorted(ok, key=lambda i: score[i])
    low = min(score[i] for i in ok)
    return sorted(ok, key=lambda i: (score[i] > low * (1 + HELD_OUT_TIE), sizes[i], score[i]))


def _verdict(families: tuple[str, ...], fits: list[FitResult], predictions: list[tuple],
             criterion: str) -> tuple[str | None, str]:  # fmt: skip
    """The family the data support by `criterion`, and the message saying so."""
    held = np.array([_median([p.nrmse for p in ps]) for ps in predictions])
    sizes = {f.ndata for f in fits}
    score = {"bic": np.array([f.bic for f in fits]), "aic": np.array([f.aic for f in fits]),
             "held_out": held}[criterion]  # fmt: skip
    ok = [i for i, f in enumerate(fits) if f.status != "failed" and np.isfinite(score[i])]
    if not ok:
        return None, "no family could be fitted: " + "; ".join(
            f"{n}: {f.message}" for n, f in zip(families, fits, strict=True))  # fmt: skip
    order = _ranked(ok, score, [f.nvarys for f in fits], criterion == "held_out")
    best = order[0]
    label = {"bic": "BIC", "aic": "AIC", "held_out": "held-out median NRMSE"}[criterion]
    text = f"the data support {families[best]}"
    if len(order) > 1:
        gap = score[order[1]] - score[best]
        gap_text = f"{100 * gap:.3g} % lower" if criterion == "held_out" else f"lower by {gap:.4g}"
        text += f" ({label} {gap_text} than {families[order[1]]}, the next)"
    if len(sizes) > 1 and criterion != "held_out":
        text += "; the fits do not share one residual (different sizes): their AIC and BIC " \
                "do not compare"  # fmt: skip
    usable = [i for i in ok if np.isfinite(held[i])]
    if usable and criterion != "held_out":
        ahead = _ranked(usable, held, [f.nvarys for f in fits], True)[0]
        text += (f"; held out, {families[ahead]} predicts best (median NRMSE "
                 f"{100 * held[ahead]:.3g} %)")  # fmt: skip
        if ahead != best:
            text += f" against {100 * held[best]:.3g} % for {families[best]}"
    if fits[best].status != "converged":
        text += f"; its fit's status is {fits[best].status}: {fits[best].message}"
    return families[best], text
