"""``presliding simulate``: a model file's motion to CSV and PNG."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

from presliding.cli.common import (
    UserError,
    check_folder,
    check_outputs,
    check_readable,
    new_figure,
    read_table,
    record_outputs,
    write_csv,
)

#: CSV header of a simulation (units in brackets).
HEADER = (
    "time [s]",
    "position [m]",
    "velocity [m/s]",
    "acceleration [m/s^2]",
    "friction_force [N]",
    "elastic_force [N]",
    "applied_force [N]",
)


def output_paths(output: Path) -> tuple[Path, Path]:
    """(CSV, PNG) for ``-o``: a .csv path, or a folder holding simulation.csv/.png."""
    if output.suffix.lower() == ".csv":
        check_folder(output.parent if str(output.parent) else Path("."))
        return output, output.with_suffix(".png")
    folder = check_folder(output)
    return folder / "simulation.csv", folder / "simulation.png"


def read_applied_force(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Samples (time, value) of u from a CSV file with columns time,value."""
    table = read_table(path, "applied-force file", example="time,value")
    hint = "the applied-force file needs columns time,value [s, N]"
    columns = []
    for signal, aliases in (("time", ("time", "t")), ("value", ("value", "u", "applied_force"))):
        i = table.find(aliases)
        if i is None:
            raise UserError(
                f"{path}: no column `{signal}`; {hint}; its columns are "
                f"{', '.join(repr(n) for n in table.names)}."
            )
        columns.append(table.columns[i])
    t, u = columns
    if t.shape[0] < 1:
        raise UserError(f"{path}: has no samples; {hint}.")
    steps = np.diff(t)
    if np.any(steps <= 0):
        i = int(np.argmax(steps <= 0)) + 1
        raise UserError(
            f"{path}: `time` must increase strictly; row {i + 1} holds {t[i]:g} after "
            f"{t[i - 1]:g}; sort the rows or remove duplicates."
        )
    return t, u


def run(args: argparse.Namespace) -> int:
    """Load, simulate, write CSV and PNG; print a summary."""
    from presliding import motion
    from presliding.model_io import load_model

    check_readable(args.model, "model file")
    spec = load_model(args.model)
    _check_options(args, spec.model)
    mo = _motion(args, spec.motion)
    csv_path, png_path = output_paths(args.output)
    check_outputs((csv_path, png_path), (args.model, args.applied_force), overwrite=args.overwrite)
    offset = spec.measurement.force_offset  # measured u = m·ÿ + F + F_0: u − F_0 acts
    force: Any = mo.applied_force - offset
    if args.applied_force is not None:
        t_u, u = read_applied_force(args.applied_force)
        if t_u[0] > 0.0:
            raise UserError(
                f"{args.applied_force}: the first time is {t_u[0]:g} s but the motion "
                "starts at 0 s; add a row at time 0."
            )
        if t_u[-1] < mo.t_end and not args.hold_last:
            raise UserError(
                f"{args.applied_force}: ends at {t_u[-1]:g} s, before motion.t_end = "
                f"{mo.t_end:g} s; extend it, shorten t_end, or pass --hold-last to hold its "
                "last value."
            )
        force = (t_u, u - offset)
    t_eval = np.linspace(0.0, mo.t_end, mo.samples)
    if args.rtol is not None and not (np.isfinite(args.rtol) and args.rtol > 0):
        raise UserError(f"--rtol must be a positive number; got {args.rtol:g}.")
    # the implicit step is chosen for an accuracy target unless --step fixes it
    rtol = args.rtol if args.rtol is not None else (DEFAULT_RTOL if args.step is None else None)
    try:
        result = motion.simulate(
            spec.model,
            mo.mass,
            applied_force=force,
            initial_position=mo.initial_position,
            initial_velocity=mo.initial_velocity,
            initial_state=mo.initial_state,
            t_eval=t_eval,
            method=args.method,
            hold=args.hold,
            step=args.step,
            rtol=rtol,
        )
    except (TypeError, ValueError) as exc:
        raise UserError(f"{args.model}: cannot simulate: {exc}") from None
    record_outputs((csv_path, png_path))
    write_csv(
        csv_path,
        HEADER,
        [
            result.time,
            result.position,
            result.velocity,
            result.acceleration,
            result.friction_force,
            result.elastic_force,
            result.applied_force,
        ],
        quiet=args.quiet,
    )
    save_motion_figure(result, png_path, title=f"{args.model.name}: {_headline(result)}")
    if not args.quiet:
        print(result.report())
        if offset:
            print(f"  applied force u − F_0, with F_0 = {offset:.6g} N from [measurement]")
        print(f"wrote {csv_path}")
        print(f"wrote {png_path}")
    if result.success and result.stop_time is None and args.applied_force is None:
        # `presliding --help`: exit 1 for a motion under a constant force still moving at the
        # end (its stop is the question); a motion driven by samples of u(t) ends where they do
        if not args.quiet:
            print(
                f"still moving at t_end = {mo.t_end:g} s (v = {result.final_velocity:.6g} m/s): "
                "exit status 1; a longer motion.t_end shows where it stops"
            )
        return 1
    return 0 if result.success else 1


DEFAULT_RTOL = 1e-3  # of the largest displacement, for the implicit step


def _check_options(args: argparse.Namespace, model: Any) -> None:
    """Options that this run would not use are refused: how samples of --applied-force are
    held without such samples, the implicit method's step and accuracy for the event method."""
    if args.applied_force is None:
        for flag, given in (("--hold-last", args.hold_last), ("--hold linear",
                                                              args.hold == "linear")):  # fmt: skip
            if given:
                raise UserError(
                    f"{flag}: says how the samples of --applied-force are held, "
                    "and none are given (the force is the model file's constant "
                    "motion.applied_force); drop it, or give --applied-force CSV."
                )
    method = args.method
    if method == "auto":
        method = "event" if model.is_discrete and args.hold == "zoh" else "implicit"
    if method == "event":
        for flag, value in (("--step", args.step), ("--rtol", args.rtol)):
            if value is not None:
                how = ("" if args.method == "event" else " (chosen by --method auto for "
                       "elements and a piecewise-constant force)")  # fmt: skip
                raise UserError(f"{flag} {value:g}: an option of the implicit method, and this "
                                f"run uses the exact event method{how}, which has no step; "
                                "drop it, or pass --method implicit.")  # fmt: skip


def _motion(args: argparse.Namespace, mo: Any) -> Any:
    """The motion settings with --mass and --initial-velocity; a missing mass, or a motion
    that nothing starts (no speed, no applied force), is refused rather than defaulted."""
    import dataclasses

    given = set(mo.given)
    changes = {}
    for key, value in (("mass", args.mass), ("initial_velocity", args.initial_velocity)):
        if value is not None:
            changes[key] = value
            given.add(key)
    if "mass" not in given:
        raise UserError(
            f"{args.model}: no `motion.mass`; a simulation needs the moving mass: add a [motion] "
            "table with mass [kg] (and initial_velocity [m/s]) or pass --mass KG."
        )
    if not given & {"initial_velocity", "applied_force"} and args.applied_force is None:
        raise UserError(
            f"{args.model}: nothing sets the mass in motion (no `motion.initial_velocity`, "
            "`motion.applied_force` or --applied-force); give one of them, or "
            "--initial-velocity M_PER_S."
        )
    return dataclasses.replace(mo, **changes, given=frozenset(given))


def _headline(result: Any) -> str:
    n = result.n_reversals
    reversals = f"{n} reversal" + ("" if n == 1 else "s")
    if result.stop_time is None:
        return f"moving at the end (v = {result.final_velocity:.3g} m/s), {reversals}"
    return (
        f"stops at t = {result.stop_time:.4g} s at y = {result.rest_position:.4g} m after "
        f"{reversals}"
    )


def save_motion_figure(result: Any, path: Path, title: str) -> None:
    """Four panels: velocity over time, forces over time, phase portrait, force loop."""
    from presliding.plotting import plot_forces, plot_motion, save_figure

    fig, axes = new_figure(2, 2, size=(11.0, 7.6))
    plot_motion(result, kind="time", ax=axes[0, 0])
    axes[0, 0].set_title("velocity")
    plot_forces(result, ax=axes[0, 1])
    axes[0, 1].set_title("forces")
    plot_motion(result, kind="phase", ax=axes[1, 0])
    axes[1, 0].set_title("phase portrait")
    plot_motion(result, kind="loop", ax=axes[1, 1])
    axes[1, 1].set_title("friction force against position")
    for ax in (axes[1, 0], axes[1, 1]):  # positions are often small: 1.5e-3, not 0.0015
        ax.ticklabel_format(axis="x", style="sci", scilimits=(-2, 3), useMathText=True)
    fig.suptitle(title)
    save_figure(fig, path)


__all__ = ["HEADER", "output_paths", "read_applied_force", "run", "save_motion_figure"]
