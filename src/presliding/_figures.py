"""How figures show themselves: the helpers behind `presliding.plotting`.

A figure survives a plain ``savefig``: a new figure has a constrained layout
(`new_axes`; legends placed outside the axes stay inside the figure), legends sit
off the data (`place_legend`, `records_legend`), a small stroke far from zero is
drawn from the record's start (`relative_positions`), a presliding branch too
narrow to see gets a zoomed inset in the emptiest corner (`zoom_presliding`), and a
residual's power of ten goes into its label (`residual_label`). `presliding.plotting`
re-exports the public ones. Shared ground: no layer is imported, matplotlib only
when drawing.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from presliding._validation import check_type

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = [
    "new_axes", "place_legend", "records_legend", "relative_positions", "residual_label",
    "save_figure", "zoom_presliding",
]  # fmt: skip


def new_axes(ax: Axes | None = None, **subplot_kw: Any) -> Axes:
    """Return `ax` (matplotlib Axes, else a TypeError), or the axes of a new pyplot figure
    with a constrained layout if None."""
    import matplotlib.pyplot as plt

    if ax is not None:
        return check_type("ax", ax, plt.Axes)
    return plt.subplots(layout="constrained", **subplot_kw)[1]


def save_figure(fig: Any, path: Any, dpi: int = 120, *, tight: bool = True) -> None:
    """Write a figure as PNG atomically (temporary file in the same folder, then rename).

    ``tight=True`` crops the image to the drawn content; ``tight=False`` keeps
    the figure size exactly (figsize × dpi pixels; use a constrained layout).
    """
    from presliding._io import atomic_path

    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi, format="png", bbox_inches="tight" if tight else None)


def records_legend(ax: Axes, most: int = 12) -> Any:
    """The legend of a pooled figure: one entry per record (its line), at most `most` named,
    and a dot for the measured samples; placed off the data."""
    from matplotlib.lines import Line2D

    handles, texts = ax.get_legend_handles_labels()
    if len(handles) > most:
        more = f"… {len(handles) - most + 1} more"
        handles, texts = (
            [*handles[: most - 1], Line2D([], [], ls="none")],
            [*texts[: most - 1], more],
        )
    handles.append(Line2D([], [], ls="none", marker=".", color="0.45"))
    texts.append("measured (dots)")
    return place_legend(ax, handles=handles, labels=texts, fontsize=8)


def relative_positions(position: ArrayLike, unit: str = "m") -> tuple[Any, str]:
    """Positions to draw, and the words for their axis label.

    A stroke small against its distance from zero (a 0.24 mm stroke at −0.11 m)
    would show as identical tick labels: it is drawn from the record's start,
    ``y − y₀``, and the label names y₀. Other positions are returned as they are.

    Returns
    -------
    values : ndarray
    label : str
        ``"y [m]"`` or ``"y − y₀ [m], y₀ = -0.11 m"``.
    """
    y = np.asarray(position, dtype=float)
    finite = y[np.isfinite(y)]
    if finite.size == 0:
        return y, f"y [{unit}]"
    stroke = float(np.ptp(finite))
    if abs(float(finite[0])) > 20.0 * stroke and stroke >= 0.0 and finite[0] != 0.0:
        y0 = float(finite[0])
        return y - y0, f"y − y₀ [{unit}], y₀ = {y0:.6g} {unit}"
    return y, f"y [{unit}]"


def place_legend(ax: Axes, **kwargs: Any) -> Any:
    """A legend off the data: ``loc="best"``, or right of the axes if that still covers data
    (lines in data coordinates, segment by segment, and scattered points; not axhline/axvline)."""
    leg = ax.legend(frameon=False, loc="best", **kwargs)
    if not hasattr((fig := ax.figure.figure).canvas, "get_renderer"):  # the root figure
        fig.draw_without_rendering()
    box = leg.get_window_extent().padded(2.0)
    paths = [ln.get_transform().transform_path(ln.get_path()) for ln in ax.get_lines()
             if ln.get_transform() is ax.transData]  # fmt: skip
    points = [c.get_offset_transform().transform(np.reshape(c.get_offsets(), (-1, 2)))
              for c in ax.collections]  # fmt: skip
    if any(p.intersects_bbox(box, filled=False) for p in paths) or any(
        box.count_contains(xy) > 0 for xy in points if xy.size
    ):
        return ax.legend(frameon=False, loc="upper left", bbox_to_anchor=(1.01, 1.0), **kwargs)
    return leg


def residual_label(ax: Axes, residual: Any, unit: str) -> None:
    """``residual [10^-8 m]``: a power of ten goes into the label, never as an offset text
    over the panel above."""
    from matplotlib.ticker import FuncFormatter

    finite = np.abs(residual[np.isfinite(residual)])
    top = float(np.max(finite)) if finite.size else 0.0
    power = int(np.floor(np.log10(top))) if top > 0.0 else 0
    power = power if power < -2 or power > 3 else 0
    scale = f"$10^{{{power}}}$ " if power else ""
    ax.set_ylabel(f"residual [{scale}{unit}]" if unit or scale else "residual")
    ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v / 10.0**power:g}"))


def _presliding_width(model: Any) -> float:
    """The travel over which a reversal's presliding branch spans (twice the largest
    threshold; for an unbounded density, twice four mean thresholds); 0 without one."""
    r = getattr(model, "threshold", None)
    if r is not None and np.size(r):
        return 2.0 * float(np.max(r))
    density = getattr(model, "density", None)
    if density is None:
        return 0.0
    big_r = float(getattr(density, "max_threshold", np.inf))
    if not np.isfinite(big_r):
        big_r = 4.0 * float(density.M2(np.inf)) / float(density.max_elastic_force)
    return 2.0 * big_r


def _free_corner(ax: Axes, x: Any, y: Any) -> tuple[float, float, float, float]:
    """The inset box [x0, y0, w, h] (axes fraction) in the corner holding the fewest samples."""
    ax.autoscale_view()
    pts = ax.transAxes.inverted().transform(ax.transData.transform(np.column_stack([x, y])))
    counts = {}
    for x0, y0 in ((0.6, 0.06), (0.06, 0.56), (0.6, 0.56), (0.06, 0.06)):
        inside = ((pts[:, 0] > x0 - 0.04) & (pts[:, 0] < x0 + 0.38) & (pts[:, 1] > y0 - 0.04)
                  & (pts[:, 1] < y0 + 0.42))  # fmt: skip
        counts[(x0, y0)] = int(np.sum(inside))
    x0, y0 = min(counts, key=lambda k: counts[k])
    return (x0, y0, 0.34, 0.38)


def zoom_presliding(
    ax: Axes, position: Any, force: Any, model: Any, centre: float | None = None
) -> Axes | None:
    """An inset magnifying the presliding branches of a force–position loop when they are a
    sliver of the axes (under a twentieth of the travel drawn); returns the inset or None.

    The inset sits in the corner with the fewest samples and shows the travel of a
    full presliding branch (twice the largest threshold) around `centre` (the rest
    position; default the last turning point drawn).
    """
    y = np.asarray(position, dtype=float)
    f = np.asarray(force, dtype=float)
    ok = np.isfinite(y) & np.isfinite(f)
    y, f = y[ok], f[ok]
    width = _presliding_width(model)
    span = float(np.ptp(y)) if y.size else 0.0
    if width <= 0.0 or span <= 0.0 or width > span / 20.0:
        return None
    if centre is None:
        turn = np.flatnonzero(np.diff(np.sign(np.diff(y))) != 0)
        centre = float(y[turn[-1] + 1]) if turn.size else float(y[-1])
    near = np.abs(y - centre) <= 1.5 * width
    if np.count_nonzero(near) < 2:
        return None
    from matplotlib.ticker import MaxNLocator

    inset = ax.inset_axes(_free_corner(ax, y, f))
    inset.plot(y[near], f[near], lw=1.2, color="C0")
    lo, hi = float(np.min(f[near])), float(np.max(f[near]))
    pad = 0.08 * (hi - lo or 1.0)
    inset.set_xlim(centre - 1.5 * width, centre + 1.5 * width)
    inset.set_ylim(lo - pad, hi + pad)
    inset.tick_params(labelsize=7)
    inset.ticklabel_format(axis="x", style="plain", useOffset=False)  # no text over the axes
    inset.xaxis.set_major_locator(MaxNLocator(3))
    inset.set_title("presliding (zoom)", fontsize=7)
    inset.grid(True, alpha=0.3)
    ax.indicate_inset_zoom(inset, edgecolor="0.4")
    return inset
