"""Reports: Markdown plus a self-contained HTML page."""

from __future__ import annotations

import base64

from presliding.cli.report import Section, write_report

PNG = base64.b64decode(
    "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAEhQGAhKmMIQAAAABJRU5ErkJggg=="
)


def test_markdown_and_html(tmp_path):
    fig = tmp_path / "a.png"
    fig.write_bytes(PNG)
    sections = [
        Section(
            "First <part>",
            "One paragraph.\n\nAnother & more.",
            (fig,),
            code="x = 1\n<y>",
            table=[("name", "value"), ("k", "1 < 2")],
        ),
        Section("Second", "Text only."),
    ]
    md_path, html_path = write_report(tmp_path, "Title", sections)
    md = md_path.read_text(encoding="utf-8")
    assert md.startswith("# Title\n")
    assert "## First <part>" in md and "![a](a.png)" in md
    assert "```text\nx = 1\n<y>\n```" in md
    assert "| name | value |\n| --- | --- |\n| k | 1 < 2 |" in md
    page = html_path.read_text(encoding="utf-8")
    assert page.startswith("<!DOCTYPE html>")
    assert "<h2>First &lt;part&gt;</h2>" in page
    assert "<p>One paragraph.</p>" in page and "<p>Another &amp; more.</p>" in page
    assert f"data:image/png;base64,{base64.b64encode(PNG).decode()}" in page
    assert "<pre>x = 1\n&lt;y&gt;</pre>" in page
    assert "<td>1 &lt; 2</td>" in page
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.png", "report.html", "report.md"]


def test_reports_are_replaced_whole(tmp_path):
    write_report(tmp_path, "Old", [Section("s", "old text")])
    write_report(tmp_path, "New", [Section("s", "new text")])
    assert "old text" not in (tmp_path / "report.md").read_text()
    assert (tmp_path / "report.md").stat().st_mode & 0o644 == 0o644
