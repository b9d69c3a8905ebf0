"""A parameter sweep on local worker processes: reversals before a free mass stops
===============================================================================

How many times does a free mass reverse before PI friction stops it? The energy
analysis (eqs. 13–16, `turning_points`) answers it for one Coulomb level and one
initial velocity; `sweep` maps it over a grid of both, in chunks, on two local
worker processes. The function is defined right here, in the script: the sweep sends
it to the workers by value, so it needs no module of its own (the same holds for a
function defined in a notebook). The count depends on c1/F_m alone: from a saturated
memory the work-energy balance holds for every initial velocity (the paper's eqs. 15–16),
so the colour changes only along the horizontal axis.

Run: python examples/sweep_reversals.py [output.png]
"""

from __future__ import annotations

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import presliding as ps
from presliding.plotting import save_figure

STIFFNESS, BREAKAWAY = [2e4, 5e3, 1.5e3, 500.0], [0.175] * 4  # F_m = 0.7 N
MASS = 1.0


def reversals(coulomb_ratio, initial_velocity):
    """Reversals before the stop for each point of a chunk (c1 as a fraction of F_m)."""
    out = np.empty(coulomb_ratio.shape[0])
    for i, (ratio, v0) in enumerate(zip(coulomb_ratio, initial_velocity, strict=True)):
        model = ps.PIFriction(ratio * 0.7, STIFFNESS, BREAKAWAY)
        out[i] = ps.turning_points(model, MASS, v0, "saturated").n_reversals
    return out


def main(path: str = "sweep_reversals.png") -> None:
    grid = {"coulomb_ratio": np.geomspace(0.05, 1.2, 16),
            "initial_velocity": np.linspace(0.01, 0.12, 8)}  # fmt: skip
    result = ps.sweep(reversals, grid, n_workers=2)
    print(result.report())
    assert result.success and np.all(np.diff(result.values, axis=0) <= 0)  # more c1: fewer

    fig, ax = plt.subplots(figsize=(7.0, 4.8), layout="constrained")
    result.plot(ax=ax, label="reversals before the stop")
    ax.set(xscale="log", xlabel="c1 / F_m [1]", ylabel="initial velocity v0 [m/s]",
           title="free motion from saturation, m = 1 kg")  # fmt: skip
    save_figure(fig, path)
    plt.close(fig)
    print(f"wrote {path}")


if __name__ == "__main__":
    main(*sys.argv[1:2])
