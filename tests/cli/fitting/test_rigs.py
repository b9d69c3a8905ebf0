"""Rigs as they come: per-signal files, trailing tabs, stops in one file, held-out files."""

from __future__ import annotations

import numpy as np
import pytest

import presliding as ps
from presliding.cli import main
from presliding.model_io import MotionSettings, load_model, save_model
from tests.helpers import one_error_line
from tests.measurement.test_segments import MODEL, servo_record


def _servo_file(tmp_path, name="servo.txt", seed=0, n_stops=4):
    """A headerless servo export: time, position [m], force [N]; every line ends in a tab."""
    t, y, u, _ = servo_record(n_stops, seed=seed)
    path = tmp_path / name
    path.write_text(
        "".join(f"{a:.6f}\t{b:.9g}\t{c:.6g}\t\n" for a, b, c in zip(t, y, u, strict=False))
    )
    return path


COLUMNS = ["--columns", "time=0", "position=1", "applied_force=2"]


def test_stops_cut_from_headerless_tab_ended_files_are_pooled(tmp_path, capsys):
    paths = [_servo_file(tmp_path, f"servo{i}.txt", seed=i) for i in range(2)]
    out = tmp_path / "fit"
    code = main(["fit", *map(str, paths), "--kind", "response", "--elements", "1", "--signal",
                 "position", "--no-header", *COLUMNS, "--segments", "stops",
                 "--no-cross-validation", "-o", str(out)])  # fmt: skip
    assert code == 0, capsys.readouterr()
    report = (out / "report.md").read_text()
    assert "## Segments" in report and "4 stops cut from servo0.txt" in report
    text = (out / "model.toml").read_text()
    # provenance: every file named, no record's own start in [motion]
    assert "servo0.txt #1" in text and "servo1.txt #4" in text
    assert "8 records pooled" in text
    spec = load_model(out / "model.toml")
    assert spec.model.coulomb_level == pytest.approx(MODEL.coulomb_level, rel=0.03)
    motion = text.split("[motion]")[1].split("[measurement]")[0]
    assert "mass = " in motion and "initial_velocity = 0.0" in motion
    assert spec.motion.initial_position == 0.0 and spec.motion.initial_state == "relaxed"


def test_one_column_for_two_signals_is_an_error(tmp_path, capsys):
    path = _servo_file(tmp_path)
    code = main(["fit", str(path), "--kind", "motion", "--columns", "time=0", "position=1",
                 "applied_force=1", "-o", str(tmp_path / "fit")])  # fmt: skip
    assert code == 2
    one_error_line(capsys, "given to both `position` and `applied_force`")


def _joint_files(tmp_path, k, seed):
    """A joint's position (degrees) and torque (N m) in files of their own."""
    t, y, u, _ = servo_record(2, seed=seed)
    q, tau = tmp_path / f"q{k}.txt", tmp_path / f"tau{k}.txt"
    np.savetxt(q, np.column_stack([t, np.degrees(y)]), header="t [s]\tq [deg]", comments="",
               delimiter="\t")  # fmt: skip
    np.savetxt(tau, np.column_stack([t, u]), header="t [s]\ttau [N m]", comments="",
               delimiter="\t")  # fmt: skip
    return str(q), str(tau)


def test_per_signal_files_are_joined_on_the_command_line(tmp_path, capsys):
    groups = [_joint_files(tmp_path, k, seed=k) for k in range(2)]
    out = tmp_path / "fit"
    argv = ["fit", "--join", f"{groups[0][0]}=position", f"{groups[0][1]}=applied_force",
            "--join", f"{groups[1][0]}=position", f"{groups[1][1]}=applied_force",
            "--kind", "response", "--elements", "1", "--signal", "position", "--segments",
            "stops", "--no-cross-validation", "-o", str(out)]  # fmt: skip
    assert main(argv) == 0, capsys.readouterr()
    text = (out / "model.toml").read_text()
    assert "q0.txt + tau0.txt #1" in text and "q1.txt + tau1.txt #2" in text
    assert "# k_j [N m/rad]" in text and "# [kg m^2]" in text
    assert "q [deg]" in text  # each file's columns and units are listed
    fitted = load_model(out / "model.toml").model
    assert fitted.coulomb_level == pytest.approx(MODEL.coulomb_level, rel=0.05)


def test_predict_held_out_files_from_a_model_file(tmp_path, capsys):
    model = tmp_path / "model.toml"
    save_model(model, MODEL, MotionSettings(mass=2.0))
    t, y, u, _ = servo_record(1, seed=5)
    data = tmp_path / "stop.csv"
    np.savetxt(data, np.column_stack([t, y * 1e3, u]), delimiter=";", comments="",
               header="t [s];x [mm];u [N]")  # fmt: skip
    eu = tmp_path / "stop_eu.csv"
    eu.write_text(data.read_text().replace(".", ","))
    out = tmp_path / "pred"
    code = main(["predict", str(model), str(data), str(eu), "--columns", "time=t", "position=x",
                 "applied_force=u", "--decimal", ",", "--signal", "position",
                 "--reversal-tolerance", "3e-6", "-o", str(out)])  # fmt: skip
    assert code == 0, capsys.readouterr()
    printed = capsys.readouterr().out
    assert "3 encoder counts of 1e-06 m" in printed
    rows = np.genfromtxt(out / "predictions.csv", delimiter=",", names=True)
    assert rows.shape == (4,)  # two files, two starts each
    assert np.all(rows["nrmse"] < 0.02)  # the true model predicts its own data
    assert np.all(rows["reversal_tolerance"] == 3e-6)
    report = (out / "report.md").read_text()
    assert "initial_velocity = " in report and "measured" in report
    assert (out / "prediction_1.png").exists()


def test_a_model_file_without_a_mass_cannot_predict(tmp_path, capsys):
    model = tmp_path / "model.toml"
    save_model(model, MODEL)
    path = _servo_file(tmp_path)
    assert main(["predict", str(model), str(path), *COLUMNS, "-o", str(tmp_path / "p")]) == 2
    one_error_line(capsys, "has no [motion] mass")


def test_fit_with_held_out_files(tmp_path, capsys):
    paths = [str(_servo_file(tmp_path, f"s{i}.txt", seed=i, n_stops=2)) for i in range(2)]
    held = str(_servo_file(tmp_path, "held.txt", seed=9, n_stops=1))
    out = tmp_path / "fit"
    code = main(["fit", *paths, "--kind", "response", "--elements", "1", *COLUMNS,
                 "--signal", "position", "--segments", "stops", "--no-cross-validation",
                 "--hold-out", held, "-o", str(out)])  # fmt: skip
    assert code == 0, capsys.readouterr()
    report = (out / "report.md").read_text()
    # the held-out file is cut into its stop as the fitted ones were (--segments stops)
    assert "## Held-out files" in report and "| held.txt #1 | measured |" in report
    assert "| held.txt #1 | fitted |" in report and (out / "held_out_1.png").exists()
    assert "1 stops cut from held.txt" in report
    # the cut stated (its values) and drawn
    assert "cut with rest speed" in report and (out / "segments.png").exists()
    head = (out / "model.toml").read_text().split("[friction]")[0]
    assert "2 stops cut from s0.txt:" in head and "cut with rest speed" in head
    assert ps.reversal_tolerance is not None


def _ramp_files(tmp_path, retreat_quanta=4):
    """Quantised loading ramps of both signs, no time column, the encoder jittering back by
    several counts where the contact slides (the force stays the virgin curve's: these
    samples are on it, so a virgin-curve fit describes every one)."""
    model = ps.PIFriction(0.1, [1e4, 3e3, 1e3], breakaway=[0.2, 0.2, 0.2])
    rng = np.random.default_rng(4)
    paths = []
    for k, sign in enumerate((1.0, -1.0, 1.0)):
        y = sign * np.linspace(0.0, 8e-4, 400)
        f = model.force(1e-6 * np.round(y / 1e-6))[0]
        for i in rng.choice(np.arange(150, 390), 3, replace=False):  # beyond every threshold
            y[i : i + 3] -= sign * retreat_quanta * 1e-6
        y = 1e-6 * np.round(y / 1e-6)
        path = tmp_path / f"ramp{k}.txt"
        np.savetxt(path, np.column_stack([y * 1e6, f]), delimiter="\t", fmt="%.9g")
        paths.append(str(path))
    return paths


def test_virgin_ramps_without_time_are_detected_and_fitted(tmp_path, capsys):
    paths = _ramp_files(tmp_path)
    cols = ["--columns", "position=0", "friction_force=1", "--units", "position=um"]
    out = tmp_path / "virgin"
    assert main(["fit", *paths, "--kind", "virgin", *cols, "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "1197 samples" in printed  # every sample of the ramps (as loops they cannot fit)
    fitted = load_model(out / "model.toml").model
    assert fitted.coulomb == pytest.approx(0.1, abs=0.01)
    out2 = tmp_path / "virgin2"
    assert main(["fit", *paths, "--kind", "virgin", *cols, "--ramps", "-o", str(out2)]) == 0
    capsys.readouterr()
    code = main(["fit", *paths, "--kind", "virgin", *cols, "--density", "uniform", "-o",
                 str(tmp_path / "v3")])  # fmt: skip
    assert code == 2
    one_error_line(
        capsys,
        "--density uniform: --kind virgin does not use it (it is for --kind "
        "response, quasi-static)",
    )


def _raw_ramp_files(tmp_path):
    """Raw ramp files as a rig writes them: rest, loading, hold, unloading, rest (time,
    position in mm, force in N; quantised position, force noise)."""
    model = ps.PIFriction(0.1, [1e4, 3e3, 1e3], breakaway=[0.2, 0.2, 0.2])
    rng = np.random.default_rng(1)
    paths = []
    for k, sign in enumerate((1.0, -1.0, 1.0)):
        up, down = np.linspace(0, 8e-4, 400), np.linspace(8e-4, 0, 400)
        y = sign * np.concatenate([np.zeros(50), up, np.full(50, 8e-4), down, np.zeros(50)])
        y = 1e-6 * np.round(y / 1e-6)
        f = model.force(y)[0] + 2e-3 * rng.standard_normal(y.size)
        path = tmp_path / f"raw{k}.csv"
        np.savetxt(
            path,
            np.column_stack([np.arange(y.size) * 1e-3, y * 1e3, f]),
            fmt="%.9g",
            delimiter=",",
            header="Time [s],Position [mm],Force [N]",
            comments="",
        )
        paths.append(str(path))
    return paths


@pytest.mark.parametrize("how", [[], ["--ramps"], ["--segments", "ramps"]])
def test_virgin_fits_raw_ramp_files(tmp_path, capsys, how):
    """Each exited 2: "at least two turning points", "must end away from its start"."""
    out = tmp_path / "virgin"
    code = main(["fit", *_raw_ramp_files(tmp_path), "--kind", "virgin", *how, "-o", str(out)])
    assert code == 0, capsys.readouterr()
    assert "a virgin loading from rest, then returns by Masing's rule" in capsys.readouterr().out
    fitted = load_model(out / "model.toml").model
    assert fitted.coulomb == pytest.approx(0.1, rel=0.02)
    np.testing.assert_allclose(fitted.stiffness, [1e4, 3e3, 1e3], rtol=0.02)
