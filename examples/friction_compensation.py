"""Feedforward friction compensation with the inverse PI operator
==============================================================

A positioning stage (mass m on a preload spring k_s) slides on a contact with
presliding friction: c1·sign(ẏ) plus three elasto-plastic elements (eq. 17).
Moved slowly, its position follows the force through the hysteresis

    y = Γ[u − c1·sign(ẏ)],    Γ = Φ⁻¹,   Φ[y] = k_s·y + Σ k_j (y − x_j(y, r_j)),

a PI operator with a linear term (the spring) and negative weights: the stage
stiffens at each reversal. Its compensator is Γ⁻¹ = ``Gamma.inverse()``: the
feedforward

    u_ff = Γ⁻¹[y_ref] + c1·sign(ẏ_ref) + m·ÿ_ref

is compared with the classical Coulomb compensation that knows the spring, the
mass and the friction level F_c = c1 + Σ c_j (eq. 9) but not the presliding,
u_C = k_s·y_ref + F_c·sign(ẏ_ref) + m·ÿ_ref. Both are applied as samples held over 0.1 ms (a
digital controller) and simulated exactly (event method) with stiction.

Run: python examples/friction_compensation.py [output.png]
"""

from __future__ import annotations

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import presliding as ps
from presliding.plotting import place_legend, save_figure


def main(path: str = "friction_compensation.png") -> None:
    m, k_s, c1 = 0.5, 50.0, 0.05
    k = np.array([4000.0, 1000.0, 300.0])
    c = np.array([0.1, 0.1, 0.1])
    # the spring as an element that never slides (threshold far beyond the stroke)
    plant = ps.PIFriction(coulomb=c1, stiffness=[*k, k_s], breakaway=[*c, k_s * 1e3])
    phi = ps.PIOperator(threshold=c / k, weight=k, linear=k_s)
    gamma = phi.inverse()  # force -> position hysteresis of the stage (c1 aside)
    print(f"Γ = Φ⁻¹: linear {gamma.linear:.4g}, weights {np.round(gamma.weight, 6).tolist()}")

    dt = 1e-4
    t = np.arange(0.0, 2.0 + dt / 2, dt)
    w = 2 * np.pi
    y_ref = 2e-3 * (1 - np.cos(w * t)) + 4e-4 * np.sin(3 * w * t) * (t > 1.0)
    v_ref = np.gradient(y_ref, dt)
    a_ref = np.gradient(v_ref, dt)

    compensator = gamma.inverse()
    u_ff = compensator.apply(y_ref)[0] + c1 * np.sign(v_ref) + m * a_ref
    u_coulomb = k_s * y_ref + (c1 + c.sum()) * np.sign(v_ref) + m * a_ref  # F_c, eq. 9
    runs = {}
    for name, u in (("Coulomb feedforward", u_coulomb), ("PI-inverse feedforward", u_ff)):
        runs[name] = ps.simulate(plant, m, (t, u), initial_velocity=v_ref[0], t_eval=t)
        err = runs[name].position - y_ref
        print(
            f"{name:24s}: max |error| {np.max(np.abs(err)) * 1e6:8.2f} µm, "
            f"rms {np.sqrt(np.mean(err**2)) * 1e6:8.2f} µm, status {runs[name].status}"
        )

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2), constrained_layout=True)
    axes[0].plot(t, y_ref * 1e3, color="k", lw=1.0, label="reference")
    for name, res in runs.items():
        axes[0].plot(t, res.position * 1e3, lw=1.2, label=name)
        axes[1].plot(t, (res.position - y_ref) * 1e6, lw=1.0, label=name)
    axes[0].set(xlabel="time t [s]", ylabel="position y [mm]", title="tracking")
    axes[1].set(xlabel="time t [s]", ylabel="error y − y_ref [µm]", title="tracking error")
    y_loop = np.linspace(-1e-3, 1e-3, 201)
    loop_y = np.concatenate([y_loop, y_loop[::-1], y_loop])
    force = phi.apply(loop_y)[0]
    axes[2].plot(force, loop_y * 1e3, lw=1.2, label="stage: y = Γ[u]")
    axes[2].plot(force, gamma.apply(force)[0] * 1e3, "--", lw=1.0, label="Γ applied to u")
    axes[2].set(xlabel="elastic force u [N]", ylabel="position y [mm]", title="Γ = Φ⁻¹")
    for ax in axes:
        ax.grid(True, alpha=0.3)
        place_legend(ax, fontsize=8)
    save_figure(fig, path)
    plt.close(fig)
    print(f"wrote {path}")


if __name__ == "__main__":
    main(*sys.argv[1:2])
