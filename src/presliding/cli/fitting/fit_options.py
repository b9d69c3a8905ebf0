"""The options of ``presliding fit`` (its sub-parser), and which kinds use each.

An option a kind does not use is refused with one line naming it and the kinds
that do (`check_fit_options`), never accepted and ignored.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from presliding.cli.common import UserError, checked

__all__ = ["USES", "add_fit_parser", "check_fit_options", "check_record_count"]

POOLED = ("response", "quasi-static", "virgin")
#: The kinds that use each option (its `dest`); an option given to another kind is refused.
USES: dict[str, tuple[str, ...]] = {
    "viscous": ("motion", "response"),
    "offset": ("presliding", "motion", "response", "quasi-static"),
    "search": ("presliding",),
    "seed": ("presliding", "response", "quasi-static"),
    "mass": ("motion", "response"),
    "cutoff": ("motion",),
    "signal": ("response",),
    "velocity": ("response",),
    "density": ("response", "quasi-static"),
    "initial_state": ("response", "quasi-static"),
    "prune": ("response",),
    "bootstrap": ("response", "quasi-static"),
    "no_cross_validation": ("response", "quasi-static"),
    "segments": POOLED,
    "ramps": ("virgin",),
    "hold_out": ("response", "quasi-static"),
    "reversal_tolerance": ("response", "quasi-static"),
    "compare": ("response",),
}


def _given(args: argparse.Namespace, dest: str) -> bool:
    value = getattr(args, dest, None)
    return value not in (None, False, 0, (), [], "none") and not (dest == "search" and
                                                                 value == "grid")  # fmt: skip


def _text(value: Any) -> str:
    if isinstance(value, (list, tuple)):
        return " ".join(Path(v).name if isinstance(v, Path) else str(v) for v in value)
    return str(value)


def check_fit_options(args: argparse.Namespace) -> None:
    """Refuse an option `args.kind` does not use, or one whose partner is missing."""
    kind = args.kind
    flag = {d: "--" + d.replace("_", "-") for d in USES}
    for dest, kinds in USES.items():
        if _given(args, dest) and kind not in kinds:
            value = getattr(args, dest)
            shown = flag[dest] if isinstance(value, bool) else f"{flag[dest]} {_text(value)}"
            raise UserError(f"{shown}: --kind {kind} does not use it (it is for --kind "
                            f"{', '.join(kinds)}); drop it.")  # fmt: skip
    if _given(args, "seed"):
        if kind == "presliding" and args.search != "global":
            raise UserError("--seed: seeds the global search; add --search global, or drop it.")
        if kind != "presliding" and not args.bootstrap:
            raise UserError("--seed: seeds the bootstrap of a pooled fit; add --bootstrap N, "
                            "or drop it.")  # fmt: skip
    from presliding.cli.inputs.cuts import segment_options

    segment_options(args)  # the options of a cut need --segments (every kind)
    if kind == "virgin" and args.segments == "stops":
        raise UserError("--segments stops: --kind virgin reads ramps or loops, not stops; use "
                        "--segments ramps or loops.")  # fmt: skip


def check_record_count(args: argparse.Namespace, n_records: int) -> None:
    """Options that need several records (the cross-validation, the bootstrap)."""
    if args.no_cross_validation and n_records < 2:
        raise UserError("--no-cross-validation: with one record there is no cross-validation "
                        "to skip; drop it.")  # fmt: skip
    if (
        args.reversal_tolerance is not None
        and not args.hold_out
        and (n_records < 2 or args.no_cross_validation)
    ):
        raise UserError("--reversal-tolerance: counts reversals in the cross-validation and "
                        "--hold-out tables, and there is neither; drop it.")  # fmt: skip
    if args.bootstrap and n_records < 3:
        raise UserError(f"--bootstrap {args.bootstrap}: a record-level bootstrap needs three "
                        f"or more records; got {n_records}.")  # fmt: skip


def add_fit_parser(
    sub: Any, parents: Sequence[argparse.ArgumentParser], fmt: Any, handler: Callable[..., int]
) -> argparse.ArgumentParser:
    """Add the ``fit`` sub-parser with every option; returns it."""
    from presliding.cli.fitting.fit import FIT_DESCRIPTION, FIT_EPILOG

    fit = sub.add_parser(
        "fit",
        help="identify a model from measured data (CSV or MAT): model TOML, report, plots",
        description=FIT_DESCRIPTION,
        epilog=FIT_EPILOG,
        formatter_class=fmt,
        parents=parents,
    )
    _add_inputs(fit)
    _add_model_options(fit)
    fit.add_argument("-o", "--output", type=Path, default=Path("presliding-fit"),
                     help="output folder (default: ./presliding-fit)")  # fmt: skip
    _add_pooled_options(fit)
    from presliding.cli.fitting.records import add_data_options

    add_data_options(fit)
    fit.set_defaults(handler=handler, command_parser=fit)
    return fit


def _add_inputs(fit: argparse.ArgumentParser) -> None:
    """The data, the kind of fit, and how the files are read (columns, units, window)."""
    fit.add_argument(
        "data",
        type=Path,
        nargs="*",
        help="measured data (delimited text, or .mat files); several files are pooled as "
        "records (--kind response, quasi-static, virgin); none with --join",
    )
    fit.add_argument(
        "--kind",
        choices=("presliding", "motion", "response", "quasi-static", "virgin"),
        required=True,
        help="what to fit (see above)",
    )
    fit.add_argument(
        "--columns",
        nargs="+",
        metavar="SIGNAL=COLUMN",
        default=(),
        help="columns by signal (time, position, velocity, acceleration, applied_force, "
        "friction_force): a header name, a 0-based index, or a MAT variable",
    )
    fit.add_argument(
        "--units",
        nargs="+",
        metavar="SIGNAL=UNIT",
        default=(),
        help="unit of a signal's values (e.g. position=mm), overriding its header",
    )
    fit.add_argument(
        "--scale",
        nargs="+",
        metavar="SIGNAL=FACTOR",
        default=(),
        help="factors applied after the unit conversion, e.g. friction_force=-1 to flip a "
        "sign; for MAT files also a scalar variable (applied_force=gtau)",
    )
    fit.add_argument(
        "--window",
        metavar="START:STOP",
        default=None,
        help="fit only the samples with START <= t <= STOP [s] (either side may be empty)",
    )
    fit.add_argument(
        "--sample-rate",
        type=checked("--sample-rate"),
        default=None,
        metavar="HZ",
        help="sample rate [Hz] when the file has no time column",
    )


def _add_model_options(fit: argparse.ArgumentParser) -> None:
    """The model's options (elements, viscous term, offset, sides, search, mass, cut-off)."""
    fit.add_argument(
        "--elements",
        type=_elements,
        default=None,
        metavar="N",
        help="number of elasto-plastic elements (default: 3 presliding, 0 motion, 4 response); "
        "response: 'auto' chooses N = 0..4 by BIC",
    )
    fit.add_argument("--viscous", action="store_true", help="motion: add a viscous term F_v·ẏ")
    fit.add_argument("--offset", action="store_true", help="add a constant force offset")
    fit.add_argument(
        "--asymmetric",
        action="store_true",
        help="separate levels for the two directions of sliding, every --kind (excludes "
        "--offset): motion and presliding c1 and c1⁻ (with --viscous σ and σ⁻); response and "
        "quasi-static F_c⁻ beside F_c⁺; virgin the two branches of ramps in ±y (--ramps). The "
        "symmetric fit runs too and the report tests the asymmetry against it",
    )
    fit.add_argument(
        "--search",
        choices=("grid", "global"),
        default="grid",
        help="presliding: start thresholds from the threshold grid (default), or also from a "
        "global search (differential evolution), keeping the better fit",
    )
    fit.add_argument(
        "--seed",
        type=checked("--seed", integer=True),
        default=None,
        help="seed of the global search (--search global) or of the bootstrap (--bootstrap): "
        "reproducible runs",
    )
    fit.add_argument(
        "--mass",
        type=checked("--mass"),
        default=None,
        help="response/motion: known mass m [kg] (held fixed)",
    )
    fit.add_argument(
        "--cutoff",
        type=checked("--cutoff"),
        default=None,
        metavar="HZ",
        help="motion: low-pass cut-off for the velocity/acceleration estimate "
        "(default: a tenth of the sampling rate)",
    )


def _add_pooled_options(fit: argparse.ArgumentParser) -> None:
    """Options of the pooled fits (response, quasi-static, virgin)."""
    fit.add_argument(
        "--signal",
        choices=("velocity", "position", "both"),
        default=None,
        help="response: what is compared (default: velocity when every file has it, else position)",
    )
    fit.add_argument(
        "--velocity",
        choices=("auto", "difference", "measured"),
        default=None,
        help="response: what each file's velocity is, and so what the model's velocity is "
        "compared with: difference (the position's difference quotient, as a drive logs it; "
        "the model's position goes through the same quotient), measured (a tachometer, a "
        "vibrometer, a filtered estimate: the exact model velocity), auto (default: "
        "difference where the velocity equals the position's quotient, else measured)",
    )
    fit.add_argument(
        "--density",
        choices=("uniform", "exponential", "piecewise_constant"),
        default=None,
        help="response, quasi-static: a continuous density instead of elements (piecewise "
        "constant: --elements cells)",
    )
    fit.add_argument(
        "--initial-state",
        choices=("saturated", "preload", "relaxed", "continuing"),
        default=None,
        help="each record's friction memory at its start (response: saturated; quasi-static: "
        "preload, a fitted elastic force per record)",
    )
    fit.add_argument(
        "--prune",
        action="store_true",
        help="response: drop elements that never slide in the data and refit",
    )
    fit.add_argument(
        "--max-evaluations",
        type=checked("--max-evaluations", integer=True, minimum=1),
        default=None,
        metavar="N",
        help="most residual evaluations of each solver run (every kind)",
    )
    fit.add_argument(
        "--bootstrap",
        type=checked("--bootstrap", integer=True, maximum=10_000),
        default=0,
        metavar="N",
        help="record-level bootstrap resamples (three or more files; at most 10000, each a "
        "full refit: the progress shows the time left)",
    )
    fit.add_argument(
        "--reversal-tolerance",
        type=checked("--reversal-tolerance", minimum=0.0),
        default=None,
        metavar="TRAVEL",
        help="travel [m or rad] by which reversals are counted in the cross-validation and "
        "--hold-out tables (default: each record's own, three encoder counts or noise levels)",
    )
    fit.add_argument(
        "--compare",
        default=None,
        metavar="FAMILIES",
        help="response: fit each model family named (comma-separated, e.g. "
        "pi,pi-asymmetric,coulomb) to the same records, tabulate status, parameters, RSS, AIC, "
        "BIC and the --hold-out files' errors (comparison.csv and the report), and keep the "
        "family of least BIC; --elements goes to the families with elements. The exit status "
        "is that family's",
    )
    fit.add_argument(
        "--no-cross-validation",
        action="store_true",
        help="skip the leave-one-record-out table (computed with two or more files)",
    )


def _elements(text: str) -> Any:
    """``--elements``: a count, or ``auto`` (the response fit chooses N)."""
    if text.strip().lower() == "auto":
        return "auto"
    return checked("--elements", integer=True, maximum=10_000)(text)
