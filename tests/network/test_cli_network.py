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


def test_the_help_example_runs(tmp_path):
    """The specification printed by `presliding network --help` is a working file (it had
    `values = [0.0, 0.0, 3.0]` with two `times`, and `step` with method = "exact")."""
    from presliding.cli.simulation.network import SCHEMA

    spec = tmp_path / "spec.toml"
    spec.write_text("\n".join(line[2:] for line in SCHEMA.splitlines()))
    assert main(["network", str(spec), "-o", str(tmp_path / "o"), "--quiet"]) == 0


@pytest.mark.parametrize(
    ("edit", "match"),
    [
        (("values = [[0.0, 2.0], [0.0, 0.0]]", "values = [[0.0, 2.0, 1.0], [0.0, 0.0, 1.0]]"),
         r"\[forcing\] `forcing` values must have shape \(2, 2\)"),
        (("samples = 201", "samples = 201\nstep = 1e-4"), "`motion.step` is the step of method"),
        (("samples = 201", "samples = 1000000000"), "`motion.samples` must be at most 10,000,000"),
        (("samples = 201", "samples = 1"), "`motion.samples` must be a whole number >= 2"),
        (("samples = 201", "samples = 2.5"), "`motion.samples` must be a whole number >= 2"),
        (("n_masses = 2", "n_masses = 100000"),
         r"\[structure\] `n_masses` must ask for at most .* Set sparse = true in \[structure\]"),
        (('kind = "chain"', 'kind = "modal"\nsparse = true'), "`structure.sparse` is for kind"),
        (("times = [0.0, 0.2]\nvalues = [[0.0, 2.0], [0.0, 0.0]]", "times = [0.0, 0.2]"),
         "`forcing.times` needs `forcing.values`"),
    ],
)  # fmt: skip
def test_the_right_table_and_key_are_named(tmp_path, capsys, edit, match):
    """A bad force names [forcing] (not [structure]); `step` without method = "moreau" was
    ignored; 1e9 samples ran out of memory; 100,000 masses gave a traceback."""
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC.replace(*edit))
    assert main(["network", str(spec), "-o", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    import re

    assert re.search(match, err), err


def test_a_sparse_chain_runs_by_moreau_from_a_file(tmp_path):
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC.replace("n_masses = 2", "n_masses = 2\nsparse = true").replace(
        "samples = 201", 'samples = 51\nmethod = "moreau"\nstep = 1e-4'))  # fmt: skip
    assert main(["network", str(spec), "-o", str(tmp_path / "o"), "--quiet"]) == 0
