"""``presliding example-data``: small records to try the commands on, written into a folder.

The files ship with the package (about 50 kB in all, in ``example_files/``) and
were made by `generate` from known models, with an encoder's quantisation and
force noise, so that ``presliding fit`` and ``presliding predict`` can be run
at once and their answers checked against the truth (`TRUTH`):

- ``stop_1.csv`` … ``stop_4.csv``: a mass pushed and left to stop (time,
  position in mm, applied force in N), for ``--kind response``; fit three,
  hold out the fourth;
- ``servo.csv``: one record of three pushes and stops, for ``--segments stops``;
- ``loops.csv``: a displacement-driven friction loop with minor loops (time,
  position in µm, friction force in mN), for ``--kind presliding``.

The tests regenerate them and compare (tests/cli/test_example_data.py).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["COMMANDS", "FILES", "TRUTH", "add_parser", "generate", "run"]

#: What each file holds.
FILES = {
    "stop_1.csv": "a push and a stop (--kind response)",
    "stop_2.csv": "a push and a stop (--kind response)",
    "stop_3.csv": "a push and a stop (--kind response)",
    "stop_4.csv": "a push and a stop, to hold out of the fit (--hold-out, presliding predict)",
    "servo.csv": "three pushes and stops in one record (--segments stops)",
    "loops.csv": "a friction loop with minor loops against displacement (--kind presliding)",
}
#: Commands to try in the folder written.
COMMANDS = (
    "presliding fit stop_1.csv stop_2.csv stop_3.csv --kind response --elements 1 "
    "--hold-out stop_4.csv -o fit-stops",
    "presliding predict fit-stops/model.toml stop_4.csv -o predict-stop",
    "presliding fit servo.csv --kind response --elements 1 --segments stops -o fit-servo",
    "presliding fit loops.csv --kind presliding --elements 3 -o fit-loops",
)
#: The models the files were made with (the answers a fit should find).
TRUTH: dict[str, Any] = {
    "stops": {"coulomb": 0.3, "stiffness": [4000.0], "breakaway": [0.35], "mass": 2.0},
    "loops": {"coulomb": 0.1, "stiffness": [2.0e4, 8.0e3, 3.0e3], "breakaway": [0.05, 0.08, 0.1]},
}
_FOLDER = Path(__file__).resolve().parent / "example_files"
_HEADER_STOPS = "Time [s],Position [mm],Force [N]"


def _stops_model() -> Any:
    import presliding as ps

    t = TRUTH["stops"]
    return ps.PIFriction(t["coulomb"], t["stiffness"], breakaway=t["breakaway"])


def _write(path: Path, header: str, columns: list[np.ndarray], formats: list[str]) -> None:
    from presliding._io import write_text

    rows = [",".join(f % v for f, v in zip(formats, row, strict=True))
            for row in zip(*columns, strict=True)]  # fmt: skip
    write_text(path, "\n".join([header, *rows]) + "\n")


def _quantised_mm(y: np.ndarray) -> np.ndarray:
    """Metres to millimetres on an encoder of 0.1 µm."""
    return 1e-4 * np.round(y * 1e3 / 1e-4)


def _stop(path: Path, v0: float, seed: int) -> None:
    import presliding as ps

    model, mass = _stops_model(), TRUTH["stops"]["mass"]
    t = np.arange(300) * 2e-3
    d = np.sign(v0)
    u = np.where(t < 0.05, -0.3 * d, 0.0)
    memory = ps.preloaded_state(model, 0.5 * model.max_elastic_force * d, direction=d)
    res = ps.simulate(model, mass, applied_force=(t, u), initial_velocity=v0,
                      initial_state=memory, t_eval=t)  # fmt: skip
    noise = 1e-3 * np.random.default_rng(seed).standard_normal(t.size)
    _write(path, _HEADER_STOPS, [t, _quantised_mm(res.position), u + noise],
           ["%.3f", "%.4f", "%.4f"])  # fmt: skip


def _servo(path: Path) -> None:
    import presliding as ps

    t = np.arange(750) * 2e-3
    u = np.zeros_like(t)
    for k, (begin, width, level) in enumerate(((0.05, 0.04, 1.0), (0.55, 0.03, 1.1),
                                               (1.05, 0.05, 0.9))):  # fmt: skip
        u[(t >= begin) & (t < begin + width)] = level * (-1) ** k
    res = ps.simulate(_stops_model(), TRUTH["stops"]["mass"], applied_force=(t, u), t_eval=t)
    noise = 1e-3 * np.random.default_rng(1).standard_normal(t.size)
    _write(path, _HEADER_STOPS, [t, _quantised_mm(res.position), u + noise],
           ["%.3f", "%.4f", "%.4f"])  # fmt: skip


def _loops(path: Path) -> None:
    import presliding as ps
    from presliding.signals import piecewise_linear

    truth = TRUTH["loops"]
    model = ps.PIFriction(truth["coulomb"], truth["stiffness"], breakaway=truth["breakaway"])
    y = piecewise_linear([0.0, 40e-6, -40e-6, 15e-6, -10e-6, 40e-6], 0.5e-6)
    y = 1e-7 * np.round(y / 1e-7)  # a stage's 0.1 µm resolution
    force = model.force(y)[0] + 2e-4 * np.random.default_rng(3).standard_normal(y.size)
    t = np.arange(y.size) * 5e-3
    _write(path, "Time [s],Position [um],Friction [mN]", [t, y * 1e6, force * 1e3],
           ["%.3f", "%.1f", "%.2f"])  # fmt: skip


def generate(folder: Path) -> list[Path]:
    """Write every example file into `folder` from the models of `TRUTH` (slow on a cold
    numba cache: it simulates); returns the paths."""
    folder.mkdir(parents=True, exist_ok=True)
    for i, v0 in enumerate((0.03, -0.045, 0.06, -0.05)):
        _stop(folder / f"stop_{i + 1}.csv", v0, seed=i)
    _servo(folder / "servo.csv")
    _loops(folder / "loops.csv")
    return [folder / name for name in FILES]


def add_parser(sub: Any, parents: list) -> argparse.ArgumentParser:
    """The ``example-data`` sub-parser."""
    p = sub.add_parser(
        "example-data",
        help="write small example records (CSV) to try presliding fit and predict on",
        description=__doc__.split("\n\n", 1)[1].replace("``", "'"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
        parents=parents,
    )
    p.add_argument("-o", "--output", type=Path, default=Path("presliding-example-data"),
                   help="output folder (default: ./presliding-example-data)")  # fmt: skip
    return p


def run(args: argparse.Namespace) -> int:
    """Copy the shipped example files into the output folder; print what to run."""
    from presliding._io import write_text
    from presliding.cli.common import check_folder, check_outputs, record_outputs

    folder = check_folder(args.output)
    outputs = [folder / name for name in FILES]
    check_outputs(outputs, (), overwrite=args.overwrite)
    record_outputs(outputs)
    for out in outputs:
        write_text(out, (_FOLDER / out.name).read_text(encoding="utf-8"))
    if not args.quiet:
        width = max(map(len, FILES))
        for name, what in FILES.items():
            print(f"wrote {folder / name}".ljust(width + len(str(folder)) + 8) + f"  {what}")
        print(f"try, in {folder}:")
        for command in COMMANDS:
            print(f"  {command}")
    return 0
