"""Presliding hysteresis loops of the paper's Figure 3
===================================================

Three stop elements with break-away forces c = [1, 1, 1] and stiffnesses
k2,3 = [10, 4]; the stiffness k1 of the first element is varied over
{500, 50, 5} (Section 2). All three models are driven along the same
displacement path: a major loop to ±0.3 with nested minor loops inside. Right
after every reversal the slope is Σ k_j (eq. 7); at unidirectional motion the
force saturates at F_c = Σ c_j = 3 (eq. 9).

Usage::

    python examples/figure3_loops.py [output.png]

The figure is written to ``figure3_loops.png`` in the current folder unless a
path is given.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from presliding import PIFriction
from presliding.plotting import place_legend, plot_hysteresis, save_figure
from presliding.signals import FIGURE3_TURNING_POINTS, piecewise_linear

FIRST_STIFFNESS = (500.0, 50.0, 5.0)


def figure3_models() -> list[PIFriction]:
    """The three models of Figure 3 (no Coulomb element: c1 = 0)."""
    return [
        PIFriction(coulomb=0.0, stiffness=[k1, 10.0, 4.0], breakaway=[1.0, 1.0, 1.0])
        for k1 in FIRST_STIFFNESS
    ]


def draw(path: Path) -> Path:
    """Draw the loops, one panel per k1 and all three overlaid, to the PNG `path`."""
    y = piecewise_linear(FIGURE3_TURNING_POINTS, step=5e-4)
    models = figure3_models()
    forces = [model.force(y)[0] for model in models]
    colors = ["C0", "C1", "C2"]

    fig = Figure(figsize=(12.0, 7.2), layout="constrained")
    grid = fig.add_gridspec(2, 3, height_ratios=[1.0, 1.15])
    panels = [fig.add_subplot(grid[0, i]) for i in range(3)]
    overlay = fig.add_subplot(grid[1, :2])
    zoom = fig.add_subplot(grid[1, 2])

    virgin_y = np.linspace(-0.3, 0.3, 601)
    moves = np.sign(np.diff(y))
    turns = np.concatenate([[0], np.flatnonzero(moves[1:] != moves[:-1]) + 1, [y.size - 1]])
    for ax, model, force, color in zip(panels, models, forces, colors, strict=True):
        k1 = model.stiffness[0]
        ax.plot(virgin_y, model.virgin_curve(virgin_y), ls="--", lw=1.0, color="0.55",
                label="virgin curve")  # fmt: skip
        n_before = len(ax.lines)
        plot_hysteresis(y, force, ax=ax, displacement_unit="m", force_unit="N")
        ax.lines[n_before].set_color(color)
        ax.plot(y[turns], force[turns], "o", ms=3.5, color="k", zorder=3,
                label="turning points")  # fmt: skip
        ax.set_title(
            f"$k_1$ = {k1:g} N/m   ($r_1$ = {model.threshold[0]:.3g} m, "
            f"$\\Sigma k_j$ = {model.initial_stiffness:g} N/m)",
            fontsize=10,
        )
        ax.set_xlim(-0.33, 0.33)
        ax.set_ylim(-3.4, 3.4)
    place_legend(panels[0], fontsize=8)
    for ax in panels[1:]:
        ax.set_ylabel("")

    labels = [f"$k_1$ = {k:g} N/m" for k in FIRST_STIFFNESS]
    plot_hysteresis(y, forces, labels=labels, ax=overlay)
    for line, width in zip(overlay.lines, (3.2, 2.0, 1.4), strict=False):
        line.set_linewidth(width)  # coinciding branches stay visible
    level = models[0].coulomb_level
    for sign in (-1, 1):
        overlay.axhline(sign * level, color="0.4", lw=0.8, ls=":", zorder=0)
    overlay.text(-0.325, level - 0.28, "$\\pm F_c = \\pm\\Sigma c_j$ (eq. 9)", fontsize=8,
                 color="0.3")  # fmt: skip
    overlay.set_title("All three models on the same path (major loop ±0.3 m, nested minor loops)",
                      fontsize=10)  # fmt: skip

    # the nested minor loops 0.15 → −0.05 → 0.08 → −0.3, enlarged
    first, last = turns[3], turns[6]  # from the reversal at 0.15 to the one at −0.3
    last = first + int(np.flatnonzero(y[first:last] < -0.12)[0])
    part = slice(first, last + 1)
    inner_turns = turns[(turns >= first) & (turns <= last)]
    for force, color, width in zip(forces, colors, (3.2, 2.0, 1.4), strict=True):
        zoom.plot(y[part], force[part], lw=width, color=color)
        zoom.plot(y[inner_turns], force[inner_turns], "o", ms=3.5, color="k", zorder=3)
    zoom.axhline(0.0, color="0.8", lw=0.8, zorder=0)
    zoom.axvline(0.0, color="0.8", lw=0.8, zorder=0)
    zoom.grid(True, alpha=0.3)
    zoom.set_xlabel("displacement y [m]")
    zoom.set_title("0.15 → −0.05 → 0.08 → −0.3 m: the minor loop closes", fontsize=10)

    fig.suptitle(
        "Presliding friction hysteresis, 3 stop elements, c = [1, 1, 1] N, "
        "$k_{2,3}$ = [10, 4] N/m (paper, Figure 3)",
        fontsize=12,
    )
    save_figure(fig, path, dpi=130)
    return path


def main(argv: list[str]) -> None:
    out = Path(argv[1]) if len(argv) > 1 else Path.cwd() / "figure3_loops.png"
    print(f"wrote {draw(out)}")


if __name__ == "__main__":
    main(sys.argv)
