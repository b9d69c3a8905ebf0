"""Legends of the plotting helpers do not sit on the data."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from presliding.plotting import place_legend, plot_hysteresis, plot_loop_fit


def _covered(ax) -> int:
    """Data points of the axes' lines inside the legend box (display coordinates)."""
    box = ax.get_legend().get_window_extent()
    count = 0
    for line in ax.get_lines():
        xy = line.get_transform().transform(np.asarray(line.get_xydata(), dtype=float))
        inside = (xy[:, 0] >= box.x0) & (xy[:, 0] <= box.x1)
        count += int(np.sum(inside & (xy[:, 1] >= box.y0) & (xy[:, 1] <= box.y1)))
    return count


def test_a_legend_moves_outside_when_the_data_fill_the_axes():
    ax = Figure(layout="constrained").subplots()
    rng = np.random.default_rng(0)
    ax.plot(rng.uniform(size=4000), rng.uniform(size=4000), ".", label="noise")
    ax.plot([0, 1], [0, 1], label="line")
    place_legend(ax)
    ax.get_figure().draw_without_rendering()
    assert _covered(ax) == 0
    assert ax.get_legend().get_window_extent().x0 > ax.get_window_extent().x1  # to the right


def test_a_sparse_plot_keeps_its_legend_inside_and_off_the_data():
    fig = Figure()
    ax = fig.subplots()
    t = np.linspace(0.0, 1.0, 200)
    plot_hysteresis(t, [t, 0.5 * t], labels=["a", "b"], ax=ax)  # the upper left is empty
    fig.draw_without_rendering()
    box = ax.get_legend().get_window_extent()
    assert _covered(ax) == 0 and box.x1 <= ax.get_window_extent().x1


def test_the_loop_fit_legend_is_off_a_loop_that_fills_the_axes():
    fig = Figure()
    ax = fig.subplots()
    y = np.concatenate([np.linspace(-1, 1, 500), np.linspace(1, -1, 500)])
    measured = np.concatenate([np.tanh(4 * (y[:500] + 0.3)), np.tanh(4 * (y[500:] - 0.3))])
    plot_loop_fit(y, measured, measured * 0.98, ax=ax)
    fig.draw_without_rendering()
    assert _covered(ax) == 0


def test_a_fast_oscillation_crossing_the_legend_between_samples_moves_it_outside():
    # few samples per period: no sample lies in a corner, but the segments cross it
    ax = Figure(layout="constrained").subplots()
    t = np.arange(400) * 0.01
    ax.plot(t, 10.0 * np.where(np.arange(400) % 2 == 0, 1.0, -1.0), label="hunting")
    ax.axhline(10.0, ls="--", label="predicted ±A")  # spans the axes: not data to avoid
    place_legend(ax)
    ax.get_figure().draw_without_rendering()
    assert ax.get_legend().get_window_extent().x0 > ax.get_window_extent().x1


def test_scattered_points_count_as_data():
    ax = Figure(layout="constrained").subplots()
    rng = np.random.default_rng(1)
    ax.scatter(rng.uniform(size=3000), rng.uniform(size=3000), s=2, label="residual")
    place_legend(ax)
    ax.get_figure().draw_without_rendering()
    assert ax.get_legend().get_window_extent().x0 > ax.get_window_extent().x1


def test_reference_lines_alone_keep_the_legend_inside():
    ax = Figure(layout="constrained").subplots()
    ax.plot([0.0, 1.0], [0.0, 0.1], label="low line")
    ax.axhline(0.5, label="reference")
    place_legend(ax)
    ax.get_figure().draw_without_rendering()
    assert ax.get_legend().get_window_extent().x1 <= ax.get_window_extent().x1
