"""Reports of a run: Markdown plus a self-contained HTML page embedding the figures."""

from __future__ import annotations

import base64
import html
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from ._io import write_text


@dataclass(frozen=True)
class Section:
    """One part of a report: a heading, a few lines of text and optional figures."""

    title: str
    text: str
    figures: Sequence[Path] = ()


def write_report(out_dir: Path, title: str, sections: Sequence[Section]) -> list[Path]:
    """Write ``report.md`` and ``report.html`` into `out_dir`; return both paths."""
    md = [f"# {title}", ""]
    body = [f"<h1>{html.escape(title)}</h1>"]
    for s in sections:
        md += [f"## {s.title}", "", s.text.strip(), ""]
        md += [f"![{p.stem}]({p.name})" for p in s.figures]
        md.append("")
        body.append(f"<h2>{html.escape(s.title)}</h2>")
        body += [f"<p>{html.escape(par.strip())}</p>" for par in s.text.strip().split("\n\n")]
        for p in s.figures:
            data = base64.b64encode(Path(p).read_bytes()).decode("ascii")
            body.append(
                f'<figure><img alt="{html.escape(p.stem)}" src="data:image/png;base64,{data}">'
                f"<figcaption>{html.escape(p.name)}</figcaption></figure>"
            )
    page = (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        f"<title>{html.escape(title)}</title><style>"
        "body{font-family:system-ui,sans-serif;max-width:920px;margin:2em auto;padding:0 1em;"
        "line-height:1.5;color:#222}img{max-width:100%;border:1px solid #ddd}"
        "figcaption{font-size:.85em;color:#666}pre{background:#f6f6f6;padding:.6em}"
        "</style></head><body>\n" + "\n".join(body) + "\n</body></html>\n"
    )
    md_path, html_path = out_dir / "report.md", out_dir / "report.html"
    write_text(md_path, "\n".join(md))
    write_text(html_path, page)
    return [md_path, html_path]
