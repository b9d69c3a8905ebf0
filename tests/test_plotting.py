"""Plot functions: axes in, axes out, no global style changes, the right content."""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest
from matplotlib.figure import Figure
from matplotlib.image import imread

import presliding as ps
from presliding import plotting
from presliding.hysteresis.densities import Exponential, Uniform


@pytest.fixture
def ax():
    return Figure().add_subplot()


@pytest.fixture
def free_motion():
    model = ps.PIFriction(0.3, [2e4, 500.0], [0.35, 0.35])
    return ps.simulate(model, 1.0, initial_velocity=0.06, initial_state="saturated", t_end=0.15)


def test_no_global_style_change(ax, free_motion):
    before = dict(matplotlib.rcParams)
    plotting.plot_forces(free_motion, ax=ax)
    plotting.plot_reversal_counts([0.1, 0.2], [2, 1], [2, 1], ax=ax)
    plotting.plot_density(Uniform(1.0, 2.0), ax=ax)
    assert dict(matplotlib.rcParams) == before


def test_plot_forces(ax, free_motion):
    assert plotting.plot_forces(free_motion, ax=ax) is ax
    friction, applied = ax.lines[:2]
    np.testing.assert_array_equal(friction.get_ydata(), free_motion.friction_force)
    np.testing.assert_array_equal(applied.get_ydata(), free_motion.applied_force)
    assert ax.get_xlabel() == "time t [s]" and ax.get_ylabel() == "force [N]"
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["friction force", "applied force u", "stop"]


def test_plot_reversal_counts(ax):
    x, pred, sim = [0.1, 0.3, 1.2], [2, 1, 0], [2, 1, 0]
    assert plotting.plot_reversal_counts(x, pred, sim, ax=ax) is ax
    np.testing.assert_array_equal(ax.lines[0].get_ydata(), pred)
    np.testing.assert_array_equal(ax.lines[1].get_ydata(), sim)
    assert ax.get_ylabel() == "reversals before the stop"
    other = Figure().add_subplot()
    plotting.plot_reversal_counts(x, pred, ax=other)
    assert len(other.lines) == 1


def test_plot_density_areas_equal_the_stiffness(ax):
    dens = Uniform(height=3.0, max_threshold=2.0)
    plotting.plot_density(dens, ax=ax, max_threshold=3.0, n_cells=7)
    values, edges, _ = ax.patches[0].get_data()
    # cell masses add up to μ([0, R]); a cell edge sits on the end of the support
    assert np.sum(values * np.diff(edges)) == pytest.approx(dens.total_stiffness, rel=1e-12)
    assert 2.0 in edges and np.all(values[edges[:-1] >= 2.0] == 0.0)
    assert ax.get_xlabel() == "threshold r [m]" and ax.get_xlim() == (0.0, 3.0)


def test_plot_density_unbounded_support(ax):
    dens = Exponential(height=2.0, length=0.5)
    plotting.plot_density(dens, ax=ax, label="exp")
    # four mean thresholds: 4·∫r² dμ/∫r dμ = 4·2b = 4
    assert ax.get_xlim()[1] == pytest.approx(4.0)
    assert ax.get_legend() is not None


def test_new_figure_when_ax_is_none(free_motion):
    import matplotlib.pyplot as plt

    before = set(plt.get_fignums())
    ax = plotting.plot_forces(free_motion)
    try:
        fig = ax.figure
        assert fig.number not in before and set(plt.get_fignums()) == before | {fig.number}
        assert fig.axes == [ax]  # a fresh figure holding only this axes
        friction, applied = ax.get_lines()[:2]
        np.testing.assert_array_equal(friction.get_xdata(), free_motion.time)
        np.testing.assert_array_equal(friction.get_ydata(), free_motion.friction_force)
        np.testing.assert_array_equal(applied.get_xdata(), free_motion.time)
        np.testing.assert_array_equal(applied.get_ydata(), free_motion.applied_force)
        assert [friction.get_label(), applied.get_label()] == ["friction force", "applied force u"]
    finally:
        plt.close(ax.figure)


@pytest.mark.parametrize("tight", [False, True])
def test_save_figure_size(tmp_path, tight):
    fig = Figure(figsize=(4.0, 3.0), layout="constrained")
    fig.add_subplot().plot([0, 1], [0, 1])
    path = tmp_path / "f.png"
    plotting.save_figure(fig, path, dpi=50, tight=tight)
    image = imread(path)
    if tight:  # cropped to the content, with a small pad
        assert abs(image.shape[1] - 200) < 20 and abs(image.shape[0] - 150) < 20
    else:  # figsize × dpi, within the rounding that differs across matplotlib versions
        assert abs(image.shape[0] - 150) <= 2 and abs(image.shape[1] - 200) <= 2
    assert [p.name for p in tmp_path.iterdir()] == ["f.png"]


@pytest.mark.parametrize(
    "model",
    [
        ps.PIFriction(0.1, [1.0, 0.5, 0.25], [0.2, 0.3, 0.4]),
        ps.PIFriction(0.05, density=Uniform(1.0, 1.0)),
    ],
    ids=["elements", "density"],
)
def test_plot_turning_points_follows_the_swings(ax, model):
    res = ps.turning_points(model, 1.0, 0.8, "saturated")
    assert res.n_reversals >= 3 and res.success
    assert res.plot(ax=ax, samples_per_swing=50) is ax
    path, band = ax.lines[0], ax.patches[0]
    y, f = path.get_xdata(), path.get_ydata()
    assert y.size == 1 + 50 * res.positions.size
    # the operator run through the knots reproduces the energy walk's forces
    knots = f[50::50]
    np.testing.assert_allclose(knots, res.elastic_forces, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(y[50::50], res.positions)
    turning, rest = ax.lines[1], ax.lines[2]
    np.testing.assert_array_equal(turning.get_xdata(), res.positions)
    assert rest.get_xdata()[0] == res.rest_position
    np.testing.assert_allclose(band.get_path().get_extents(band.get_transform()).y0,
                               ax.transData.transform((0.0, -model.coulomb))[1])  # fmt: skip
    np.testing.assert_allclose(band.get_path().get_extents(band.get_transform()).y1,
                               ax.transData.transform((0.0, model.coulomb))[1])  # fmt: skip
    assert ax.get_title() == f"{res.n_reversals} reversal(s); stopped"


def test_plot_turning_points_of_finite_elements_walked_as_a_memory(ax):
    model = ps.PIFriction(0.01, [50.0, 10.0, 4.0], [0.01, 0.05, 0.2])
    res = ps.turning_points(model, 1.0, 2.0, ps.MemoryState.relaxed(0.0))
    res.plot(ax=ax, samples_per_swing=20)
    f = ax.lines[0].get_ydata()
    np.testing.assert_allclose(f[20::20], res.elastic_forces, rtol=0, atol=1e-9)


def test_plot_turning_points_without_a_stop_and_bad_samples(ax):
    res = ps.turning_points(ps.PIFriction(0.0, [4.0], [3.0]), 1.0, 3.0, "saturated")
    assert res.status == "oscillating" and not res.success
    res.plot(ax=ax)
    assert len(ax.patches) == 0  # c1 = 0: no stick band
    assert [t.get_text() for t in ax.get_legend().get_texts()] == [
        "elastic force along the swings",
        "turning points",
    ]
    rule = r"^`samples_per_swing` must be a positive integer; got 0\.$"
    with pytest.raises(ValueError, match=rule):
        res.plot(samples_per_swing=0)
    with pytest.raises(TypeError, match="samples_per_swing"):
        res.plot(samples_per_swing=2.5)


def test_loops_far_from_the_origin_keep_their_own_scale(ax):
    """A loop at −110 mm (a tribometer stage) is drawn over its own span from its start."""
    t = np.linspace(0.0, 4 * np.pi, 400)
    y = -0.110 + 1.2e-4 * np.sin(t)
    force = 2.0 + 0.5 * np.tanh(np.gradient(y) * 1e6)
    plotting.plot_loop_fit(y, force, force + 0.01, ax=ax)
    lo, hi = ax.get_xlim()
    assert -3e-4 < lo < hi < 3e-4 and hi - lo < 1e-3  # y − y₀, y₀ named in the label
    assert ax.get_xlabel() == "displacement y − y₀ [m], y₀ = -0.11 m"
    lo, hi = ax.get_ylim()
    assert lo > 1.0  # the forces stay positive: no axis line pulls 0 into view
    centred = plotting.plot_hysteresis(y + 0.110, force - 2.0)  # crosses both axes: lines drawn
    assert len(centred.lines) == 3
