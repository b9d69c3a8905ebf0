"""Column roles: the force column is taken or the user told why not; a model file's mapping is
what `presliding predict` reads new files by."""

from __future__ import annotations

import argparse
import shlex
from pathlib import Path

import numpy as np
import pytest

from presliding.cli import main
from presliding.cli.example_data import TRUTH
from presliding.cli.example_data import run as write_examples
from presliding.cli.inputs.columns import assign_columns
from presliding.model_io import DataSettings, MotionSettings, load_model, save_model
from tests.helpers import one_error_line


def _examples(folder: Path) -> Path:
    write_examples(argparse.Namespace(output=folder, overwrite=False, quiet=True))
    return folder


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    """Two stops fitted (the files' header: Time [s],Position [mm],Force [N]), one held out."""
    data = _examples(tmp_path_factory.mktemp("examples"))
    out = data / "fit"
    argv = ["fit", str(data / "stop_1.csv"), str(data / "stop_2.csv"), "--kind", "response",
            "--elements", "1", "--hold-out", str(data / "stop_4.csv"),
            "--no-cross-validation", "--quiet", "-o", str(out)]  # fmt: skip
    return data, out, main(argv)


def test_the_force_column_is_taken_and_said_so(fitted):
    """It was dropped: the records were fitted free, per unit mass, exit 1."""
    _, out, code = fitted
    assert code == 0
    report = (out / "report.md").read_text()
    assert "no record has an applied force" not in report
    assert ("applied_force = 'Force [N]' (its unit says force, and no other column does: "
            "--kind response takes it as the applied force u (eq. 17))") in report  # fmt: skip
    spec = load_model(out / "model.toml")
    assert spec.motion.mass == pytest.approx(TRUTH["stops"]["mass"], rel=0.02)
    assert spec.data.columns == {"time": "Time [s]", "position": "Position [mm]",
                                 "applied_force": "Force [N]"}  # fmt: skip


def test_the_model_file_reruns_as_written(fitted):
    """ "identified by" dropped --sample-rate and --hold-out."""
    _, out, _ = fitted
    line = (out / "model.toml").read_text().splitlines()[0]
    assert line == ("# identified by `presliding fit stop_1.csv stop_2.csv --kind response "
                    "--elements 1 --no-cross-validation --hold-out stop_4.csv`")  # fmt: skip


def test_predict_reads_new_files_as_the_model_file_states(fitted, tmp_path, capsys):
    """predict dropped the force the fit had used: 21.6 % NRMSE instead of 2 %."""
    data, out, _ = fitted
    capsys.readouterr()
    pred = tmp_path / "pred"
    assert main(["predict", str(out / "model.toml"), str(data / "stop_4.csv"), "-o",
                 str(pred)]) == 0  # fmt: skip
    printed = capsys.readouterr().out
    assert "Read as the model file's [data] table states: the columns time = 'Time [s]'" in printed
    assert "applied_force = 'Force [N]' (as the model file's [data] table states)" in printed
    rows = np.genfromtxt(pred / "predictions.csv", delimiter=",", names=True, dtype=None,
                         encoding="utf-8")  # fmt: skip
    assert list(rows["file_name"]) == ["stop_4.csv", "stop_4.csv"]  # the table names its files
    assert rows["nrmse"][0] < 0.05  # the measured start: the force drives it
    # a file whose force column has another name: found by its name, the difference said
    other = tmp_path / "renamed.csv"
    other.write_text((data / "stop_4.csv").read_text().replace("Force [N]", "u [N]", 1))
    assert main(["predict", str(out / "model.toml"), str(other), "-o", str(pred)]) == 0
    printed = capsys.readouterr().out
    assert ("applied_force = 'u [N]' (by its name; the model file reads it from 'Force [N]', "
            "which renamed.csv lacks)") in printed  # fmt: skip
    # a file without any force: predicted free, and said so
    bare = tmp_path / "bare.csv"
    lines = (data / "stop_4.csv").read_text().splitlines()
    bare.write_text("\n".join(",".join(ln.split(",")[:2]) for ln in lines) + "\n")
    main(["predict", str(out / "model.toml"), str(bare), "-o", str(pred)])
    assert ("no applied force: the model file reads it from 'Force [N]', which bare.csv "
            "lacks") in capsys.readouterr().out  # fmt: skip


def test_a_model_file_without_a_data_table_says_so(tmp_path, capsys):
    data = _examples(tmp_path / "ex")
    model = tmp_path / "model.toml"
    truth = TRUTH["stops"]
    import presliding as ps

    save_model(model, ps.PIFriction(truth["coulomb"], truth["stiffness"],
                                    breakaway=truth["breakaway"]),
               MotionSettings(mass=truth["mass"]))  # fmt: skip
    assert main(["predict", str(model), str(data / "stop_4.csv"), "-o",
                 str(tmp_path / "p")]) == 0  # fmt: skip
    printed = capsys.readouterr().out
    assert "The model file has no [data] table" in printed
    assert "applied_force = 'Force [N]' (its unit says force" in printed


def test_predict_cuts_as_the_model_file_states(tmp_path, capsys):
    """presliding predict takes --segments, and a model file's cut by default."""
    data = _examples(tmp_path / "ex")
    truth = TRUTH["stops"]
    import presliding as ps

    model = tmp_path / "model.toml"
    save_model(model, ps.PIFriction(truth["coulomb"], truth["stiffness"],
                                    breakaway=truth["breakaway"]),
               MotionSettings(mass=truth["mass"]),
               data=DataSettings(segments={"kind": "stops", "lead_in": 0.02}))  # fmt: skip
    pred = tmp_path / "pred"
    assert main(["predict", str(model), str(data / "servo.csv"), "-o", str(pred)]) == 0
    assert "the cut --segments stops --lead-in 0.02" in capsys.readouterr().out
    rows = np.genfromtxt(pred / "predictions.csv", delimiter=",", names=True)
    assert list(rows["segment"]) == [1, 1, 2, 2, 3, 3]
    assert np.all(rows["nrmse"][rows["fitted_start"] == 1] < 0.01)  # the true model
    assert main(["predict", str(model), str(data / "servo.csv"), "--segments", "none",
                 "-o", str(pred)]) == 0  # fmt: skip
    assert np.genfromtxt(pred / "predictions.csv", delimiter=",", names=True).shape == (2,)


def _roles(header: str, kind: str, **kw):
    return assign_columns(kind, header.split(","), {}, where="f.csv", **kw)


def test_column_roles_and_the_reasons_for_the_others():
    roles = _roles("Time [s],Normal [uN],Position [mm],Friction [uN]", "response")
    assert "applied_force" not in roles.taken
    assert roles.unused == {
        "Normal [uN]": "a normal load, which --kind response does not use",
        "Friction [uN]": "its name says friction force, which --kind response does not use (it "
        "takes applied_force); name it with --columns applied_force='Friction [uN]' if it is "
        "that",
    }
    roles = _roles("t [s],x [mm],torque [mN m],Temp [degC]", "motion")  # a torque: the input
    assert roles.taken["applied_force"][0] == "torque [mN m]"
    assert roles.unused["Temp [degC]"].startswith("its name says no signal --kind motion reads")
    roles = _roles("t [s],x [mm],torque [N m]", "presliding")  # a torque: the friction here
    assert roles.taken["friction_force"][0] == "torque [N m]"
    roles = _roles("t [s],x [mm],tau [N m]", "presliding")  # tau: a motor's, not taken
    assert "friction_force" not in roles.taken
    assert roles.unused["tau [N m]"].startswith("its name says applied force, which --kind "
                                                "presliding does not use")  # fmt: skip
    roles = _roles("t [s],x [mm],u [N],F [N]", "response")  # u by name; F said why not
    assert roles.taken["applied_force"][0] == "u [N]"
    assert roles.unused["F [N]"] == (
        "a force, but applied_force is 'u [N]' (--columns chooses another)"
    )


def test_two_force_columns_for_one_force_are_an_error(tmp_path, capsys):
    path = tmp_path / "two.csv"
    path.write_text("Time [s],Position [mm],F1 [N],F2 [N]\n0,0,1,2\n0.001,0.1,1,2\n")
    assert main(["fit", str(path), "--kind", "response", "-o", str(tmp_path / "o")]) == 2
    one_error_line(capsys, "the columns 'F1 [N]', 'F2 [N]' all hold a force",
                   "--columns applied_force=COLUMN")  # fmt: skip


def test_a_column_the_kind_does_not_use_is_refused(tmp_path, capsys):
    data = _examples(tmp_path / "ex")
    code = main(["fit", str(data / "stop_1.csv"), "--kind", "response", "--columns",
                 "friction_force=Force [N]", "-o", str(tmp_path / "o")])  # fmt: skip
    assert code == 2
    one_error_line(capsys, "--columns friction_force=Force [N]: --kind response does not use "
                   "`friction_force`")  # fmt: skip


def test_the_rerun_line_parses_back_to_the_same_options():
    from presliding.cli.command_line import rerun_line
    from presliding.cli.commands import _build_parser

    argv = ["fit", "a.csv", "b c.csv", "--kind", "response", "--columns", "time=Time [s]",
            "applied_force=2", "--units", "position=mm", "--sample-rate", "1000",
            "--no-header", "--decimal", ",", "--segments", "stops", "--lead-in", "0.02",
            "--hold-out", "held.csv", "--elements", "auto", "--prune", "--reversal-tolerance",
            "3e-6", "--window", "1:", "--seed", "4", "--bootstrap", "10", "-o", "out",
            "--overwrite"]  # fmt: skip
    parser = _build_parser()
    args = parser.parse_args(argv)
    line = rerun_line(args, args.command_parser, "fit")
    assert line.startswith("presliding fit a.csv 'b c.csv' --kind response")
    assert "-o" not in line.split() and "--overwrite" not in line
    again = parser.parse_args(shlex.split(line)[1:])
    for key, value in vars(args).items():
        if key not in ("output", "overwrite", "handler", "command_parser"):
            assert vars(again)[key] == value, key
