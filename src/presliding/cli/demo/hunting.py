"""The hunting part of ``presliding demo``: a limit cycle predicted by the describing
function against the exact sampled-data loop."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from presliding.cli.demo._common import _figure, _save
from presliding.cli.report import Section
from presliding.friction.pi_friction import PIFriction
from presliding.plotting import place_legend

#: A bank without the Coulomb element (the mass never rests), a PI position loop whose
#: linear part is unstable without friction: presliding damping holds it on a cycle.
HUNTING_MODEL: dict[str, Any] = dict(
    coulomb=0.0, stiffness=[2e4, 5e3, 1.5e3, 500.0], breakaway=[0.2] * 4
)
HUNTING_GAINS = (400.0, 4e4, 0.0)
HUNTING_DT = 1e-4
HUNTING_T_END = 4.0


def hunting_part() -> dict[str, Any]:
    """The prediction and the exact loop started near rest."""
    from presliding.control import PID, predict_limit_cycles, simulate_loop

    model = PIFriction(**HUNTING_MODEL)
    pid = PID(*HUNTING_GAINS, dt=HUNTING_DT)
    cycles = predict_limit_cycles(1.0, model, pid)
    res = simulate_loop(model, 1.0, pid, 0.0, t_end=HUNTING_T_END, initial_velocity=1e-3)
    return {"model": model, "pid": pid, "cycles": cycles, "loop": res,
            "measured": res.limit_cycle(0.5 * HUNTING_T_END)}  # fmt: skip


def hunting_figure(part: dict[str, Any], out_dir: Path) -> Path:
    """Nyquist curve with −1/N(A), and the position with the predicted amplitude."""
    cycles, res = part["cycles"], part["loop"]
    fig, axes = _figure(2, (11.0, 4.4))
    cycles.plot(ax=axes[0])
    st = np.flatnonzero(cycles.stable)
    ax = axes[1]
    ax.plot(res.time[::5], res.position[::5] * 1e6, color="C0", lw=0.8, label="exact loop")
    if st.size:
        a = cycles.amplitude[st[0]] * 1e6
        for sign in (1, -1):
            ax.axhline(sign * a, color="C3", ls="--", lw=1.2,
                       label="predicted ±A" if sign == 1 else None)  # fmt: skip
    ax.set(xlabel="time t [s]", ylabel="position y [µm]",
           title="hunting: the loop settles on the predicted cycle")  # fmt: skip
    place_legend(ax, fontsize=8)
    return _save(fig, out_dir / "hunting.png")


def hunting_section(part: dict[str, Any], path: Path) -> Section:
    cycles, sim, pid = part["cycles"], part["measured"], part["pid"]
    rows = [("", "amplitude [m]", "frequency [rad/s]", "stable")]
    for a, w, s in zip(cycles.amplitude, cycles.frequency, cycles.stable, strict=True):
        rows.append(("predicted (describing function)", f"{a:.5g}", f"{w:.5g}", str(bool(s))))
    rows.append(("exact loop, second half", f"{sim.amplitude:.5g}", f"{sim.frequency:.5g}",
                 "steady" if sim.steady else "not steady"))  # fmt: skip
    text = (
        f"A PI position loop (kp = {pid.kp:g} N/m, ki = {pid.ki:g} N/(m·s), sampled at "
        f"{pid.dt:g} s) on a 1 kg mass with four presliding elements and no Coulomb element. "
        "Without friction the loop would be unstable (a PI on a mass has no damping); the "
        "presliding elements damp it as soon as the stiffest one slides, so the loop hunts "
        "on a small cycle. Harmonic balance G(jω)·N(A) = −1 with the exact describing "
        "function predicts that stable cycle (and a larger unstable one beyond which motions "
        "grow); the exact sampled-data loop started near rest settles on it. With a Coulomb "
        "element c1 the mass rests at reversals and the describing function, which assumes "
        "sinusoidal motion, no longer describes it (`benchmarks/bench_loop.py` shows where)."
    )
    return Section("Hunting: predicted against simulated limit cycle", text, (path,), table=rows)


__all__ = ["hunting_figure", "hunting_part", "hunting_section"]
