"""The built-in main job behind ``presliding demo``."""

from __future__ import annotations

from pathlib import Path

from .friction import PIFriction
from .signals import FIGURE3_TURNING_POINTS, piecewise_linear

#: The paper's Figure 3 model: c = [1, 1, 1], k2,3 = [10, 4], k1 in {500, 50, 5}.
FIGURE3_FIRST_STIFFNESS = (500.0, 50.0, 5.0)


def figure3_models() -> list[PIFriction]:
    """The three models of the paper's Figure 3 (c1 = 0, eq. 4)."""
    return [
        PIFriction(coulomb=0.0, stiffness=[k1, 10.0, 4.0], breakaway=[1.0, 1.0, 1.0])
        for k1 in FIGURE3_FIRST_STIFFNESS
    ]


def figure3_loops(out_dir: Path) -> Path:
    """Draw the Figure 3 hysteresis loops to ``out_dir/figure3_loops.png``."""
    from matplotlib.figure import Figure

    from .plotting import plot_hysteresis, save_figure

    y = piecewise_linear(FIGURE3_TURNING_POINTS, step=1e-3)
    forces = [m.force(y)[0] for m in figure3_models()]
    fig = Figure(figsize=(6.4, 4.8))
    ax = fig.add_subplot()
    plot_hysteresis(y, forces, labels=[f"$k_1$ = {k:g}" for k in FIGURE3_FIRST_STIFFNESS], ax=ax)
    ax.set_title("Presliding hysteresis, 3 stop elements, c = [1, 1, 1] (Figure 3)")
    path = out_dir / "figure3_loops.png"
    save_figure(fig, path)
    return path


def run_demo(out_dir: Path) -> list[Path]:
    """Write every demo output to `out_dir`; return the paths written."""
    out_dir.mkdir(parents=True, exist_ok=True)
    return [figure3_loops(out_dir)]


__all__ = ["figure3_loops", "figure3_models", "run_demo"]
