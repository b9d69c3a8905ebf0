"""``presliding fit``: identification from a CSV file (section 4) to a model file and report."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

from presliding._progress import progress
from presliding.cli.common import (
    Table,
    UserError,
    check_folder,
    check_options,
    check_outputs,
    new_figure,
    read_table,
    record_outputs,
    tidy_fit_axes,
)

SIGNALS = ("time", "position", "velocity", "acceleration", "applied_force", "friction_force")
#: Column names tried for each signal (after `column_key` normalisation).
ALIASES = {
    "time": ("time", "t"),
    "position": ("position", "displacement", "y", "x"),
    "velocity": ("velocity", "v", "speed"),
    "acceleration": ("acceleration", "a"),
    "applied_force": ("applied_force", "u", "force_applied", "input"),
    "friction_force": ("friction_force", "friction", "force", "f"),
}
#: Signals each kind needs (one of a tuple), and those it uses when present.
NEEDS = {
    "presliding": (("position",), ("friction_force",)),
    "motion": (("time",), ("position",), ("applied_force",)),
    "response": (("time",), ("velocity", "position")),
}
OPTIONAL = {
    "presliding": (),
    "motion": ("velocity", "acceleration"),
    "response": ("applied_force",),
}
DEFAULT_ELEMENTS = {"presliding": 3, "motion": 0, "response": 4}


def read_signals(args: argparse.Namespace) -> dict[str, np.ndarray]:
    """The signals the fit kind needs, by name, scaled; clear errors for what is missing."""
    columns = check_options(args.columns, "--columns", SIGNALS)
    scales = check_options(args.scale, "--scale", SIGNALS)
    factors = {}
    for key, text in scales.items():
        try:
            factors[key] = float(text)
        except ValueError:
            raise UserError(f"--scale {key}={text}: the factor must be a number.") from None
        if not np.isfinite(factors[key]) or factors[key] == 0.0:
            raise UserError(f"--scale {key}={text}: the factor must be finite and nonzero.")
    table = read_table(args.data, "data file", example=",".join(_example(args.kind)))
    out: dict[str, np.ndarray] = {}
    for group in NEEDS[args.kind]:
        for signal in group:
            arr = _find(table, signal, columns)
            if arr is not None:
                out[signal] = arr
        if not any(s in out for s in group):
            names = " or ".join(f"`{s}`" for s in group)
            raise UserError(
                f"{args.data}: no column for {names} (needed by --kind {args.kind}); the "
                f"columns are {', '.join(repr(n) for n in table.names)}; name it with "
                f"--columns {group[0]}=COLUMN."
            )
    for signal in OPTIONAL[args.kind]:
        arr = _find(table, signal, columns)
        if arr is not None:
            out[signal] = arr
    return {k: v * factors.get(k, 1.0) for k, v in out.items()}


def _example(kind: str) -> list[str]:
    return [group[0] for group in NEEDS[kind]]


def _find(table: Table, signal: str, columns: dict[str, str]) -> np.ndarray | None:
    if signal in columns:
        i = table.find((columns[signal],))
        if i is None:
            raise UserError(
                f"{table.path}: no column {columns[signal]!r} (given by --columns "
                f"{signal}=...); the columns are {', '.join(repr(n) for n in table.names)}."
            )
        return table.columns[i]
    i = table.find(ALIASES[signal])
    return None if i is None else table.columns[i]


def fit(args: argparse.Namespace, sig: dict[str, np.ndarray]) -> Any:
    """Run the fit of `args.kind` on the signals; returns the FitResult."""
    n = DEFAULT_ELEMENTS[args.kind] if args.elements is None else args.elements
    if n < 0:
        raise UserError(f"--elements must be 0 or more; got {n}.")
    if args.kind == "presliding":
        from presliding.identification.fit_presliding import fit_presliding

        return fit_presliding(
            sig["position"], sig["friction_force"], n, offset=args.offset, search=args.search,
            seed=args.seed,
        )  # fmt: skip
    from presliding.identification.measurement import Measurement

    meas = Measurement(**sig)
    fixed = None if args.mass is None else {"mass": args.mass}
    if args.kind == "motion":
        from presliding.identification.fit_motion import fit_motion

        if meas.velocity is None or meas.acceleration is None:
            cutoff = args.cutoff
            if cutoff is None:
                cutoff = 0.1 / meas.sampling_step
            meas = meas.resample(meas.sampling_step) if not meas.is_uniform else meas
            meas = meas.differentiate(cutoff)
        return fit_motion(meas, n, viscous=args.viscous, offset=args.offset, fixed=fixed)
    from presliding.identification.fit_response import fit_response

    signal = "velocity" if meas.velocity is not None else "position"
    return fit_response(meas, n, mass=args.mass, signal=signal)


def _motion_settings(args: argparse.Namespace, sig: dict[str, np.ndarray], result: Any) -> Any:
    """[motion] table reproducing the fitted response (response and motion kinds)."""
    from presliding.model_io import MotionSettings

    mass = result.parameters.get("mass")
    if mass is None or args.kind != "response":
        return None if mass is None else MotionSettings(mass=float(mass))
    t = sig["time"]
    v = sig["velocity"] if "velocity" in sig else np.gradient(sig["position"], t)
    u = sig.get("applied_force")
    return MotionSettings(
        mass=float(mass),
        initial_velocity=float(result.parameters.get("initial_velocity", v[0])),
        initial_position=float(
            result.parameters.get(
                "initial_position", sig["position"][0] if "position" in sig else 0.0
            )
        ),
        initial_state="saturated",
        applied_force=float(u[0]) if u is not None and np.all(u == u[0]) else 0.0,
        t_end=float(t[-1] - t[0]),
        samples=int(t.shape[0]),
    )


def run(args: argparse.Namespace) -> int:
    """Read, fit, write model.toml, fit.png and the report; print the fit report."""
    from presliding.cli.report import Section, write_report
    from presliding.model_io import save_model

    folder = check_folder(args.output)
    paths = {
        "model": folder / "model.toml",
        "figure": folder / "fit.png",
        "md": folder / "report.md",
        "html": folder / "report.html",
    }
    check_outputs(paths.values(), (args.data,), overwrite=args.overwrite)
    with progress(3, f"fit ({args.kind})", quiet=args.quiet, unit="stage") as bar:
        sig = read_signals(args)
        bar.update()
        try:
            result = fit(args, sig)
        except (TypeError, ValueError) as exc:
            raise UserError(f"{args.data}: cannot fit: {exc}") from None
        bar.update()
        record_outputs(paths.values())
        _save_fit_figure(args, sig, result, paths["figure"])
        written = [paths["figure"]]
        if result.model is not None:
            save_model(
                paths["model"], result.model, _motion_settings(args, sig, result), overwrite=True
            )
            written.insert(0, paths["model"])
        else:  # no model from this fit: an earlier run's model.toml would be taken for it
            paths["model"].unlink(missing_ok=True)
        text = (
            f"Fit of {args.data.name} (--kind {args.kind}): {result.status}. "
            f"NRMSE {100 * result.nrmse:.3g} %."
        )
        written += write_report(
            folder,
            f"presliding fit: {args.data.name}",
            [Section("Result", text, (paths["figure"],), code=result.report())],
        )
        bar.update()
    if not args.quiet:
        print(result.report())
        for p in written:
            print(f"wrote {p}")
    return 0 if result.success else 1


#: Units of the fitted signal by kind (the signal of `FitResult.signal_label`).
UNITS = {"presliding": "N", "motion": "N", "response": "m/s"}


def _save_fit_figure(args: argparse.Namespace, sig: dict, result: Any, path: Path) -> None:
    from presliding.plotting import plot_fit, plot_loop_fit, save_figure

    unit = UNITS[args.kind]
    if args.kind == "response" and result.signal_label == "position":
        unit = "m"
    head = f"{args.data.name}: {result.kind} fit, {result.status}, NRMSE {100 * result.nrmse:.2f} %"
    if args.kind == "presliding":
        fig, axes = new_figure(2, 1, size=(13.2, 4.8))
        ax = plot_loop_fit(result.abscissa, result.measured, result.fitted, ax=axes[0, 0])
        ax.set_title("friction force against displacement")
        ax = plot_fit(
            np.arange(result.measured.shape[0]),
            result.measured,
            result.fitted,
            ax=axes[0, 1],
            xlabel="sample",
            title="measured and fitted force",
        )
        fig.suptitle(head)
    else:
        fig, axes = new_figure(1, 1, size=(8.0, 5.2))
        ax = result.plot(ax=axes[0, 0])
        ax.set_title(head)
    tidy_fit_axes(fig, ax, result.signal_label, unit)
    save_figure(fig, path)


__all__ = ["ALIASES", "fit", "read_signals", "run"]
