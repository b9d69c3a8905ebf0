"""The command line: exit codes, written files, user errors in one line (exit 2)."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

import presliding as ps
from presliding import analysis
from presliding.cli import main
from presliding.cli.common import LOCK, MANIFEST
from presliding.model_io import load_model
from presliding.signals import piecewise_linear
from tests.helpers import one_error_line

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"

MODEL_TOML = """\
[friction]
coulomb = 0.3
stiffness = [2e4, 5e3, 1.5e3, 500.0]
breakaway = [0.175, 0.175, 0.175, 0.175]

[motion]
mass = 1.0
initial_velocity = 0.06
initial_state = "saturated"
t_end = 0.12
samples = 601
"""


@pytest.fixture
def model_file(tmp_path):
    path = tmp_path / "model.toml"
    path.write_text(MODEL_TOML, encoding="utf-8")
    return path


def _is_png(path):
    data = path.read_bytes()
    return len(data) > 1000 and data[:8] == PNG_MAGIC


def _no_temporaries(folder):
    hidden = [p.name for p in folder.iterdir() if p.name.startswith(".")]
    assert not [n for n in hidden if n not in (MANIFEST, LOCK)]


# ---------------------------------------------------------------------- basics
def test_version_and_help(capsys):
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"presliding {ps.__version__}"
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    assert "examples:" in out and "presliding simulate" in out and "[friction]" in out
    assert main([]) == 0
    assert "COMMAND" in capsys.readouterr().out
    for cmd in ("demo", "simulate", "analyze", "fit"):
        assert main([cmd, "--help"]) == 0
        assert "example" in capsys.readouterr().out


def test_usage_error_is_exit_2(capsys):
    assert main(["simulate"]) == 2  # the model file is missing
    assert "required" in capsys.readouterr().err
    assert main(["fit", "x.csv", "--kind", "nonsense", "-o", "out"]) == 2


def test_python_dash_m():
    proc = subprocess.run(
        [sys.executable, "-m", "presliding", "--version"], capture_output=True, text=True
    )
    assert proc.returncode == 0
    assert proc.stdout.strip() == f"presliding {ps.__version__}"


# ---------------------------------------------------------------------- simulate
def test_simulate_writes_csv_equal_to_the_library(tmp_path, model_file, capsys):
    out = tmp_path / "run"
    assert main(["simulate", str(model_file), "-o", str(out)]) == 0
    assert "stops at" in capsys.readouterr().out
    csv, png = out / "simulation.csv", out / "simulation.png"
    header = csv.read_text().splitlines()[0]
    assert header == (
        "time [s],position [m],velocity [m/s],acceleration [m/s^2],friction_force [N],"
        "elastic_force [N],applied_force [N]"
    )
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    spec = load_model(model_file)
    ref = ps.simulate(
        spec.model,
        1.0,
        initial_velocity=0.06,
        initial_state="saturated",
        t_eval=np.linspace(0.0, 0.12, 601),
    )
    assert data.shape == (601, 7)
    names = ("time", "position", "velocity", "acceleration", "friction_force", "elastic_force")
    for j, name in enumerate((*names, "applied_force")):
        np.testing.assert_allclose(data[:, j], getattr(ref, name), rtol=1e-13, atol=1e-15)
    assert _is_png(png)
    _no_temporaries(out)


def test_simulate_to_a_csv_path_and_quiet(tmp_path, model_file, capsys):
    target = tmp_path / "sub" / "result.csv"
    assert main(["--quiet", "simulate", str(model_file), "-o", str(target)]) == 0
    assert main(["simulate", str(model_file), "-o", str(target), "--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == ""  # no progress bar off a terminal
    assert target.exists() and _is_png(target.with_suffix(".png"))


@pytest.mark.parametrize("hold", ["zoh", "linear"])
def test_simulate_with_applied_force_csv(tmp_path, model_file, hold):
    t = np.array([0.0, 0.03, 0.06, 0.09])
    u = np.array([1.2, -0.5, 0.8, 0.0])
    force = tmp_path / "u.csv"
    force.write_text(
        "time [s],value [N]\n" + "".join(f"{a},{b}\n" for a, b in zip(t, u, strict=True))
    )
    out = tmp_path / "out.csv"
    args = ["simulate", str(model_file), "--applied-force", str(force), "--hold", hold]
    assert main([*args, "-o", str(out)]) == 2  # the samples end at 0.09 s, t_end is 0.12 s
    assert main([*args, "--hold-last", "-o", str(out)]) == 0
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    ref = ps.simulate(
        load_model(model_file).model,
        1.0,
        applied_force=(t, u),
        initial_velocity=0.06,
        initial_state="saturated",
        t_eval=np.linspace(0.0, 0.12, 601),
        hold=hold,
        rtol=1e-3 if hold == "linear" else None,  # the implicit step for an accuracy target
    )
    np.testing.assert_allclose(data[:, 1], ref.position, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(data[:, 6], ref.applied_force, rtol=1e-13, atol=1e-15)


def test_simulate_hold_linear_meets_its_accuracy_target(tmp_path, model_file, capsys):
    t = np.array([0.0, 0.03, 0.06, 0.09, 0.12])
    u = np.array([1.2, -0.5, 0.8, 0.0, 0.3])
    force = tmp_path / "u.csv"
    force.write_text(
        "time [s],value [N]\n" + "".join(f"{a},{b}\n" for a, b in zip(t, u, strict=True))
    )
    out = tmp_path / "out.csv"
    assert main(["simulate", str(model_file), "--applied-force", str(force), "--hold", "linear",
                 "-o", str(out)]) == 0  # fmt: skip
    printed = capsys.readouterr().out
    assert "position error estimate" in printed
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    fine = ps.simulate(load_model(model_file).model, 1.0, applied_force=(t, u), hold="linear",
                       initial_velocity=0.06, initial_state="saturated",
                       t_eval=np.linspace(0.0, 0.12, 601), step=2e-7)  # fmt: skip
    scale = np.max(np.abs(fine.position - fine.position[0]))
    err = np.max(np.abs(data[:, 1] - fine.position))
    assert err <= 2e-3 * scale  # the target 1e-3 of the displacement, with the estimate's slack
    estimate = float(printed.split("position error estimate (step doubling):")[1].split()[0])
    assert err / 2 <= estimate <= 2 * err  # the printed estimate is the actual error


# ---------------------------------------------------------------------- analyze
def test_analyze_json_matches_the_library(model_file, capsys):
    assert main(["analyze", str(model_file), "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    model = load_model(model_file).model
    assert got["coulomb_level"] == model.coulomb_level == 1.0
    assert got["max_elastic_force"] == pytest.approx(0.7, rel=1e-15)
    assert got["initial_stiffness"] == 27000.0
    assert got["turning_point"] == analysis.turning_point(model)
    assert got["stops_at_turning_point"] is True
    free = got["free_motion"]
    sim = ps.simulate(model, 1.0, initial_velocity=0.06, initial_state="saturated", t_end=1.0)
    assert free["reversals"] == sim.n_reversals == 1
    assert free["rest_position"] == pytest.approx(sim.rest_position, rel=1e-12)


def test_analyze_text_and_density_model(tmp_path, capsys):
    path = tmp_path / "dens.toml"
    path.write_text(
        '[friction]\ncoulomb = 0.1\n[friction.density]\nkind = "uniform"\n'
        "height = 3.5e7\nmax_threshold = 2e-4\n",
        encoding="utf-8",
    )
    assert main(["analyze", str(path)]) == 0
    out = capsys.readouterr().out
    assert "eq. 15" in out and "eq. 16" in out and "Uniform" in out
    assert "3 reversal(s)" in out  # from the saturated start (see the demo's density part)


def test_analyze_no_reversal_when_coulomb_exceeds_fm(tmp_path, capsys):
    path = tmp_path / "m.json"
    path.write_text(
        json.dumps({"friction": {"coulomb": 2.0, "stiffness": [10.0], "breakaway": [1.0]}})
    )
    assert main(["analyze", str(path), "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert got["turning_point"] is None and got["free_motion"]["reversals"] == 0


# ---------------------------------------------------------------------- fit
def _loops_csv(tmp_path, noise=0.0):
    model = ps.PIFriction(0.5, [500.0, 50.0, 4.0], [1.0, 1.0, 1.0])
    y = piecewise_linear([0.0, 0.8, -0.8, 0.4, -0.2, 0.1, -0.05, 0.6, -0.6], 1e-3)
    force, _ = model.force(y)
    force = force + np.random.default_rng(1).normal(0.0, noise, force.shape) * (noise > 0)
    path = tmp_path / "loops.csv"
    np.savetxt(
        path,
        np.column_stack([y, force]),
        delimiter=",",
        header="displacement [m],friction force [N]",
        comments="",
    )
    return path, model


def test_fit_presliding_round_trip(tmp_path, capsys):
    data, true = _loops_csv(tmp_path)
    out = tmp_path / "fit"
    assert main(["fit", str(data), "--kind", "presliding", "-o", str(out)]) == 0
    assert "converged" in capsys.readouterr().out
    fitted = load_model(out / "model.toml").model
    np.testing.assert_allclose(fitted.stiffness, true.stiffness, rtol=1e-6)
    np.testing.assert_allclose(fitted.breakaway, true.breakaway, rtol=1e-6)
    assert fitted.coulomb == pytest.approx(true.coulomb, rel=1e-6)
    assert _is_png(out / "fit.png")
    assert "data:image/png;base64," in (out / "report.html").read_text()
    assert "stiffness_1" in (out / "report.md").read_text()
    _no_temporaries(out)
    # the global search: the same fit here, and the report says how the start was found
    args = ["fit", str(data), "--kind", "presliding", "--search", "global", "--seed", "3"]
    assert main([*args, "-o", str(out), "--quiet"]) == 0
    again = load_model(out / "model.toml").model
    np.testing.assert_allclose(again.stiffness, true.stiffness, rtol=1e-6)
    assert "global search" in (out / "report.md").read_text()


def test_fit_motion_with_columns_and_scale(tmp_path):
    true = ps.PIFriction(0.5)  # pure Coulomb: m·ÿ + c1·sign(ẏ) = u holds at every moving sample
    t = np.linspace(0.0, 2.0, 2001)
    u = 1.5 * np.sin(2 * np.pi * t)
    res = ps.simulate(true, 2.0, applied_force=(t, u), t_eval=t)
    path = tmp_path / "data.csv"
    cols = [res.time, res.position * 1e3, res.velocity, res.acceleration, res.applied_force]
    np.savetxt(path, np.column_stack(cols), delimiter=",", header="t,y_mm,v,a,u_N", comments="")
    out = tmp_path / "fit"
    args = ["fit", str(path), "--kind", "motion", "--viscous", "-o", str(out)]
    args += ["--scale", "position=1e-3"]
    args += ["--columns", "position=y_mm", "velocity=v", "acceleration=a", "applied_force=u_N"]
    assert main(args) == 0
    spec = load_model(out / "model.toml")
    assert spec.motion.mass == pytest.approx(2.0, rel=1e-9)
    assert spec.model.coulomb == pytest.approx(0.5, rel=1e-9)
    assert "viscous" in (out / "report.md").read_text()


def test_fit_response_writes_a_runnable_model(tmp_path, model_file):
    true = ps.PIFriction(0.3, [3e3], [0.7])
    t = np.linspace(0.0, 0.12, 1201)
    res = ps.simulate(true, 1.0, initial_velocity=0.06, initial_state="saturated", t_eval=t)
    path = tmp_path / "free.csv"
    np.savetxt(
        path,
        np.column_stack([t, res.velocity]),
        delimiter=",",
        header="time [s],velocity [m/s]",
        comments="",
    )
    out = tmp_path / "fit"
    assert main(["fit", str(path), "--kind", "response", "--elements", "1", "-o", str(out)]) == 0
    spec = load_model(out / "model.toml")
    assert spec.model.coulomb == pytest.approx(0.3, rel=1e-4)
    np.testing.assert_allclose(spec.model.stiffness, [3e3], rtol=1e-4)
    assert spec.motion.initial_state == "saturated" and spec.motion.samples == 1201
    assert main(["simulate", str(out / "model.toml"), "-o", str(tmp_path / "again")]) == 0


# ---------------------------------------------------------------------- user errors
@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("[friction\ncoulomb = 1\n", "not valid TOML"),
        ("[friction]\ncoulomb = 1.0\nstifness = [1.0]\n", "friction.stifness"),
        ("[friction]\ncoulomb = 1.0\nstiffness = [-3.0]\nbreakaway = [1.0]\n", "stiffness"),
        ("[friction]\ncoulomb = 1.0\n[motion]\nmass = 0\n", "motion.mass"),
        ('[friction]\ncoulomb = 1.0\n[friction.density]\nkind = "gauss"\n', "density.kind"),
    ],
)
def test_bad_model_file_is_one_line_exit_2(tmp_path, capsys, text, needle):
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    for cmd in (["simulate", str(path), "-o", str(tmp_path / "o")], ["analyze", str(path)]):
        assert main(cmd) == 2
        one_error_line(capsys, "bad.toml", needle)
    assert not (tmp_path / "o" / "simulation.csv").exists()


def test_missing_file(tmp_path, capsys):
    assert main(["analyze", str(tmp_path / "absent.toml")]) == 2
    one_error_line(capsys, "absent.toml", "no such file")
    assert (
        main(["fit", str(tmp_path / "nope.csv"), "--kind", "presliding", "-o", str(tmp_path / "f")])
        == 2
    )
    one_error_line(capsys, "nope.csv", "no such file")


def test_missing_column(tmp_path, capsys):
    path = tmp_path / "d.csv"
    path.write_text("displacement,temperature\n0,1\n1,2\n", encoding="utf-8")
    assert main(["fit", str(path), "--kind", "presliding", "-o", str(tmp_path / "f")]) == 2
    one_error_line(capsys, "d.csv", "friction_force", "--columns friction_force=COLUMN")
    args = ["fit", str(path), "--kind", "presliding", "--columns", "friction_force=F"]
    assert main([*args, "-o", str(tmp_path / "f")]) == 2
    one_error_line(capsys, "d.csv", "'F'", "temperature")
    u = tmp_path / "u.csv"
    u.write_text("time,force\n0,1\n", encoding="utf-8")
    model = tmp_path / "m.toml"
    model.write_text(MODEL_TOML, encoding="utf-8")
    assert main(["simulate", str(model), "--applied-force", str(u), "-o", str(tmp_path)]) == 2
    one_error_line(capsys, "u.csv", "value")


@pytest.mark.parametrize(
    ("body", "needle"),
    [
        ("displacement,friction\n0,1\n1,abc\n", "'abc'"),
        ("displacement,friction\n0,1\n1,nan\n", "finite"),
        ("displacement,friction\n0,1\n1\n", "line 3 has 1 cells"),
        ("0,1\n1,2\n", "header"),
        ("", "empty"),
    ],
)
def test_bad_data_rows(tmp_path, capsys, body, needle):
    path = tmp_path / "d.csv"
    path.write_text(body, encoding="utf-8")
    assert main(["fit", str(path), "--kind", "presliding", "-o", str(tmp_path / "f")]) == 2
    one_error_line(capsys, "d.csv", needle)


def test_bad_parameter_from_the_library(tmp_path, capsys):
    path = tmp_path / "flat.csv"
    path.write_text("displacement,friction\n" + "".join(f"{i},1.0\n" for i in range(20)))
    assert main(["fit", str(path), "--kind", "presliding", "-o", str(tmp_path / "f")]) == 2
    one_error_line(capsys, "flat.csv", "cannot fit")
    assert (
        main(
            [
                "fit",
                str(path),
                "--kind",
                "presliding",
                "--elements",
                "-1",
                "-o",
                str(tmp_path / "f"),
            ]
        )
        == 2
    )
    one_error_line(capsys, "--elements")
    assert (
        main(
            [
                "fit",
                str(path),
                "--kind",
                "presliding",
                "--scale",
                "position=zero",
                "-o",
                str(tmp_path / "f"),
            ]
        )
        == 2
    )
    one_error_line(capsys, "--scale")


def test_output_never_overwrites_an_input(tmp_path, model_file, capsys):
    u = tmp_path / "u.csv"
    original = "time,value\n0,0.5\n"
    u.write_text(original, encoding="utf-8")
    assert main(["simulate", str(model_file), "--applied-force", str(u), "-o", str(u)]) == 2
    one_error_line(capsys, "u.csv", "input")
    assert u.read_text() == original
    out = tmp_path / "fitdir"
    out.mkdir()
    data = out / "report.md"  # a data file where the fit writes its report
    data.write_text("displacement,friction\n0,1\n1,2\n", encoding="utf-8")
    assert main(["fit", str(data), "--kind", "presliding", "-o", str(out)]) == 2
    one_error_line(capsys, "report.md", "input")
    assert data.read_text() == "displacement,friction\n0,1\n1,2\n"


def test_existing_files_presliding_did_not_write_are_kept(tmp_path, model_file, capsys):
    out = tmp_path / "run"
    out.mkdir()
    mine = out / "simulation.png"
    mine.write_bytes(b"the user's own figure")
    assert main(["simulate", str(model_file), "-o", str(out)]) == 2
    one_error_line(capsys, "simulation.png", "not written by presliding", "--overwrite")
    assert mine.read_bytes() == b"the user's own figure"
    assert sorted(p.name for p in out.iterdir()) == ["simulation.png"]  # nothing written
    # --overwrite replaces it; later runs replace their own outputs without asking
    assert main(["simulate", str(model_file), "-o", str(out), "--overwrite", "--quiet"]) == 0
    assert _is_png(mine)
    assert main(["simulate", str(model_file), "-o", str(out), "--quiet"]) == 0
    listed = (out / MANIFEST).read_text(encoding="utf-8").splitlines()
    assert [n for n in listed if not n.startswith("#")] == ["simulation.csv", "simulation.png"]
    # an input file stays protected even with --overwrite
    u = tmp_path / "u.csv"
    u.write_text("time,value\n0,0.5\n", encoding="utf-8")
    args = ["simulate", str(model_file), "--applied-force", str(u), "-o", str(u), "--overwrite"]
    assert main(args) == 2
    one_error_line(capsys, "u.csv", "input")
    assert u.read_text(encoding="utf-8") == "time,value\n0,0.5\n"


def test_a_run_that_fails_on_its_options_creates_no_folder(tmp_path, model_file, capsys):
    out = tmp_path / "never"
    assert main(["simulate", str(model_file), "--step", "-1", "-o", str(out)]) == 2
    one_error_line(capsys, "step")
    assert not out.exists()


def test_demo_output_must_be_a_folder(tmp_path, capsys):
    f = tmp_path / "file"
    f.write_text("x")
    assert main(["demo", "-o", str(f)]) == 2
    one_error_line(capsys, "is a file")


def test_debug_shows_the_traceback(tmp_path):
    with pytest.raises(ValueError, match=r"absent\.toml"):
        main(["--debug", "analyze", str(tmp_path / "absent.toml")])


# ---------------------------------------------------------------------- progress, CSV output
def test_progress_only_on_a_terminal(monkeypatch):
    import io

    from presliding._progress import progress, progress_enabled

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    monkeypatch.setattr(sys, "stderr", Terminal())
    assert progress_enabled() and not progress_enabled(quiet=True)
    with progress(2, "working", unit="part") as bar:
        bar.update(2)
    assert "working" in sys.stderr.getvalue()
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    assert not progress_enabled()
    with progress(2, "silent") as bar:
        bar.update(2)
    assert sys.stderr.getvalue() == ""


def test_write_csv_in_blocks(tmp_path, monkeypatch):
    from presliding.cli import common as _cli_common

    monkeypatch.setattr(_cli_common, "CSV_BLOCK", 7)
    cols = [np.linspace(0.0, 1.0, 50), np.sin(np.arange(50.0)) / 3]
    path = tmp_path / "x.csv"
    _cli_common.write_csv(path, ["a [s]", "b [N]"], cols)
    assert path.read_text().splitlines()[0] == "a [s],b [N]"
    np.testing.assert_allclose(np.loadtxt(path, delimiter=",", skiprows=1).T, cols, rtol=1e-14)
    assert [p.name for p in tmp_path.iterdir()] == ["x.csv"]


def test_simulate_a_continuous_density(tmp_path, capsys):
    path = tmp_path / "dens.toml"
    path.write_text(
        '[friction]\ncoulomb = 0.1\n[friction.density]\nkind = "exponential"\nheight = 7e7\n'
        "length = 1e-4\n[motion]\nmass = 1.0\ninitial_velocity = 0.06\n"
        'initial_state = "saturated"\n'
        "t_end = 0.3\nsamples = 301\n",
        encoding="utf-8",
    )
    out = tmp_path / "run.csv"
    assert main(["simulate", str(path), "--step", "1e-5", "-o", str(out)]) == 0
    assert "method implicit" in capsys.readouterr().out
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    pred = analysis.turning_points(load_model(path).model, 1.0, 0.06, "saturated")
    assert data[-1, 2] == 0.0  # at rest, exactly
    assert data[-1, 1] == pytest.approx(pred.rest_position, rel=5e-4)
    assert main(["simulate", str(path), "--step", "-1", "-o", str(out)]) == 2
    one_error_line(capsys, "`--step` must be positive")  # the option, checked on parsing


def test_simulate_asks_for_the_mass_and_a_start_instead_of_defaults(tmp_path, capsys):
    """A fitted model without [motion] is refused (not 1 kg and v0 = 0, "stops at t = 0")."""
    path = tmp_path / "fitted.toml"
    path.write_text("[friction]\ncoulomb = 0.3\nstiffness = [2e4]\nbreakaway = [0.2]\n")
    out = tmp_path / "run"
    assert main(["simulate", str(path), "-o", str(out)]) == 2
    one_error_line(capsys, "no `motion.mass`")
    assert main(["simulate", str(path), "--mass", "2", "-o", str(out)]) == 2
    one_error_line(capsys, "nothing sets the mass in motion")
    assert not out.exists()
    argv = ["simulate", str(path), "--mass", "2", "--initial-velocity", "0.05", "-o", str(out)]
    assert main(argv) == 0
    data = np.loadtxt(out / "simulation.csv", delimiter=",", skiprows=1)
    ref = ps.simulate(load_model(path).model, 2.0, initial_velocity=0.05,
                      t_eval=np.linspace(0.0, 1.0, 2001))  # fmt: skip
    np.testing.assert_allclose(data[:, 1], ref.position, rtol=1e-13, atol=1e-15)


def test_a_free_motion_still_moving_at_the_end_exits_1(tmp_path, capsys):
    path = tmp_path / "m.toml"
    path.write_text(MODEL_TOML.replace("t_end = 0.12", "t_end = 0.002"))
    assert main(["simulate", str(path), "-o", str(tmp_path / "run")]) == 1
    out = capsys.readouterr().out
    assert "still moving at t_end = 0.002 s" in out and "exit status 1" in out


def test_analyze_names_y_e_as_the_travel_back_from_the_first_turning_point(model_file, capsys):
    assert main(["analyze", str(model_file)]) == 0
    out = capsys.readouterr().out
    assert "second turning point y_e" not in out
    assert "travel back y_e (eq. 15)" in out and "from the 1st turning point to the 2nd" in out
