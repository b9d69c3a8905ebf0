"""``presliding sweep``: written files, values against direct computations, user errors."""

from __future__ import annotations

import functools
import json
import os
import pickle
import sys

import numpy as np
import pytest

import presliding as ps
from presliding import analysis
from presliding.cli import main
from presliding.cli.sweeping.sweep import chunk_size, default_workers
from presliding.cli.sweeping.sweep_spec import load_spec
from presliding.sweep._tasks import evaluate_chunk
from tests.helpers import one_error_line

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
STIFFNESS = [200.0, 40.0, 10.0]
BREAKAWAY = [0.3, 0.3, 0.4]  # F_m = 1 N

BASE = """\
[friction]
stiffness = [200.0, 40.0, 10.0]
breakaway = [0.3, 0.3, 0.4]

[motion]
mass = 1.0
initial_state = "relaxed"
t_end = 60.0
"""

TWO_AXES = (
    BASE
    + """
[sweep]
quantity = "reversals"

[sweep.axes]
coulomb_ratio = {start = 0.04, stop = 1.2, num = 9}
initial_velocity = {values = [0.05, 0.3, 1.0, 2.5]}
"""
)


def _write(tmp_path, text, name="spec.toml"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _read_csv(path):
    lines = path.read_text().splitlines()
    return lines[0].split(","), np.loadtxt(lines[1:], delimiter=",", ndmin=2)


def _png_size(path):
    data = path.read_bytes()
    assert data[:8] == PNG_MAGIC and len(data) > 5000
    return int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")


# ---------------------------------------------------------------------- runs
def test_two_axes_map_equals_turning_points(tmp_path, capsys):
    spec = _write(tmp_path, TWO_AXES)
    out = tmp_path / "map"
    assert main(["sweep", str(spec), "-o", str(out)]) == 0
    stdout = capsys.readouterr().out
    assert "36 points (product)" in stdout and "in this process" in stdout
    for name in ("sweep.csv", "sweep.png", "report.md", "report.html"):
        assert f"wrote {out / name}" in stdout
    header, data = _read_csv(out / "sweep.csv")
    assert header == [
        "coulomb_ratio [-]",
        "initial_velocity [m/s]",
        "reversals [-]",
        "stopped [0/1]",
    ]
    ratio, v0 = np.meshgrid(np.linspace(0.04, 1.2, 9), [0.05, 0.3, 1.0, 2.5], indexing="ij")
    # first axis varies slowest; the CSV holds 15 significant digits
    np.testing.assert_allclose(data[:, 0], ratio.ravel(), rtol=1e-14)
    np.testing.assert_allclose(data[:, 1], v0.ravel(), rtol=1e-14)
    expected = [
        analysis.turning_points(ps.PIFriction(r, STIFFNESS, BREAKAWAY), 1.0, v).n_reversals
        for r, v in zip(ratio.ravel(), v0.ravel(), strict=True)
    ]
    np.testing.assert_array_equal(data[:, 2], expected)
    assert data[:, 2].max() >= 3 and data[:, 2].min() == 0  # the map is not trivial
    np.testing.assert_array_equal(data[:, 3], 1.0)
    assert _png_size(out / "sweep.png")[0] > 600
    report = (out / "report.md").read_text()
    assert "![sweep](sweep.png)" in report and "| reversals | points |" in report
    assert "data:image/png;base64," in (out / "report.html").read_text()
    temporaries = [p for p in out.iterdir() if p.name.endswith(".tmp")]
    assert not temporaries and (out / ".presliding-outputs").is_file()


def test_analysis_method_gives_the_same_map(tmp_path):
    sim = _write(tmp_path, TWO_AXES)
    ana = _write(
        tmp_path,
        TWO_AXES.replace('"reversals"\n', '"reversals"\nmethod = "analysis"\n'),
        "analysis.toml",
    )
    assert main(["sweep", str(sim), "-o", str(tmp_path / "a"), "--quiet"]) == 0
    assert main(["sweep", str(ana), "-o", str(tmp_path / "b"), "--quiet"]) == 0
    _, a = _read_csv(tmp_path / "a" / "sweep.csv")
    _, b = _read_csv(tmp_path / "b" / "sweep.csv")
    np.testing.assert_array_equal(a, b)


def test_one_axis_density_rest_position(tmp_path, capsys):
    spec = _write(
        tmp_path,
        '[friction]\ncoulomb = 0.1\n[friction.density]\nkind = "uniform"\nheight = 3.5e7\n'
        'max_threshold = 2e-4\n[motion]\ninitial_state = "saturated"\ninitial_velocity = 0.05\n'
        '[sweep]\nquantity = "rest_position"\n[sweep.axes]\n'
        "coulomb_ratio = {start = 0.05, stop = 1.1, num = 7}\n",
    )
    out = tmp_path / "line"
    assert main(["sweep", str(spec), "-o", str(out), "--workers", "1"]) == 0
    assert "rest_position [m] in" in capsys.readouterr().out
    header, data = _read_csv(out / "sweep.csv")
    assert header == ["coulomb_ratio [-]", "rest_position [m]", "stopped [0/1]"]
    model = load_spec(spec).model
    fm = model.max_elastic_force
    for ratio, rest in zip(np.linspace(0.05, 1.1, 7), data[:, 1], strict=True):
        point = ps.PIFriction(ratio * fm, density=model.density)
        tp = analysis.turning_points(point, 1.0, 0.05, "saturated")
        assert rest == pytest.approx(tp.rest_position, rel=1e-14)  # 15 digits in the CSV
    assert data[-1, 1] > 0 and data[0, 1] != data[-1, 1]  # c1 > F_m: stops without reversal
    assert _png_size(out / "sweep.png")[0] > 600


def test_stop_time_closed_form_and_mass_axis(tmp_path):
    # k = 100 N/m, c = 2 N, c1 = 1 N, v0 = 1 m/s from saturation: one reversal; the stop
    # time of the motion.simulate example for m = 1 kg.
    spec = _write(
        tmp_path,
        "[friction]\ncoulomb = 1.0\nstiffness = [100.0]\nbreakaway = [2.0]\n[motion]\n"
        'initial_velocity = 1.0\ninitial_state = "saturated"\nt_end = 5.0\n[sweep]\n'
        'quantity = "stop_time"\n[sweep.axes]\nmass = {values = [0.5, 1.0, 2.0]}\n',
    )
    assert main(["sweep", str(spec), "-o", str(tmp_path / "o"), "--quiet"]) == 0
    _, data = _read_csv(tmp_path / "o" / "sweep.csv")
    assert data[1, 1] == pytest.approx(0.647492598692, abs=1e-12)
    model = ps.PIFriction(1.0, [100.0], [2.0])
    for m, t_stop, _ in data:
        res = ps.simulate(model, m, initial_velocity=1.0, initial_state="saturated", t_end=5.0)
        assert t_stop == pytest.approx(res.stop_time, rel=1e-13)


def test_points_not_at_rest_exit_1_with_nan(tmp_path, capsys):
    text = TWO_AXES.replace("t_end = 60.0", "t_end = 0.5").replace("start = 0.04", "start = 0.0")
    spec = _write(tmp_path, text)
    assert main(["sweep", str(spec), "-o", str(tmp_path / "o")]) == 1
    line = one_error_line(capsys, "did not come to rest", "raise motion.t_end")
    assert "presliding sweep:" in line
    _, data = _read_csv(tmp_path / "o" / "sweep.csv")
    moving = data[:, 3] == 0
    assert moving.any() and np.isnan(data[moving, 2]).all() and np.isfinite(data[~moving, 2]).all()
    assert "| not at rest |" in (tmp_path / "o" / "report.md").read_text()


def test_worker_processes_equal_this_process(tmp_path, capsys):
    spec = _write(tmp_path, TWO_AXES.replace('"reversals"', '"rest_position"'))
    assert main(["sweep", str(spec), "-o", str(tmp_path / "a"), "--workers", "1"]) == 0
    assert main(["sweep", str(spec), "-o", str(tmp_path / "b"), "--workers", "2"]) == 0
    assert "on 2 local worker processes" in capsys.readouterr().out
    _, a = _read_csv(tmp_path / "a" / "sweep.csv")
    _, b = _read_csv(tmp_path / "b" / "sweep.csv")
    np.testing.assert_array_equal(a, b)


def test_json_spec_default_output_and_quiet(tmp_path, monkeypatch, capsys):
    data = {
        "friction": {"coulomb": 0.2, "stiffness": STIFFNESS, "breakaway": BREAKAWAY},
        "motion": {"t_end": 30.0},
        "sweep": {
            "quantity": "reversals",
            "axes": {"initial_velocity": {"start": 0.1, "stop": 1.0, "num": 4, "scale": "log"}},
        },
    }
    spec = _write(tmp_path, json.dumps(data), "spec.json")
    monkeypatch.chdir(tmp_path)
    assert main(["sweep", str(spec), "--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == ""
    header, values = _read_csv(tmp_path / "presliding-sweep" / "sweep.csv")
    assert header[0] == "initial_velocity [m/s]" and values.shape == (4, 3)
    np.testing.assert_allclose(values[:, 0], [0.1, 0.1 * 10 ** (1 / 3), 0.1 * 10 ** (2 / 3), 1.0],
                               rtol=1e-14)  # fmt: skip
    model = ps.PIFriction(0.2, STIFFNESS, BREAKAWAY)
    for v0, count in zip(np.geomspace(0.1, 1.0, 4), values[:, 1], strict=True):
        assert count == analysis.turning_points(model, 1.0, v0).n_reversals


def test_help_shows_the_schema(capsys):
    assert main(["sweep", "--help"]) == 0
    out = capsys.readouterr().out
    for needle in ("[sweep.axes]", "coulomb_ratio", "c1/F_m [-]", "--scheduler", "v0 [m/s]"):
        assert needle in out
    assert main(["--help"]) == 0
    assert "presliding sweep spec.toml" in capsys.readouterr().out


def test_chunk_function_is_picklable_and_defaults(tmp_path):
    spec = load_spec(_write(tmp_path, TWO_AXES))
    fn = functools.partial(evaluate_chunk, spec.task(single_thread=True))
    again = pickle.loads(pickle.dumps(fn))
    out = again(coulomb_ratio=np.array([0.5, 2.0]), initial_velocity=np.array([1.0, 1.0]))
    np.testing.assert_array_equal(out, [[1.0, 1.0], [0.0, 1.0]])
    assert default_workers(spec) == 1 and chunk_size(spec, 1) == 500
    big = load_spec(
        _write(
            tmp_path,
            TWO_AXES.replace("num = 9", "num = 10000").replace(
                '"reversals"\n', '"reversals"\nmethod = "analysis"\n'
            ),
        )
    )
    assert default_workers(big) == (os.cpu_count() or 1) and chunk_size(big, 2) == 625


# ---------------------------------------------------------------------- user errors
def _axes(text):
    return BASE.replace("[friction]", "[friction]\ncoulomb = 0.2") + (
        '\n[sweep]\nquantity = "reversals"\n[sweep.axes]\n' + text
    )


# fmt: off
BAD_SPECS = [
    ("not toml [", "not valid TOML"),
    (BASE, "missing table `sweep`"),
    (TWO_AXES.replace('"reversals"', '"turns"'), "`sweep.quantity` must be one of"),
    (TWO_AXES.replace('quantity = "reversals"', 'quantity = "reversals"\nmethod = "ode"'),
     "`sweep.method` must be"),
    (TWO_AXES.replace("[sweep]\n", "[sweep]\nworkers = 2\n"), "unknown key `sweep.workers`"),
    (TWO_AXES + "[extra]\n", "unknown table `extra`"),
    (TWO_AXES.replace("t_end = 60.0", "samples = 10"), "`motion.samples` has no use"),
    (TWO_AXES.replace("mass = 1.0", "mass = -1.0"), "`motion.mass` must be positive"),
    (TWO_AXES.replace("stiffness", "stifness"), "unknown key `friction.stifness`"),
    (BASE + '\n[sweep]\nquantity = "reversals"\n', "missing table `sweep.axes`"),
    (_axes("mass = {values = [1.0]}\ncoulomb = {values = [1.0]}\n"
           "initial_velocity = {values = [1.0]}\n"), "got 3 axes"),
    (_axes("damping = {values = [1.0]}\n"), "unknown axis `sweep.axes.damping`"),
    (_axes("mass = 2.0\n"), "`sweep.axes.mass` must be a table"),
    (_axes("mass = {start = 1.0, stop = 2.0}\n"), "missing `sweep.axes.mass.num`"),
    (_axes("mass = {start = 1.0, stop = 2.0, num = 0}\n"),
     "`sweep.axes.mass.num` must be a whole number >= 1; got 0"),
    (_axes("mass = {start = 1.0, stop = 2.0, num = 2.5}\n"), "`sweep.axes.mass.num` must be"),
    (_axes("mass = {start = 2.0, stop = 1.0, num = 3}\n"),
     "`sweep.axes.mass.start` must be less than"),
    (_axes('mass = {start = "a", stop = 1.0, num = 3}\n'), "`sweep.axes.mass.start` must be a"),
    (_axes("mass = {start = 1.0, stop = 2.0, num = 3, step = 1}\n"),
     "unknown key `sweep.axes.mass.step`"),
    (_axes('mass = {start = 1.0, stop = 2.0, num = 3, scale = "ln"}\n'),
     "`sweep.axes.mass.scale` must be"),
    (_axes('coulomb = {start = 0.0, stop = 2.0, num = 3, scale = "log"}\n'),
     "must be positive with scale 'log'"),
    (_axes("mass = {values = [1.0, 1.0]}\n"), "`sweep.axes.mass.values` must increase"),
    (_axes("mass = {values = []}\n"), "`sweep.axes.mass.values` must be a non-empty list"),
    (_axes("mass = {values = [1.0], num = 3}\n"), "`sweep.axes.mass.values` excludes"),
    (_axes("mass = {values = [0.0, 1.0]}\n"), "`sweep.axes.mass` must be positive"),
    (_axes("coulomb_ratio = {values = [-0.1, 1.0]}\n"), "must be nonnegative"),
    (_axes("coulomb_ratio = {values = [0.5]}\ncoulomb = {values = [0.5]}\n"), "keep one"),
    (_axes("mass = {start = 1.0, stop = 2.0, num = 4000}\n"
           "coulomb = {start = 1.0, stop = 2.0, num = 4000}\n"), "at most 10000000"),
    ('[friction]\ncoulomb = 1.0\n[sweep]\nquantity = "reversals"\n[sweep.axes]\n'
     "coulomb_ratio = {values = [0.5]}\n", "needs elasto-plastic elements"),
    (TWO_AXES.replace('"relaxed"', '"saturated"').replace("0.05, 0.3", "0.0, 0.3"),
     "`sweep.axes.initial_velocity` holds 0; `motion.initial_state`"),
    (TWO_AXES.replace('"reversals"', '"stop_time"\nmethod = "analysis"'),
     "'stop_time' needs method = 'simulate'"),
    ('[friction]\ncoulomb = 0.1\n[friction.density]\nkind = "uniform"\nheight = 1.0\n'
     'max_threshold = 1.0\n[sweep]\nquantity = "reversals"\nmethod = "simulate"\n'
     "[sweep.axes]\nmass = {values = [1.0]}\n", "'simulate' needs finite elements"),
    (TWO_AXES.replace("t_end = 60.0", "applied_force = 0.5").replace(
        'quantity = "reversals"', 'quantity = "reversals"\nmethod = "analysis"'),
     "`motion.applied_force` must be 0 with method 'analysis'"),
    (TWO_AXES.replace("[sweep]\n", "[sweep]\nchunk_size = 0\n"), "`sweep.chunk_size` must be"),
]
# fmt: on


@pytest.mark.parametrize(("text", "needle"), BAD_SPECS)
def test_bad_specification_is_one_line_exit_2(tmp_path, capsys, text, needle):
    spec = _write(tmp_path, text)
    assert main(["sweep", str(spec), "-o", str(tmp_path / "o")]) == 2
    line = one_error_line(capsys, needle)
    assert line.startswith(f"presliding sweep: error: {spec}:")
    assert not (tmp_path / "o" / "sweep.csv").exists()


def test_missing_file_and_bad_options(tmp_path, capsys):
    assert main(["sweep", str(tmp_path / "nope.toml")]) == 2
    one_error_line(capsys, "nope.toml: no such file")
    spec = _write(tmp_path, TWO_AXES)
    assert main(["sweep", str(spec), "--workers", "0", "-o", str(tmp_path / "o")]) == 2
    one_error_line(capsys, "`--workers` must be a positive integer; got 0")
    args = ["sweep", str(spec), "--workers", "2", "--scheduler", "tcp://127.0.0.1:1"]
    assert main(args) == 2
    one_error_line(capsys, "give one of the two")
    assert main(["sweep", str(spec), "-o", str(spec)]) == 2  # -o is the input file
    one_error_line(capsys, "is a file, not a folder")


def test_never_writes_onto_the_input(tmp_path, capsys):
    out = tmp_path / "o"
    out.mkdir()
    spec = _write(out, TWO_AXES, "report.md")  # a TOML file that an output would replace
    assert main(["sweep", str(spec), "-o", str(out)]) == 2
    one_error_line(capsys, "is the input file")
    assert spec.read_text() == TWO_AXES and not (out / "sweep.csv").exists()


def test_scheduler_address_and_missing_dask(tmp_path, capsys, monkeypatch):
    spec = _write(tmp_path, TWO_AXES)
    assert main(["sweep", str(spec), "-o", str(tmp_path / "o"), "--scheduler", "nonsense"]) == 2
    one_error_line(
        capsys, "--scheduler nonsense: `scheduler` must be a scheduler address", "tcp://"
    )
    monkeypatch.setitem(sys.modules, "distributed", None)
    args = ["sweep", str(spec), "-o", str(tmp_path / "o"), "--scheduler", "tcp://127.0.0.1:1"]
    assert main(args) == 2
    one_error_line(capsys, r'pip install "presliding[dask]"')
    assert not (tmp_path / "o" / "sweep.csv").exists()


def test_dask_local_cluster_equals_this_process(tmp_path, capsys):
    distributed = pytest.importorskip("distributed")
    spec = _write(tmp_path, TWO_AXES)
    assert main(["sweep", str(spec), "-o", str(tmp_path / "a"), "--quiet"]) == 0
    with distributed.LocalCluster(
        n_workers=1,
        processes=True,
        threads_per_worker=1,
        host="127.0.0.1",
        dashboard_address=None,
    ) as cluster:
        args = ["sweep", str(spec), "-o", str(tmp_path / "b")]
        assert main([*args, "--scheduler", cluster.scheduler_address]) == 0
    assert "on 1 Dask workers" in capsys.readouterr().out
    assert (tmp_path / "a" / "sweep.csv").read_text() == (tmp_path / "b" / "sweep.csv").read_text()


def _failing_chunk(task, **columns):
    raise RuntimeError("no motion here")


def test_a_failed_chunk_exits_1_and_writes_nothing(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr("presliding.cli.sweeping.sweep.evaluate_chunk", _failing_chunk)
    spec = _write(tmp_path, TWO_AXES)
    assert main(["sweep", str(spec), "-o", str(tmp_path / "o"), "--workers", "1"]) == 1
    one_error_line(capsys, "presliding sweep: failed:", "RuntimeError: no motion here")
    assert not (tmp_path / "o" / "sweep.csv").exists()


def test_viscous_term_of_the_base_model_is_swept_and_analysis_refuses_it(tmp_path, capsys):
    # the Coulomb-viscous stop: t = (m/σ)·ln(1 + σ·v0/c1) for every mass of the axis
    spec = _write(
        tmp_path,
        "[friction]\ncoulomb = 1.0\nviscous = 2.0\n[motion]\ninitial_velocity = 3.0\n"
        't_end = 5.0\n[sweep]\nquantity = "stop_time"\n[sweep.axes]\n'
        "mass = {values = [0.5, 1.0, 2.0]}\n",
    )
    assert main(["sweep", str(spec), "-o", str(tmp_path / "o"), "--quiet"]) == 0
    _, data = _read_csv(tmp_path / "o" / "sweep.csv")
    np.testing.assert_allclose(data[:, 1], data[:, 0] / 2.0 * np.log1p(2.0 * 3.0), rtol=1e-13)
    bad = _write(
        tmp_path,
        TWO_AXES.replace(
            "breakaway = [0.3, 0.3, 0.4]", "breakaway = [0.3, 0.3, 0.4]\nviscous = 1.0"
        ).replace('quantity = "reversals"', 'quantity = "reversals"\nmethod = "analysis"'),
        "bad.toml",
    )
    assert main(["sweep", str(bad), "-o", str(tmp_path / "o2")]) == 2
    one_error_line(capsys, "`friction.viscous` must be 0 with method 'analysis'")
