"""``presliding network``: a specification file to CSV, figures and report."""

from __future__ import annotations

import numpy as np
import pytest

from presliding.cli import main

SPEC = """\
[structure]
kind = "chain"
n_masses = 2
mass = 1.0
spring = 500.0
[friction]
coulomb = 0.5
stiffness = [1e4, 2e3]
breakaway = [0.2, 0.3]
[forcing]
times = [0.0, 0.2]
values = [[0.0, 2.0], [0.0, 0.0]]
[motion]
t_end = 0.5
initial_velocity = [0.2, -0.1]
samples = 201
"""


def test_writes_the_samples_figures_and_report(tmp_path, capsys):
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC)
    out = tmp_path / "net"
    assert main(["network", str(spec), "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "network motion (event): success" in text
    for name in ("network.csv", "hysteresis.png", "timeline.png", "energy.png", "report.md",
                 "report.html"):  # fmt: skip
        assert (out / name).stat().st_size > 0
    header = (out / "network.csv").read_text().splitlines()[0].split(",")
    assert header[:3] == ["time [s]", "q0 [m]", "q1 [m]"] and "force1 [N]" in header
    data = np.loadtxt(out / "network.csv", delimiter=",", skiprows=1)
    assert data.shape == (201, len(header)) and data[-1, 0] == 0.5
    # a second run replaces its own outputs; a file it did not write is refused
    assert main(["network", str(spec), "-o", str(out), "--quiet"]) == 0


def test_moreau_method_and_contact_tables(tmp_path):
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC.replace("[friction]", "[[contact]]").replace(
        "breakaway = [0.2, 0.3]\n", "breakaway = [0.2, 0.3]\n[[contact]]\ncoulomb = 0.8\n"
    ).replace("samples = 201", "samples = 51\nmethod = \"moreau\"\nstep = 1e-4"))  # fmt: skip
    out = tmp_path / "net"
    assert main(["network", str(spec), "-o", str(out), "--quiet"]) == 0
    data = np.loadtxt(out / "network.csv", delimiter=",", skiprows=1)
    assert data.shape[0] == 51


@pytest.mark.parametrize(
    ("edit", "match"),
    [
        (("n_masses = 2", "n_masses = 2\ncolour = 1"), "unknown key `structure.colour`"),
        (("t_end = 0.5", 't_end = "long"'), "motion.t_end` must be a finite number"),
        (('kind = "chain"', 'kind = "ring"'), "structure.kind` must be"),
        (("samples = 201", 'samples = 201\nmethod = "moreau"'), "motion.step` is needed"),
        (("coulomb = 0.5", "coulomb = 0.0"), "Coulomb element c1 > 0"),
        (("spring = 500.0", "spring = 500.0\n[extra]"), "unknown table `extra`"),
    ],
)
def test_bad_specification_is_one_line_naming_the_field(tmp_path, capsys, edit, match):
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC.replace(*edit))
    assert main(["network", str(spec), "-o", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert match in err and len(err.strip().splitlines()) == 1
