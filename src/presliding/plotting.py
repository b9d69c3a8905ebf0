"""Plot functions. Each takes ``ax=None`` (a new figure is made), returns the axes,
and changes no global style; matplotlib is imported only when a plot is drawn. Figures
survive a plain ``savefig``, with a unit on every axis and legends off the data (the
rules and helpers of `presliding._figures`, re-exported here)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, cast

import numpy as np
from numpy.typing import ArrayLike

from presliding._figures import (
    new_axes,
    place_legend,
    records_legend,
    relative_positions,
    residual_label,
    save_figure,
    zoom_presliding,
)

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.ticker import MaxNLocator

__all__ = [
    "new_axes", "place_legend", "plot_batch", "plot_density", "plot_fit", "plot_forces",
    "plot_free_response", "plot_hysteresis", "plot_loop_fit", "plot_motion",
    "plot_reversal_counts", "plot_sweep", "plot_turning_points", "relative_positions",
    "save_figure", "zoom_presliding",
]  # fmt: skip


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
    y, words = relative_positions(displacement, displacement_unit)
    curves: Any = force  # one curve, or a sequence of curves (possibly of several lengths)
    forces = [curves] if np.ndim(curves) == 1 else list(curves)
    for i, f in enumerate(forces):
        label = None if labels is None else labels[i]
        ax.plot(y, np.asarray(f, dtype=float), lw=1.6, label=label)
    # axes through the origin only where the data reach them: a loop far from
    # y = 0 (a stage at -110 mm) must not be squeezed into a vertical line
    if y.size and y.min() <= 0.0 <= y.max():
        ax.axvline(0.0, color="0.8", lw=0.8, zorder=0)
    values = np.concatenate([np.ravel(np.asarray(f, dtype=float)) for f in forces])
    if values.size and values.min() <= 0.0 <= values.max():
        ax.axhline(0.0, color="0.8", lw=0.8, zorder=0)
    ax.set_xlabel(f"displacement {words}")
    ax.set_ylabel(f"friction force F [{force_unit}]")
    ax.grid(True, alpha=0.3)
    if labels is not None:
        place_legend(ax)
    return ax


def plot_loop_fit(
    displacement: ArrayLike,
    measured: ArrayLike,
    fitted: ArrayLike,
    *,
    ax: Axes | None = None,
    measured_label: str = "measured",
    displacement_unit: str = "m",
    force_unit: str = "N",
) -> Axes:
    """Measured force as dots and the fitted model as a line, against displacement."""
    ax = plot_hysteresis(displacement, measured, ax=ax, displacement_unit=displacement_unit,
                         force_unit=force_unit)  # fmt: skip
    ax.lines[0].set(ls="none", marker=".", ms=2.0, color="0.55", label=measured_label)
    y = relative_positions(displacement, displacement_unit)[0]
    ax.plot(y, np.asarray(fitted), color="C1", lw=1.4, label="fitted model")
    place_legend(ax)
    return ax


def plot_fit(
    abscissa: ArrayLike,
    measured: ArrayLike,
    fitted: ArrayLike,
    *,
    ax: Axes | None = None,
    xlabel: str = "sample [index]",
    ylabel: str = "signal",
    title: str | None = None,
    records: Sequence[tuple[int, int]] = (),
    labels: Sequence[str] | None = None,
    fitted_label: str = "fitted",
) -> Axes:
    """Measured against fitted signal, with the residual (measured − fitted) in a panel below.

    The residual panel is appended under `ax` (sharing its x axis), or is the
    lower panel of a new figure when `ax` is None; the main axes are returned.

    Parameters
    ----------
    records : sequence of (start, stop), optional
        Sample ranges of the records of a pooled fit: each record is drawn on its
        own, in its own colour, with its label (`labels`, default "record 1", ...),
        and no line joins one record to the next.
    labels : sequence of str, optional
        A name per record (the file names).
    fitted_label : str
        The legend's name of the model's line ("predicted" for a prediction).
    """
    from mpl_toolkits.axes_grid1 import make_axes_locatable

    if ax is None:  # a new figure: both panels in its constrained layout
        import matplotlib.pyplot as plt

        fig = plt.figure(layout="constrained", figsize=(6.4, 5.2))
        ax, res_ax = fig.subplots(2, 1, sharex=True, height_ratios=[3.0, 1.0])
    else:  # the caller's axes: the residual panel is cut from them
        ax = new_axes(ax)
        res_ax = make_axes_locatable(ax).append_axes("bottom", size="30%", pad=0.08, sharex=ax)
    x = np.asarray(abscissa, dtype=float)
    m = np.asarray(measured, dtype=float)
    f = np.asarray(fitted, dtype=float)
    spans = [(int(a), int(b)) for a, b in records] or [(0, x.shape[0])]
    pooled = len(spans) > 1
    if labels is not None and len(labels) != len(spans):
        raise ValueError(
            f"`labels` must name each of the {len(spans)} records; got {len(labels)} labels."
        )
    names = list(labels) if labels is not None else [f"record {i + 1}" for i in range(len(spans))]
    for i, (a, b) in enumerate(spans):
        colour = f"C{i % 10}" if pooled else "C1"
        ax.plot(x[a:b], m[a:b], ".", ms=2.5, color=colour if pooled else "0.45",
                alpha=0.45 if pooled else 1.0, label=None if pooled else "measured")  # fmt: skip
        ax.plot(x[a:b], f[a:b], lw=1.3, color=colour,
                label=names[i] if pooled else fitted_label)  # fmt: skip
        res_ax.plot(x[a:b], m[a:b] - f[a:b], ".", ms=2.0, color=colour if pooled else "C3")
    ax.set_ylabel(ylabel)
    ax.grid(True, alpha=0.3)
    if pooled:  # dots: measured; lines: the fit; one colour per record
        records_legend(ax)
    else:
        place_legend(ax)
    if title:
        ax.set_title(title)
    res_ax.axhline(0.0, color="0.6", lw=0.8)
    unit = ylabel[ylabel.rfind("[") + 1 : -1] if ylabel.rstrip().endswith("]") else ""
    residual_label(res_ax, m - f, unit)
    res_ax.set_xlabel(xlabel)
    res_ax.grid(True, alpha=0.3)
    ax.tick_params(labelbottom=False)
    return ax


def plot_sweep(
    axes: Sequence[ArrayLike],
    values: ArrayLike,
    names: Sequence[str],
    *,
    ax: Axes | None = None,
    label: str = "value",
    cmap: str = "viridis",
) -> Axes:
    """Values of a sweep over a 1-D grid (a curve) or a 2-D grid (a colour map).

    Parameters
    ----------
    axes : sequence of 1 or 2 arrays
        The grid axes; ``values[i, j]`` belongs to ``(axes[0][i], axes[1][j])``.
        The first axis is drawn along x.
    values : array_like, shape (len(axes[0]),) or (len(axes[0]), len(axes[1]))
    names : sequence of str
        Axis labels.
    label : str
        Name of the values (y label, or colour-bar label).
    """
    ax = new_axes(ax)
    v = np.asarray(values, dtype=float)
    if len(axes) == 1:
        ax.plot(np.asarray(axes[0], dtype=float), v, lw=1.6)
        ax.set_xlabel(names[0])
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        return ax
    x, y = (np.asarray(a, dtype=float) for a in axes)
    mesh = ax.pcolormesh(x, y, v.T, shading="nearest", cmap=cmap)
    ax.figure.colorbar(mesh, ax=ax, label=label)
    ax.set_xlabel(names[0])
    ax.set_ylabel(names[1])
    return ax


def plot_motion(result: Any, *, kind: str = "time", ax: Axes | None = None) -> Axes:
    """A simulated motion (`presliding.motion.MotionResult`).

    kind "time": velocity over time, turning points and the stop marked (the
    paper's Figures 4, 5a); "phase": velocity against position (Figure 5b);
    "loop": friction force against position (the presliding loops).
    """
    from presliding._validation import as_choice

    kind = as_choice("kind", kind, ("time", "phase", "loop"))
    ax = new_axes(ax)
    t, y, v = result.time, result.position, result.velocity
    if kind == "time":
        ax.plot(t, v, lw=1.4, color="C0", label="velocity")
        ax.set_xlabel("time t [s]")
        ax.set_ylabel("velocity [m/s]")
        if result.reversal_times.size:
            ax.plot(result.reversal_times, np.zeros(result.reversal_times.shape), "o",
                    ms=4, color="C1", label="reversal")  # fmt: skip
        if result.stop_time is not None:
            ax.axvline(result.stop_time, color="C3", lw=0.9, ls="--", label="stop")
    elif kind == "phase":
        ax.plot(y, v, lw=1.4, color="C0")
        if result.stop_time is not None:
            ax.plot([result.rest_position], [0.0], "s", ms=5, color="C3", label="rest")
        ax.set_xlabel("position y [m]")
        ax.set_ylabel("velocity [m/s]")
    else:
        ax.plot(y, result.friction_force, lw=1.4, color="C0")
        ax.set_xlabel("position y [m]")
        ax.set_ylabel("friction force [N]")
    ax.axhline(0.0, color="0.8", lw=0.8, zorder=0)
    ax.grid(True, alpha=0.3)
    if kind != "loop" and ax.get_legend_handles_labels()[0]:
        place_legend(ax)
    if kind == "loop":
        zoom_presliding(ax, y, result.friction_force, result.model, result.rest_position)
    return ax


def plot_turning_points(
    result: Any, *, ax: Axes | None = None, samples_per_swing: int = 200
) -> Axes:
    """Elastic force along the swings of a free motion (`presliding.analysis.TurningPoints`).

    The path y0 → y1 → … through the turning points is sampled with
    `samples_per_swing` points per swing and run through the model from the
    initial memory, so each swing follows its Masing branch; the turning points
    are marked and the band |F_el| <= c1 in which the mass sticks (eq. 16) is
    shaded.
    """
    from presliding._validation import as_count
    from presliding.hysteresis.general_pi import MemoryState, run_density

    n = as_count("samples_per_swing", samples_per_swing, minimum=1, maximum=10**6)  # a plot
    model, state = result.model, result.initial_state
    knots = np.concatenate(([state.last_input], result.positions))
    swings = np.linspace(knots[:-1], knots[1:], n + 1, axis=1)[:, 1:]  # ends exactly at knots
    path = np.concatenate((knots[:1], swings.ravel()))
    if isinstance(state, MemoryState):  # also for finite elements walked as a Discrete density
        force = run_density(model.density, path, state)[0]
    else:
        force = model.elastic_force(path, state)[0]
    ax = new_axes(ax)
    c1 = model.coulomb
    if c1 > 0.0:
        ax.axhspan(-c1, c1, color="C2", alpha=0.15, lw=0, label="sticks here: |F_el| ≤ c1")
    ax.plot(path, force, lw=1.4, color="C0", label="elastic force along the swings")
    ax.plot(result.positions, result.elastic_forces, "o", ms=4.5, color="C1",
            label="turning points")  # fmt: skip
    if result.rest_position is not None:
        ax.plot([result.rest_position], [result.elastic_forces[-1]], "s", ms=6, color="C3",
                label="rest")  # fmt: skip
    ax.axhline(0.0, color="0.8", lw=0.8, zorder=0)
    ax.set(xlabel="position y [m]", ylabel="elastic force F_el [N]")
    ax.set_title(f"{result.n_reversals} reversal(s); {result.status}")
    ax.grid(True, alpha=0.3)
    place_legend(ax)
    return ax


def plot_forces(result: Any, *, ax: Axes | None = None) -> Axes:
    """Friction force and applied force u of a motion (`MotionResult`) over time."""
    ax = new_axes(ax)
    t = result.time
    ax.plot(t, result.friction_force, lw=1.4, color="C3", label="friction force")
    ax.plot(t, result.applied_force, lw=1.1, color="0.35", ls="--", label="applied force u")
    if result.stop_time is not None:
        ax.axvline(result.stop_time, color="C3", lw=0.9, ls=":", label="stop")
    ax.axhline(0.0, color="0.8", lw=0.8, zorder=0)
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("force [N]")
    ax.grid(True, alpha=0.3)
    place_legend(ax)
    return ax


def plot_reversal_counts(
    abscissa: ArrayLike,
    predicted: ArrayLike,
    simulated: ArrayLike | None = None,
    *,
    ax: Axes | None = None,
    xlabel: str = "c1 / F_m",
) -> Axes:
    """Number of reversals before a stop: predicted (stop analysis) against simulated.

    Parameters
    ----------
    abscissa : array_like, shape (n,)
        The swept quantity (e.g. the ratio c1/F_m of eqs. 15, 16).
    predicted : array_like of int, shape (n,)
        Counts from the energy analysis (eqs. 12–16).
    simulated : array_like of int, shape (n,), optional
        Counts from time simulations of the same motions.
    """
    ax = new_axes(ax)
    x = np.asarray(abscissa, dtype=float)
    ax.step(x, np.asarray(predicted, dtype=float), where="mid", lw=1.8, color="C1",
            label="predicted (energy analysis, eqs. 15–16)")  # fmt: skip
    if simulated is not None:
        ax.plot(x, np.asarray(simulated, dtype=float), "o", ms=4.5, mfc="none", color="C0",
                label="simulated (exact event method)")  # fmt: skip
    ax.set_xlabel(xlabel)
    ax.set_ylabel("reversals before the stop")
    cast("MaxNLocator", ax.yaxis.get_major_locator()).set_params(integer=True)
    ax.grid(True, alpha=0.3)
    place_legend(ax)
    return ax


def plot_density(
    density: Any,
    *,
    ax: Axes | None = None,
    max_threshold: float | None = None,
    n_cells: int = 200,
    threshold_unit: str = "m",
    label: str | None = None,
    color: str = "C2",
) -> Axes:
    """The distribution dμ/dr of a `presliding.hysteresis.densities.Density` over the thresholds r.

    Drawn as the mean density μ(cell)/width on `n_cells` equal cells of
    [0, R]; `max_threshold` sets R for an unbounded support (default: four
    times the mean threshold ∫r² dμ / ∫r dμ).
    """
    ax = new_axes(ax)
    big_r = max_threshold
    if big_r is None:
        big_r = float(getattr(density, "max_threshold", np.inf))
        if not np.isfinite(big_r):
            big_r = 4.0 * float(density.M2(np.inf)) / float(density.max_elastic_force)
    edges = np.linspace(0.0, big_r, n_cells + 1)
    support = float(getattr(density, "max_threshold", np.inf))
    if 0.0 < support < big_r:  # a cell edge at the end of the support: no straddling cell
        edges = np.union1d(edges, [support])
    mass = -np.diff(np.asarray(density.tail(edges), dtype=float))
    ax.stairs(mass / np.diff(edges), edges, fill=True, alpha=0.25, color=color)
    ax.stairs(mass / np.diff(edges), edges, color=color, lw=1.4, label=label)
    ax.set_xlabel(f"threshold r [{threshold_unit}]")
    ax.set_ylabel(f"dμ/dr [N/{threshold_unit}²]")
    ax.set_xlim(0.0, big_r)
    ax.grid(True, alpha=0.3)
    if label is not None:
        place_legend(ax)
    return ax


def plot_batch(batch: Any, *, kind: str = "velocity", ax: Axes | None = None) -> Axes:
    """All motions of a batch (`presliding.motion.MotionBatch`) over time.

    kind "velocity" or "position": one line per member; the stop of each member
    that comes to rest is marked (at zero velocity, or at its rest position).
    """
    from presliding._validation import as_choice

    kind = as_choice("kind", kind, ("velocity", "position"))
    ax = new_axes(ax)
    t = batch.time
    values = batch.velocity if kind == "velocity" else batch.position
    n = values.shape[0]
    lw = 1.2 if n <= 10 else 0.6
    for i in range(n):
        ax.plot(t, values[i], lw=lw, color=f"C{i % 10}")
    stopped = np.isfinite(batch.stop_time)
    if stopped.any():
        rest = np.zeros(int(stopped.sum())) if kind == "velocity" else batch.final_position[stopped]
        ax.plot(batch.stop_time[stopped], rest, "s", ms=4, color="k", label="stop")
        place_legend(ax)
    unit = "m/s" if kind == "velocity" else "m"
    ax.set_xlabel("time t [s]")
    ax.set_ylabel(f"{kind} [{unit}]")
    ax.set_title(f"{n} motions; {int(stopped.sum())} at rest at the end")
    ax.axhline(0.0, color="0.8", lw=0.8, zorder=0)
    ax.grid(True, alpha=0.3)
    return ax


def plot_free_response(result: Any, *, ax: Axes | None = None) -> Axes:
    """Velocity over time of a `presliding.motion.FreeResponse`, the stop marked."""
    ax = new_axes(ax)
    ax.plot(result.time, result.velocity, lw=1.4, color="C0", label="velocity")
    if result.stop_time is not None:
        ax.axvline(result.stop_time, color="C3", lw=0.9, ls="--", label="stop")
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("velocity [m/s]")
    if not result.success:
        ax.set_title(result.message)
    ax.axhline(0.0, color="0.8", lw=0.8, zorder=0)
    ax.grid(True, alpha=0.3)
    place_legend(ax)
    return ax
