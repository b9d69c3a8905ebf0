"""The HTML report reads well: code in backticks, wide figures at full width, sentence captions."""

from __future__ import annotations

import io
import re

from matplotlib.figure import Figure

from presliding.cli.report import Section, write_report


def _png(width_in: float, height_in: float) -> bytes:
    fig = Figure(figsize=(width_in, height_in))
    fig.subplots().plot([0, 1], [0, 1])
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=50)
    return buf.getvalue()


def test_backticks_captions_and_wide_figures(tmp_path):
    wide, square = tmp_path / "three_panels.png", tmp_path / "loop.png"
    wide.write_bytes(_png(15.0, 4.6))
    square.write_bytes(_png(6.0, 4.5))
    sections = [
        Section(
            "Fit of `data.csv`",
            "The column `force [N]` was fitted.",
            (wide, square),
            table=[("name", "value"), ("`k_1`", "1")],
            captions=("Measured and fitted force, with the residual below",),
        ),
        Section("free motion to a stop", "Text.", (square,)),
    ]
    _, html_path = write_report(tmp_path, "Report of `run`", sections)
    page = html_path.read_text(encoding="utf-8")
    assert "`" not in re.sub(r'alt="[^"]*"', "", page.split("<body>")[1])
    assert "<p>The column <code>force [N]</code> was fitted.</p>" in page
    assert "<h2>Fit of <code>data.csv</code></h2>" in page and "<td><code>k_1</code></td>" in page
    captions = re.findall(r"<figcaption>(.*?)</figcaption>", page)
    assert captions == [
        "Figure 1. Measured and fitted force, with the residual below.",
        "Figure 2. Fit of <code>data.csv</code>, part 2 of 2.",
        "Figure 3. Free motion to a stop.",
    ]
    assert not any(name in c for c in captions for name in ("three_panels", "loop.png"))
    figures = re.findall(r"<figure([^>]*)>", page)
    assert figures == [' class="wide"', "", ""]
    assert "figure.wide{width:min(96vw,1600px)" in page and "figure.wide img{width:100%}" in page
    md = (tmp_path / "report.md").read_text(encoding="utf-8")
    assert "*Figure 3. Free motion to a stop.*" in md
