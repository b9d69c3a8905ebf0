"""``presliding fit`` on real-world files: units, headerless files, MAT files, windows, status."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from scipy import io

import presliding as ps
from presliding.cli import main
from presliding.cli.fitting.fit import model_problem, parse_window
from presliding.cli.simulation.simulate import read_applied_force
from presliding.model_io import load_model
from presliding.signals import piecewise_linear
from tests.helpers import one_error_line

TRUE = ps.PIFriction(0.5, [500.0, 50.0, 4.0], [1.0, 1.0, 1.0])


def _loops(scale_y=1.0, scale_f=1.0):
    y = piecewise_linear([0.0, 0.8, -0.8, 0.4, -0.2, 0.1, -0.05, 0.6, -0.6], 1e-3)
    force, _ = TRUE.force(y)
    t = np.arange(y.shape[0]) * 1e-3
    return t, y * scale_y, force * scale_f


def _fit(tmp_path, data, *options, out="fit"):
    return main(["fit", str(data), "--kind", "presliding", *options, "-o", str(tmp_path / out)])


def test_units_in_the_header_are_converted(tmp_path, capsys):
    t, y, f = _loops(1e3, 1e3)  # mm and mN
    path = tmp_path / "loops.csv"
    np.savetxt(path, np.column_stack([t * 1e3, y, f]), delimiter=";", comments="",
               header="t [ms];Position [mm];Friction [mN]")  # fmt: skip
    assert _fit(tmp_path, path) == 0
    out = capsys.readouterr().out
    assert "'Position [mm]' in mm → m (× 0.001)" in out and "stiffness_1" in out
    model_file = tmp_path / "fit" / "model.toml"
    fitted = load_model(model_file).model
    np.testing.assert_allclose(fitted.stiffness, TRUE.stiffness, rtol=1e-6)
    np.testing.assert_allclose(fitted.breakaway, TRUE.breakaway, rtol=1e-6)
    head = model_file.read_text().split("[friction]")[0]
    assert "# data: text file" in head and "'Friction [mN]' in mN → N (× 0.001)" in head
    report = (tmp_path / "fit" / "report.md").read_text()
    assert "Position [mm]" in report and " N/m " in report


def test_headerless_files_by_index_with_units_and_a_window(tmp_path, capsys):
    t, y, f = _loops()
    path = tmp_path / "loops.txt"
    np.savetxt(path, np.column_stack([t, y * 1e6, f]))  # whitespace, no header; y in um
    assert _fit(tmp_path, path) == 2
    one_error_line(capsys, "no header line", "--columns time=0 position=1")
    cols = ["--columns", "time=0", "position=1", "friction_force=2", "--units", "position=um"]
    assert _fit(tmp_path, path, *cols, "--window", ":5") == 0
    out = capsys.readouterr().out
    assert "window: start to 5 s" in out and "taken as N (no unit given)" in out
    fitted = load_model(tmp_path / "fit" / "model.toml").model
    np.testing.assert_allclose(fitted.stiffness, TRUE.stiffness, rtol=1e-5)
    assert _fit(tmp_path, path, *cols, "--window", "50:60") == 2
    one_error_line(capsys, "--window 50:60", "at least 2 samples")


@pytest.mark.parametrize("text", ["8", "a:b", "1:inf", "::"])
def test_bad_windows(text):
    with pytest.raises(ValueError, match="--window"):
        parse_window(text)


def test_window_bounds_parse():
    assert parse_window("8:210") == (8.0, 210.0)
    assert parse_window(":5") == (None, 5.0) and parse_window(None) is None


def _motion_mat(tmp_path):
    """A Coulomb mass driven by a sampled voltage, force = gain × voltage, plus an offset."""
    true, mass, gain, offset = ps.PIFriction(20.0), 95.0, 35.0, -3.0
    t = np.arange(0.0, 4.0, 1e-3)
    u = 60.0 * np.sin(2 * np.pi * 0.5 * t)
    res = ps.simulate(true, mass, applied_force=(t, u - offset), t_eval=t)
    path = tmp_path / "rig.mat"
    io.savemat(path, {"t": t[:, None], "qm": res.position[:, None], "vir": (u / gain)[:, None],
                      "gtau": gain, "qd": res.velocity, "qdd": res.acceleration})  # fmt: skip
    return path, t, u, mass, offset


def test_mat_files_scale_by_a_variable_and_round_trip_through_simulate(tmp_path, capsys):
    path, t, u, mass, offset = _motion_mat(tmp_path)
    args = ["fit", str(path), "--kind", "motion", "--offset", "--columns", "time=t",
            "position=qm", "velocity=qd", "acceleration=qdd", "applied_force=vir",
            "--scale", "applied_force=gtau", "-o", str(tmp_path / "fit")]  # fmt: skip
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "scaled × 35 (variable gtau)" in out
    spec = load_model(tmp_path / "fit" / "model.toml")
    assert spec.motion.mass == pytest.approx(mass, rel=1e-5)
    assert spec.model.coulomb == pytest.approx(20.0, rel=1e-5)
    assert spec.measurement.force_offset == pytest.approx(offset, abs=1e-4)
    # fit → save → load is exact: the file holds the library's fitted values bit for bit
    meas = ps.Measurement.from_mat(
        path, position="qm", velocity="qd", acceleration="qdd", applied_force="vir",
        scale={"applied_force": "gtau"},
    )  # fmt: skip
    res = ps.fit_motion(meas, offset=True)
    assert spec.motion.mass == res.parameters["mass"]
    assert spec.model.coulomb == res.parameters["coulomb"]
    assert spec.measurement.force_offset == res.parameters["offset"]
    # the file holds the fitted values exactly, and simulate applies u − F_0 with them
    force = tmp_path / "u.csv"
    np.savetxt(force, np.column_stack([t, u]), delimiter=",", header="time,value", comments="")
    sim_args = ["simulate", str(tmp_path / "fit" / "model.toml"), "--applied-force", str(force)]
    assert main([*sim_args, "-o", str(tmp_path / "sim.csv"), "--quiet"]) == 0
    data = np.loadtxt(tmp_path / "sim.csv", delimiter=",", skiprows=1)
    f0 = spec.measurement.force_offset
    ref = ps.simulate(spec.model, spec.motion.mass, applied_force=(t, u - f0),
                      t_eval=np.linspace(0.0, spec.motion.t_end, spec.motion.samples))  # fmt: skip
    np.testing.assert_allclose(data[:, 1], ref.position, rtol=1e-12, atol=1e-15)
    # a CSV cannot name a variable
    csv = tmp_path / "d.csv"
    csv.write_text("t,x,u\n0,0,1\n1,1,2\n2,0,1\n")
    assert main(["fit", str(csv), "--kind", "motion", "--scale", "applied_force=gtau",
                 "-o", str(tmp_path / "g")]) == 2  # fmt: skip
    one_error_line(capsys, "--scale applied_force=gtau", "MATLAB files only")


def test_a_csv_with_a_mat_suffix_and_binary_data_are_named(tmp_path, capsys):
    fake = tmp_path / "data.mat"
    fake.write_text("t,x\n0,1\n")
    assert _fit(tmp_path, fake) == 2
    one_error_line(capsys, "data.mat", "is a text file, not a MATLAB file")
    blob = tmp_path / "blob.csv"
    blob.write_bytes(b"\x00\xff\x10" * 50)
    assert _fit(tmp_path, blob) == 2
    one_error_line(capsys, "blob.csv", "not a text file")


def test_a_flipped_sign_is_a_poor_fit_with_exit_1_and_no_model(tmp_path, capsys):
    _, y, f = _loops()
    path = tmp_path / "loops.csv"
    np.savetxt(path, np.column_stack([y, f]), delimiter=",", header="position,friction",
               comments="")  # fmt: skip
    assert _fit(tmp_path, path) == 0
    assert (tmp_path / "fit" / "model.toml").exists()
    capsys.readouterr()
    assert _fit(tmp_path, path, "--scale", "friction_force=-1") == 1
    out = capsys.readouterr().out
    assert "poor_fit" in out and "sign" in out and "No model.toml written" in out
    assert not (tmp_path / "fit" / "model.toml").exists()  # the earlier run's is gone
    assert "poor_fit" in (tmp_path / "fit" / "report.md").read_text()


def test_model_problem_refuses_absurd_or_failed_models():
    meas = SimpleNamespace(position=np.array([0.0, 0.8]))
    ok = SimpleNamespace(status="converged", model=TRUE, parameters={"coulomb": 0.5})
    assert model_problem(ok, meas) == ""
    wild = ps.PIFriction(0.5, [1e-9], threshold=[7.5e9])
    bad = SimpleNamespace(status="not_identifiable", model=wild, parameters={"coulomb": 0.5})
    assert "times the measured travel" in model_problem(bad, meas)
    poor = SimpleNamespace(status="poor_fit", model=TRUE, parameters={})
    assert "poor_fit" in model_problem(poor, meas)
    inf = SimpleNamespace(status="at_bound", model=TRUE, parameters={"coulomb": np.inf})
    assert "not finite" in model_problem(inf, meas)


def test_a_byte_order_mark_in_an_applied_force_file(tmp_path):
    path = tmp_path / "u.csv"
    path.write_bytes("\ufefftime,value\n0,1\n1,2\n".encode())
    _, u = read_applied_force(path)
    np.testing.assert_array_equal(u, [1.0, 2.0])


def test_analyze_says_when_it_replaces_a_zero_initial_velocity(tmp_path, capsys):
    path = tmp_path / "m.toml"
    path.write_text("[friction]\ncoulomb = 0.3\nstiffness = [2e4]\nbreakaway = [0.7]\n")
    assert main(["analyze", str(path)]) == 0
    assert "initial_velocity is 0, so the free motion starts at 1 m/s" in capsys.readouterr().out


def test_progress_on_a_terminal_unless_quiet_and_the_same_model(tmp_path, capsys, monkeypatch):
    """Off a terminal a fit prints no progress; on one (stderr taken for a terminal here, so
    the progress comes as plain lines) it shows its parts, stages and the global search from
    the start; --quiet prints nothing; the fitted model does not depend on it."""
    t, y, f = _loops()
    path = tmp_path / "loops.csv"
    np.savetxt(path, np.column_stack([t, y, f]), delimiter=",", comments="",
               header="time,position,friction_force")  # fmt: skip
    options = ("--search", "global", "--seed", "3")
    monkeypatch.setattr("presliding.cli.fitting.fit.PROGRESS_DELAY", 0.0)
    assert _fit(tmp_path, path, *options, out="piped") == 0
    assert capsys.readouterr().err == ""
    monkeypatch.setattr(
        "presliding.cli.fitting.fit.progress_enabled", lambda quiet=False: not quiet
    )
    assert _fit(tmp_path, path, *options, out="loud") == 0
    lines = capsys.readouterr().err.splitlines()
    assert lines[0] == "presliding fit: [1/3] reading loops.csv"
    assert f"presliding fit: [2/3] fitting (--kind presliding, {t.shape[0]} samples)" in lines
    assert "presliding fit: linear start on a grid of 48 thresholds" in lines
    assert any(ln.startswith("presliding fit: global search: generation") for ln in lines)
    assert lines[-1] == f"presliding fit: [3/3] writing {tmp_path / 'loud'}"
    assert _fit(tmp_path, path, *options, "--quiet", out="quiet") == 0
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == ""
    loud, quiet = (
        (tmp_path / name / "model.toml").read_text().split("[friction]")[1]
        for name in ("loud", "quiet")
    )
    assert loud == quiet
    assert (tmp_path / "piped" / "model.toml").read_text().split("[friction]")[1] == loud


def test_motion_fit_with_asymmetric_friction(tmp_path, capsys):
    """--asymmetric: c1⁺, c1⁻, σ⁺ and σ⁻ from a MAT file, written to the model file."""
    true = ps.PIFriction(20.0, coulomb_negative=12.0, viscous=150.0, viscous_negative=220.0)
    mass, gain = 95.0, 35.0
    t = np.arange(0.0, 4.0, 1e-3)
    u = 80.0 * np.sin(2 * np.pi * 0.5 * t)
    res = ps.simulate(true, mass, applied_force=(t, u), hold="zoh", t_eval=t)
    path = tmp_path / "rig.mat"
    io.savemat(path, {"t": t[:, None], "qm": res.position[:, None], "vir": (u / gain)[:, None],
                      "gtau": gain, "qd": res.velocity, "qdd": res.acceleration})  # fmt: skip
    args = ["fit", str(path), "--kind", "motion", "--viscous", "--asymmetric", "--columns",
            "time=t", "position=qm", "velocity=qd", "acceleration=qdd", "applied_force=vir",
            "--scale", "applied_force=gtau", "-o", str(tmp_path / "fit")]  # fmt: skip
    assert main(args) == 0
    assert "coulomb_negative" in capsys.readouterr().out
    spec = load_model(tmp_path / "fit" / "model.toml")
    model = spec.model
    assert spec.motion.mass == pytest.approx(mass, rel=1e-4)
    assert (model.coulomb, model.coulomb_negative) == pytest.approx((20.0, 12.0), rel=1e-4)
    assert (model.viscous, model.viscous_negative) == pytest.approx((150.0, 220.0), rel=1e-4)
    text = (tmp_path / "fit" / "model.toml").read_text(encoding="utf-8")
    assert "--asymmetric" in text and "coulomb_negative" in text
    assert main([*args[:-1], str(tmp_path / "g"), "--offset"]) == 2


def test_presliding_fit_with_asymmetric_friction(tmp_path, capsys):
    """--asymmetric with --kind presliding (ignored before): c1⁻ fitted, tested against the
    symmetric fit in the report, written to the model file."""
    t, y, _ = _loops()
    sided = ps.PIFriction(TRUE.coulomb, TRUE.stiffness, TRUE.breakaway,
                          coulomb_negative=0.5 * TRUE.coulomb)  # fmt: skip
    path = tmp_path / "loops.csv"
    np.savetxt(path, np.column_stack([t, y, sided.force(y)[0]]), delimiter=",", comments="",
               header="time,position,friction")  # fmt: skip
    assert _fit(tmp_path, path, "--asymmetric") == 0
    assert "asymmetry: supported" in capsys.readouterr().out
    model = load_model(tmp_path / "fit" / "model.toml").model
    assert model.coulomb_negative == pytest.approx(0.5 * TRUE.coulomb, rel=1e-6)
