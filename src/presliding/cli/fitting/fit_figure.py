"""The figure of ``presliding fit`` (fit.png)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

from presliding.cli.common import new_figure, tidy_fit_axes

__all__ = ["figure_title", "save_fit_figure"]


def _timed(meas: Any) -> bool:
    """True unless the samples were only numbered (a presliding file without time)."""
    src = meas.source
    return src.sample_rate is not None or any(c.signal == "time" for c in src.conversions)


def figure_title(name: str, result: Any) -> str:
    """``loops.csv: presliding fit, converged, NRMSE 0.000582 %`` (significant digits, never
    a rounded 0.00 %)."""
    return f"{name}: {result.kind} fit, {result.status}, NRMSE {100 * result.nrmse:.3g} %"


def save_fit_figure(
    args: argparse.Namespace, meas: Any, result: Any, path: Path, labels: Any = None
) -> None:
    """fit.png; `labels` names the records of a pooled fit (one colour and label each)."""
    from presliding._axes import axis_unit
    from presliding.plotting import plot_fit, plot_loop_fit, save_figure

    axis = getattr(meas, "axis", None) or "linear"
    unit = result.signal_unit or axis_unit("force", axis)
    name = Path(args.data[0] if isinstance(args.data, list) else args.data).name
    if labels is not None and len(labels) > 1:
        name = f"{len(labels)} files ({', '.join(labels[:3])}{', …' if len(labels) > 3 else ''})"
    head = figure_title(name, result)
    if args.kind == "presliding":
        fig, axes = new_figure(2, 1, size=(13.2, 4.8))
        ax = plot_loop_fit(result.abscissa, result.measured, result.fitted, ax=axes[0, 0],
                           displacement_unit=axis_unit("position", axis))  # fmt: skip
        ax.set_title("friction force against displacement")
        timed = _timed(meas) and meas.n_samples == result.measured.shape[0]
        ax = plot_fit(
            meas.time if timed else np.arange(result.measured.shape[0]),
            result.measured,
            result.fitted,
            ax=axes[0, 1],
            xlabel="time [s]" if timed else "sample [index]",
            title="measured and fitted force",
        )
        fig.suptitle(head)
    else:
        fig, axes = new_figure(1, 1, size=(8.0, 5.2))
        pooled = labels is not None and len(result.records) == len(labels) > 1
        ax = result.plot(ax=axes[0, 0], labels=list(labels) if pooled else None)
        ax.set_title(head)
    tidy_fit_axes(fig, ax, result.signal_label, unit)
    save_figure(fig, path)
