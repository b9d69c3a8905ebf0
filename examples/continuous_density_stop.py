"""Free stop of a mass with a continuous distribution of stops (section 3, eqs. 10–16)
===================================================================================

Friction with an untruncated exponential density dμ/dr = a·exp(−r/b) (a
Dahl-like virgin curve) and a Coulomb element c1 = 0.1·F_m. The mass starts
from steady sliding (every stop saturated) and is left free: it decelerates,
reverses a few times inside presliding and sticks exactly. The motion is the
implicit stepper with the exact continuous operator; the dots are the turning
points and the rest position from the exact work-energy analysis
(`turning_points`, no time stepping). For comparison, the same model without
the Coulomb element (c1 = 0) never stops: its oscillation decays forever.

Panels: velocity over time, phase portrait, friction force over position.

Run: python examples/continuous_density_stop.py [output.png]
"""

from __future__ import annotations

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import presliding as ps
from presliding.analysis import turning_points
from presliding.plotting import place_legend, save_figure


def main(path: str = "continuous_density_stop.png") -> None:
    density = ps.Exponential(height=3.0, length=0.4)  # F_m = a·b² = 0.48 N, μ = a·b = 1.2 N/m
    fm = density.max_elastic_force
    m, v0 = 1.0, 0.8
    t = np.linspace(0.0, 16.0, 4001)
    model = ps.PIFriction(0.1 * fm, density=density)
    res = ps.simulate(model, m, initial_velocity=v0, initial_state="saturated", t_eval=t,
                      step=2e-4)  # fmt: skip
    exact = turning_points(model, m, v0, "saturated")
    free = ps.PIFriction(0.0, density=density)
    undamped = ps.simulate(free, m, initial_velocity=v0, initial_state="saturated", t_eval=t,
                           step=2e-4)  # fmt: skip

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.4), constrained_layout=True)
    ax = axes[0]
    ax.plot(t, undamped.velocity, lw=1.0, color="0.6", label="c1 = 0: never stops")
    res.plot(ax, kind="time")
    ax.set_title(f"velocity: {res.n_reversals} reversals, stop at t = {res.stop_time:.3f} s")
    place_legend(ax)

    ax = axes[1]
    ax.plot(undamped.position, undamped.velocity, lw=0.8, color="0.7", label="c1 = 0")
    res.plot(ax, kind="phase")
    ax.plot(exact.positions, np.zeros(exact.positions.shape), "o", mfc="none", color="C1",
            ms=8, label="turning points (energy balance)")  # fmt: skip
    ax.set_title("phase portrait")
    place_legend(ax)

    ax = axes[2]
    moving = res.time < res.stop_time
    ax.plot(res.position[moving], res.friction_force[moving], lw=1.4, color="C0",
            label="friction force c1·σ + F_el")  # fmt: skip
    ax.plot(res.position, res.elastic_force, lw=1.0, ls="--", color="C2",
            label="elastic part F_el (eq. 10)")  # fmt: skip
    ax.plot(
        [res.rest_position],
        [res.elastic_force[-1]],
        "s",
        color="C3",
        ms=6,
        label=f"rest: |F_el| = {abs(res.elastic_force[-1]):.3f} <= c1 = {model.coulomb:.3f}",
    )
    for level in (fm, -fm):
        ax.axhline(level, color="0.75", lw=0.8, ls=":")
    ax.axhline(0.0, color="0.8", lw=0.8, zorder=0)
    ax.set_xlabel("position y [m]")
    ax.set_ylabel("force [N]")
    ax.set_title("force–displacement: presliding loops to the stop")
    ax.grid(True, alpha=0.3)
    place_legend(ax, fontsize=8)
    fig.suptitle(
        f"Exponential density a = {density.height:g} N/m², b = {density.length:g} m "
        f"(F_m = {fm:.2f} N), c1 = 0.1·F_m, m = {m:g} kg, v0 = {v0:g} m/s from saturation"
    )
    save_figure(fig, path)
    plt.close(fig)
    print(res.report())
    print(exact.report())
    print(f"wrote {path}")


if __name__ == "__main__":
    main(*sys.argv[1:2])
