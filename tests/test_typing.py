"""The package type-checks: mypy, with the configuration of pyproject.toml, finds no error."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]  # the checkout (or unpacked sdist) of the tests


def test_mypy_reports_no_errors(tmp_path):
    """``mypy`` from the repository root (``files = src/presliding``) reports 0 errors.

    The compiled kernels are typed through `presliding.hysteresis._jit.njit`, so
    calls into them are checked too. The cache goes to a temporary folder, so each
    run is a cold one (about half a minute on two cores).
    """
    if importlib.util.find_spec("mypy") is None:
        pytest.skip("mypy is not installed (the test extra has it)")
    if not (ROOT / "src" / "presliding").is_dir():
        pytest.skip("the package sources are not beside the tests")
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "mypy",
            "--config-file",
            str(ROOT / "pyproject.toml"),
            "--cache-dir",
            str(tmp_path / "mypy-cache"),
        ],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=600,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    assert "Success: no issues found" in run.stdout, run.stdout
