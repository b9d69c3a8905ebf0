"""Plot functions. Each takes ``ax=None`` (a new figure is made), returns the axes,
and changes no global style; matplotlib is imported only when a plot is drawn."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["new_axes", "plot_hysteresis", "save_figure"]


def new_axes(ax: Axes | None = None, **subplot_kw: Any) -> Axes:
    """Return `ax`, or the axes of a new pyplot figure when it is None."""
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    _, ax = plt.subplots(**subplot_kw)
    return ax


def plot_hysteresis(
    displacement: ArrayLike,
    force: ArrayLike | Sequence[ArrayLike],
    *,
    labels: Sequence[str] | None = None,
    ax: Axes | None = None,
    displacement_unit: str = "m",
    force_unit: str = "N",
) -> Axes:
    """Force against displacement: one or several hysteresis curves on one path.

    Parameters
    ----------
    displacement : array_like, shape (T,)
    force : array_like, shape (T,), or a sequence of them
    labels : sequence of str, optional
        One label per force curve, shown in a legend.
    ax : matplotlib Axes, optional
    """
    ax = new_axes(ax)
    y = np.asarray(displacement, dtype=float)
    forces = [force] if np.ndim(force) == 1 else list(force)
    for i, f in enumerate(forces):
        label = None if labels is None else labels[i]
        ax.plot(y, np.asarray(f, dtype=float), lw=1.6, label=label)
    ax.axhline(0.0, color="0.8", lw=0.8, zorder=0)
    ax.axvline(0.0, color="0.8", lw=0.8, zorder=0)
    ax.set_xlabel(f"displacement y [{displacement_unit}]")
    ax.set_ylabel(f"friction force F [{force_unit}]")
    ax.grid(True, alpha=0.3)
    if labels is not None:
        ax.legend(frameon=False)
    return ax


def save_figure(fig: Any, path: Any, dpi: int = 120) -> None:
    """Write a figure as PNG atomically (temporary file in the same folder, then rename)."""
    from ._io import atomic_path

    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi, format="png", bbox_inches="tight")
