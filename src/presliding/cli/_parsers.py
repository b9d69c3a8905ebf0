"""The options of the `demo`, `simulate`, `analyze`, `sweep` and `precompile` sub-commands
(`presliding.cli.commands` builds the parser and dispatches; the other commands keep their
options in their own modules)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from presliding.cli.common import checked

Parser = argparse.ArgumentParser

__all__ = ["add_analyze", "add_demo", "add_precompile", "add_simulate", "add_sweep"]


def add_demo(
    sub: Any, common: argparse.ArgumentParser, writes: argparse.ArgumentParser
) -> argparse.ArgumentParser:
    """The `demo` sub-command's options."""
    fmt = argparse.RawDescriptionHelpFormatter
    demo = sub.add_parser(
        "demo",
        help="run the built-in main job and write its figures and report",
        description="The paper's Figure 3 loops, a free stop with reversals (Figures 4, 5) "
        "against the stop analysis (eqs. 15-16), a continuous density and an "
        "identification round trip; PNGs, report.md and report.html in the output folder.",
        epilog="example:\n  presliding demo -o out/",
        formatter_class=fmt,
        parents=[common, writes],
    )
    demo.add_argument(
        "-o",
        "--output",
        type=Path,
        default=Path("presliding-demo"),
        help="output folder (default: ./presliding-demo)",
    )
    return demo


def add_simulate(
    sub: Any, common: argparse.ArgumentParser, writes: argparse.ArgumentParser
) -> argparse.ArgumentParser:
    """The `simulate` sub-command's options."""
    fmt = argparse.RawDescriptionHelpFormatter
    simulate = sub.add_parser(
        "simulate",
        help="simulate the motion of a model file (CSV and PNG)",
        description="Simulate m·ÿ + c1·Sign(ẏ) + F_el(y) = u (eq. 17) for the [friction] and "
        "[motion] tables of a model file, with exact stiction; a [measurement] force_offset "
        "F_0 is subtracted from the applied force (measured u = m·ÿ + F + F_0). Writes the "
        "samples as CSV (time, position, velocity, acceleration, friction_force, "
        "elastic_force, applied_force; units in the header) and a figure. The file needs "
        "motion.mass (or --mass) and something that starts the motion (an initial velocity "
        "or an applied force); exit status 1 when a motion under a constant force is still "
        "moving at t_end.",
        epilog="examples:\n  presliding simulate model.toml -o run/\n"
        "  presliding simulate model.toml --applied-force u.csv -o run.csv",
        formatter_class=fmt,
        parents=[common, writes],
    )
    simulate.add_argument("model", type=Path, help="model file (.toml, or .json)")
    simulate.add_argument(
        "--applied-force",
        type=Path,
        metavar="CSV",
        help="applied force u(t): a CSV file with columns time,value [s, N] (replaces "
        "motion.applied_force)",
    )
    simulate.add_argument(
        "--hold-last",
        action="store_true",
        help="hold the last applied-force sample when the CSV ends before t_end (else an error)",
    )
    simulate.add_argument(
        "--hold",
        choices=("zoh", "linear"),
        default="zoh",
        help="how the applied-force samples are held: zoh (piecewise constant, default; exact "
        "event method) or linear (implicit method)",
    )
    simulate.add_argument(
        "--method",
        choices=("auto", "event", "implicit"),
        default="auto",
        help="simulation method (default auto: event whenever it applies)",
    )
    simulate.add_argument(
        "--step",
        type=checked("--step"),
        default=None,
        metavar="SECONDS",
        help="largest step of the implicit method (default: chosen by step doubling for --rtol)",
    )
    simulate.add_argument(
        "--rtol",
        type=checked("--rtol"),
        default=None,
        metavar="R",
        help="accuracy target of the implicit method: the step is halved until the estimated "
        "position error is at most R times the largest displacement (default 1e-3 unless "
        "--step is given); the estimate is printed",
    )
    simulate.add_argument(
        "--mass",
        type=checked("--mass"),
        default=None,
        metavar="KG",
        help="the moving mass m [kg] (replaces motion.mass; needed when the file has none, "
        "e.g. a fitted model)",
    )
    simulate.add_argument(
        "--initial-velocity",
        type=float,
        default=None,
        metavar="M_PER_S",
        help="initial velocity [m/s] (replaces motion.initial_velocity)",
    )
    simulate.add_argument(
        "-o",
        "--output",
        type=Path,
        default=Path("presliding-simulate"),
        help="output folder (simulation.csv and simulation.png in it; default: "
        "./presliding-simulate), or a .csv path (the figure next to it with the suffix .png)",
    )
    return simulate


def add_analyze(
    sub: Any, common: argparse.ArgumentParser, writes: argparse.ArgumentParser
) -> argparse.ArgumentParser:
    """The `analyze` sub-command's options."""
    fmt = argparse.RawDescriptionHelpFormatter
    analyze = sub.add_parser(
        "analyze",
        help="stop analysis of a model file (F_c, F_m, eq. 7, y_e, stop test, reversals)",
        description="Key quantities of a model file: Coulomb level F_c (eq. 9), maximal "
        "elastic force F_m, stiffness after a reversal (eq. 7), the second turning point y_e "
        "(eq. 15), the stop test (eq. 16) and the number of reversals of a free motion from "
        "a saturated start.",
        epilog="examples:\n  presliding analyze model.toml\n  presliding analyze model.toml "
        "--json > analysis.json",
        formatter_class=fmt,
        parents=[common],
    )
    analyze.add_argument("model", type=Path, help="model file (.toml, or .json)")
    analyze.add_argument("--json", action="store_true", help="print JSON for machines")
    return analyze


def add_sweep(
    sub: Any, common: argparse.ArgumentParser, writes: argparse.ArgumentParser
) -> argparse.ArgumentParser:
    """The `sweep` sub-command's options."""
    fmt = argparse.RawDescriptionHelpFormatter
    from presliding.cli.sweeping.sweep_spec import SCHEMA

    sweep = sub.add_parser(
        "sweep",
        help="a quantity of the free motion over a grid of 1 or 2 parameters (CSV, map, report)",
        description="Evaluate the number of reversals, the rest position or the stop time of "
        "the free motion m·ÿ + c1·Sign(ẏ) + F_el(y) = u (eqs. 12, 17) on a grid over one or "
        "two parameters (c1/F_m, c1, v0, m), with the exact batch simulation or the "
        "turning-point analysis (eqs. 13-16). Runs on local worker processes, or on a Dask "
        'cluster with --scheduler (pip install "presliding[dask]"; the workers need presliding '
        "installed). Writes sweep.csv (one row per point, units in the header), sweep.png "
        "and report.md/report.html.",
        epilog="examples:\n  presliding sweep spec.toml -o map/\n"
        "  presliding sweep spec.toml --workers 1\n"
        "  presliding sweep spec.toml --scheduler tcp://10.0.0.5:8786 -o map/\n\n"
        "specification file (TOML, or JSON with the same tables; units in brackets):\n" + SCHEMA,
        formatter_class=fmt,
        parents=[common, writes],
    )
    sweep.add_argument("spec", type=Path, help="sweep specification (.toml, or .json)")
    sweep.add_argument(
        "-o",
        "--output",
        type=Path,
        default=Path("presliding-sweep"),
        help="output folder (default: ./presliding-sweep)",
    )
    sweep.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        default=None,
        help="run on the Dask cluster of this scheduler address (e.g. tcp://host:8786)",
    )
    sweep.add_argument(
        "--workers",
        type=checked("--workers", integer=True, minimum=1),
        default=None,
        metavar="N",
        help="local worker processes; 1 runs in this process (default: 1 for method "
        "simulate, whose batch kernel uses every core anyway, and for analysis grids under "
        "20000 points; else the machine's cores)",
    )
    retries = "with --scheduler: re-run a chunk that raised up to N times (default: 2)"
    sweep.add_argument(
        "--retries",
        type=checked("--retries", integer=True),
        default=None,
        metavar="N",
        help=retries,
    )
    return sweep


def add_precompile(
    sub: Any, common: argparse.ArgumentParser, writes: argparse.ArgumentParser
) -> argparse.ArgumentParser:
    """The `precompile` sub-command's options."""
    fmt = argparse.RawDescriptionHelpFormatter
    precompile = sub.add_parser(
        "precompile",
        help="compile the numba kernels into the cache (for CI images and containers)",
        description="Compile the numba kernels that the commands and a first call can use "
        "(by running the demo's computations and each further route once on a small case: "
        "viscous motions, the implicit stepper, the pooled and quasi-static fits, closed "
        "loops and both network paths; writing nothing but the cache) so that a later first "
        "run does not compile. Run it when building a CI image or a container, with the same "
        "NUMBA_CACHE_DIR (if any) as the runs that follow; it prints where the kernels are "
        "cached.",
        epilog="example:\n  NUMBA_CACHE_DIR=/opt/numba-cache presliding precompile",
        formatter_class=fmt,
        parents=[common],
    )
    return precompile
