"""The ``presliding`` command line.

User errors (a bad file, a bad parameter) print one line on stderr and exit
with code 2; ``--debug`` shows the traceback instead.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from ._version import __version__

EXAMPLES = """\
examples:
  presliding demo                      # the main job, written to ./presliding-demo
  presliding demo -o out/              # the same, into out/
"""


class UserError(Exception):
    """An error the user can fix: reported in one line, exit code 2."""


def _build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="presliding",
        description="Dry friction with presliding hysteresis (Prandtl–Ishlinskii operators).",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"presliding {__version__}")
    parser.add_argument("--debug", action="store_true", help="show tracebacks for errors")
    parser.add_argument("--quiet", action="store_true", help="print nothing but errors")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    demo = sub.add_parser("demo", help="run the built-in main job and write its figures")
    demo.add_argument(
        "-o",
        "--output",
        type=Path,
        default=Path("presliding-demo"),
        help="output folder (default: ./presliding-demo)",
    )
    demo.set_defaults(handler=_cmd_demo)
    return parser


def _cmd_demo(args: argparse.Namespace) -> int:
    from ._demo import run_demo

    out = args.output
    if out.exists() and not out.is_dir():
        raise UserError(f"{out}: is a file, not a folder; pass another path with -o.")
    paths = run_demo(out)
    if not args.quiet:
        print(f"presliding demo: wrote {len(paths)} files to {out.resolve()}")
        for p in paths:
            print(f"  {p}")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code."""
    parser = _build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 0
    try:
        return int(args.handler(args))
    except (UserError, ValueError, TypeError, OSError) as exc:
        if args.debug:
            raise
        print(f"presliding {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
