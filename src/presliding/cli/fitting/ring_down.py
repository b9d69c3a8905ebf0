"""``presliding ring-down``: a measured free decay to ω(A), ζ(A) and a fitted joint model.

The file (delimited text or a MATLAB .mat file) holds time and a displacement, velocity
or acceleration of one point of the structure. Its decay is read by the analytic signal
or by peak tracking (`presliding.analyze_ring_down`: band-pass around the mode, the ends
trimmed and said), and a joint model with the mode's viscous (fixture) damping is fitted
to ω(A) and ζ(A) (`presliding.fit_joint`; Segalman's four-parameter Iwan model by
default). Written: ring_down.csv (the estimates with their stated errors), joint.json (the
fitted parameters, their intervals, units and status), ring_down.png (ζ and ω against the
amplitude, with the fitted model) and report.md. Exit status 0 when the fit converged,
1 when it did not (its status says why), 2 for a user error.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from presliding.cli.common import (
    UserError,
    check_folder,
    check_outputs,
    new_figure,
    record_outputs,
    write_csv,
)

OUTPUTS = ("ring_down.csv", "joint.json", "ring_down.png", "report.md")


def add_parser(sub: Any, parents: list) -> argparse.ArgumentParser:
    """The ``ring-down`` sub-parser (its handler is set by `presliding.cli.commands`)."""
    from presliding.cli.common import checked
    from presliding.cli.fitting.records import add_data_options

    p = sub.add_parser(
        "ring-down",
        help="a measured free decay: amplitude-dependent frequency and damping, a joint fit",
        description=__doc__.split("\n\n", 1)[1].replace("``", "'"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
        parents=parents,
    )
    p.add_argument("data", type=Path, help="the ring-down file (text or .mat)")
    for option, help_text in (
        ("--columns", "columns by signal, e.g. time=0 acceleration=1"),
        ("--units", "unit of a signal's values, e.g. acceleration=g"),
        ("--scale", "factor applied after the unit conversion, e.g. position=1e-3"),
    ):
        p.add_argument(option, nargs="+", default=(), metavar="SIGNAL=VALUE", help=help_text)
    p.add_argument("--window", default=None, metavar="START:STOP", help="time window [s]")
    options: list[tuple[tuple[str, ...], dict[str, Any]]] = [
        (("--sample-rate",), {"type": checked("--sample-rate"), "metavar": "HZ",
                              "help": "sample rate [Hz] of files without a time column"}),
        (("--signal",), {"choices": ("position", "velocity", "acceleration"),
                         "help": "the signal analysed (default: the first present in that "
                                 "order)"}),
        (("--method",), {"choices": ("hilbert", "peaks"), "default": "hilbert",
                         "help": "analytic signal (default) or peak tracking"}),
        (("--frequency",), {"type": checked("--frequency"), "metavar": "RAD_S",
                            "help": "the mode's frequency [rad/s] (default: the spectrum's "
                                    "peak)"}),
        (("--band",), {"nargs": 2, "type": checked("--band"), "metavar": ("LOW", "HIGH"),
                       "help": "band-pass [rad/s] (default 0.5–1.5 × ω₀)"}),
        (("--trim",), {"type": checked("--trim"), "metavar": "SECONDS",
                       "help": "seconds trimmed at each end (default eight periods)"}),
        (("--joint",), {"choices": ("segalman", "mindlin", "jenkins"), "default": "segalman",
                        "help": "the joint model fitted (default: Segalman's Iwan model)"}),
        (("--no-fit",), {"action": "store_true", "help": "estimate ω(A), ζ(A) only"}),
        (("-o", "--output"), {"type": Path, "default": Path("presliding-ring-down"),
                              "help": "output folder (default: ./presliding-ring-down)"}),
    ]  # fmt: skip
    for flags, kw in options:
        p.add_argument(*flags, **kw)
    add_data_options(p, fit=False)
    return p


def _read(args: argparse.Namespace) -> Any:
    from presliding.cli.inputs.files import read_measurement

    ns = argparse.Namespace(**{**vars(args), "kind": "ring-down"})
    return read_measurement(ns)


def run(args: argparse.Namespace) -> int:
    """Read, analyse, fit and write (module notes)."""
    from presliding._io import write_text
    from presliding.structural import analyze_ring_down, fit_joint

    folder = check_folder(args.output)
    outputs = [folder / name for name in OUTPUTS]
    check_outputs(outputs, [args.data], overwrite=args.overwrite)
    meas = _read(args)
    try:
        rd = analyze_ring_down(meas, signal=args.signal, method=args.method,
                               frequency=args.frequency,
                               band=None if args.band is None else tuple(args.band),
                               trim=args.trim)  # fmt: skip
    except ValueError as exc:
        raise UserError(f"{args.data}: {exc}") from None
    fit = None if args.no_fit else fit_joint(rd, args.joint)
    summary = json.dumps(_summary(rd, fit, args), indent=2) + "\n"
    report = _report(rd, fit, args)
    record_outputs(outputs)
    folder.mkdir(parents=True, exist_ok=True)
    write_csv(folder / "ring_down.csv",
              ["time [s]", "amplitude [m]", "frequency [rad/s]", "frequency_error [rad/s]",
               "damping_ratio", "damping_ratio_error"],
              [rd.time, rd.amplitude, rd.frequency, rd.frequency_error, rd.damping_ratio,
               rd.damping_ratio_error], quiet=True)  # fmt: skip
    write_text(folder / "joint.json", summary)
    _figure(rd, fit, folder / "ring_down.png")
    write_text(folder / "report.md", report)
    if not args.quiet:
        print(rd.report())
        if fit is not None:
            print(fit.report())
        print(f"presliding ring-down: wrote {len(outputs)} files to {folder.resolve()}")
    return 0 if fit is None or fit.success else 1


def _summary(rd: Any, fit: Any, args: argparse.Namespace) -> dict[str, Any]:
    out: dict[str, Any] = {"data": str(args.data), "method": rd.method, "signal": rd.signal,
                           "band_rad_s": rd.band.tolist(), "analysed_s": rd.analysed.tolist(),
                           "ring_down_message": rd.message}  # fmt: skip
    if fit is not None:
        out["joint"] = {
            "model": args.joint, "status": fit.status, "message": fit.message,
            "parameters": {k: {"value": v, "unit": fit.units.get(k, ""),
                               "interval": list(fit.confidence_interval.get(k, (math.nan,) * 2)),
                               "level": fit.confidence_level}
                           for k, v in fit.parameters.items()},
            "derived": fit.derived, "per_unit_modal_mass": True,
        }  # fmt: skip
    return out


def _figure(rd: Any, fit: Any, path: Path) -> None:
    from presliding._figures import place_legend, save_figure

    fig, axes = new_figure(ncols=2, size=(11.0, 4.4))
    ax_z, ax_w = axes[0]
    rd.plot(ax_z, quantity="damping")
    rd.plot(ax_w, quantity="frequency")
    if fit is not None:
        from presliding.structural._joint_model import JOINTS, predict

        a = np.geomspace(rd.amplitude.min(), rd.amplitude.max(), 200)
        kind = fit.kind.split("(")[-1].rstrip(")")
        w, z, _ = predict(JOINTS[_joint_name(fit)], fit.parameters, a, kind)
        ax_z.plot(a, z, "-", label=f"fitted joint ({fit.status})")
        ax_w.plot(a, w, "-", label=f"fitted joint ({fit.status})")
        for ax in (ax_z, ax_w):
            place_legend(ax)
    save_figure(fig, path)


def _joint_name(fit: Any) -> str:
    names = set(fit.parameters)
    if "exponent" in names:
        return "segalman"
    return "mindlin" if "slip_displacement" in names else "jenkins"


def _report(rd: Any, fit: Any, args: argparse.Namespace) -> str:
    lines = [f"# Ring-down of {args.data}", "", "```", rd.report(), "```", ""]
    if fit is not None:
        lines += [f"## Joint fit ({args.joint}, per unit modal mass)", "", "```", fit.report(),
                  "```", ""]  # fmt: skip
    lines += ["![ring-down](ring_down.png)", ""]
    return "\n".join(lines)
