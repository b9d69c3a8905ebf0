"""The built-in main job behind ``presliding demo``.

Five parts, each a figure and a report section:

1. the paper's Figure 3 loops (finite elements, eq. 4);
2. free motion to a stop with a reversal (the paper's Figures 4 and 5), simulated
   exactly, beside the turning points predicted by the energy analysis (eqs. 12–16);
3. reversal counts over a sweep of c1/F_m: analysis against simulation;
4. a continuous density (section 3, eq. 10): uniform and exponential μ with the
   same F_m and eq. 7 stiffness, their loops (exact general PI operator) and free stops;
5. an identification round trip: loops simulated, noise added, parameters fitted
   (section 4) and compared with the truth.

``quick=True`` (for the tests) uses fewer samples and smaller sweeps; the
figures keep their size.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ._progress import progress
from ._report import Section, write_report
from .friction import PIFriction
from .signals import FIGURE3_TURNING_POINTS, piecewise_linear

#: The paper's Figure 3 model: c = [1, 1, 1], k2,3 = [10, 4], k1 in {500, 50, 5}.
FIGURE3_FIRST_STIFFNESS = (500.0, 50.0, 5.0)
#: Pixels per inch of the demo figures (sizes are exact: figsize × DPI).
DPI = 110
#: The free-stop model: F_c = 1 N, c1 = 0.3 N, four elements with equal break-away
#: forces (F_c − c1)/4 as in the paper's fits, mass 1 kg.
STOP_COULOMB, STOP_LEVEL, STOP_MASS = 0.3, 1.0, 1.0
STOP_STIFFNESS = (2.0e4, 5.0e3, 1.5e3, 500.0)
STOP_SPEED = 0.06  # m/s at the start of the free response


def figure3_models() -> list[PIFriction]:
    """The three models of the paper's Figure 3 (c1 = 0, eq. 4)."""
    return [
        PIFriction(coulomb=0.0, stiffness=[k1, 10.0, 4.0], breakaway=[1.0, 1.0, 1.0])
        for k1 in FIGURE3_FIRST_STIFFNESS
    ]


def stop_model(coulomb: float = STOP_COULOMB) -> PIFriction:
    """Four elements with equal break-away forces (F_c − c1)/4, F_c = STOP_LEVEL."""
    c = (STOP_LEVEL - STOP_COULOMB) / len(STOP_STIFFNESS)
    return PIFriction(coulomb, list(STOP_STIFFNESS), [c] * len(STOP_STIFFNESS))


def _figure(ncols: int, size: tuple[float, float]) -> tuple[Any, Any]:
    from ._cli_common import new_figure

    fig, axes = new_figure(ncols, 1, size=size)
    return fig, axes[0]


def _save(fig: Any, path: Path) -> Path:
    from .plotting import save_figure

    save_figure(fig, path, dpi=DPI, tight=False)
    return path


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" + ("" if n == 1 else "s")


# ---------------------------------------------------------------------- 1. Figure 3
def figure3_loops(out_dir: Path) -> Path:
    """Draw the Figure 3 hysteresis loops to ``out_dir/figure3_loops.png``."""
    from .plotting import plot_hysteresis

    y = piecewise_linear(FIGURE3_TURNING_POINTS, step=1e-3)
    forces = [m.force(y)[0] for m in figure3_models()]
    fig, (ax,) = _figure(1, (7.2, 5.0))
    labels = [
        f"$k_1$ = {k:g} N/m (Σk = {m.initial_stiffness:g} N/m)"
        for k, m in zip(FIGURE3_FIRST_STIFFNESS, figure3_models(), strict=True)
    ]
    plot_hysteresis(y, forces, labels=labels, ax=ax)
    ax.set_title("Presliding hysteresis, 3 stop elements, c = [1, 1, 1] N (Figure 3)")
    ax.legend(frameon=False, loc="upper left", fontsize=9)
    return _save(fig, out_dir / "figure3_loops.png")


def _figure3_section(path: Path) -> Section:
    return Section(
        "Presliding hysteresis loops (Figure 3)",
        "Three elasto-plastic stop elements with break-away forces c = [1, 1, 1] N, "
        "k2,3 = [10, 4] N/m and k1 in {500, 50, 5} N/m, driven along one displacement path "
        "with nested minor loops. Every reversal starts with the stiffness Σk (eq. 7), the "
        "force saturates at F_c = Σc = 3 N (eq. 9), and minor loops close on their reversal "
        "points (return-point memory).",
        (path,),
    )


# ---------------------------------------------------------------------- 2. free stop
@dataclass(frozen=True)
class FreeStop:
    """The free-stop part: the two experiments and the predicted turning points."""

    switch_off: Any  # MotionResult, experiment I
    free: Any  # MotionResult, experiment II
    predicted: Any  # analysis.TurningPoints of experiment II
    turning_point: float | None  # y_e of eq. 15
    stops_at_turning_point: bool  # eq. 16


def free_stop(quick: bool = False) -> FreeStop:
    """Simulate the paper's two experiments and predict experiment II's turning points."""
    from . import analysis
    from .motion import simulate

    model = stop_model()
    n = 801 if quick else 4001
    exp1 = simulate(
        model, STOP_MASS, applied_force=(np.array([0.0, 0.05]), np.array([STOP_LEVEL, 0.0])),
        initial_velocity=0.05, initial_state="saturated", t_eval=np.linspace(0.0, 0.15, n),
    )  # fmt: skip
    exp2 = simulate(
        model, STOP_MASS, initial_velocity=STOP_SPEED, initial_state="saturated",
        t_eval=np.linspace(0.0, 0.1, n),
    )  # fmt: skip
    pred = analysis.turning_points(model, STOP_MASS, STOP_SPEED, "saturated")
    y_e = analysis.turning_point(model) if model.coulomb < model.max_elastic_force else None
    return FreeStop(exp1, exp2, pred, y_e, bool(analysis.stops_at_turning_point(model)))


def free_stop_figure(part: FreeStop, out_dir: Path) -> Path:
    """Velocity over time (I and II) and the phase portrait of II, predictions marked."""
    from .plotting import plot_motion

    exp1, exp2, pred = part.switch_off, part.free, part.predicted
    fig, axes = _figure(3, (15.0, 4.6))
    ax = plot_motion(exp1, kind="time", ax=axes[0])
    ax2 = ax.twinx()
    ax2.step(exp1.time, exp1.applied_force, where="post", color="0.5", lw=1.0, ls="--")
    ax2.set_ylabel("applied force u [N]", color="0.4")
    ax2.set_ylim(-0.3, 3.3)
    ax2.set_yticks([0.0, 0.5, 1.0])
    ax.plot([], [], color="0.5", lw=1.0, ls="--", label="applied force u")
    ax.legend(frameon=False, loc="lower left", fontsize=9)
    ax.set_title(f"I: force switched off at 0.05 s, stop at {exp1.stop_time:.4f} s")
    _zoom_inset(ax, exp1)
    ax = plot_motion(exp2, kind="time", ax=axes[1])
    ax.legend(frameon=False, loc="lower left", fontsize=9)
    ax.set_title(
        f"II: free response, {_plural(exp2.n_reversals, 'reversal')} simulated, "
        f"{pred.n_reversals} predicted"
    )
    _zoom_inset(ax, exp2)
    ax = plot_motion(exp2, kind="phase", ax=axes[2])
    ax.plot(pred.positions, np.zeros_like(pred.positions), "x", ms=9, mew=2.0, color="C1",
            label="turning points, energy analysis")  # fmt: skip
    ax.legend(frameon=False, loc="upper right", fontsize=9)
    ax.ticklabel_format(axis="x", style="sci", scilimits=(-3, 3), useMathText=True)
    ax.set_title("II: phase portrait (Figure 5b)")
    inset = ax.inset_axes((0.1, 0.1, 0.45, 0.42))
    near = exp2.time >= (exp2.reversal_times[0] - 0.008 if exp2.n_reversals else 0.0)
    inset.plot(exp2.position[near] * 1e3, exp2.velocity[near] * 1e3, color="C0", lw=1.2)
    inset.plot(pred.positions * 1e3, np.zeros_like(pred.positions), "x", ms=7, mew=1.6,
               color="C1")  # fmt: skip
    inset.axhline(0.0, color="0.7", lw=0.7)
    inset.set_title("near the stop [mm, mm/s]", fontsize=8)
    inset.tick_params(labelsize=7)
    return _save(fig, out_dir / "free_stop.png")


def _zoom_inset(ax: Any, res: Any) -> None:
    """Inset magnifying the velocity around the reversal and the stop (mm/s)."""
    if not res.n_reversals or res.stop_time is None:
        return
    t = res.time
    lo, hi = res.reversal_times[0], res.stop_time
    pad = 0.25 * (hi - lo)
    near = (t > lo - pad) & (t < hi + pad)
    inset = ax.inset_axes((0.6, 0.5, 0.37, 0.38))
    inset.plot(t[near], res.velocity[near] * 1e3, color="C0", lw=1.2)
    inset.axhline(0.0, color="0.7", lw=0.7)
    inset.axvline(res.stop_time, color="C3", lw=0.8, ls="--")
    inset.set_title("overshoot after the reversal [mm/s]", fontsize=8)
    inset.tick_params(labelsize=7)


def _free_stop_section(part: FreeStop, path: Path) -> Section:
    exp2, pred = part.free, part.predicted
    model = stop_model()
    c = (STOP_LEVEL - STOP_COULOMB) / len(STOP_STIFFNESS)
    y_e = "none (c1 >= F_m)" if part.turning_point is None else f"{part.turning_point:.6g} m"
    rows = [
        ("", "energy analysis (eqs. 12–16)", "exact simulation (eq. 17)"),
        ("reversals before the stop", str(pred.n_reversals), str(exp2.n_reversals)),
        ("rest position [m]", f"{pred.rest_position:.10g}", f"{exp2.rest_position:.10g}"),
    ]
    if pred.positions.shape[0] > 1 and exp2.n_reversals:
        rows.append(
            (
                "first turning point [m]",
                f"{pred.positions[0]:.10g}",
                f"{exp2.reversal_positions[0]:.10g}",
            )  # fmt: skip
        )
    text = (
        f"A mass m = {STOP_MASS:g} kg with F_c = {STOP_LEVEL:g} N, c1 = {STOP_COULOMB:g} N and "
        f"four elements k = {list(STOP_STIFFNESS)} N/m with equal break-away forces "
        f"c_j = (F_c − c1)/4 = {c:g} N, as in the paper's fits. I (Figure 4): steady sliding "
        "under u = F_c, switched off at 0.05 s; the velocity falls linearly at F_c/m, "
        "overshoots slightly negative after the reversal and then sticks exactly. "
        f"II (Figure 5): a free response from steady sliding at {STOP_SPEED:g} m/s.\n\n"
        f"From the saturated start the stop analysis gives y_e = {y_e} (eq. 15, measured from "
        f"the first turning point) and the stop test c1 >= Φ(y_e) (eq. 16) is "
        f"{'met' if part.stops_at_turning_point else 'not met'}: "
        f"{_plural(pred.n_reversals, 'reversal')} predicted, "
        f"{_plural(exp2.n_reversals, 'reversal')} simulated. The simulation is exact "
        f"(event-driven); its energy balance closes to {exp2.energy.max_relative_residual:.1e} "
        f"of the initial energy, and the mass at rest does not creep (F_c = "
        f"{model.coulomb_level:g} N, F_m = {model.max_elastic_force:g} N)."
    )
    return Section("Free motion to a stop (Figures 4 and 5)", text, (path,), table=rows)


# ---------------------------------------------------------------------- 3. reversal sweep
def reversal_sweep(quick: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """(c1/F_m, predicted counts, simulated counts, F_m) over a sweep of c1."""
    from . import analysis
    from .motion import simulate_batch

    fm = stop_model().max_elastic_force
    ratio = np.geomspace(0.004, 1.4, 24 if quick else 90)
    coulomb = ratio * fm
    predicted = np.array(
        [
            analysis.turning_points(stop_model(c1), STOP_MASS, STOP_SPEED, "saturated").n_reversals
            for c1 in coulomb
        ]  # fmt: skip
    )
    k = np.tile(np.asarray(STOP_STIFFNESS), (coulomb.shape[0], 1))
    c = np.full(k.shape, (STOP_LEVEL - STOP_COULOMB) / len(STOP_STIFFNESS))
    batch = simulate_batch(
        coulomb=coulomb, stiffness=k, breakaway=c, mass=STOP_MASS, initial_velocity=STOP_SPEED,
        initial_state="saturated", t_end=60.0, t_eval=np.linspace(0.0, 60.0, 3),
    )  # fmt: skip
    simulated = np.where(batch.stopped, batch.n_reversals, -1)
    return ratio, predicted, simulated, fm


def reversal_figure(sweep: tuple, out_dir: Path) -> Path:
    from .plotting import plot_reversal_counts

    ratio, predicted, simulated, _ = sweep
    fig, (ax,) = _figure(1, (7.2, 4.8))
    from matplotlib.ticker import NullLocator, ScalarFormatter

    one = ratio[predicted == 1]
    if one.size:
        ax.axvspan(one.min(), one.max(), color="C2", alpha=0.12, lw=0,
                   label="eq. 16 met: exactly one reversal")  # fmt: skip
    plot_reversal_counts(ratio, predicted, simulated, ax=ax, xlabel="c1 / F_m")
    ax.set_xscale("log")
    ax.set_yscale("symlog", linthresh=4.0, linscale=1.5)
    top = int(max(predicted.max(), simulated.max()))
    ax.set_yticks([t for t in (0, 1, 2, 3, 4, 6, 10, 20, 40, 100, 200) if t <= 1.2 * top])
    ax.yaxis.set_major_formatter(ScalarFormatter())
    ax.yaxis.set_minor_locator(NullLocator())
    ax.set_ylim(-0.3, 1.3 * top)
    ax.axvline(1.0, color="0.4", lw=0.9, ls=":")
    ax.text(0.93, 6.0, "c1 > F_m: no reversal →", fontsize=8, ha="right", va="center",
            color="0.3")  # fmt: skip
    ax.legend(frameon=False, loc="upper right", fontsize=9)
    ax.set_title("Reversals before the stop, free motion from saturation")
    return _save(fig, out_dir / "reversals.png")


def _reversal_section(sweep: tuple, path: Path) -> Section:
    ratio, predicted, simulated, fm = sweep
    agree = int(np.sum(predicted == simulated))
    one = ratio[predicted == 1]
    text = (
        f"The same four elements (F_m = {fm:g} N) with the Coulomb element c1 swept over "
        f"{ratio[0]:.3g}·F_m .. {ratio[-1]:.3g}·F_m: the number of reversals of a free motion "
        "from a saturated start, predicted by the work-energy balance along Masing branches "
        "(eqs. 12–16 continued to any number of reversals, no time stepping) and counted in "
        f"exact simulations. They agree in {agree} of {ratio.shape[0]} cases. Exactly one "
        f"reversal (eq. 16 met) for c1/F_m in [{one.min():.3g}, {one.max():.3g}] of the "
        "sweep; none once c1 > F_m; more and more as c1 → 0."
    )
    return Section("Reversal count against c1/F_m (eqs. 15–16)", text, (path,))


# ---------------------------------------------------------------------- 4. densities
def density_models() -> dict[str, PIFriction]:
    """Uniform and exponential μ with F_m = 0.7 N and μ([0, R]) = 7000 N/m, c1 = 0.1 N."""
    from .densities import Exponential, Uniform

    return {
        "uniform": PIFriction(0.1, density=Uniform(height=3.5e7, max_threshold=2e-4)),
        "exponential": PIFriction(0.1, density=Exponential(height=7e7, length=1e-4)),
    }


def density_part(quick: bool = False) -> dict[str, Any]:
    """Loops (exact operator), predicted turning points and a fine-discretisation motion."""
    from . import analysis
    from .motion import simulate

    y = piecewise_linear(np.asarray(FIGURE3_TURNING_POINTS) * 2e-3, step=2e-6)
    n_cells = 100 if quick else 400
    out: dict[str, Any] = {"path": y}
    for name, model in density_models().items():
        force, _ = model.force(y)
        pred = analysis.turning_points(model, STOP_MASS, STOP_SPEED, "saturated")
        dens = model.density
        big_r = dens.max_threshold if np.isfinite(dens.max_threshold) else 12 * dens.length
        fine = PIFriction(model.coulomb, density=dens.discretize(n_cells, big_r))
        motion = simulate(
            fine, STOP_MASS, initial_velocity=STOP_SPEED, initial_state="saturated",
            t_eval=np.linspace(0.0, 0.3, 1501 if quick else 6001),
        )  # fmt: skip
        out[name] = {"model": model, "force": force, "predicted": pred, "motion": motion,
                     "cells": n_cells}  # fmt: skip
    return out


def density_figure(part: dict[str, Any], out_dir: Path) -> Path:
    from .plotting import plot_density, plot_hysteresis

    fig, axes = _figure(3, (15.0, 4.6))
    colours = {"uniform": "C2", "exponential": "C4"}
    for name, colour in colours.items():
        plot_density(part[name]["model"].density, ax=axes[0], max_threshold=6e-4, label=name,
                     color=colour)  # fmt: skip
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
        ax.plot(res.position[near] * 1e3, res.velocity[near] * 1e3, color=colour, lw=1.3,
                label=f"{name}: {_plural(res.n_reversals, 'reversal')} simulated")  # fmt: skip
        ax.plot(pred.positions * 1e3, np.zeros_like(pred.positions), "x", ms=8, mew=1.8,
                color=colour)  # fmt: skip
    ax.plot([], [], "x", color="0.3", label="turning points, energy analysis")
    ax.axhline(0.0, color="0.8", lw=0.8, zorder=0)
    ax.set_xlabel("position y [mm]")
    ax.set_ylabel("velocity [mm/s]")
    ax.grid(True, alpha=0.3)
    ax.legend(frameon=False, fontsize=8, loc="upper left")
    ax.set_title("free stop near the turning points")
    return _save(fig, out_dir / "density.png")


def _density_section(part: dict[str, Any], path: Path) -> Section:
    rows = [("", "F_m [N]", "Σk [N/m] (eq. 7)", "reversals: analysis", "simulation",
             "rest position: analysis [m]", "simulation [m]")]  # fmt: skip
    for name in ("uniform", "exponential"):
        d = part[name]
        m, pred, res = d["model"], d["predicted"], d["motion"]
        rows.append((
            name, f"{m.max_elastic_force:.4g}", f"{m.initial_stiffness:.4g}",
            str(pred.n_reversals), str(res.n_reversals), f"{pred.rest_position:.8g}",
            f"{res.rest_position:.8g}" if res.rest_position is not None else "moving",
        ))  # fmt: skip
    text = (
        "Section 3: a continuum of stops with distribution μ (eq. 10). A uniform density "
        "(3.5e7 N/m² on [0, 0.2 mm]) and an untruncated exponential one (7e7·exp(−r/0.1 mm) "
        "N/m²) share F_m = ∫r dμ = 0.7 N and the stiffness after a reversal μ([0, R]) = "
        "7000 N/m, but their virgin curves, and so every loop (Madelung/Masing), differ. The "
        "loops are evaluated exactly, without discretising μ. With c1 = 0.1 N the free motion "
        "from saturation at 0.06 m/s is predicted exactly by the energy analysis (crosses); "
        f"the curves are exact simulations of a {part['uniform']['cells']}-cell midpoint "
        "discretisation of each density (differences O(1/n²))."
    )
    return Section("A continuous density (section 3)", text, (path,), table=rows)


# ---------------------------------------------------------------------- 5. identification
#: The identification model: c1 = 0.5 N and three elements (Figure 3 with k1 = 500 N/m).
FIT_TRUE = {"coulomb": 0.5, "stiffness": (500.0, 50.0, 4.0), "breakaway": (1.0, 1.0, 1.0)}
FIT_NOISE = 0.02  # N, standard deviation of the force noise


def identification(quick: bool = False) -> dict[str, Any]:
    """Simulate loops, add noise, fit eq. 8 (section 4), compare with the truth."""
    from .fit_presliding import fit_presliding

    true = PIFriction(FIT_TRUE["coulomb"], FIT_TRUE["stiffness"], FIT_TRUE["breakaway"])
    y = piecewise_linear([0.0, 0.8, -0.8, 0.4, -0.2, 0.1, -0.05, 0.6, -0.6],
                         4e-3 if quick else 1e-3)  # fmt: skip
    force, _ = true.force(y)
    rng = np.random.default_rng(20240607)
    measured = force + rng.normal(0.0, FIT_NOISE, force.shape)
    fit = fit_presliding(y, measured, n_elements=3)
    return {"true": true, "path": y, "clean": force, "measured": measured, "fit": fit}


def identification_figure(part: dict[str, Any], out_dir: Path) -> Path:
    from .plotting import plot_fit, plot_hysteresis

    fit = part["fit"]
    fig, axes = _figure(2, (13.2, 4.8))
    y = part["path"]
    ax = plot_hysteresis(y, part["measured"], ax=axes[0])
    ax.lines[0].set(ls="none", marker=".", ms=2.0, color="0.55", label="measured (noisy)")
    ax.plot(fit.abscissa, fit.fitted, color="C1", lw=1.4, label="fitted model")
    ax.legend(frameon=False, loc="upper left")
    ax.set_title("loops: simulated with noise, and the fitted model")
    plot_fit(np.arange(fit.measured.shape[0]), fit.measured, fit.fitted, ax=axes[1],
             xlabel="sample", ylabel="friction force [N]",
             title=f"force along the path (NRMSE {100 * fit.nrmse:.2f} %)")  # fmt: skip
    residual_ax = fig.axes[-1]
    residual_ax.set_ylabel("residual [N]")
    fig.align_ylabels([axes[1], residual_ax])
    return _save(fig, out_dir / "identification.png")


def _identification_section(part: dict[str, Any], path: Path) -> Section:
    fit, true = part["fit"], part["true"]
    truth = {"coulomb": true.coulomb}
    for j in range(true.n_elements):
        truth[f"stiffness_{j + 1}"] = float(true.stiffness[j])
        truth[f"threshold_{j + 1}"] = float(true.threshold[j])
    rows = [("parameter", "true", "fitted", "standard error", "95 % interval", "covers")]
    for name, value in truth.items():
        est = fit.parameters.get(name, float("nan"))
        lo, hi = fit.confidence_interval.get(name, (float("nan"), float("nan")))
        rows.append((
            name, f"{value:.6g}", f"{est:.6g}", f"{fit.standard_error.get(name, np.nan):.3g}",
            f"[{lo:.6g}, {hi:.6g}]", "yes" if lo <= value <= hi else "no",
        ))  # fmt: skip
    text = (
        "Section 4 on simulated data: the force of c1 = 0.5 N and three elements "
        "(k = [500, 50, 4] N/m, c = [1, 1, 1] N) along a path with nested loops, plus "
        f"Gaussian noise of {FIT_NOISE:g} N, as a tribometer measures it (displacement in, "
        "friction force out). fit_presliding starts from nonnegative least squares for the "
        "stiffnesses on a threshold grid and refines the thresholds by nonlinear least "
        f"squares: status {fit.status}, NRMSE {100 * fit.nrmse:.2f} %, residual RMS "
        f"{fit.residual_rms:.3g} N (the noise level)."
    )
    return Section("Identification round trip (section 4)", text, (path,), table=rows)


# ---------------------------------------------------------------------- the job
def run_demo(out_dir: Path, *, quick: bool = False, quiet: bool = True) -> list[Path]:
    """Write every demo output to `out_dir`; return the paths written."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    sections = []
    with progress(5, "presliding demo", quiet=quiet, unit="part") as bar:
        path = figure3_loops(out_dir)
        sections.append(_figure3_section(path))
        bar.update()
        stop = free_stop(quick)
        sections.append(_free_stop_section(stop, free_stop_figure(stop, out_dir)))
        bar.update()
        sweep = reversal_sweep(quick)
        sections.append(_reversal_section(sweep, reversal_figure(sweep, out_dir)))
        bar.update()
        dens = density_part(quick)
        sections.append(_density_section(dens, density_figure(dens, out_dir)))
        bar.update()
        ident = identification(quick)
        sections.append(_identification_section(ident, identification_figure(ident, out_dir)))
        bar.update()
    figures = [p for s in sections for p in s.figures]
    reports = write_report(out_dir, "presliding demo", sections)
    return figures + reports


__all__ = ["figure3_loops", "figure3_models", "run_demo"]
