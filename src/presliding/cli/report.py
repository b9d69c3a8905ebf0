"""Reports of a run: Markdown plus a self-contained HTML page embedding the figures."""

from __future__ import annotations

import base64
import html
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from presliding._io import write_text


@dataclass(frozen=True)
class Section:
    """One part of a report: a heading, paragraphs of text, figures and preformatted text.

    Paragraphs in `text` are separated by blank lines; `table` (a header row
    then data rows, all strings) follows the text; `code` (for example a
    result's ``report()``) is shown verbatim after the figures.
    """

    title: str
    text: str
    figures: Sequence[Path] = ()
    code: str = ""
    table: Sequence[Sequence[str]] = ()


def write_report(out_dir: Path, title: str, sections: Sequence[Section]) -> list[Path]:
    """Write ``report.md`` and ``report.html`` into `out_dir`; return both paths.

    The Markdown file links the PNGs by name (they sit next to it); the HTML
    page embeds them (base64), so it can be moved or mailed on its own. Both
    are written atomically.
    """
    md = [f"# {title}", ""]
    body = [f"<h1>{html.escape(title)}</h1>"]
    for s in sections:
        md += [f"## {s.title}", "", s.text.strip(), ""]
        if s.table:
            md += [*_md_table(s.table), ""]
        md += [f"![{p.stem}]({p.name})" for p in s.figures]
        md.append("")
        if s.code:
            md += ["```text", s.code.rstrip(), "```", ""]
        body.append(f"<h2>{html.escape(s.title)}</h2>")
        body += [f"<p>{html.escape(par.strip())}</p>" for par in s.text.strip().split("\n\n")]
        if s.table:
            body.append(_html_table(s.table))
        for p in s.figures:
            data = base64.b64encode(Path(p).read_bytes()).decode("ascii")
            body.append(
                f'<figure><img alt="{html.escape(p.stem)}" src="data:image/png;base64,{data}">'
                f"<figcaption>{html.escape(p.name)}</figcaption></figure>"
            )
        if s.code:
            body.append(f"<pre>{html.escape(s.code.rstrip())}</pre>")
    page = (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        f"<title>{html.escape(title)}</title><style>"
        "body{font-family:system-ui,sans-serif;max-width:920px;margin:2em auto;padding:0 1em;"
        "line-height:1.5;color:#222}img{max-width:100%;border:1px solid #ddd}"
        "figcaption{font-size:.85em;color:#666}pre{background:#f6f6f6;padding:.6em;"
        "overflow-x:auto}table{border-collapse:collapse;margin:.5em 0}"
        "td,th{border:1px solid #ccc;padding:.2em .6em;text-align:right}"
        "th{background:#f0f0f0}td:first-child,th:first-child{text-align:left}"
        "</style></head><body>\n" + "\n".join(body) + "\n</body></html>\n"
    )
    md_path, html_path = out_dir / "report.md", out_dir / "report.html"
    write_text(md_path, "\n".join(md))
    write_text(html_path, page)
    return [md_path, html_path]


def _md_table(rows: Sequence[Sequence[str]]) -> list[str]:
    head, *data = rows
    lines = ["| " + " | ".join(head) + " |", "|" + "|".join(" --- " for _ in head) + "|"]
    return lines + ["| " + " | ".join(r) + " |" for r in data]


def _html_table(rows: Sequence[Sequence[str]]) -> str:
    head, *data = rows
    out = ["<table><tr>" + "".join(f"<th>{html.escape(c)}</th>" for c in head) + "</tr>"]
    out += ["<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in r) + "</tr>" for r in data]
    return "".join(out) + "</table>"
