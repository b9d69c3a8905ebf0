"""`presliding example-data`: the shipped records are the library's own, and fit at once."""

from __future__ import annotations

import numpy as np
import pytest

from presliding.cli import main
from presliding.cli.example_data import _FOLDER, COMMANDS, FILES, TRUTH, generate
from presliding.cli.fitting.fit_figure import figure_title
from presliding.model_io import load_model


def test_the_command_writes_the_files_and_says_what_to_run(tmp_path, capsys):
    out = tmp_path / "data"
    assert main(["example-data", "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    for name in FILES:
        assert (out / name).read_text() == (_FOLDER / name).read_text()
    assert all(command in printed for command in COMMANDS)
    assert sum((_FOLDER / n).stat().st_size for n in FILES) < 60_000  # small: about 50 kB
    assert main(["example-data", "-o", str(out), "--quiet"]) == 0  # its own files: replaced


def test_the_shipped_files_are_what_the_library_makes(tmp_path):
    """Regenerated from `TRUTH`: the same samples to the files' last digit (the position to an
    encoder count, the force to its rounding)."""
    for path in generate(tmp_path):
        made = np.genfromtxt(path, delimiter=",", skip_header=1)
        shipped = np.genfromtxt(_FOLDER / path.name, delimiter=",", skip_header=1)
        assert made.shape == shipped.shape, path.name
        np.testing.assert_allclose(made, shipped, rtol=0, atol=0.11e-3 if path.name !=
                                   "loops.csv" else 0.011, err_msg=path.name)  # fmt: skip


def test_the_loops_fit_at_once(tmp_path):
    out = tmp_path / "fit"
    code = main(["fit", str(_FOLDER / "loops.csv"), "--kind", "presliding", "--elements", "3",
                 "--quiet", "-o", str(out)])  # fmt: skip
    assert code == 0
    fitted = load_model(out / "model.toml").model
    assert fitted.coulomb == pytest.approx(TRUTH["loops"]["coulomb"], rel=0.02)
    np.testing.assert_allclose(fitted.stiffness, TRUTH["loops"]["stiffness"], rtol=0.02)


class _Result:
    kind, status, nrmse = "presliding", "converged", 5.82e-6


def test_the_figure_title_keeps_significant_digits():
    """It said "NRMSE 0.00 %" where the report said 0.000582 %."""
    assert figure_title("loops.csv", _Result()) == (
        "loops.csv: presliding fit, converged, NRMSE 0.000582 %"
    )
