"""The ``presliding`` command line (also ``python -m presliding``).

Subcommands: ``demo`` (the built-in main job), ``simulate`` (a model file to a
motion CSV and figure), ``analyze`` (stop analysis of a model file, eqs. 7, 9,
14–16), ``fit`` (identification from a CSV file, section 4), ``sweep`` (a
quantity of the free motion over a parameter grid, locally or on Dask) and
``loop`` (a PID loop with PI friction: exact response, predicted limit cycles),
``network`` (a structure with many friction contacts, stick/slip per contact),
``predict`` (a model file predicting records it never saw), ``example-data``
(small records to try ``fit`` and ``predict`` on) and ``ring-down`` (a measured free
decay: ω(A), ζ(A) and a fitted joint model).

User errors (a bad file, a missing column, a bad parameter) print one line on
stderr naming the file or field and the fix, and exit with code 2; ``--debug``
shows the traceback instead. Outputs are written atomically and never onto an
input file.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from typing import NoReturn

from presliding._version import __version__
from presliding.cli import _parsers
from presliding.cli.common import UserError

__all__ = ["UserError", "main"]

EXAMPLES = """\
examples:
  presliding demo                          # the main job, written to ./presliding-demo
  presliding demo -o out/                  # the same, into out/
  presliding simulate model.toml -o run/   # motion of the model file: run/simulation.csv, .png
  presliding simulate model.toml --applied-force u.csv --hold linear -o run.csv
  presliding analyze model.toml            # F_c, F_m, eq. 7 stiffness, y_e, stop test
  presliding analyze model.toml --json
  presliding fit loops.csv --kind presliding --elements 4 -o fit/
  presliding fit run.csv --kind response --columns velocity='v [m/s]' -o fit/
  presliding fit DATA.mat --kind motion --columns time=t position=qm applied_force=vir \\
      --scale applied_force=gtau --viscous --offset --window 0:20 -o fit/
  presliding sweep spec.toml -o map/       # e.g. reversal counts over c1/F_m and v0
  presliding sweep spec.toml --scheduler tcp://10.0.0.5:8786   # on a Dask cluster
  presliding loop spec.toml -o loop/       # PID loop: exact response, predicted limit cycles
  presliding precompile                    # fill numba's cache (CI images, containers)
  presliding network spec.toml -o net/     # many masses and contacts: stick/slip per contact
  presliding example-data -o data/         # small records to try fit and predict on
  presliding ring-down decay.csv -o rd/    # a free decay: ω(A), ζ(A), a fitted joint model

model files (TOML, or JSON with the same tables; units in brackets):
  [friction]
  coulomb = 0.3                    # c1 [N], the Coulomb element (eq. 8)
  stiffness = [2e4, 5e3, 1.5e3]    # k_j [N/m]
  breakaway = [0.2, 0.2, 0.3]      # c_j [N]  (or threshold = [...] r_j [m], eq. 6)
  viscous = 0.0                    # σ [N s/m], optional viscous term σ·ẏ (default 0)
  [motion]                         # optional
  mass = 1.0                       # m [kg]
  initial_velocity = 0.05          # [m/s]
  initial_state = "saturated"      # or "relaxed"
  t_end = 0.2                      # [s]
  samples = 2001                   # at most 10,000,000
  [measurement]                    # optional: measured force = model force + F_0
  force_offset = -3.16             # F_0 [N]; simulate applies u - F_0
  [data]                           # optional: how presliding fit read the records
  columns = { time = "Time [s]", position = "Position [mm]", applied_force = "Force [N]" }
  (and units, scale, sample_rate, decimal, header, axis, segments: predict reads alike)
  A continuous density instead of elements (section 3, eq. 10):
  [friction.density]
  kind = "uniform"                 # height [N/m^2], max_threshold [m]
  (or kind = "exponential": height, length, max_threshold; or "piecewise_constant":
  breaks [m], heights [N/m^2])

exit status: 0 success, 1 a computation that did not succeed (a fit that did not
converge or is poor; a motion under a constant force, or a sweep point, still moving at
t_end; see its message), 2 a user error (bad file, column, unit or parameter), 130
interrupted.
"""


class _Parser(argparse.ArgumentParser):
    """A value refused by the shared validation (`common.checked`) is one line, no usage."""

    def error(self, message: str) -> NoReturn:
        if message.startswith("argument ") and "`" in message:
            self.exit(2, f"{self.prog}: error: {message}\n")
        super().error(message)


def _build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="presliding",
        description="Dry friction with presliding hysteresis (Prandtl–Ishlinskii operators): "
        "simulation with exact stiction, stop analysis and identification.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"presliding {__version__}")
    parser.add_argument("--debug", action="store_true", help="show tracebacks for errors")
    parser.add_argument(
        "--quiet", action="store_true", help="print nothing but errors (no progress bars)"
    )
    # The same two options after the subcommand name (`presliding demo --quiet`);
    # SUPPRESS keeps a value given before it.
    common = _Parser(add_help=False)
    common.add_argument(
        "--debug", action="store_true", default=argparse.SUPPRESS, help="show tracebacks for errors"
    )
    common.add_argument(
        "--quiet",
        action="store_true",
        default=argparse.SUPPRESS,
        help="print nothing but errors (no progress bars)",
    )
    writes = _Parser(add_help=False)
    writes.add_argument(
        "--overwrite",
        action="store_true",
        help="replace existing output files that no earlier presliding run wrote (files "
        "presliding wrote are replaced anyway; input files never are)",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    fmt = argparse.RawDescriptionHelpFormatter
    _parsers.add_demo(sub, common, writes).set_defaults(handler=_cmd_demo)
    _parsers.add_simulate(sub, common, writes).set_defaults(handler=_cmd_simulate)
    _parsers.add_analyze(sub, common, writes).set_defaults(handler=_cmd_analyze)
    from presliding.cli.fitting.fit_options import add_fit_parser

    add_fit_parser(sub, [common, writes], fmt, _cmd_fit)

    _parsers.add_sweep(sub, common, writes).set_defaults(handler=_cmd_sweep)
    _parsers.add_precompile(sub, common, writes).set_defaults(handler=_cmd_precompile)

    from presliding.cli.simulation.loop import add_parser as add_loop_parser

    add_loop_parser(sub, [common, writes]).set_defaults(handler=_cmd_loop)

    from presliding.cli.simulation.network import add_parser as add_network_parser

    add_network_parser(sub, [common, writes]).set_defaults(handler=_cmd_network)

    from presliding.cli.fitting.predict import add_parser as add_predict_parser

    add_predict_parser(sub, [common, writes]).set_defaults(handler=_cmd_predict)

    from presliding.cli.example_data import add_parser as add_example_parser

    add_example_parser(sub, [common, writes]).set_defaults(handler=_cmd_example_data)
    from presliding.cli.fitting.ring_down import add_parser as add_ring_down_parser

    add_ring_down_parser(sub, [common, writes]).set_defaults(handler=_cmd_ring_down)
    return parser


def _cmd_ring_down(args: argparse.Namespace) -> int:
    from presliding.cli.fitting.ring_down import run

    return run(args)


def _cmd_example_data(args: argparse.Namespace) -> int:
    from presliding.cli.example_data import run

    return run(args)


def _cmd_predict(args: argparse.Namespace) -> int:
    from presliding.cli.fitting.predict import run

    return run(args)


def _cmd_demo(args: argparse.Namespace) -> int:
    from presliding.cli.common import check_folder, check_outputs, record_outputs
    from presliding.cli.demo.command import DEMO_OUTPUTS, run_demo

    out = check_folder(args.output)
    outputs = [out / name for name in DEMO_OUTPUTS]
    check_outputs(outputs, (), overwrite=args.overwrite)
    record_outputs(outputs)
    paths = run_demo(out, quiet=args.quiet)
    if not args.quiet:
        print(f"presliding demo: wrote {len(paths)} files to {out.resolve()}")
        for p in paths:
            print(f"  {p.name}")
        print(f"open {(out / 'report.html').resolve()} to see them together.")
    return 0


def _cmd_precompile(args: argparse.Namespace) -> int:
    from presliding.cli.precompile import run

    return run(args)


def _cmd_simulate(args: argparse.Namespace) -> int:
    from presliding.cli.simulation.simulate import run

    return run(args)


def _cmd_analyze(args: argparse.Namespace) -> int:
    from presliding.cli.simulation.analyze import run

    return run(args)


def _cmd_fit(args: argparse.Namespace) -> int:
    from presliding.cli.command_line import rerun_line
    from presliding.cli.fitting.fit_options import check_fit_options
    from presliding.cli.fitting.records import check_sources

    # the command as given (model.toml's "identified by"), before anything is read
    args.command_line = rerun_line(args, args.command_parser, "fit")
    check_fit_options(args)
    check_sources(args)
    if args.kind in ("response", "quasi-static", "virgin"):
        from presliding.cli.fitting.fit_pooled import run_pooled

        return run_pooled(args)
    from presliding.cli.fitting.fit import run
    from presliding.cli.fitting.records import prepare_single

    prepare_single(args)
    return run(args)


def _cmd_sweep(args: argparse.Namespace) -> int:
    from presliding.cli.sweeping.sweep import run

    return run(args)


def _cmd_loop(args: argparse.Namespace) -> int:
    from presliding.cli.simulation.loop import run

    return run(args)


def _cmd_network(args: argparse.Namespace) -> int:
    from presliding.cli.simulation.network import run

    return run(args)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line with `argv` (default: sys.argv[1:]); return the exit code."""
    parser = _build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, or a usage error (code 2)
        return int(exc.code or 0)
    if args.command is None:
        parser.print_help()
        return 0
    from presliding.cli.common import release_folders

    try:
        return int(args.handler(args))
    except KeyboardInterrupt:
        print(f"presliding {args.command}: interrupted", file=sys.stderr)
        return 130
    except ImportError as exc:  # an optional package that is not installed: one line
        if args.debug:
            raise
        from presliding._interop import missing_extra

        print(f"presliding {args.command}: error: {missing_extra(exc)}", file=sys.stderr)
        return 2
    except (UserError, ValueError, TypeError, OSError, NotImplementedError) as exc:
        if args.debug:
            raise
        from presliding.cli.common import cli_words

        text = cli_words(" ".join(str(exc).split())) or type(exc).__name__
        print(f"presliding {args.command}: error: {text}", file=sys.stderr)
        return 2
    finally:
        release_folders()


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
