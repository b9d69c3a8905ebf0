"""``presliding ring-down``: a decay file to ω(A), ζ(A), a fitted joint, figures; the
outputs equal to the library's; user errors in one line."""

import json

import numpy as np

import presliding as ps
from presliding.cli import main

W, ZETA = 3.4641, 0.0072


def _decay(tmp_path, jenkins=False):
    """A linear decay, or the exact ring-down of a mass on a spring with a Jenkins joint."""
    if jenkins:
        st = ps.JointedStructure(1.0, 10.0, [[1.0]], [ps.PIFriction(0.0, [2.0], [0.1])],
                                 damping=0.01)  # fmt: skip
        motion = ps.simulate_ring_down(st, 0, 1.0, 100.0, samples_per_period=40)
        t, x = motion.time, motion.position[:, 0]
    else:
        t = np.arange(0.0, 150.0, 2 * np.pi / W / 40)
        x = np.exp(-ZETA * W * t) * np.sin(W * np.sqrt(1 - ZETA**2) * t)
    path = tmp_path / "decay.csv"
    np.savetxt(path, np.c_[t, x], delimiter=",", header="time [s],position [m]", comments="")
    return path, t, x


def test_a_decay_file_gives_the_library_estimates_and_a_fit(tmp_path):
    path, t, x = _decay(tmp_path, jenkins=True)
    out = tmp_path / "rd"
    code = main(["ring-down", str(path), "--method", "peaks", "--joint", "jenkins", "-o",
                 str(out), "--quiet"])  # fmt: skip
    assert code == 0
    table = np.loadtxt(out / "ring_down.csv", delimiter=",", skiprows=1)
    ref = ps.analyze_ring_down((t, x), method="peaks")
    np.testing.assert_allclose(table[:, 4], ref.damping_ratio, rtol=1e-12)
    np.testing.assert_allclose(table[:, 2], ref.frequency, rtol=1e-12)
    summary = json.loads((out / "joint.json").read_text())
    assert summary["method"] == "peaks" and "joint" in summary
    assert summary["joint"]["status"] == "converged"
    fitted = summary["joint"]["parameters"]
    assert abs(fitted["slip_force"]["value"] / 0.1 - 1) < 0.02
    assert fitted["slip_force"]["unit"] == "N/kg"
    assert (out / "ring_down.png").stat().st_size > 1000
    assert "Ring-down of" in (out / "report.md").read_text()


def test_no_fit_and_the_estimates_only(tmp_path):
    path, _, _ = _decay(tmp_path)
    out = tmp_path / "rd"
    assert main(["ring-down", str(path), "--no-fit", "-o", str(out), "--quiet"]) == 0
    assert "joint" not in json.loads((out / "joint.json").read_text())


def test_user_errors_are_one_line(tmp_path, capsys):
    path, _, _ = _decay(tmp_path)
    short = tmp_path / "short.csv"
    np.savetxt(short, np.loadtxt(path, delimiter=",", skiprows=1)[:200], delimiter=",",
               header="time [s],position [m]", comments="")  # fmt: skip
    assert main(["ring-down", str(short), "-o", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err
    assert "must keep at least" in err and err.count("\n") == 1
    assert main(["ring-down", str(tmp_path / "missing.csv"), "-o", str(tmp_path / "y")]) == 2
    assert main(["ring-down", str(path), "--method", "fft"]) == 2
