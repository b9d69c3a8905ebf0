"""What the package declares and ships: typing marker, Python versions, citation, sdist."""

from __future__ import annotations

import importlib.resources
import importlib.util
import re
import subprocess
import sys
import tarfile
from pathlib import Path

import pytest

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
PAPER_TITLE = (
    "Use of Prandtl-Ishlinskii hysteresis operators for Coulomb friction modeling with presliding"
)


def _pyproject() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))


def test_the_package_ships_its_type_hints():
    assert importlib.resources.files("presliding").joinpath("py.typed").is_file()
    package_data = _pyproject()["tool"]["setuptools"]["package-data"]["presliding"]
    assert "py.typed" in package_data


def test_supported_pythons_are_declared():
    project = _pyproject()["project"]
    assert project["requires-python"] == ">=3.10"
    versions = {
        c.rsplit(" :: ", 1)[1]
        for c in project["classifiers"]
        if re.fullmatch(r"Programming Language :: Python :: 3\.\d+", c)
    }
    assert versions == {"3.10", "3.11", "3.12", "3.13"}
    assert "Typing :: Typed" in project["classifiers"]


def test_the_test_extra_brings_every_optional_interface():
    extras = _pyproject()["project"]["optional-dependencies"]
    test = " ".join(extras["test"])
    for extra in ("control", "dask", "pandas", "xarray", "docs"):
        assert extra in extras
        assert extra in test, extra
    assert "mypy" in test  # tests/test_typing.py runs it in CI
    assert "presliding[test]" in extras["dev"]
    assert _pyproject()["tool"]["mypy"]["files"] == ["src/presliding"]


def test_citation_cites_the_software_and_the_paper():
    text = (ROOT / "CITATION.cff").read_text(encoding="utf-8")
    assert re.search(r"^cff-version: 1\.2\.0$", text, re.M)
    assert re.search(r"^type: software$", text, re.M)
    version = re.search(r"^version: (\S+)$", text, re.M).group(1)
    from presliding import __version__

    assert version == __version__
    reference = text.split("references:", 1)[1]
    assert re.search(r"^\s+- type: article$", reference, re.M)
    assert f'title: "{PAPER_TITLE}"' in reference
    yaml = pytest.importorskip("yaml")  # with distributed, in the test extra
    data = yaml.safe_load(text)
    assert data["references"][0]["title"] == PAPER_TITLE
    assert data["references"][0]["authors"]


def test_changelog_keeps_an_unreleased_section():
    text = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    assert "Keep a Changelog" in text
    assert text.index("## [Unreleased]") < text.index("### Added")


def test_changelog_lists_breaking_changes_first_and_the_release_s_work():
    text = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    release = text.split("## [Unreleased]", 1)[1].split("\n## [", 1)[0]
    assert release.index("### Breaking changes") < release.index("### Added")
    breaking = release.split("### Breaking changes", 1)[1].split("\n### ", 1)[0]
    assert "`displacement`" in breaking and "deformations" in breaking  # to_iosys
    for name in ("PIBatch", "friction_batch", "fit_quasi_static", "fit_virgin_curve",
                 "masing_check", "cross_validate", "PIInverse", "quasi_static_response",
                 "preloaded_state", "simulate_loop", "describing_function", "predict_limit_cycles",
                 "Measurement.join", "from_dataframe", "viscous", "--window", "--sample-rate",
                 "retries", "progress=", "ARCHITECTURE.md", "CITATION.cff"):  # fmt: skip
        assert name in release, name


def test_the_sdist_carries_what_its_tests_need(tmp_path):
    """Build the sdist (setuptools, offline) and list what it holds."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        major = int(version("setuptools").split(".")[0])
    except (PackageNotFoundError, ValueError):
        major = 0
    if major < 77:  # the build-system requirement of pyproject.toml (the test extra has it)
        pytest.skip("setuptools >= 77 is not installed")
    code = (
        "import sys; from setuptools import build_meta; print(build_meta.build_sdist(sys.argv[1]))"
    )
    run = subprocess.run(
        [sys.executable, "-c", code, str(tmp_path)],
        cwd=ROOT, capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr[-3000:]
    name = run.stdout.strip().splitlines()[-1]
    with tarfile.open(tmp_path / name) as sdist:
        members = {m.name.split("/", 1)[1] for m in sdist.getmembers() if "/" in m.name}
    for needed in (
        "src/presliding/py.typed",
        "src/presliding/cli/example_files/stop_1.csv",  # presliding example-data
        "tests/conftest.py",
        "tests/helpers.py",
        "tests/_reference.py",
        "tests/__init__.py",
        "examples/figure3_loops.py",
        "examples/GALLERY_HEADER.rst",
        "docs/conf.py",
        "docs/index.rst",
        "docs/user_guide/equations.rst",
        "docs/_ext/gallery_hooks.py",
        "README.md",
        "CHANGELOG.md",
        "CITATION.cff",
        "CONTRIBUTING.md",
        "LICENSE",
        ".ci/run",
    ):
        assert needed in members, needed
    tests_here = {str(p.relative_to(ROOT)) for p in (ROOT / "tests").rglob("*.py")}
    assert tests_here <= members
    generated = [m for m in members if "/generated/" in m or "auto_examples" in m]
    assert generated == [] and not any(m.endswith((".pyc", ".nbi", ".nbc")) for m in members)


def test_python_control_is_core_and_the_main_job_needs_no_extra():
    """README's first command installs no extra: the demo must run on the core dependencies
    (.ci/run runs it for real in a fresh environment; here its imports with extras blocked)."""
    import subprocess
    import sys

    core = _pyproject()["project"]["dependencies"]
    assert any(d.startswith("control>=") for d in core)
    blocked = ("pandas", "dask", "distributed", "xarray", "h5py", "lmfit", "cloudpickle")
    code = (
        "import sys\n"
        f"for name in {blocked!r}:\n"
        "    sys.modules[name] = None\n"
        "from presliding.cli.demo import command, hunting, sections\n"
        "import presliding.control.limit_cycles, presliding.control.iosys\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=300)  # fmt: skip
    assert run.returncode == 0, run.stderr


def test_ci_runs_the_lowest_versions_the_pins_allow(tmp_path):
    """.ci/lowest installs every core dependency and the pandas, lmfit and h5py extras at the
    floor of its pin (read from pyproject.toml here), and .ci/run runs it after the tests."""
    try:
        import tomllib
    except ImportError:  # Python 3.10
        import tomli as tomllib

    script = (ROOT / ".ci" / "lowest").read_text(encoding="utf-8")
    floors_code = script.split("<<'PY'\n", 1)[1].split("\nPY\n", 1)[0]
    out = tmp_path / "floors.txt"
    run = subprocess.run([sys.executable, "-c", floors_code, str(out)], cwd=ROOT,
                         capture_output=True, text=True, timeout=60)  # fmt: skip
    assert run.returncode == 0, run.stderr
    floors = dict(line.split("==") for line in out.read_text().split())
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    pins = [*project["dependencies"], *(project["optional-dependencies"][e][0]
                                        for e in ("pandas", "lmfit", "h5py"))]  # fmt: skip
    for pin in pins:
        if ">=" in pin and ";" not in pin:
            name, floor = pin.split(">=")
            assert floors[name.strip()] == floor.strip(), pin
    assert {"pytest", "hypothesis", "numpy", "numba", "pint", "pandas"} <= set(floors)
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert ci.rstrip().endswith("bash .ci/lowest") and '-c "$work/floors.txt"' in script
