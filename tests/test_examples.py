"""The scripts in examples/ run and write their figure (they call the public API only)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = sorted((Path(__file__).resolve().parents[1] / "examples").glob("*.py"))
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def test_there_are_examples():
    assert len(EXAMPLES) >= 4


@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.stem)
def test_example_runs_and_writes_its_figure(script, tmp_path):
    out = tmp_path / f"{script.stem}.png"
    env = {**os.environ, "MPLBACKEND": "Agg"}
    done = subprocess.run(
        [sys.executable, str(script), str(out)],
        cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    data = out.read_bytes()
    assert data[:8] == PNG_MAGIC and len(data) > 20_000


@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.stem)
def test_example_follows_the_gallery_conventions(script):
    """The docs' gallery (sphinx-gallery) needs a title line underlined with "=" at the top of
    the docstring, and runs the script in-process, so it must not raise SystemExit."""
    text = script.read_text(encoding="utf-8")
    first, second = text.split("\n", 2)[:2]
    assert first.startswith('"""') and len(first) > 3, "the docstring must open the file"
    assert set(second) == {"="} and len(second) >= len(first) - 3, (
        f"{script.name}: underline the docstring's first line (the gallery title) with '='"
    )
    assert "raise SystemExit" not in text and "sys.exit(" not in text
