"""Parts 4 and 5 of ``presliding demo``: a continuous density and an identification round trip."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from presliding.cli.common import tidy_fit_axes
from presliding.cli.demo._common import STOP_MASS, STOP_SPEED, _figure, _plural, _save
from presliding.cli.report import Section
from presliding.friction._parts import density_of
from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis.densities import Exponential
from presliding.signals import FIGURE3_TURNING_POINTS, piecewise_linear


# ---------------------------------------------------------------------- 4. densities
def density_models() -> dict[str, PIFriction]:
    """Uniform and exponential μ with F_m = 0.7 N and μ([0, R]) = 7000 N/m, c1 = 0.1 N."""
    from presliding.hysteresis.densities import Uniform

    return {
        "uniform": PIFriction(0.1, density=Uniform(height=3.5e7, max_threshold=2e-4)),
        "exponential": PIFriction(0.1, density=Exponential(height=7e7, length=1e-4)),
    }


#: Step of the implicit simulation of the continuous models [s] (first order in the step).
DENSITY_STEP = 1e-5


def density_part() -> dict[str, Any]:
    """Loops (exact operator), predicted turning points, and two simulations of the free stop.

    ``motion``: the continuous model itself, implicit method (section 3 as it
    stands); ``discrete``: a 400-cell midpoint discretisation, exact event method.
    """
    from presliding import analysis
    from presliding.motion.simulation import simulate

    y = piecewise_linear(np.asarray(FIGURE3_TURNING_POINTS) * 2e-3, step=2e-6)
    n_cells = 400
    t_eval = np.linspace(0.0, 0.3, 6001)
    start: dict[str, Any] = {
        "initial_velocity": STOP_SPEED,
        "initial_state": "saturated",
        "t_eval": t_eval,
    }
    out: dict[str, Any] = {"path": y, "cells": n_cells, "step": DENSITY_STEP}
    for name, model in density_models().items():
        force, _ = model.force(y)
        dens = density_of(model)
        # an exponential μ has R = inf: cut it at 12 decay lengths
        big_r = 12 * dens.length if isinstance(dens, Exponential) else dens.max_threshold
        fine = PIFriction(model.coulomb, density=dens.discretize(n_cells, big_r))
        out[name] = {
            "model": model,
            "force": force,
            "predicted": analysis.turning_points(model, STOP_MASS, STOP_SPEED, "saturated"),
            "motion": simulate(model, STOP_MASS, method="implicit", step=DENSITY_STEP, **start),
            "discrete": simulate(fine, STOP_MASS, **start),
        }
    return out


def density_figure(part: dict[str, Any], out_dir: Path) -> Path:
    from presliding.plotting import plot_density, plot_hysteresis

    fig, axes = _figure(3, (15.0, 4.6))
    colours = {"uniform": "C2", "exponential": "C4"}
    for name, colour in colours.items():
        plot_density(
            part[name]["model"].density, ax=axes[0], max_threshold=6e-4, label=name, color=colour
        )
    axes[0].legend(frameon=False)
    axes[0].ticklabel_format(axis="both", style="sci", scilimits=(-3, 3), useMathText=True)
    axes[0].set_title("distribution dμ/dr (same F_m, same Σk)")
    y = part["path"]
    plot_hysteresis(y, [part[n]["force"] for n in colours], labels=list(colours), ax=axes[1])
    for line, colour in zip(axes[1].lines, colours.values(), strict=False):
        line.set_color(colour)
    axes[1].legend(frameon=False, loc="upper left")
    axes[1].ticklabel_format(axis="x", style="sci", scilimits=(-3, 3), useMathText=True)
    axes[1].set_title("loops, exact general PI operator (eq. 10)")
    ax = axes[2]
    for name, colour in colours.items():
        res, pred = part[name]["motion"], part[name]["predicted"]
        near = res.time >= (res.reversal_times[0] - 0.01 if res.n_reversals else 0.0)
        ax.plot(
            res.position[near] * 1e3,
            res.velocity[near] * 1e3,
            color=colour,
            lw=1.3,
            label=f"{name}: {_plural(res.n_reversals, 'reversal')}, implicit simulation",
        )
        ax.plot(
            pred.positions * 1e3, np.zeros_like(pred.positions), "x", ms=8, mew=1.8, color=colour
        )
    ax.plot([], [], "x", color="0.3", label="turning points, energy analysis")
    ax.axhline(0.0, color="0.8", lw=0.8, zorder=0)
    ax.set_xlabel("position y [mm]")
    ax.set_ylabel("velocity [mm/s]")
    ax.grid(True, alpha=0.3)
    ax.legend(frameon=False, fontsize=8, loc="upper left")
    ax.set_title("free stop near the turning points")
    return _save(fig, out_dir / "density.png")


def _rest_error(part: dict[str, Any], key: str) -> float:
    """Largest relative distance of a simulated rest position from the exact one."""
    errors = [
        abs(part[n][key].rest_position - part[n]["predicted"].rest_position)
        / abs(part[n]["predicted"].rest_position)
        for n in ("uniform", "exponential")
    ]
    return max(errors)


def density_section(part: dict[str, Any], path: Path) -> Section:
    rows = [
        ("", "F_m [N]", "Σk [N/m]", "reversals", "rest position [m]"),
    ]
    for name in ("uniform", "exponential"):
        d = part[name]
        m, pred, res, disc = d["model"], d["predicted"], d["motion"], d["discrete"]
        rows.append(
            (
                f"{name}: energy analysis (exact)",
                f"{m.max_elastic_force:.4g}",
                f"{m.initial_stiffness:.4g}",
                str(pred.n_reversals),
                f"{pred.rest_position:.10g}",
            )
        )
        for label, r in (("implicit simulation", res), (f"{part['cells']} cells, exact", disc)):
            rest = "moving" if r.rest_position is None else f"{r.rest_position:.10g}"
            rows.append((f"{name}: {label}", "", "", str(r.n_reversals), rest))
    text = (
        "Section 3: a continuum of stops with distribution μ (eq. 10). A uniform density "
        "(3.5e7 N/m² on [0, 0.2 mm]) and an untruncated exponential one (7e7·exp(−r/0.1 mm) "
        "N/m²) share F_m = ∫r dμ = 0.7 N and the stiffness after a reversal μ([0, R]) = "
        "7000 N/m (eq. 7), but their virgin curves, and so every loop (Madelung/Masing), "
        "differ. The loops are evaluated exactly, without discretising μ. With c1 = 0.1 N "
        "the free motion from saturation at 0.06 m/s is predicted exactly by the energy "
        "analysis (crosses). The curves simulate the continuous models themselves with the "
        f"implicit method (step {part['step']:g} s, first order: the rest positions agree "
        f"to {_rest_error(part, 'motion'):.1e} relative); an exact simulation of a "
        f"{part['cells']}-cell midpoint discretisation agrees to "
        f"{_rest_error(part, 'discrete'):.1e} (O(1/n²))."
    )
    return Section("A continuous density (section 3)", text, (path,), table=rows)


# ---------------------------------------------------------------------- 5. identification
#: The identification model: c1 = 0.5 N and three elements (Figure 3 with k1 = 500 N/m).
FIT_TRUE: dict[str, Any] = {
    "coulomb": 0.5,
    "stiffness": (500.0, 50.0, 4.0),
    "breakaway": (1.0, 1.0, 1.0),
}
FIT_NOISE = 0.02  # N, standard deviation of the force noise


def identification() -> dict[str, Any]:
    """Simulate loops, add noise, fit eq. 8 (section 4), compare with the truth."""
    from presliding.identification.fit_presliding import fit_presliding

    true = PIFriction(FIT_TRUE["coulomb"], FIT_TRUE["stiffness"], FIT_TRUE["breakaway"])
    y = piecewise_linear([0.0, 0.8, -0.8, 0.4, -0.2, 0.1, -0.05, 0.6, -0.6], 1e-3)
    force, _ = true.force(y)
    rng = np.random.default_rng(20240607)
    measured = force + rng.normal(0.0, FIT_NOISE, force.shape)
    fit = fit_presliding(y, measured, n_elements=3)
    return {"true": true, "path": y, "clean": force, "measured": measured, "fit": fit}


def identification_figure(part: dict[str, Any], out_dir: Path) -> Path:
    from presliding.plotting import plot_fit, plot_loop_fit

    fit = part["fit"]
    fig, axes = _figure(2, (13.2, 4.8))
    ax = plot_loop_fit(
        fit.abscissa, fit.measured, fit.fitted, ax=axes[0], measured_label="measured (noisy)"
    )
    ax.set_title("loops: simulated with noise, and the fitted model")
    ax = plot_fit(
        np.arange(fit.measured.shape[0]),
        fit.measured,
        fit.fitted,
        ax=axes[1],
        xlabel="sample",
        title=f"force along the path (NRMSE {100 * fit.nrmse:.3g} %)",
    )
    tidy_fit_axes(fig, ax, "friction force", "N")
    return _save(fig, out_dir / "identification.png")


def identification_section(part: dict[str, Any], path: Path) -> Section:
    fit, true = part["fit"], part["true"]
    truth = {"coulomb": true.coulomb}
    for j in range(true.n_elements):
        truth[f"stiffness_{j + 1}"] = float(true.stiffness[j])
        truth[f"threshold_{j + 1}"] = float(true.threshold[j])
    rows = [("parameter", "true", "fitted", "standard error", "95 % interval", "covers")]
    for name, value in truth.items():
        est = fit.parameters.get(name, float("nan"))
        lo, hi = fit.confidence_interval.get(name, (float("nan"), float("nan")))
        rows.append(
            (
                name,
                f"{value:.6g}",
                f"{est:.6g}",
                f"{fit.standard_error.get(name, np.nan):.3g}",
                f"[{lo:.6g}, {hi:.6g}]",
                "yes" if lo <= value <= hi else "no",
            )
        )
    text = (
        "Section 4 on simulated data: the force of c1 = 0.5 N and three elements "
        "(k = [500, 50, 4] N/m, c = [1, 1, 1] N) along a path with nested loops, plus "
        f"Gaussian noise of {FIT_NOISE:g} N, as a tribometer measures it (displacement in, "
        "friction force out). fit_presliding starts from nonnegative least squares for the "
        "stiffnesses on a threshold grid and refines the thresholds by nonlinear least "
        f"squares: status {fit.status}, NRMSE {100 * fit.nrmse:.3g} %, residual RMS "
        f"{fit.residual_rms:.3g} N (the noise level)."
    )
    return Section("Identification round trip (section 4)", text, (path,), table=rows)


__all__ = [
    "density_figure",
    "density_models",
    "density_part",
    "density_section",
    "identification",
    "identification_figure",
    "identification_section",
]
