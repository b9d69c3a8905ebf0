"""The documentation builds offline with warnings as errors, and its code runs.

The build (Sphinx, numpydoc, sphinx-gallery; the ``docs`` extra, part of the
``test`` extra) runs on a copy of ``docs/`` and ``examples/`` in a temporary
folder, so the source tree is left as it is, with ``-D plot_gallery=0``: the
gallery pages are rendered without running the scripts, which
``tests/test_examples.py`` runs. The Python blocks of the user guide run
here; a block that starts with ``# needs: PATH`` runs only where PATH exists
(the measured data), and ``# needs: a Dask scheduler`` is left to
``tests/sweep``. Every number a block prints is checked against `PRINTED`: a
block that prints a number nobody checks fails.
"""

from __future__ import annotations

import contextlib
import importlib
import importlib.util
import io
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import presliding
from presliding import _progress

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
GUIDE = sorted((DOCS / "user_guide").glob("*.rst"))
BLOCK = re.compile(r"^\.\. code-block:: python\n\n((?:(?:   .*)?\n)+)", re.M)
DOCS_PACKAGES = ("sphinx", "numpydoc", "sphinx_gallery", "pydata_sphinx_theme")


#: The numbers the user guide prints, by (page, block index from 0): (pattern, expected,
#: relative tolerance[, absolute tolerance]); group 1 of the pattern (searched line by line)
#: is the printed value; an expected str is compared exactly.
PRINTED: dict[tuple[str, int], list[tuple]] = {
    ("citing", 0): [(r"^(\S+)$", presliding.__version__)],
    ("install", 0): [(r"^presliding (\S+)$", presliding.__version__)],
    ("command_line", 1): [(r"^compiled kernels cached: (.*)$",
                           f"{_progress.LOCATION}" + (f" {_progress.FOLDER}" if _progress.FOLDER
                                                      else ""))],
    ("rate_models", 0): [(r"stops at (\S+) s", 0.1668, 1e-3), (r"PI: (\S+) s", 0.1740, 1e-3)],
    ("rate_models", 1): [(r"creeps (\S+) while", 1.276e-05, 1e-3),
                         (r"J·u = (\S+)\)", 1.5e-05, 1e-9)],
    ("rate_models", 2): [(r"lower BIC: (\S+) ", "gms"), (r"\| (\S+) \|", "not_identifiable"),
                         (r"\| \S+ \| (\S+)$", "model_inadequate")],
    ("control", 1): [(r"^(\d+) reversals", 5.0, 0.0),
                     (r"at rest from (\S+) s", 1.2248167712325622, 1e-6),
                     (r" s at (\S+)$", 0.05026722669232527, 1e-6)],
    ("control", 3): [(r"(\d+) limit cycle\(s\) predicted, (?:\d+) stable", 2.0, 0.0),
                     (r"^  (\S+) +\S+ +\S+ +True$", 1.00981e-05, 1e-3),
                     (r"^  \S+ +(\S+) +\S+ +True$", 165.425, 1e-3),
                     (r"^  (\S+) +\S+ +\S+ +False$", 0.000662831, 1e-3),
                     (r"^  \S+ +(\S+) +\S+ +False$", 33.3901, 1e-3)],
    ("identification", 0): [(r"^coulomb +(\S+) N", 0.200218, 1e-3),
                             (r"^stiffness_1 +(\S+) N/m", 400.062, 1e-3),
                             (r"^threshold_3 +(\S+) m", 0.0150022, 1e-3),
                             (r"explained variance (\S+) %", 100.0, 1e-4)],
    # the tribometer: F_c of about 2.4 N (|F/N| of about 0.47 at a normal load of 5 N)
    ("identification", 1): [(r"^F_c \[N\]: (\S+)$", 2.365, 0.02),
                            (r"^validation RMS \[N\]: (\S+)$", 0.1158, 0.05),
                            (r"^offset +(\S+) N", 0.0993, 0.05),
                            (r"^stiffness_1 +(\S+) N/m", 2.75e4, 0.1)],  # its split with
    # stiffness_2 (thresholds 53 and 62 µm) moves by ~7 % between optima of equal cost
    # EMPS: the published reference is M = 95.11 kg, 203.5 N s/m, 20.39 N, offset -3.16 N
    ("identification", 2): [(r"^mass +(\S+) kg", 94.97, 2e-3),
                            (r"^viscous +(\S+) N s/m", 204.6, 2e-3),
                            (r"^coulomb +(\S+) N", 20.28, 2e-3),
                            (r"^offset +(\S+) N", -3.152, 5e-3),
                            (r"^validation RMS (\S+) N, F_c = 20.28 N$", 3.952, 1e-2),
                            (r"^validation RMS (\S+) N, F_c = 20.47 N$", 3.816, 1e-2)],
    ("measurements", 0): [(r"factor=(\S+?),", 0.001, 1e-12),
                          (r"scale=(\S+?),", 1.0, 0.0)],
    ("pooled_fits", 0): [(r"^(\d+) samples in 3 records", 1800.0, 0.0),
                         (r"^mass +(\S+) kg", 2.0, 1e-3),
                         (r"^coulomb_level +(\S+) N", 1.0, 1e-3),
                         (r"^coulomb +(\S+) N", 0.3, 1e-3)],
    ("pooled_fits", 2): [(r"median NRMSE (\S+) %", 0.0, 0.0, 0.05),
                         (r"reversal counts exact in (\S+) %", 100.0, 0.0)],
    ("pooled_fits", 4): [(r"within (\S+) % of the force range", 0.0, 0.0, 1e-6),
                         (r"\(tolerance (\S+) %\)", 3.0, 0.0),
                         (r"^  (\d+) branches", 2.0, 0.0)],
    # asymmetric stops (F_c⁻ = 0.8 F_c⁺): both levels, the asymmetry supported
    ("pooled_fits", 5): [(r"^F_c\+ = (\S+) N", 1.0, 1e-3), (r"F_c- = (\S+) N", 0.8, 1e-3),
                         (r"N: (\S+)$", "supported")],
    ("pooled_fits", 6): [(r"the data support (\S+) \(", "pi-asymmetric"),
                         (r"^  pi-asymmetric \(supported\) +(\S+) ", "converged"),
                         (r"predicts best \(median NRMSE (\S+) %", 1.52, 0.1)],
    ("quickstart", 3): [(r"stops at t = (\S+) s", 0.0852924142586, 1e-6),
                        (r"at position (\S+) m", 0.00176242655942, 1e-6),
                        (r"^  reversals: (\d+)$", 1.0, 0.0),
                        (r"balance residual (\S+) ", 0.0, 0.0, 1e-12)],
    ("results", 0): [(r"max_events = (\d+) was reached", 20.0, 0.0),
                     (r"reached at t = (\S+) s$", 6.12611, 1e-5)],
    ("emps", 0): [(r"^\((\S+), ", 1.5, 0.0), (r"^\(\S+, (\S+)\)$", 0.85, 0.0),
                  (r"^(\S+) -", 0.15707963267948966, 1e-12),
                  (r"^\S+ (-\S+)$", -5e-4, 1e-9)],
    ("emps", 1): [(r"^symmetric +0 elements: (\S+) %", 4.10, 0.0, 0.006),
                  (r"^symmetric +0 elements: \S+ % (\S+) %", 5.98, 0.0, 0.006),
                  (r"^symmetric +4 elements: (\S+) %", 3.92, 0.0, 0.006),
                  (r"^symmetric +4 elements: \S+ % (\S+) %", 5.84, 0.0, 0.006),
                  (r"^asymmetric 0 elements: (\S+) %", 3.15, 0.0, 0.006),
                  (r"^asymmetric 0 elements: \S+ % (\S+) %", 5.38, 0.0, 0.006),
                  (r"^asymmetric 4 elements: (\S+) %", 2.94, 0.0, 0.006),
                  (r"^asymmetric 4 elements: \S+ % (\S+) %", 5.24, 0.0, 0.006)],
    # Segalman's Iwan with K_T 2, F_S 3, χ -0.1, β 0.1: φ_max, R and S
    ("joints", 0): [(r"^(\S+) \S+ \S+$", 2.876147, 1e-7), (r"^\S+ (\S+) \S+$", 0.632339, 1e-6),
                    (r"^\S+ \S+ (\S+)$", 0.181818, 1e-6)],
    ("joints", 1): [(r"n=(\d+),", 30.0, 0.0), (r"amplitude=\[(\S+), ", 1e-4, 1e-12),
                    (r"amplitude=\[\S+, (\S+)\] m", 1.0, 0.0)],
    ("joints", 2): [(r"^\[(\S+) ", -1.0, 0.0), (r"(2)\.\s*\]$", 2.0, 0.0),
                    (r"(1\.14285714)", 1.14285714, 1e-8)],
    ("joints", 3): [(r"stiffness=\[(\S+), ", 100.0, 1e-12),
                    (r"stiffness=\[\S+, (\S+)\]", 50.0, 1e-12),
                    (r"breakaway=\[(\S+), ", 0.5, 1e-12),
                    (r"breakaway=\[\S+, (\S+)\]", 1.0, 1e-12),
                    (r"coulomb=(\S+),", 0.0, 0.0), (r"^(\S+)$", 8.68e-4, 1e-3)],
    ("network", 0): [(r"^(\d+) \d+ ", 3.0, 0.0), (r"^\d+ (\d+) ", 3.0, 0.0),
                     (r"\[(1)\. 1\. 1\.\]", 1.0, 0.0)],
    # the friction oscillator: 7 reversals, rest at atan2(6, 13) + 7π
    ("network", 1): [(r"^\[(\d+)\]", 7.0, 0.0), (r"\[(\S+)\]$", 22.42355635, 1e-9)],
    ("network", 2): [(r"in (\d+) events", 60.0, 0.0), (r"to t = (\S+) s", 1.0, 0.0),
                     (r"coordinates (\d+)", 3.0, 0.0),
                     (r"residual\| / scale = (\S+)$", 0.0, 0.0, 1e-11),
                     (r"^ +0 +(\d+) ", 8.0, 0.0), (r"^ +2 +(\d+) ", 3.0, 0.0),
                     (r"^ +0 +\d+ +(\S+)", 0.425612, 1e-5)],
    ("network", 4): [(r"^(\S+)$", 2.5e-4, 0.5)],
    # NLvib's chain: the stuck modes; the backbone of mode 0 from ω0 towards K's own
    ("structural", 0): [(r"^\[(\S+) ", 1.374878, 1e-6), (r" (\S+) \S+\]$", 2.974046, 1e-6),
                        (r" (\S+)\]$", 7.434027, 1e-6)],
    ("structural", 1): [(r"^(\S+) \S+$", 1.374878, 1e-6), (r"^\S+ (\S+)$", 1.089694, 1e-6)],
    # ring-down against the slow-decay ζ_d and against the secant's ζ (median |Δζ|)
    ("structural", 2): [(r"^(\S+) \S+$", 3.9e-5, 0.2), (r"^\S+ (\S+)$", 3.5e-4, 0.2)],
    ("structural", 4): [(r"^\[(\S+) ", 0.066487, 1e-5), (r" (\S+) \S+\]$", 0.120075, 1e-5),
                        (r" (\S+)\]$", 0.161172, 1e-5)],
    ("rigs", 2): [(r"^(\d+) stops cut", 4.0, 0.0),
                  (r"^ +1 +(\S+) s to", 0.128, 1e-9), (r"^ +4 +\S+ s to (\S+)", 1.931, 1e-9),
                  (r"^ +2 .* (\d+) samples", 304.0, 0.0),
                  (r"rest speed (\S+) m/s", 0.001102, 1e-3),
                  (r"at least (\d+) samples", 10.0, 0.0)],
    ("rigs", 3): [(r"NRMSE (\S+) %", 0.131, 0.05), (r"reversals: measured (\d+)", 1.0, 0.0),
                  (r"predicted (\d+) \(tolerance", 1.0, 0.0),
                  (r"\((3) encoder counts", 3.0, 0.0),
                  (r"rest position: measured (\S+),", -0.00032, 0.02)],
}  # fmt: skip


def _check_printed(page: str, index: int, out: str) -> None:
    """The printed numbers of a block are those of `PRINTED`; a number nobody checks fails."""
    expected = PRINTED.get((page, index))
    if expected is None:
        assert not re.search(r"\d", out), (
            f"{page}.rst block {index} prints numbers that tests/test_docs.py does not check; "
            f"add them to PRINTED:\n{out[:500]}"
        )
        return
    for pattern, value, *tol in expected:
        found = re.search(pattern, out, re.M)
        assert found, f"{page}.rst block {index}: {pattern!r} not in the output:\n{out[:2000]}"
        if isinstance(value, str):
            assert found.group(1) == value, (page, index, pattern)
        else:
            rel, absolute = [*tol, 0.0][:2]
            assert float(found.group(1)) == pytest.approx(value, rel=rel, abs=absolute), (
                page, index, pattern, found.group(0))  # fmt: skip


def test_every_checked_block_exists():
    for page, index in PRINTED:
        assert index < len(_blocks(DOCS / "user_guide" / f"{page}.rst")), (page, index)


def _blocks(page: Path) -> list[str]:
    text = page.read_text(encoding="utf-8")
    return ["\n".join(ln[3:] for ln in b.splitlines()) for b in BLOCK.findall(text)]


def test_the_user_guide_has_its_pages():
    names = {p.stem for p in GUIDE}
    pages = ("install", "quickstart", "equations", "operators", "measurements", "identification",
             "pooled_fits", "control", "dask", "command_line", "citing")  # fmt: skip
    assert set(pages) <= names
    index = (DOCS / "user_guide.rst").read_text(encoding="utf-8")
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
    "Exit status", ".presliding.lock", "progress=True", "CITATION.cff", "GMSFriction",
    "CreepingFriction", 'family="gms"', "creep=True", "asymmetric=True", "compare_fits",
    "register_family", "--compare",
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
    for index, code in enumerate(blocks):
        needs = re.match(r"# needs: (.*)", code)
        if needs and needs.group(1).startswith("a Dask scheduler"):
            continue
        if needs and not (ROOT / needs.group(1)).exists():
            continue
        if "control" in code and importlib.util.find_spec("control") is None:
            continue
        # data paths are relative to the repository root; anything written goes to tmp_path
        monkeypatch.chdir(ROOT if needs else tmp_path)
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            exec(compile(code, str(page), "exec"), namespace)
        _check_printed(page.stem, index, printed.getvalue())
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
    shutil.copy(ROOT / "CHANGELOG.md", tmp_path / "CHANGELOG.md")
    out = tmp_path / "html"
    run = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-b", "html", "-q",
         "-D", "plot_gallery=0", "-d", str(tmp_path / "doctrees"), str(tmp_path / "docs"),
         str(out)],
        capture_output=True, text=True, timeout=600, cwd=tmp_path,
    )  # fmt: skip
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-5000:]
    for page in ("index", "user_guide/equations", "user_guide/dask", "auto_examples/index",
                 "user_guide/install", "changelog"):  # fmt: skip
        assert (out / f"{page}.html").exists(), page
    _check_navigation_statuses_links(out)
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
    _check_every_member_has_an_entry(out)
    # paper symbols in docstrings keep their bars (|x| is not a reST substitution)
    play = (out / "api" / "generated" / "presliding.play.html").read_text(encoding="utf-8")
    assert "|y − x_j| &lt;= r_j" in play or "|y − x_j| <= r_j" in play
    equations = (out / "user_guide" / "equations.html").read_text(encoding="utf-8")
    for target in ("presliding.play", "presliding.PIOperator", "presliding.stop",
                   "presliding.PIFriction", "presliding.GeneralPIOperator",
                   "presliding.simulate", "presliding.phi", "presliding.turning_point",
                   "presliding.stops_at_turning_point", "presliding.turning_points"):  # fmt: skip
        assert f"{target}.html" in equations, target


def _public_members(cls: type) -> set[str]:
    """The public methods and properties of `cls`, its own and those it inherits from
    presliding's classes (not those of Python's builtins: a named tuple's count/index)."""
    import inspect

    out = set()
    for name in dir(cls):
        if name.startswith("_"):
            continue
        owner = next(c for c in cls.__mro__ if name in vars(c))
        if owner.__module__.split(".")[0] != "presliding":
            continue
        member = inspect.getattr_static(cls, name)
        if isinstance(member, property) or callable(getattr(cls, name, None)):
            out.add(name)
    return out


def _check_every_member_has_an_entry(out: Path) -> None:
    """Every public method and property of every public class has its entry on its class's
    page, the inherited ones included (111 of 341 had none: Measurement.from_csv,
    FitResult.to_lmfit, every result's to_pandas and to_dict)."""
    import inspect

    missing, total = [], 0
    for page in (out / "api" / "generated").glob("presliding.*.html"):
        path = page.stem
        module, _, name = path.rpartition(".")
        cls = getattr(importlib.import_module(module), name, None)
        if not inspect.isclass(cls):
            continue
        text = page.read_text(encoding="utf-8")
        members = _public_members(cls)
        total += len(members)
        missing += [f"{path}.{m}" for m in sorted(members) if f'id="{path}.{m}"' not in text]
    assert total > 300 and missing == [], missing


def _text(html: str) -> str:
    return re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", html)).replace("&quot;", '"')


def _check_navigation_statuses_links(out: Path) -> None:
    """The API reference in the top navigation (not under "More"), the statuses table
    rendered as one table with a row per result, links to the other projects' docs, the
    changelog and the shared modules' reference pages."""
    index = (out / "index.html").read_text(encoding="utf-8")
    header = index[index.find("<header") : index.find("</header>")]
    assert 'href="api/index.html"' in header and 'href="user_guide.html"' in header
    assert 'href="changelog.html"' in header
    assert ">More<" not in header and "dropdown" not in header.split('href="api/index.html"')[0]
    results = (out / "user_guide" / "results.html").read_text(encoding="utf-8")
    table = results[results.find("<table") : results.find("</table>")]
    assert "statuses" in table[:200]
    rows = [_text(r) for r in re.findall(r"<tr.*?</tr>", table, re.S)]
    fit = [r for r in rows if "FitResult" in r]
    assert len(rows) == 12 and len(fit) == 1, rows  # the header and 11 results
    for status in ("converged", "local_minimum", "not_identifiable", "poor_fit", "at_bound",
                   "max_evaluations", "failed"):  # fmt: skip
        assert f'"{status}"' in fit[0], status
    assert not any("LoopResult" in r and "MotionResult" not in r for r in rows)
    pages = "".join(p.read_text(encoding="utf-8") for p in (out / "user_guide").glob("*.html"))
    for link in ("https://numpy.org/doc/stable/reference/generated/numpy.ndarray.html",
                 "https://docs.scipy.org/doc/scipy/reference/generated/scipy.signal.butter.html",
                 "https://matplotlib.org/stable/api/_as_gen/matplotlib.axes.Axes.html",
                 "https://docs.python.org/3/library/exceptions.html#KeyboardInterrupt",
                 "https://python-control.readthedocs.io/en/latest/generated/"
                 "control.TransferFunction.html",
                 "https://pandas.pydata.org/docs/reference/api/pandas.DataFrame.html",
                 "https://lmfit.github.io/lmfit-py/parameters.html#lmfit.parameter.Parameters",
                 "https://pint.readthedocs.io/en/stable/api/base.html#pint.Quantity"):  # fmt: skip
        assert link in pages, link
    changelog = (out / "changelog.html").read_text(encoding="utf-8")
    assert "Breaking changes" in changelog and "<li>" in changelog
    generated = out / "api" / "generated"
    for name in ("presliding.plotting.plot_fit", "presliding.plotting.place_legend",
                 "presliding.model_io.load_model", "presliding.model_io.save_model",
                 "presliding.signals.piecewise_linear"):  # fmt: skip
        assert (generated / f"{name}.html").exists(), name
