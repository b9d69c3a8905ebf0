"""Friction compensation in a closed position loop: none, Coulomb and PI feedforward
=================================================================================

A 1 kg stage under a sampled PID (0.1 ms, saturating at 20 N, derivative of the error,
so that a moving reference costs no velocity error) follows a smooth
back-and-forth reference with reversals. The contact has presliding friction,
c1·sign(ẏ) plus three elasto-plastic elements (eq. 8, F_c = 1 N). Three
feedforwards are added to the PID's output:

* none;
* Coulomb: F_c·sign(ẏ_ref) + m·ÿ_ref, the classical compensation that knows the
  friction level (eq. 9) but not the presliding;
* PI: the whole friction model along the reference, c1 included, + m·ÿ_ref.

Each loop is simulated exactly with `simulate_loop` (closed-form motion between
samples, exact stiction) and the tracking errors are tabulated: overall, and in
the windows after the reversals where presliding acts.

Where the PI feedforward comes from. Moved slowly, the contact follows the
applied force through the hysteresis y = Γ[u]: the elastic force follows u
through a play of threshold c1 and the bank is inverted on its range −F_c < u < F_c.
The library builds Γ as ``ps.friction_inverse(model)`` (a `PIInverse`, c1
included). The feedforward that makes the contact follow y_ref is Γ⁻¹[y_ref],
and Γ⁻¹ is the friction model itself, c1·sign(ẏ) + Σ k_j (y − x_j) (eq. 8):
``model.force(y_ref)``. The script checks that round trip: in every presliding
transition (−F_c < u < F_c), Γ maps the feedforward's friction part back onto the
reference. In gross sliding the force sits at F_c and no position follows from
it (Γ raises there), so the round trip is checked on the transitions only.

Run: python examples/closed_loop_compensation.py [output.png]
"""

from __future__ import annotations

import itertools
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import presliding as ps
from presliding.plotting import place_legend, save_figure


def check_round_trip(model: ps.PIFriction, y_ref: np.ndarray, friction: np.ndarray) -> float:
    """Largest |Γ[u] − y_ref| [m] over the presliding transitions, Γ = friction_inverse(model).

    `friction` is the model's force along `y_ref`; each stretch where it stays
    below F_c in magnitude is fed to the inverse, started from the model's memory
    at the stretch's first sample.
    """
    gamma = ps.friction_inverse(model)  # u -> y, c1 included, defined for |u| < F_c
    inside = np.abs(friction) < gamma.force_limit * (1 - 1e-12)
    change = np.flatnonzero(np.diff(inside.astype(np.int8))) + 1
    bounds = np.concatenate([[0], change, [inside.size]])
    worst = 0.0
    for start, stop in itertools.pairwise(bounds):
        if not inside[start]:
            continue  # gross sliding: no quasi-static position
        # the memory after the samples before the stretch (relaxed at the start)
        state = model.force(y_ref[:start])[1] if start else model.relaxed_state(float(y_ref[0]))
        y, _ = gamma.apply(friction[start:stop], state)
        worst = max(worst, float(np.max(np.abs(y - y_ref[start:stop]))))
    return worst


def main(path: str = "closed_loop_compensation.png") -> None:
    m = 1.0
    model = ps.PIFriction(coulomb=0.1, stiffness=[3e4, 8e3, 2e3], breakaway=[0.3, 0.3, 0.3])
    pid = ps.PID(2000.0, 2e4, 40.0, dt=1e-4, limit=20.0, derivative_on="error")
    t = np.arange(0.0, 2.0 + pid.dt / 2, pid.dt)
    w = 2 * np.pi
    y_ref = 5e-4 * (1 - np.cos(w * t)) + 1e-4 * np.sin(3 * w * t)
    v_ref = np.gradient(y_ref, pid.dt)
    a_ref = np.gradient(v_ref, pid.dt)
    fc = model.coulomb_level
    friction, _ = model.force(y_ref)  # Γ⁻¹[y_ref]: the whole model, c1 as sign(ẏ_ref)
    print(f"round trip through friction_inverse on the presliding transitions: "
          f"{check_round_trip(model, y_ref, friction):.1e} m")  # fmt: skip
    feedforwards = {
        "none": np.zeros_like(t),
        "Coulomb feedforward": fc * np.sign(v_ref) + m * a_ref,
        "PI feedforward": friction + m * a_ref,
    }
    runs = {name: ps.simulate_loop(model, m, pid, y_ref, feedforward=ff,
                                   initial_velocity=v_ref[0])
            for name, ff in feedforwards.items()}  # fmt: skip
    reversal = np.flatnonzero(np.diff(np.sign(v_ref)) != 0)
    near = np.zeros(t.size, dtype=bool)
    for i in reversal:
        near[i : i + int(0.05 / pid.dt)] = True  # 50 ms after each reversal of the reference
    print(f"{'compensation':22s} {'rms error':>12s} {'max |error|':>12s} "
          f"{'max after reversals':>20s}   [µm]")  # fmt: skip
    for name, res in runs.items():
        e = res.error * 1e6
        outcome = "exact" if res.success else res.message
        print(f"{name:22s} {np.sqrt(np.mean(e**2)):12.3f} {np.max(np.abs(e)):12.3f} "
              f"{np.max(np.abs(e[near])):20.3f}   {outcome}")  # fmt: skip

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2), constrained_layout=True)
    axes[0].plot(t, y_ref * 1e3, color="k", lw=1.0, label="reference")
    for name, res in runs.items():
        axes[0].plot(t, res.measured * 1e3, lw=1.0, label=name)
        axes[1].plot(t, res.error * 1e6, lw=0.9, label=name)
        axes[2].plot(t, res.error * 1e6, lw=0.9, label=name)
    axes[0].set(xlabel="time t [s]", ylabel="position y [mm]", title="tracking")
    axes[1].set(xlabel="time t [s]", ylabel="error r − y [µm]", title="tracking error")
    i0 = reversal[1]
    axes[2].set_xlim(t[i0] - 0.02, t[i0] + 0.12)
    axes[2].set(xlabel="time t [s]", ylabel="error r − y [µm]", title="after a reversal")
    for ax in axes:
        ax.grid(True, alpha=0.3)
        place_legend(ax, fontsize=8)
    save_figure(fig, path)
    plt.close(fig)
    print(f"wrote {path}")


if __name__ == "__main__":
    main(*sys.argv[1:2])
