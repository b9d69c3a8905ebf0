"""``--segments stops | loops | ramps``: records cut into pieces, the cut stated and drawn.

The same cut serves the fit, its ``--hold-out`` files and ``presliding
predict`` (which takes a model file's cut unless told otherwise), so a held-out
record is predicted the way the fitted ones were cut. Its options
(``--lead-in``, ``--rest-speed`` for stops, ``--segment-tolerance`` for loops
and ramps, ``--min-samples``) are refused without ``--segments`` or for a kind
of cut that has no use for them. The values the cut used, defaults resolved
for each record, are written into the report and the model file's header
(`presliding.measurement.Segments.parameters`), and ``segments.png`` shows the
windows on every record cut (`presliding.measurement.Segments.plot`).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from presliding.cli.common import UserError, cli_words, new_figure

__all__ = ["OPTIONS", "add_segment_options", "cut_records", "save_segments_figure",
           "segment_options"]  # fmt: skip

#: The command-line flag of each option of `Measurement.segments`.
OPTIONS = {"lead_in": "--lead-in", "rest_speed": "--rest-speed",
           "tolerance": "--segment-tolerance", "min_samples": "--min-samples"}  # fmt: skip
#: Most records drawn in segments.png (one panel each).
MOST_PANELS = 8


def add_segment_options(parser: argparse.ArgumentParser) -> None:
    """--segments and the options of the cut."""
    from presliding.cli.common import checked

    parser.add_argument(
        "--segments", choices=("stops", "loops", "ramps", "none"), default=None,
        help="cut each record into stops, loops or ramps, each piece a record of its own "
        "(predict: default the model file's cut; none: whole files)",
    )  # fmt: skip
    for flag, metavar, text in (
        ("--lead-in", "SECONDS", "--segments stops: time kept before each drop of the input "
         "(default: a fifth of each deceleration)"),
        ("--rest-speed", "SPEED", "--segments stops: speed [m/s or rad/s] below which a "
         "record is at rest (default: 2 %% of its 99th-percentile speed)"),
        ("--segment-tolerance", "TRAVEL", "--segments loops or ramps: the retreat [m or rad] "
         "that makes a turning point (default: three encoder counts, else 1 %% of the span)"),
    ):  # fmt: skip
        kind = checked(flag, minimum=0.0) if flag == "--lead-in" else checked(flag)
        parser.add_argument(flag, type=kind, default=None, metavar=metavar, help=text)
    parser.add_argument(
        "--min-samples", type=checked("--min-samples", integer=True, minimum=2), default=None,
        metavar="N", help="--segments: shortest piece kept (default 10 samples)",
    )  # fmt: skip


def segment_options(args: argparse.Namespace, kind: str | None = None) -> dict[str, Any]:
    """The options of the cut given on the command line (refused without ``--segments``)."""
    kind = getattr(args, "segments", None) if kind is None else kind
    given = {name: getattr(args, name if name != "tolerance" else "segment_tolerance", None)
             for name in OPTIONS}  # fmt: skip
    given = {k: v for k, v in given.items() if v is not None}
    if given and kind in (None, "none"):
        flags = " and ".join(f"{OPTIONS[k]} {v}" for k, v in given.items())
        raise UserError(f"{flags}: an option of --segments, which is not given; add "
                        "--segments stops, loops or ramps, or drop it.")  # fmt: skip
    return given


def _words(text: str) -> str:
    """A message of `Measurement.segments` in the command line's terms."""
    for name, flag in OPTIONS.items():
        text = text.replace(f"`{name}`", flag).replace(f"{name}=", f"{flag} ")
    return cli_words(text)


def cut_records(
    records: list[Any], labels: list[str], kind: str | None, options: dict[str, Any]
) -> tuple[list[Any], list[str], list[str], list[Any]]:
    """(pieces, their labels, a text per record cut, the `Segments`) of records cut by `kind`.

    Without a cut (`kind` None or ``"none"``) the records come back whole.
    """
    if kind in (None, "none"):
        return list(records), list(labels), [], []
    pieces, names, cuts, segs = [], [], [], []
    for meas, label in zip(records, labels, strict=True):
        try:
            seg = meas.segments(kind, **options)
        except (TypeError, ValueError) as exc:
            raise UserError(_words(f"{label}: --segments {kind}: {exc}")) from None
        pieces += list(seg.records)
        names += [f"{label} #{i + 1}" for i in range(len(seg))]
        cuts.append(seg.report().replace(f"cut from {seg.source}", f"cut from {label}"))
        segs.append(seg)
    return pieces, names, cuts, segs


def save_segments_figure(segs: list[Any], labels: list[str], path: Path) -> str:
    """segments.png: each record cut (at most `MOST_PANELS`) with its windows; the caption."""
    from presliding.plotting import save_figure

    shown = segs[:MOST_PANELS]
    fig, axes = new_figure(1, len(shown), size=(10.0, 2.6 * len(shown) + 0.6))
    for ax, seg, label in zip(axes[:, 0], shown, labels, strict=False):
        seg.plot(ax=ax)
        ax.set_title(f"{label}: {len(seg)} {seg.kind} ({seg.describe_parameters()})",
                     fontsize="medium")  # fmt: skip
    save_figure(fig, path)
    more = f" (the first {len(shown)} of {len(segs)} records)" if len(segs) > len(shown) else ""
    return (f"The windows cut by --segments {segs[0].kind} on each record{more}, numbered as "
            "the pieces in the tables; the applied force on the right axis.")  # fmt: skip
