"""Bad command lines and bad model/sweep files: one error line naming the option or the file
and the value, exit code 2 (a failed run: 1), and no RuntimeWarning on the way."""

from __future__ import annotations

import warnings

import pytest

from presliding.cli import main
from tests.helpers import one_error_line

MODEL = """\
[friction]
coulomb = 0.3
stiffness = [100.0, 50.0]
breakaway = [0.02, 0.015]

[motion]
mass = 1.0
initial_velocity = 0.1
t_end = 0.5
samples = 101
"""
SWEEP = """\
[friction]
stiffness = [200.0, 40.0, 10.0]
breakaway = [0.3, 0.3, 0.4]

[motion]
mass = 1.0
initial_state = "relaxed"
t_end = 60.0

[sweep]
quantity = "reversals"

[sweep.axes]
coulomb_ratio = {start = 0.04, stop = 1.2, num = 5}
initial_velocity = {values = [0.05, 0.3]}
"""


def _run(argv):
    """main(argv) with every RuntimeWarning an error (none may leak to the user)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        return main(argv)


def _model(tmp_path, old, new, text=MODEL, name="m.toml"):
    path = tmp_path / name
    assert old in text
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("old", "new", "needles"),
    [
        ("t_end = 0.5", "t_end = inf", ("`motion.t_end` must be finite", "inf")),
        ("t_end = 0.5", "t_end = nan", ("`motion.t_end` must be finite", "nan")),
        ("t_end = 0.5", "t_end = 1e308", ("`motion.t_end` must keep the simulated time span",)),
        ("t_end = 0.5", "t_end = -1.0", ("`motion.t_end` must be positive",)),
        ("t_end = 0.5", 't_end = "x"', ("`motion.t_end` must be a number",)),
        ("t_end = 0.5", "t_end = true", ("`motion.t_end` must be a number",)),
        ("samples = 101", "samples = 1e12", ("`motion.samples` must be at most",)),
        ("samples = 101", "samples = 1.5", ("`motion.samples` must be a whole number",)),
        ("mass = 1.0", "mass = inf", ("`motion.mass` must be finite",)),
        ("mass = 1.0", "mass = 0.0", ("`motion.mass` must be positive",)),
        ("initial_velocity = 0.1", "initial_velocity = nan", ("initial_velocity` must be finite",)),
        ("initial_velocity = 0.1", "initial_velocity = 1e200", ("`initial_velocity`",)),
        ("stiffness = [100.0, 50.0]", "stiffness = [1e308, 1e308]", ("`stiffness` must give",)),
        ("stiffness = [100.0, 50.0]", "stiffness = [inf, 1.0]", ("`stiffness` must be finite",)),
        ("stiffness = [100.0, 50.0]", 'stiffness = ["x", 1.0]', ("`stiffness` must be",)),
        ("breakaway = [0.02, 0.015]", "breakaway = [1e308, 0.01]", ("must give a finite",)),
    ],
)
@pytest.mark.parametrize("command", ["simulate", "analyze"])
def test_bad_model_values_are_one_line(tmp_path, capsys, command, old, new, needles):
    path = _model(tmp_path, old, new)
    argv = [command, str(path)] + (["-o", str(tmp_path / "out")] if command == "simulate" else [])
    assert _run(argv) == 2
    line = one_error_line(capsys, *needles)
    assert line.startswith(f"presliding {command}: error: ")
    if "`motion." in needles[0]:
        assert str(path) in line  # a file's own value names the file


def test_huge_values_that_are_legal_give_finite_output_without_warnings(tmp_path, capsys):
    """A stiffness of 1e308 (Σk finite) analyses without overflow warnings."""
    path = _model(tmp_path, "stiffness = [100.0, 50.0]", "stiffness = [1e308, 1.0]")
    assert _run(["analyze", str(path)]) == 0
    out = capsys.readouterr().out
    assert "1e+308 N/m" in out and "inf" not in out and "nan" not in out


@pytest.mark.parametrize(
    ("content", "needle"),
    [(None, "no such file"), (b"\x00\x01\xff", "not valid TOML"), (b"", "missing table")],
    ids=["missing", "binary", "empty"],
)
@pytest.mark.parametrize("command", ["simulate", "analyze", "sweep"])
def test_missing_binary_and_empty_files_are_one_line(tmp_path, capsys, command, content, needle):
    path = tmp_path / "f.toml"
    if content is not None:
        path.write_bytes(content)
    argv = [command, str(path)] + (["-o", str(tmp_path / "o")] if command != "analyze" else [])
    assert _run(argv) == 2
    line = one_error_line(capsys, str(path))
    assert needle in line or command == "sweep"


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (
            ["fit", "{data}", "--kind", "presliding", "--cutoff", "-1"],
            "`--cutoff` must be positive",
        ),
        (["fit", "{data}", "--kind", "presliding", "--mass", "nan"], "`--mass` must be finite"),
        (["fit", "{data}", "--kind", "presliding", "--elements", "2.5"], "`--elements` must be a"),
        (
            ["fit", "{data}", "--kind", "presliding", "--max-evaluations", "0"],
            "`--max-evaluations`",
        ),
        (["fit", "{data}", "--kind", "presliding", "--sample-rate", "inf"], "`--sample-rate`"),
        (["simulate", "{model}", "--rtol", "inf"], "`--rtol` must be finite"),
        (["simulate", "{model}", "--step", "0"], "`--step` must be positive"),
        (["simulate", "{model}", "--mass", "-1"], "`--mass` must be positive"),
        (
            ["fit", "{data}", "--kind", "response", "--bootstrap", "100000"],
            "`--bootstrap` must be at most 10000",
        ),
        (["sweep", "{model}", "--workers", "0"], "`--workers` must be a positive integer"),
        (["sweep", "{model}", "--retries", "x"], "`--retries` must be a whole number"),
    ],
)
def test_numeric_options_are_checked_on_parsing(tmp_path, capsys, argv, needle):
    data = tmp_path / "d.csv"
    data.write_text("time,position,friction_force\n0,0,0\n1,1,1\n")
    model = _model(tmp_path, "t_end", "t_end")
    argv = [a.format(data=data, model=model) for a in argv] + ["-o", str(tmp_path / "o")]
    try:
        code = _run(argv)
    except SystemExit as exc:  # argparse's own exit
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert needle in err[-1] and "got" in err[-1]


def test_sweep_num_is_checked_before_the_axis_is_allocated(tmp_path, capsys):
    path = _model(tmp_path, "stop = 1.2, num = 5", "stop = 1.2, num = 1000000000000", SWEEP)
    assert _run(["sweep", str(path), "-o", str(tmp_path / "o")]) == 2
    one_error_line(capsys, "`sweep.axes.coulomb_ratio.num` must be at most", "1000000000000")


@pytest.mark.parametrize(("t_end", "state"), [("0.001", "failed"), ("0.5", "partial")])
def test_a_sweep_with_points_not_at_rest_is_not_reported_ok(tmp_path, capsys, t_end, state):
    """A blank map (no point at rest) fails, a map with gaps is partial; both exit 1."""
    text = SWEEP.replace("start = 0.04", "start = 0.0")
    path = _model(tmp_path, "t_end = 60.0", f"t_end = {t_end}", text)
    assert _run(["sweep", str(path), "-o", str(tmp_path / "o")]) == 1
    captured = capsys.readouterr()
    first = captured.out.splitlines()[0]
    assert first.startswith(f"sweep: {state} (") and "not at rest" in first
    assert "sweep: ok" not in captured.out
    assert "did not come to rest" in captured.err
