"""The documentation builds offline with warnings as errors, and its code runs.

The build (Sphinx, numpydoc, sphinx-gallery; the ``docs`` extra, part of the
``test`` extra) runs on a copy of ``docs/`` and ``examples/`` in a temporary
folder, so the source tree is left as it is, with ``-D plot_gallery=0``: the
gallery pages are rendered without running the scripts, which
``tests/test_examples.py`` runs. The Python blocks of the user guide run
here; a block that starts with ``# needs: PATH`` runs only where PATH exists
(the measured data), and ``# needs: a Dask scheduler`` is left to
``tests/sweep``.
"""

from __future__ import annotations

import importlib
import importlib.util
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import presliding

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
GUIDE = sorted((DOCS / "user_guide").glob("*.rst"))
BLOCK = re.compile(r"^\.\. code-block:: python\n\n((?:(?:   .*)?\n)+)", re.M)
DOCS_PACKAGES = ("sphinx", "numpydoc", "sphinx_gallery", "pydata_sphinx_theme")


def _blocks(page: Path) -> list[str]:
    text = page.read_text(encoding="utf-8")
    return ["\n".join(ln[3:] for ln in b.splitlines()) for b in BLOCK.findall(text)]


def test_the_user_guide_has_its_pages():
    names = {p.stem for p in GUIDE}
    pages = ("quickstart", "equations", "operators", "measurements", "identification",
             "pooled_fits", "control", "dask", "command_line", "citing")  # fmt: skip
    assert set(pages) <= names
    index = (DOCS / "index.rst").read_text(encoding="utf-8")
    for name in names:
        assert f"user_guide/{name}" in index


#: Public names of this release that the user guide shows (not only the API reference).
GUIDED = (
    "Measurement.from_csv", "Measurement.from_mat", "Measurement.from_dataframe",
    "Measurement.join", "window(", "sample_rate", "viscous=", "fit_response(records",
    "initial_state=\"preload\"", "covariance", "fit_quasi_static", "fit_virgin_curve",
    "PIInverse", "friction_inverse", "quasi_static_response", "preloaded_state", "masing_check",
    "cross_validate", "PIBatch", "friction_batch", "simulate_loop", "PID(",
    "describing_function", "predict_limit_cycles", "FrictionNonlinearity", "retries=",
    "dask worker", "NUMBA_CACHE_DIR", "--units", "--window", "--sample-rate", ".mat",
    "Exit status", ".presliding.lock", "progress=True", "CITATION.cff",
)  # fmt: skip


def test_the_user_guide_shows_every_public_name_of_this_release():
    text = "\n".join(p.read_text(encoding="utf-8") for p in GUIDE)
    assert [name for name in GUIDED if name not in text] == []


@pytest.mark.parametrize("page", GUIDE, ids=lambda p: p.stem)
def test_every_user_guide_page_has_code_that_runs_here(page):
    blocks = _blocks(page)
    assert blocks, f"{page.name} has no Python code block"
    assert any(not b.startswith("# needs:") for b in blocks), f"{page.name}: all need data"


@pytest.mark.parametrize("page", GUIDE, ids=lambda p: p.stem)
def test_user_guide_code_runs(page, tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    blocks = _blocks(page)
    if not blocks:
        pytest.skip("no Python code on this page")
    namespace: dict[str, object] = {}
    ran = 0
    for code in blocks:
        needs = re.match(r"# needs: (.*)", code)
        if needs and needs.group(1).startswith("a Dask scheduler"):
            continue
        if needs and not (ROOT / needs.group(1)).exists():
            continue
        if "control" in code and importlib.util.find_spec("control") is None:
            continue
        # data paths are relative to the repository root; anything written goes to tmp_path
        monkeypatch.chdir(ROOT if needs else tmp_path)
        exec(compile(code, str(page), "exec"), namespace)
        ran += 1
    plt.close("all")
    if ran == 0:
        pytest.skip("every block needs data or a cluster that is not here")


def test_docs_build_offline_with_warnings_as_errors(tmp_path):
    missing = [m for m in DOCS_PACKAGES if importlib.util.find_spec(m) is None]
    if missing:
        pytest.skip(f"the docs extra is not installed ({', '.join(missing)})")
    shutil.copytree(DOCS, tmp_path / "docs", ignore=shutil.ignore_patterns(
        "_build", "generated", "auto_examples", "sg_execution_times.rst"))  # fmt: skip
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    out = tmp_path / "html"
    run = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-b", "html", "-q",
         "-D", "plot_gallery=0", "-d", str(tmp_path / "doctrees"), str(tmp_path / "docs"),
         str(out)],
        capture_output=True, text=True, timeout=600, cwd=tmp_path,
    )  # fmt: skip
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-5000:]
    for page in ("index", "user_guide/equations", "user_guide/dask", "auto_examples/index"):
        assert (out / f"{page}.html").exists(), page
    # every public name has its page: the root's and each layer's __all__
    pages = {p.stem for p in (out / "api" / "generated").glob("*.html")}
    names = {f"presliding.{n}" for n in presliding.__all__ if not n.startswith("_")}
    for layer in ("hysteresis", "friction", "motion", "analysis", "identification", "control",
                  "sweep"):  # fmt: skip
        module = importlib.import_module(f"presliding.{layer}")
        names |= {
            f"presliding.{n}" if n in presliding.__all__ else f"presliding.{layer}.{n}"
            for n in module.__all__
        }
    assert names - pages == set()
    # paper symbols in docstrings keep their bars (|x| is not a reST substitution)
    play = (out / "api" / "generated" / "presliding.play.html").read_text(encoding="utf-8")
    assert "|y − x_j| &lt;= r_j" in play or "|y − x_j| <= r_j" in play
    equations = (out / "user_guide" / "equations.html").read_text(encoding="utf-8")
    for target in ("presliding.play", "presliding.PIOperator", "presliding.stop",
                   "presliding.PIFriction", "presliding.GeneralPIOperator",
                   "presliding.simulate", "presliding.phi", "presliding.turning_point",
                   "presliding.stops_at_turning_point", "presliding.turning_points"):  # fmt: skip
        assert f"{target}.html" in equations, target
