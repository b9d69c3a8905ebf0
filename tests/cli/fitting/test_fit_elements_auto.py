"""presliding fit --elements auto: the number of elements from the data (response fits)."""

from __future__ import annotations

import numpy as np

import presliding as ps
from presliding.cli import main
from tests.helpers import stop_records

MODEL = ps.PIFriction(0.3, [4000.0], breakaway=[0.7])


def _stop_files(tmp_path, n=2):
    records, _ = stop_records(3, n, MODEL, samples=400)
    paths = []
    for i, r in enumerate(records):
        path = tmp_path / f"stop{i + 1}.csv"
        np.savetxt(path, np.column_stack([r.time, r.position, r.applied_force]), delimiter=",",
                   header="time,position,applied_force", comments="")  # fmt: skip
        paths.append(str(path))
    return paths


def test_elements_auto_chooses_the_order_and_reports_the_table(tmp_path, capsys):
    out = tmp_path / "fit"
    code = main(["fit", *_stop_files(tmp_path), "--kind", "response", "--elements", "auto",
                 "--initial-state", "preload", "--no-cross-validation", "-o", str(out),
                 "--quiet"])  # fmt: skip
    report = (out / "report.md").read_text()
    assert code == 0, report
    assert "model order (n_elements='auto', by BIC)" in report and "<- chosen" in report
    assert "1 element(s) by BIC" in report


def test_elements_auto_is_for_response_fits(tmp_path, capsys):
    code = main(["fit", *_stop_files(tmp_path, 1), "--kind", "quasi-static", "--elements",
                 "auto", "-o", str(tmp_path / "q")])  # fmt: skip
    assert code == 2
    assert "--elements auto is for --kind response" in capsys.readouterr().err
