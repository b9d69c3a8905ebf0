"""Every result's figure survives a plain ``savefig``: nothing cut off, units on every axis,
legends off the data, pooled records apart, a zoom where presliding is a sliver."""

from __future__ import annotations

import io
import re

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest

import presliding as ps
from presliding import plotting
from tests.test_result_convention import BUILDERS, MODEL

#: axis labels that name a count or an index
COUNTS = {"reversals before the stop"}
#: results whose axes are named by the caller (a sweep's grid: the caller's units)
CALLER_NAMED = {"SweepResult"}
TOL = 0.02  # inches


def _saved(fig):
    fig.savefig(io.BytesIO(), format="png", dpi=60)  # plain: no bbox_inches
    return fig.canvas.get_renderer()


def _inside(fig, renderer) -> None:
    tight = fig.get_tightbbox(renderer)
    w, h = fig.get_size_inches()
    assert tight.x0 >= -TOL and tight.y0 >= -TOL, (tight, (w, h))
    assert tight.x1 <= w + TOL and tight.y1 <= h + TOL, (tight, (w, h))


def _covered(ax) -> int:
    """Data samples of the axes' lines inside the legend box (display coordinates)."""
    box = ax.get_legend().get_window_extent()
    count = 0
    for line in ax.get_lines():
        if line.get_transform() is not ax.transData:
            continue  # axhline/axvline: references across the axes
        xy = line.get_transform().transform(np.asarray(line.get_xydata(), dtype=float))
        inside = (xy[:, 0] > box.x0) & (xy[:, 0] < box.x1)
        count += int(np.sum(inside & (xy[:, 1] > box.y0) & (xy[:, 1] < box.y1)))
    return count


def _check_figure(fig, name: str) -> None:
    renderer = _saved(fig)
    _inside(fig, renderer)
    for ax in fig.axes:
        for label in (ax.get_xlabel(), ax.get_ylabel()):
            if label and name not in CALLER_NAMED and label not in COUNTS:
                assert re.search(r"\[[^\]]+\]", label), f"{name}: no unit in {label!r}"
        if ax.get_legend() is not None:
            assert _covered(ax) == 0, f"{name}: the legend covers data"


@pytest.mark.parametrize("name", sorted(BUILDERS))
def test_every_result_figure_survives_a_plain_savefig(name):
    res = BUILDERS[name]()
    ax = res.plot()
    try:
        _check_figure(ax.figure, name)
    finally:
        plt.close(ax.figure)


@pytest.mark.parametrize("kind", ["time", "phase", "loop", "tracking", "error", "control"])
def test_every_loop_figure_survives_a_plain_savefig(kind):
    ax = BUILDERS["LoopResult"]().plot(kind=kind)
    try:
        _check_figure(ax.figure, f"LoopResult {kind}")
    finally:
        plt.close(ax.figure)


def test_the_readme_turning_points_figure_is_not_clipped():
    tp = ps.turning_points(ps.PIFriction(0.3, [2e4, 500.0], [0.35, 0.35]), 1.0, 0.06)
    ax = tp.plot()
    try:
        assert ax.get_legend() is not None
        _check_figure(ax.figure, "TurningPoints")
    finally:
        plt.close(ax.figure)


def _pooled():
    records = []
    for v0 in (0.04, 0.06, 0.08):
        t = np.arange(300) * 1e-3
        res = ps.simulate(MODEL, 1.0, initial_velocity=v0, t_eval=t)
        records.append(ps.Measurement(t, position=res.position, velocity=res.velocity,
                                      applied_force=np.zeros_like(t)))  # fmt: skip
    return ps.fit_response(records)


def test_a_pooled_fit_draws_one_line_per_record_and_names_each():
    fit = _pooled()
    assert len(fit.records) == 3
    ax = fit.plot(labels=["a.csv", "b.csv", "c.csv"])
    try:
        lines = [ln for ln in ax.get_lines() if ln.get_linestyle() not in ("None", "none", "")]
        assert len(lines) == 3  # the fits; no line joins one record to the next
        for line, (a, b) in zip(lines, fit.records, strict=True):
            np.testing.assert_array_equal(line.get_xdata(), fit.abscissa[a:b])
        assert len({ln.get_color() for ln in lines}) == 3
        texts = [t.get_text() for t in ax.get_legend().get_texts()]
        assert texts[:3] == ["a.csv", "b.csv", "c.csv"]
        _check_figure(ax.figure, "pooled FitResult")
    finally:
        plt.close(ax.figure)
    with pytest.raises(ValueError, match="`labels` must name each of the 3 records; got 1"):
        fit.plot(labels=["a.csv"])


def test_a_narrow_presliding_branch_gets_a_zoom_in_a_free_corner():
    model = ps.PIFriction(0.3, [2e4, 500.0], [0.35, 0.35])  # thresholds 17.5 µm, 0.7 mm
    wide = ps.simulate(model, 1.0, initial_velocity=0.3, t_end=2.0)
    ax = wide.plot(kind="loop")
    try:
        insets = [c for c in ax.child_axes]
        assert len(insets) == 1
        lo, hi = insets[0].get_xlim()
        assert hi - lo == pytest.approx(3.0 * 2.0 * 0.35 / 500.0)
        _check_figure(ax.figure, "MotionResult loop")
    finally:
        plt.close(ax.figure)
    broad = ps.simulate(ps.PIFriction(0.3, [100.0], [0.3]), 1.0, initial_velocity=0.05,
                        t_end=2.0)  # fmt: skip
    ax = broad.plot(kind="loop")
    assert ax.child_axes == []  # presliding fills the figure already: no zoom
    plt.close(ax.figure)


def test_a_small_stroke_far_from_zero_is_drawn_from_its_start():
    y = -0.11 + 1.2e-4 * np.sin(np.linspace(0.0, 6.0, 400))
    values, words = plotting.relative_positions(y)
    assert values[0] == 0.0 and np.ptp(values) == pytest.approx(np.ptp(y))
    assert words == "y − y₀ [m], y₀ = -0.11 m"
    ax = plotting.plot_loop_fit(y, np.tanh(y + 0.11), np.tanh(y + 0.11))
    try:
        assert ax.get_xlabel().startswith("displacement y − y₀ [m]")
        assert np.max(np.abs(ax.lines[0].get_xdata())) < 3e-4
        _check_figure(ax.figure, "plot_loop_fit")
    finally:
        plt.close(ax.figure)
    near = np.linspace(-1e-3, 1e-3, 5)
    assert plotting.relative_positions(near)[1] == "y [m]"
