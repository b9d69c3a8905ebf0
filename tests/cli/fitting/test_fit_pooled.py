"""presliding fit FILE [FILE ...] for pooled response, quasi-static and virgin fits."""

from __future__ import annotations

import numpy as np
import pytest

import presliding as ps
from presliding.cli import main
from presliding.model_io import load_model
from tests.helpers import stop_records

MODEL = ps.PIFriction(0.3, [4000.0, 1000.0], breakaway=[0.35, 0.35])


def _stop_files(tmp_path, n=3, records=None):
    records = stop_records(7, n, MODEL)[0] if records is None else records
    paths = []
    for i, r in enumerate(records):
        path = tmp_path / f"stop{i + 1}.csv"
        np.savetxt(path, np.column_stack([r.time, r.position * 1e3, r.velocity, r.applied_force]),
                   delimiter=",", header="time [s],position [mm],velocity [m/s],applied_force [N]",
                   comments="")  # fmt: skip
        paths.append(str(path))
    return paths


def test_pooled_response_files_with_a_cross_validation_table(tmp_path, capsys):
    paths = _stop_files(tmp_path)
    out = tmp_path / "fit"
    code = main(["fit", *paths, "--kind", "response", "--elements", "2", "--signal", "both",
                 "--initial-state", "preload", "-o", str(out)])  # fmt: skip
    assert code == 0, capsys.readouterr().out
    spec = load_model(out / "model.toml")
    assert spec.model.coulomb == pytest.approx(0.3, rel=1e-4)
    assert spec.motion.mass == pytest.approx(2.0, rel=1e-4)
    report = (out / "report.md").read_text()
    assert "## Cross-validation" in report and "| stop2.csv |" in report
    assert "in 3 records" in report


def test_quasi_static_and_virgin_kinds(tmp_path):
    model = ps.PIFriction(0.05, [2e4, 6e3], breakaway=[0.2, 0.2])
    t = np.linspace(0.0, 4.0, 500)
    paths = []
    for i, (amp, f0) in enumerate([(0.35, 0.02), (0.3, -0.03)]):
        u = f0 + amp * np.sin(np.pi * t)
        state = ps.preloaded_state(model, f0, direction=-1.0)
        y = ps.quasi_static_response(model, u, state).position
        path = tmp_path / f"loop{i}.csv"
        np.savetxt(path, np.column_stack([t, y, u]), delimiter=",",
                   header="time,position,applied_force", comments="")  # fmt: skip
        paths.append(str(path))
    out = tmp_path / "qs"
    assert main(["fit", *paths, "--kind", "quasi-static", "--elements", "2", "--quiet",
                 "-o", str(out)]) == 0  # fmt: skip
    assert load_model(out / "model.toml").model.coulomb == pytest.approx(0.05, rel=1e-4)
    out = tmp_path / "virgin"
    assert main(["fit", *paths, "--kind", "virgin", "--elements", "2", "--quiet",
                 "-o", str(out)]) in (0, 1)  # fmt: skip
    assert "virgin curve fit" in (out / "report.md").read_text()


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (["--kind", "presliding"], "takes one data file"),
        (
            ["--kind", "response", "--max-evaluations", "0"],
            "`--max-evaluations` must be a positive integer; got 0",
        ),
        (["--kind", "response", "--bootstrap", "-1"], "`--bootstrap` must be nonnegative; got -1"),
    ],
)
def test_user_errors(tmp_path, capsys, extra, needle):
    paths = _stop_files(tmp_path, 2)
    assert main(["fit", *paths, *extra, "-o", str(tmp_path / "o")]) == 2
    assert needle in capsys.readouterr().err


def test_pooled_fits_show_each_left_out_record(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr("presliding.cli.fitting.fit.PROGRESS_DELAY", 0.0)
    monkeypatch.setattr(
        "presliding.cli.fitting.fit.progress_enabled", lambda quiet=False: not quiet
    )
    paths = _stop_files(tmp_path, 2)
    args = ["fit", *paths, "--kind", "response", "--elements", "2"]
    code = main([*args, "-o", str(tmp_path / "a")])  # two short stops: 0 or 1 (see the report)
    err = capsys.readouterr().err
    assert "presliding fit: [2/3] fitting (--kind response, 2 record(s))" in err
    assert "presliding fit: least squares: 2 record(s)" in err
    assert "presliding fit: cross-validation: stop2.csv left out (2 of 2)" in err
    assert main([*args, "--quiet", "-o", str(tmp_path / "b")]) == code
    assert capsys.readouterr().err == ""
    a, b = ((tmp_path / x / "model.toml").read_text().split("[friction]")[1] for x in "ab")
    assert a == b


def _quotient_files(tmp_path):
    """Stops whose velocity column is the position's difference quotient (as a drive logs)."""
    records, _ = stop_records(7, 3, MODEL)
    paths = []
    for i, r in enumerate(records):
        path = tmp_path / f"drive{i + 1}.csv"
        v = np.gradient(r.position, r.time)
        np.savetxt(path, np.column_stack([r.time, r.position, v, r.applied_force]),
                   delimiter=",", header="time [s],position [m],velocity [m/s],applied_force [N]",
                   comments="")  # fmt: skip
        paths.append(str(path))
    return paths


def test_velocity_option_says_what_the_velocity_column_is(tmp_path, capsys):
    """--velocity difference compares the model's own quotient: the truth to rounding;
    --velocity measured compares the exact model velocity with the quotient: biased."""
    paths = _quotient_files(tmp_path)
    common = ["--kind", "response", "--elements", "2", "--signal", "both", "--initial-state",
              "preload", "--no-cross-validation", "--quiet"]  # fmt: skip
    fits = {}
    for choice in ("difference", "measured"):
        out = tmp_path / choice
        code = main(["fit", *paths, *common, "--velocity", choice, "-o", str(out)])
        fits[choice] = (code, (out / "report.md").read_text())
    code, _ = fits["difference"]
    assert code == 0, capsys.readouterr()
    spec = load_model(tmp_path / "difference" / "model.toml")
    assert spec.model.coulomb == pytest.approx(0.3, rel=1e-8)
    assert spec.motion.mass == pytest.approx(2.0, rel=1e-8)
    code, report = fits["measured"]
    assert code == 1 and "not_identifiable" in report  # the quotient's bias: not the truth


@pytest.mark.parametrize("kind", ["quasi-static", "virgin"])
def test_velocity_option_is_refused_where_no_velocity_is_compared(tmp_path, capsys, kind):
    paths = _stop_files(tmp_path, 2)
    code = main(["fit", *paths, "--kind", kind, "--velocity", "measured", "--quiet",
                 "-o", str(tmp_path / "out")])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 2 and f"--velocity measured: --kind {kind} does not use it" in err, err


ASYMMETRIC = ps.PIFriction(0.3, [4000.0, 1000.0], breakaway=[0.35, 0.35], coulomb_negative=0.24,
                           breakaway_negative=[0.28, 0.28])  # fmt: skip


def _asymmetric_files(tmp_path, n=5):
    from tests.helpers import random_preload_stops

    return _stop_files(tmp_path, records=random_preload_stops(5, ASYMMETRIC, n_records=n,
                                                              samples=500))  # fmt: skip


def test_compare_families_table_and_exit_status(tmp_path, capsys):
    """--compare: each family fitted to the same files, the table in comparison.csv and the
    report, held-out files predicted by each; the asymmetric family wins on asymmetric stops,
    its model is written and the exit status is its fit's."""
    paths = _asymmetric_files(tmp_path)
    out = tmp_path / "cmp"
    code = main(["fit", *paths[:4], "--hold-out", paths[4], "--kind", "response", "--elements",
                 "2", "--initial-state", "preload", "--compare", "pi,pi-asymmetric,coulomb",
                 "--quiet", "-o", str(out)])  # fmt: skip
    assert code == 0, capsys.readouterr().err
    rows = (out / "comparison.csv").read_text().splitlines()
    assert rows[0].startswith("family,status,free parameters,RSS,AIC")
    assert [r.split(",")[0] for r in rows[1:]] == ["pi", "pi-asymmetric (supported)", "coulomb"]
    report = (out / "report.md").read_text()
    assert "## Model families" in report and "the data support pi-asymmetric" in report
    model = load_model(out / "model.toml").model
    assert model.coulomb_levels[1] / model.coulomb_levels[0] == pytest.approx(0.8, abs=0.01)
    assert "# model family pi-asymmetric: the least BIC" in (out / "model.toml").read_text()


@pytest.mark.parametrize(("extra", "needle"), [
    (["--kind", "quasi-static", "--compare", "pi"], "--compare pi: --kind quasi-static does"),
    (["--kind", "response", "--compare", "pi,lugre-x"], "name families of"),
    (["--kind", "response", "--compare", "pi", "--asymmetric"], "name pi-asymmetric"),
    (["--kind", "response", "--asymmetric", "--offset"], "--asymmetric: the two directions"),
])  # fmt: skip
def test_compare_and_asymmetric_refusals(tmp_path, capsys, extra, needle):
    paths = _stop_files(tmp_path, 2)
    assert main(["fit", *paths, *extra, "-o", str(tmp_path / "o")]) == 2
    assert needle in capsys.readouterr().err


def test_asymmetric_response_and_virgin_kinds(tmp_path, capsys):
    """--asymmetric is used by --kind response (F_c⁻ and the test in the report, an
    asymmetric model file) and by --kind virgin on ramps (refused on loops)."""
    paths = _asymmetric_files(tmp_path, 3)
    out = tmp_path / "r"
    code = main(["fit", *paths, "--kind", "response", "--elements", "2", "--initial-state",
                 "preload", "--asymmetric", "--no-cross-validation", "--quiet",
                 "-o", str(out)])  # fmt: skip
    assert code in (0, 1), capsys.readouterr().err
    report = (out / "report.md").read_text()
    assert "coulomb_level_negative" in report and "\nasymmetry: " in report
    assert not load_model(out / "model.toml").model.is_symmetric
    model = ps.PIFriction(0.1, [500.0, 100.0], threshold=[0.001, 0.01], coulomb_negative=0.08,
                          threshold_negative=[0.0008, 0.007])  # fmt: skip
    ramps = []
    for i, sign in enumerate((1.0, -1.0)):
        y = sign * np.linspace(0.0, 0.03, 200)
        path = tmp_path / f"ramp{i}.csv"
        np.savetxt(path, np.column_stack([y, model.force(y)[0]]), delimiter=",",
                   header="position,friction_force", comments="")  # fmt: skip
        ramps.append(str(path))
    assert main(["fit", *ramps, "--kind", "virgin", "--elements", "2", "--asymmetric",
                 "--ramps", "--quiet", "-o", str(tmp_path / "v")]) == 0  # fmt: skip
    assert "threshold_negative_1" in (tmp_path / "v" / "report.md").read_text()
    loops = _stop_files(tmp_path, 2)
    assert main(["fit", *loops, "--kind", "virgin", "--asymmetric", "--columns",
                 "friction_force=applied_force [N]", "-o", str(tmp_path / "w")]) == 2  # fmt: skip
