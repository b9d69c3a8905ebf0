"""``presliding sweep``: a quantity of the free motion over a grid of parameters.

Reads a specification (schema in `presliding.cli.sweeping.sweep_spec`), evaluates the
quantity on every grid point with `presliding.sweep.sweep` (local worker
processes, or a Dask cluster with ``--scheduler``) and writes ``sweep.csv``,
``sweep.png`` and ``report.md``/``report.html`` to the output folder.
"""

from __future__ import annotations

import argparse
import functools
import math
import os
import sys
from pathlib import Path
from typing import Any

import numpy as np

from presliding.cli.common import (
    UserError,
    check_folder,
    check_outputs,
    check_readable,
    new_figure,
    record_outputs,
)
from presliding.cli.sweeping.sweep_spec import AXES, QUANTITIES, SweepSpec, load_spec
from presliding.friction._parts import elements
from presliding.sweep._tasks import evaluate_chunk

#: Files written into the output folder.
OUTPUTS = ("sweep.csv", "sweep.png", "report.md", "report.html")
#: Below this many points an "analysis" sweep runs in this process: starting worker
#: processes (an import of presliding and its compiled kernels each, about 2 s) costs more.
PROCESS_THRESHOLD = 20_000


def default_workers(spec: SweepSpec) -> int:
    """Local workers when --workers is not given.

    "simulate" runs in this process: its batch kernel already spreads a chunk over
    every core, and worker processes would only add their start-up. "analysis"
    (Python per point, about 0.3 ms) uses one process per core on large grids.
    """
    if spec.method == "simulate" or spec.n_points < PROCESS_THRESHOLD:
        return 1
    return os.cpu_count() or 1


def chunk_size(spec: SweepSpec, workers: int) -> int:
    """The specification's chunk size, else about 64 chunks (at least 4 per worker) of at
    least 500 points: a progress bar that moves, with little overhead per call."""
    if spec.chunk_size is not None:
        return spec.chunk_size
    return max(500, math.ceil(spec.n_points / max(64, 4 * workers)))


def check_scheduler(address: str) -> None:
    """A one-line error for a missing Dask or a malformed address, before any connection."""
    from presliding.sweep.runner import check_address

    try:
        check_address(address)
    except (ImportError, ValueError) as exc:
        raise UserError(f"--scheduler {address}: {exc}") from None


def run(args: argparse.Namespace) -> int:
    """Load the specification, run the sweep, write CSV, PNG and report; print a summary."""
    from presliding.sweep.runner import sweep

    check_readable(args.spec, "sweep specification")
    spec = load_spec(args.spec)
    if args.workers is not None and args.workers < 1:
        raise UserError(f"--workers must be a whole number >= 1; got {args.workers}.")
    if args.retries is not None and args.retries < 0:
        raise UserError(f"--retries must be a whole number >= 0; got {args.retries}.")
    if args.retries is not None and args.scheduler is None:
        raise UserError(
            f"--retries {args.retries}: re-runs the chunks that failed on a Dask "
            "cluster (--scheduler); a local sweep never retries: drop it."
        )
    if args.workers is not None and args.scheduler is not None:
        raise UserError(
            "--workers sets local worker processes; with --scheduler the cluster's workers run "
            "the sweep: give one of the two."
        )
    if args.scheduler is not None:
        check_scheduler(args.scheduler)
    folder = check_folder(args.output)
    paths = [folder / name for name in OUTPUTS]
    check_outputs(paths, (args.spec,), overwrite=args.overwrite)
    workers = args.workers if args.workers is not None else default_workers(spec)
    in_process = args.scheduler is None and workers == 1
    fn = functools.partial(evaluate_chunk, spec.task(single_thread=not in_process))
    try:
        result = sweep(
            fn,
            spec.grid,
            args.scheduler,
            chunk_size=chunk_size(spec, workers),
            n_workers=None if args.scheduler is not None else workers,
            progress=not args.quiet,
            retries=(2 if args.retries is None else args.retries) if args.scheduler else 0,
        )
    except (OSError, ValueError, RuntimeError) as exc:
        if args.scheduler is None or args.debug:
            raise
        text = " ".join(str(exc).split())
        raise UserError(
            f"--scheduler {args.scheduler}: cannot run the sweep there ({text}); is the "
            "scheduler running and reachable?"
        ) from None
    if not result.success:
        print(f"presliding sweep: failed: {result.message}", file=sys.stderr)
        return 1
    value, stopped = result.values[..., 0], result.values[..., 1] == 1.0
    csv_path, png_path = paths[0], paths[1]
    record_outputs(paths)
    _write_csv(csv_path, spec, value, stopped, quiet=args.quiet)
    save_sweep_figure(spec, value, stopped, png_path)
    summary = _summary(spec, result, value, stopped)
    written = [csv_path, png_path, *_write_report(folder, spec, summary, value, stopped, png_path)]
    if not args.quiet:
        print(summary)
        for p in written:
            print(f"wrote {p}")
    n_moving = int(np.count_nonzero(~stopped))
    if n_moving:
        hint = (
            f"still moving at motion.t_end = {spec.motion.t_end:g} s: raise motion.t_end"
            if spec.method == "simulate"
            else "c1 = 0 never stops, or more than 1000 reversals"
        )
        print(
            f"presliding sweep: {n_moving} of {stopped.size} points did not come to rest "
            f"({hint}); they hold nan in {csv_path.name}.",
            file=sys.stderr,
        )
        return 1
    return 0


def _summary(spec: SweepSpec, result: Any, value: Any, stopped: Any) -> str:
    """The run (grid, backend, time) and the range of the quantity."""
    lines = [ln for ln in result.report().splitlines() if not ln.startswith("  values in")]
    name, unit = spec.quantity, QUANTITIES[spec.quantity][0]
    ok = value[stopped]
    if ok.size < value.size:  # the run is not "ok" when points hold no value (a gap or blank map)
        state = "failed" if ok.size == 0 else "partial"
        lines[0] = f"sweep: {state} ({value.size - ok.size} of {value.size} points not at rest)"
    if ok.size:
        lines.append(f"  {name} [{unit}] in [{ok.min():.6g}, {ok.max():.6g}]")
    if ok.size < value.size:
        lines.append(f"  not at rest: {value.size - ok.size} of {value.size} points")
    return "\n".join(lines)


def _quantity_label(spec: SweepSpec) -> str:
    return f"{spec.quantity} [{QUANTITIES[spec.quantity][0]}]"


def _write_csv(path: Path, spec: SweepSpec, value: Any, stopped: Any, *, quiet: bool) -> None:
    """One row per grid point, the first axis varying slowest; units in the header."""
    from presliding.cli.common import write_csv

    mesh = np.meshgrid(*(a.values for a in spec.axes), indexing="ij")
    header = [a.label for a in spec.axes] + [_quantity_label(spec), "stopped [0/1]"]
    columns = [m.ravel() for m in mesh] + [value.ravel(), stopped.ravel().astype(float)]
    write_csv(path, header, columns, quiet=quiet)


def save_sweep_figure(spec: SweepSpec, value: Any, stopped: Any, path: Path) -> None:
    """A colour map (two axes; discrete colours for reversal counts) or a curve (one axis)."""
    from presliding.plotting import plot_sweep, save_figure

    fig, axes = new_figure(size=(7.4, 5.4))
    ax = axes[0, 0]
    names = [_plot_label(*AXES[a.name][::-1]) for a in spec.axes]
    label = _plot_label(*QUANTITIES[spec.quantity][::-1])
    counts = spec.quantity == "reversals"
    if len(spec.axes) == 2:
        plot_sweep([a.values for a in spec.axes], value, names, ax=ax, label=label)
        mesh = ax.collections[0]
        cmap = mesh.get_cmap().with_extremes(bad="0.82")
        if counts and np.any(stopped):
            top = int(np.nanmax(value))
            cmap = cmap.resampled(top + 1).with_extremes(bad="0.82")
            mesh.set_clim(-0.5, top + 0.5)
            step = max(1, (top + 1) // 12)
            mesh.colorbar.set_ticks(range(0, top + 1, step))
        mesh.set_cmap(cmap)
    else:
        plot_sweep([spec.axes[0].values], value, names, ax=ax, label=label)
        line = ax.get_lines()[0]
        line.set_marker("o" if spec.axes[0].values.size <= 60 else "")
        line.set_markersize(3.5)
        if counts:
            line.set_drawstyle("steps-mid")
            ax.yaxis.get_major_locator().set_params(integer=True)
    for axis, set_scale in zip(spec.axes, (ax.set_xscale, ax.set_yscale), strict=False):
        if axis.scale == "log":
            set_scale("log")
    first = spec.axes[0]
    if first.name == "coulomb_ratio" and first.values.min() < 1.0 < first.values.max():
        ax.axvline(1.0, color="white" if len(spec.axes) == 2 else "0.4", lw=1.0, ls="--")
        ax.annotate("c1 = F_m", (1.0, 1.0), xycoords=("data", "axes fraction"),
                    xytext=(4, -14), textcoords="offset points", fontsize=9,
                    color="white" if len(spec.axes) == 2 else "0.3")  # fmt: skip
    n_moving = int(np.count_nonzero(~stopped))
    moving = f"; grey: {n_moving} points not at rest" if n_moving else ""
    fig.suptitle(
        f"{spec.path.name}: {QUANTITIES[spec.quantity][1]} ({spec.method}, "
        f"{spec.motion.initial_state} start){moving}",
        fontsize=11,
    )
    save_figure(fig, path)


def _plot_label(text: str, unit: str) -> str:
    return text if unit == "-" else f"{text} [{unit}]"


def _summary_table(spec: SweepSpec, value: Any, stopped: Any) -> list[list[str]]:
    if spec.quantity == "reversals":
        counts = np.bincount(value[stopped].astype(np.int64).ravel())
        rows = [["reversals", "points"]]
        rows += [[str(i), str(c)] for i, c in enumerate(counts) if c]
    else:
        unit = QUANTITIES[spec.quantity][0]
        ok = value[stopped]
        rows = [["statistic", f"{spec.quantity} [{unit}]"]]
        if ok.size:
            rows += [[k, f"{f(ok):.6g}"] for k, f in (("min", np.min), ("median", np.median),
                                                       ("max", np.max))]  # fmt: skip
    if np.any(~stopped):
        rows.append(["not at rest", str(int(np.count_nonzero(~stopped)))])
    return rows


def _describe(spec: SweepSpec) -> str:
    """The base model and motion, leaving out what the axes replace."""
    swept = {a.name for a in spec.axes}
    model, mo = spec.model, spec.motion
    parts = []
    if not swept & {"coulomb", "coulomb_ratio"}:
        parts.append(f"c1 = {model.coulomb:.6g} N")
    if model.is_discrete:
        stiffness, _, breakaway = elements(model)
        k = ", ".join(f"{v:.6g}" for v in stiffness)
        c = ", ".join(f"{v:.6g}" for v in breakaway)
        parts.append(f"{model.n_elements} elements with k = [{k}] N/m, c = [{c}] N")
    else:
        parts.append(f"the density {model.density!r}")
    parts.append(f"F_m = {model.max_elastic_force:.6g} N")
    if model.viscous:
        parts.append(f"σ = {model.viscous:.6g} N s/m")
    if "mass" not in swept:
        parts.append(f"m = {mo.mass:g} kg")
    if "initial_velocity" not in swept:
        parts.append(f"v0 = {mo.initial_velocity:g} m/s")
    parts += [f"y0 = {mo.initial_position:g} m", f"{mo.initial_state} start"]
    parts.append(f"u = {mo.applied_force:g} N")
    return ", ".join(parts)


def _write_report(
    folder: Path, spec: SweepSpec, summary: str, value: Any, stopped: Any, png_path: Path
) -> list[Path]:
    from presliding.cli.report import Section, write_report

    axes = "; ".join(
        f"{AXES[a.name][1]} ({a.name}): {a.values.size} values from {a.values[0]:.6g} to "
        f"{a.values[-1]:.6g}"
        + ("" if a.unit == "-" else f" {a.unit}")
        + (" (log scale)" if a.scale == "log" else "")
        for a in spec.axes
    )
    method = (
        "the exact event-driven batch simulation (simulate_batch) up to "
        f"t_end = {spec.motion.t_end:g} s"
        if spec.method == "simulate"
        else "the turning points of the work-energy balance (analysis.turning_points, eqs. 13-16)"
    )
    text = (
        f"{QUANTITIES[spec.quantity][1].capitalize()} [{QUANTITIES[spec.quantity][0]}] of the "
        f"free motion m·ÿ + c1·Sign(ẏ) + F_el(y) = u (eqs. 12, 17) on a grid of "
        f"{spec.n_points} points, by {method}.\n\n"
        f"Axes: {axes}.\n\nFixed: {_describe(spec)}.\n\n"
        f"Values per point: {OUTPUTS[0]} (one row per point, units in the header)."
    )
    table = _summary_table(spec, value, stopped)
    section = Section("Sweep", text, (png_path,), code=summary, table=table)
    return write_report(folder, f"presliding sweep: {spec.path.name}", [section])


__all__ = [
    "OUTPUTS",
    "check_scheduler",
    "chunk_size",
    "default_workers",
    "run",
    "save_sweep_figure",
]
