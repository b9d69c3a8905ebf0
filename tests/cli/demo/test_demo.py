"""`presliding demo` end to end: files, image sizes, and the numbers it shows."""

from __future__ import annotations

import contextlib
import io

import numpy as np
import pytest
from matplotlib.image import imread

from presliding import analysis
from presliding.cli import main
from presliding.cli.common import LOCK, MANIFEST
from presliding.cli.demo import command as _demo
from presliding.cli.demo import sections as _demo_sections

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
#: Figure sizes in pixels (width, height): figsize × DPI of `_demo`. Matplotlib rounds
#: figsize × DPI differently across versions (1650 × 505 or 506), so sizes are checked
#: within `SIZE_TOLERANCE` pixels.
SIZE_TOLERANCE = 2
SIZES = {
    "figure3_loops.png": (792, 550),
    "free_stop.png": (1650, 506),
    "reversals.png": (792, 528),
    "density.png": (1650, 506),
    "identification.png": (1452, 528),
    "hunting.png": (1210, 484),
}


@pytest.fixture(scope="module")
def demo_dir(tmp_path_factory):
    """The demo run once with --quiet: it prints nothing at all."""
    out = tmp_path_factory.mktemp("demo") / "out"
    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        assert main(["demo", "-o", str(out), "--quiet"]) == 0
    assert stdout.getvalue() == "" and stderr.getvalue() == ""
    return out


def test_demo_writes_every_file(demo_dir, capsys):
    names = sorted(p.name for p in demo_dir.iterdir())
    assert names == sorted([*SIZES, "report.md", "report.html", MANIFEST, LOCK])
    # the list the command checks before writing is the list it writes
    assert sorted(_demo.DEMO_OUTPUTS) == sorted([*SIZES, "report.md", "report.html"])
    listed = (demo_dir / MANIFEST).read_text(encoding="utf-8").splitlines()[1:]
    assert listed == sorted(_demo.DEMO_OUTPUTS)


def test_demo_keeps_files_it_did_not_write(tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.md").write_text("my notes", encoding="utf-8")
    assert main(["demo", "-o", str(out), "--quiet"]) == 2
    assert "report.md: exists and was not written by presliding" in capsys.readouterr().err
    assert (out / "report.md").read_text(encoding="utf-8") == "my notes"
    assert sorted(p.name for p in out.iterdir()) == ["report.md"]


@pytest.mark.parametrize("name", sorted(SIZES))
def test_pngs_are_images_of_the_right_size(demo_dir, name):
    path = demo_dir / name
    data = path.read_bytes()
    assert data[:8] == PNG_MAGIC and len(data) > 20_000
    image = imread(path)
    width, height = SIZES[name]
    assert abs(image.shape[1] - width) <= SIZE_TOLERANCE, image.shape
    assert abs(image.shape[0] - height) <= SIZE_TOLERANCE, image.shape
    assert image.shape[2] in (3, 4)
    assert float(np.std(image[..., :3])) > 0.05  # not blank
    # drawn over the whole figure: ink in each quarter of the width, most of it white
    ink = np.any(image[..., :3] < 0.9, axis=2)
    quarters = np.array_split(ink, 4, axis=1)
    assert all(q.mean() > 0.005 for q in quarters), [round(q.mean(), 4) for q in quarters]
    assert 0.01 < ink.mean() < 0.6


def test_report_embeds_and_links_every_figure(demo_dir):
    md = (demo_dir / "report.md").read_text(encoding="utf-8")
    page = (demo_dir / "report.html").read_text(encoding="utf-8")
    for name in SIZES:
        assert f"({name})" in md
    assert page.count("data:image/png;base64,") == len(SIZES)
    for heading in (
        "Figure 3",
        "Figures 4 and 5",
        "eqs. 15–16",
        "continuous density",
        "Identification",
    ):
        assert heading in md
    assert "| reversals before the stop | 1 | 1 |" in md


def test_demo_prints_where_and_shows_progress(tmp_path, capsys):
    assert main(["demo", "-o", str(tmp_path / "d")]) == 0
    captured = capsys.readouterr()
    assert str((tmp_path / "d").resolve()) in captured.out and "report.html" in captured.out
    # stderr is not a terminal here: one plain line per part, in order
    parts = [ln for ln in captured.err.splitlines() if ln.startswith("presliding demo: [")]
    assert [ln.split("]")[0] for ln in parts] == [f"presliding demo: [{i}/6" for i in range(1, 7)]
    assert parts[0] == "presliding demo: [1/6] the paper's Figure 3 loops"
    # in the order of the report: one process, nothing compiled ahead in another
    assert parts[-1] == "presliding demo: [6/6] hunting of a PI loop (describing function)"
    others = [ln for ln in captured.err.splitlines() if ln not in parts]
    # on a cold cache: the note, and a heartbeat at least every 5 s while kernels compile
    assert all(ln.startswith("presliding demo: compiling (first run only)") for ln in others)


def test_free_stop_prediction_equals_simulation():
    part = _demo.free_stop()
    sim, pred = part.free, part.predicted
    assert sim.n_reversals == pred.n_reversals == 1
    assert part.stops_at_turning_point
    assert sim.rest_position == pytest.approx(pred.rest_position, rel=1e-12)
    assert part.turning_point == pytest.approx(pred.positions[0] - pred.positions[1], rel=1e-12)
    assert part.switch_off.n_reversals == 1 and part.switch_off.stop_time is not None


def test_reversal_sweep_agrees_everywhere():
    ratio, predicted, simulated, fm = _demo.reversal_sweep()
    np.testing.assert_array_equal(predicted, simulated)
    assert predicted[0] > 10 and predicted[-1] == 0
    assert np.all(np.diff(predicted) <= 0)  # fewer reversals with more Coulomb friction
    one = ratio[predicted == 1]
    model = _demo.stop_model(float(one.mean() * fm))
    assert analysis.stops_at_turning_point(model)


def test_density_part_matches_the_analysis():
    part = _demo_sections.density_part()
    for name in ("uniform", "exponential"):
        pred = part[name]["predicted"]
        implicit, discrete = part[name]["motion"], part[name]["discrete"]
        assert implicit.method == "implicit" and not part[name]["model"].is_discrete
        assert implicit.n_reversals == discrete.n_reversals == pred.n_reversals >= 2
        # first order in the step (1e-5 s), and O(1/n²) for the 400-cell discretisation
        assert implicit.rest_position == pytest.approx(pred.rest_position, rel=5e-4)
        assert discrete.rest_position == pytest.approx(pred.rest_position, rel=1e-4)


def test_identification_round_trip_covers_the_truth():
    part = _demo_sections.identification()
    fit, true = part["fit"], part["true"]
    assert fit.status == "converged"
    truth = {"coulomb": true.coulomb}
    truth.update({f"stiffness_{j + 1}": k for j, k in enumerate(true.stiffness)})
    truth.update({f"threshold_{j + 1}": r for j, r in enumerate(true.threshold)})
    for name, value in truth.items():
        lo, hi = fit.confidence_interval[name]
        assert lo <= value <= hi, name
    assert fit.residual_rms == pytest.approx(_demo_sections.FIT_NOISE, rel=0.1)
