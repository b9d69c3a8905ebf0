"""``presliding loop``: outputs equal to the library, schema in --help, one-line user errors."""

import numpy as np
import pytest

pytest.importorskip("control")

from presliding import PID, PIFriction, predict_limit_cycles, simulate_loop
from presliding.cli import main

SPEC = """\
[friction]
coulomb = 0.0
stiffness = [2e4, 5e3, 1.5e3, 500.0]
breakaway = [0.2, 0.2, 0.2, 0.2]
[plant]
mass = 1.0
initial_velocity = 0.001
[controller]
kp = 400.0
ki = 4e4
dt = 1e-4
limit = 2.0
[reference]
kind = "step"
value = 0.0
t_end = 1.0
"""


def test_loop_writes_what_the_library_computes(tmp_path, capsys):
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC)
    out = tmp_path / "out"
    assert main(["loop", str(spec), "-o", str(out)]) == 0
    names = sorted(p.name for p in out.iterdir() if not p.name.startswith("."))
    assert names == sorted(["loop.csv", "loop.png", "nyquist.png", "report.md", "report.html"])
    assert "loop.csv" in (out / ".presliding-outputs").read_text()
    data = np.loadtxt(out / "loop.csv", delimiter=",", skiprows=1)
    model = PIFriction(0.0, [2e4, 5e3, 1.5e3, 500.0], [0.2] * 4)
    pid = PID(400.0, 4e4, 0.0, dt=1e-4, limit=2.0)
    res = simulate_loop(model, 1.0, pid, 0.0, t_end=1.0, initial_velocity=1e-3)
    np.testing.assert_allclose(data[:, 2], res.measured, rtol=1e-14, atol=1e-20)
    np.testing.assert_allclose(data[:, 4], res.control, rtol=1e-14, atol=1e-20)
    report = (out / "report.md").read_text()
    cycles = predict_limit_cycles(1.0, model, pid)
    assert f"{cycles.amplitude[0]:.6g}" in report and "Limit cycles" in report
    # a second run replaces its own outputs
    capsys.readouterr()
    assert main(["loop", str(spec), "-o", str(out), "--quiet"]) == 0
    assert capsys.readouterr().out == ""


def test_help_prints_the_schema(capsys):
    assert main(["loop", "--help"]) == 0
    text = capsys.readouterr().out
    assert "[controller]" in text and "anti_windup" in text and "t_end" in text


@pytest.mark.parametrize(
    ("edit", "needle"),
    [
        (("[plant]\nmass = 1.0", "[plant]\nmass = -1.0"), "`plant.mass` must be positive"),
        (('kind = "step"', 'kind = "square"'), "`reference.kind` must be 'step'"),
        (("t_end = 1.0", "t_end = 1.00005"), "whole number of sample periods"),
        (("dt = 1e-4", "dt = 1e-4\ngain = 3"), "unknown key `controller.gain`"),
        (("[reference]", "[references]"), "unknown table `references`"),
        (("kp = 400.0", 'kp = "big"'), "`controller.kp` must be a finite number"),
        (('kind = "step"', 'kind = "sine"'), "a sine reference needs `reference.frequency`"),
        (("value = 0.0", "value = 0.0\nfrequency = 2.0"), "applies to kind = 'sine' only"),
        # 1e10 periods: refused before anything is allocated, not a MemoryError
        (("t_end = 1.0", "t_end = 1e6"), "`t_end` must ask for at most"),
    ],
)
def test_bad_specification_is_one_line_exit_2(tmp_path, capsys, edit, needle):
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC.replace(*edit))
    assert main(["loop", str(spec), "-o", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert needle in err and err.count("\n") == 1 and str(spec) in err


@pytest.mark.parametrize("module", ["control", "pandas"])
def test_a_missing_package_is_one_line_and_exit_2(tmp_path, capsys, monkeypatch, module):
    """python-control is core, but a partial install (or a missing extra) is one line, exit 2."""
    import sys

    from presliding.cli import commands

    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC)

    def needs_it(args):
        __import__(module)

    monkeypatch.setitem(sys.modules, module, None)
    if module == "control":
        argv = ["loop", str(spec), "-o", str(tmp_path / "o"), "--quiet"]
    else:
        monkeypatch.setattr(commands, "_cmd_loop", needs_it)
        argv = ["loop", str(spec), "-o", str(tmp_path / "o")]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert f'pip install "presliding[{module}]"' in err
