"""Free motion to a stop with Coulomb friction and presliding (the paper's Figures 4 and 5)
========================================================================================

Left: steady sliding under a constant force u = F_c, switched off at t = 0.05 s;
the velocity decreases linearly at F_c/m, overshoots slightly negative after
the reversal and stops exactly (experiment I). Middle and right: a free
response from steady sliding, its velocity and phase portrait (experiment II).
Both use four elements with equal break-away forces c_j = (F_c − c1)/4, as in
the paper's fits. Simulated with the exact event-driven method.

Run: python examples/free_motion_stop.py [output.png]
"""

from __future__ import annotations

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import presliding as ps
from presliding.plotting import place_legend, save_figure


def main(path: str = "free_motion_stop.png") -> None:
    fc, c1, m = 1.0, 0.3, 1.0
    c = (fc - c1) / 4
    model = ps.PIFriction(coulomb=c1, stiffness=[2e4, 5e3, 1.5e3, 500.0], breakaway=[c] * 4)

    # Experiment I: u = F_c until 0.05 s, then off
    t1 = np.linspace(0.0, 0.16, 3201)
    u = (np.array([0.0, 0.05]), np.array([fc, 0.0]))
    exp1 = ps.simulate(model, m, applied_force=u, initial_velocity=0.05,
                       initial_state="saturated", t_eval=t1)  # fmt: skip
    # Experiment II: free response from steady sliding
    t2 = np.linspace(0.0, 0.12, 3001)
    exp2 = ps.simulate(model, m, initial_velocity=0.06, initial_state="saturated", t_eval=t2)

    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2), constrained_layout=True)
    ax = exp1.plot(axes[0], kind="time")
    ax2 = ax.twinx()
    ax2.step(t1, exp1.applied_force, where="post", color="0.55", lw=1.0, label="u")
    ax2.set_ylabel("applied force u [N]", color="0.4")
    ax2.set_ylim(-0.6, 1.2)
    place_legend(ax)
    ax.set_title(f"I: force switched off, stop at {exp1.stop_time:.4f} s")
    inset = ax.inset_axes([0.5, 0.42, 0.46, 0.33])
    near = (t1 > exp1.reversal_times[0] - 0.004) & (t1 < exp1.stop_time + 0.004)
    inset.plot(t1[near], exp1.velocity[near] * 1e3, color="C0", lw=1.2)
    inset.axhline(0.0, color="0.7", lw=0.7)
    inset.set_title("overshoot [mm/s]", fontsize=8)
    inset.tick_params(labelsize=7)

    exp2.plot(axes[1], kind="time")
    axes[1].set_title(f"II: free response, {exp2.n_reversals} reversal(s)")
    exp2.plot(axes[2], kind="phase")
    axes[2].set_title("II: phase portrait")
    axes[2].ticklabel_format(axis="x", style="sci", scilimits=(0, 0))
    save_figure(fig, path)
    plt.close(fig)
    print(exp1.report())
    print(exp2.report())
    print(f"wrote {path}")


if __name__ == "__main__":
    main(*sys.argv[1:2])
