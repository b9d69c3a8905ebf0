"""Every option is used or refused; messages name flags, not Python arguments; unclear errors
made clear."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pytest

from presliding.cli import main
from presliding.cli.common import cli_words
from presliding.cli.example_data import run as write_examples
from tests.helpers import one_error_line


@pytest.fixture(scope="module")
def data(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("examples")
    write_examples(argparse.Namespace(output=folder, overwrite=False, quiet=True))
    return folder


def _fit(data: Path, tmp_path: Path, *extra: str, files=("stop_1.csv", "stop_2.csv")) -> int:
    paths = [str(data / f) for f in files]
    return main(["fit", *paths, *extra, "-o", str(tmp_path / "out")])


@pytest.mark.parametrize(
    ("kind", "options", "needle"),
    [
        ("quasi-static", ["--prune"], "--prune: --kind quasi-static does not use it"),
        ("presliding", ["--viscous"], "--viscous: --kind presliding does not use it"),
        ("virgin", ["--offset"], "--offset: --kind virgin does not use it"),
        ("response", ["--search", "global"], "--search global: --kind response does not use"),
        ("response", ["--cutoff", "50"], "--cutoff 50.0: --kind response does not use it"),
        ("presliding", ["--mass", "2"], "--mass 2.0: --kind presliding does not use it"),
        ("response", ["--ramps"], "--ramps: --kind response does not use it"),
        ("virgin", ["--initial-state", "preload"], "--initial-state preload: --kind virgin"),
        ("virgin", ["--hold-out", "stop_3.csv"], "--hold-out stop_3.csv: --kind virgin"),
        ("motion", ["--segments", "stops"], "--segments stops: --kind motion does not use it"),
        ("presliding", ["--seed", "3"], "--seed: seeds the global search; add --search global"),
        ("response", ["--seed", "3"], "--seed: seeds the bootstrap of a pooled fit"),
        ("virgin", ["--segments", "stops"], "--kind virgin reads ramps or loops, not stops"),
        ("response", ["--lead-in", "0.02"], "--lead-in 0.02: an option of --segments, which is "
         "not given"),
        ("presliding", ["--rest-speed", "1e-3"], "--rest-speed 0.001: an option of --segments"),
        ("response", ["--segments", "loops", "--lead-in", "0.02"], "--lead-in is an option of "
         "cutting stops, not loops"),
        ("response", ["--segments", "stops", "--segment-tolerance", "1e-6"],
         "--segment-tolerance is an option of cutting loops and ramps"),
        ("response", ["--interpolate"], "--interpolate: an option of --join"),
        ("response", ["--bootstrap", "20"], "--bootstrap 20: a record-level bootstrap needs "
         "three or more records; got 2"),
        ("response", ["--reversal-tolerance", "1e-6", "--no-cross-validation"],
         "--reversal-tolerance: counts reversals in the cross-validation and --hold-out tables"),
    ],
)  # fmt: skip
def test_an_option_the_run_would_ignore_is_refused(data, tmp_path, capsys, kind, options,
                                                   needle):  # fmt: skip
    options = [str(data / o) if o.endswith(".csv") else o for o in options]
    assert _fit(data, tmp_path, "--kind", kind, *options) == 2
    one_error_line(capsys, needle)


def test_options_of_one_record_are_refused(data, tmp_path, capsys):
    code = _fit(data, tmp_path, "--kind", "response", "--no-cross-validation",
                files=("stop_1.csv",))  # fmt: skip
    assert code == 2
    one_error_line(capsys, "--no-cross-validation: with one record there is no cross-validation")
    path = tmp_path / "full.csv"  # velocity and acceleration columns: nothing to estimate
    path.write_text("t [s],x [m],v [m/s],a [m/s^2],u [N]\n"
                    + "".join(f"{i * 1e-3},{i},{1},{0},{1}\n" for i in range(50)))  # fmt: skip
    assert main(["fit", str(path), "--kind", "motion", "--cutoff", "50", "-o",
                 str(tmp_path / "o")]) == 2  # fmt: skip
    one_error_line(capsys, "--cutoff 50: ", "full.csv has velocity and acceleration columns")


def test_text_options_for_a_matlab_file_are_refused(tmp_path, capsys):
    from scipy.io import savemat

    path = tmp_path / "rig.mat"
    savemat(path, {"t": np.arange(50) * 1e-3, "x": np.linspace(0, 1e-3, 50),
                   "f": np.linspace(0, 1, 50)})  # fmt: skip
    for flag in (["--decimal", ","], ["--no-header"]):
        assert main(["fit", str(path), "--kind", "presliding", "--columns", "position=x",
                     "friction_force=f", *flag, "-o", str(tmp_path / "o")]) == 2  # fmt: skip
        one_error_line(capsys, f"{flag[0]}: {path} is a MATLAB file")


def test_a_held_out_file_is_never_fitted_too(data, tmp_path, capsys):
    code = _fit(data, tmp_path, "--kind", "response", "--hold-out", str(data / "stop_2.csv"))
    assert code == 2
    one_error_line(capsys, "stop_2.csv: is also a file to fit")


def test_join_beside_data_files_is_refused(data, tmp_path, capsys):
    """A data file after --join is read as one of its parts: the two ways do not mix."""
    code = _fit(data, tmp_path, "--kind", "response", "--join", str(data / "stop_3.csv"))
    assert code == 2
    one_error_line(capsys, "--join beside data files (stop_1.csv, stop_2.csv)")


def test_a_missing_time_column_suggests_a_sample_rate(tmp_path, capsys):
    path = tmp_path / "x.csv"
    path.write_text("Position [mm],Force [N]\n0,1\n0.1,2\n0.2,3\n")
    assert main(["fit", str(path), "--kind", "response", "-o", str(tmp_path / "o")]) == 2
    one_error_line(capsys, "no column for `time`", "(or give --sample-rate HZ)")
    bare = tmp_path / "bare.csv"
    bare.write_text("0,1\n0.1,2\n0.2,3\n")
    assert main(["fit", str(bare), "--kind", "response", "-o", str(tmp_path / "o")]) == 2
    one_error_line(capsys, "no header line", "--columns time=0 position=1",
                   "(or give --sample-rate HZ)")  # fmt: skip


def test_a_forgotten_decimal_comma_names_the_option(tmp_path, capsys):
    path = tmp_path / "eu.csv"
    path.write_text("t [s];x [mm];F [N]\n0;0,001;1,5\n0,001;0,002;1,6\n")
    assert main(["fit", str(path), "--kind", "presliding", "-o", str(tmp_path / "o")]) == 2
    one_error_line(capsys, "'0,001' is not a number; it looks like a number with a decimal "
                   "comma ('0.001'): read the file with --decimal ,.")  # fmt: skip


def test_simulate_has_a_default_folder_and_refuses_what_it_would_ignore(tmp_path, capsys,
                                                                        monkeypatch):  # fmt: skip
    import presliding as ps
    from presliding.model_io import MotionSettings, save_model

    model = tmp_path / "model.toml"
    save_model(
        model,
        ps.PIFriction(0.3, [100.0], breakaway=[0.3]),
        MotionSettings(mass=1.0, initial_velocity=0.05, t_end=0.5, samples=201),
    )
    monkeypatch.chdir(tmp_path)
    assert main(["simulate", str(model), "--quiet"]) == 0  # no -o needed
    assert (tmp_path / "presliding-simulate" / "simulation.csv").exists()
    for flags, needle in ((["--hold-last"], "--hold-last: says how the samples of "
                                            "--applied-force are held"),
                          (["--hold", "linear"], "--hold linear: says how the samples"),
                          (["--step", "1e-3"], "--step 0.001: an option of the implicit method"),
                          (["--rtol", "1e-4", "--method", "event"], "--rtol 0.0001: an option "
                           "of the implicit method")):  # fmt: skip
        assert main(["simulate", str(model), *flags]) == 2
        one_error_line(capsys, needle)


def test_sweep_retries_only_on_a_cluster(tmp_path, capsys):
    spec = tmp_path / "spec.toml"
    spec.write_text("[friction]\ncoulomb = 0.3\n")
    assert main(["sweep", str(spec), "--retries", "3", "-o", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "--retries 3" in err or "spec.toml" in err  # refused, or the spec named first


@pytest.mark.parametrize(
    ("python", "flags"),
    [
        ("element(s) 2 never slide (prune=True drops them)", "(--prune drops them)"),
        ("forces in N/kg); give `mass` or `coulomb_level` to scale them", "give --mass to scale"),
        ("`offset` must be False with `asymmetric`=True: while the mass slides a constant "
         "offset and levels); got offset=True.", "--offset cannot be combined with "
         "--asymmetric"),
        ("`records` 0 and 1 are sampled at different times (x); pass interpolate=True to "
         "interpolate onto the times of record 0, or resample them first.", "pass "
         "--interpolate"),
        ("the path (fit a virgin loading with fit_virgin_curve(..., loops=False)).",
         "with --kind virgin"),
        ("`units` names 'velocity', which is not read", "--units names 'velocity'"),
        ("or give it with `units` (--units).", "or give it with --units."),
        ("a force: give its unit N and the ratio with `units` and `scale` (--units u=N "
         "--scale u=RATIO)", "with --units u=N --scale u=RATIO"),
    ],
)  # fmt: skip
def test_messages_name_flags_not_python_arguments(python, flags):
    text = cli_words(python)
    assert flags in text
    for word in ("=True", "=False", "`mass`", "fit_virgin_curve(", "`units`", "`scale`"):
        assert word not in text
