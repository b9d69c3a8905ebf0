"""Reports of a run: Markdown plus a self-contained HTML page embedding the figures."""

from __future__ import annotations

import base64
import html
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from presliding._io import write_text


@dataclass(frozen=True)
class Section:
    """One part of a report: a heading, paragraphs of text, figures and preformatted text.

    Paragraphs in `text` are separated by blank lines; text in backticks is
    shown as code. `table` (a header row then data rows, all strings) follows
    the text; `code` (for example a result's ``report()``) is shown verbatim
    after the figures. `captions` holds one sentence per figure; by default a
    figure is captioned with its number and the section title.
    """

    title: str
    text: str
    figures: Sequence[Path] = ()
    code: str = ""
    table: Sequence[Sequence[str]] = ()
    captions: Sequence[str] = ()


def write_report(out_dir: Path, title: str, sections: Sequence[Section]) -> list[Path]:
    """Write ``report.md`` and ``report.html`` into `out_dir`; return both paths.

    The Markdown file links the PNGs by name (they sit next to it); the HTML
    page embeds them (base64), so it can be moved or mailed on its own. Both
    are written atomically.
    """
    md = [f"# {title}", ""]
    body = [f"<h1>{_inline(title)}</h1>"]
    number = 0
    for s in sections:
        md += [f"## {s.title}", "", s.text.strip(), ""]
        if s.table:
            md += [*_md_table(s.table), ""]
        captions = []
        for i, p in enumerate(s.figures):
            number += 1
            captions.append(_caption(number, s, i))
            md += [f"![{Path(p).stem}]({Path(p).name})", "", f"*{captions[-1]}*", ""]
        if s.code:
            md += ["```text", s.code.rstrip(), "```", ""]
        body.append(f"<h2>{_inline(s.title)}</h2>")
        body += [f"<p>{_inline(par.strip())}</p>" for par in s.text.strip().split("\n\n")]
        if s.table:
            body.append(_html_table(s.table))
        for p, caption in zip(s.figures, captions, strict=True):
            raw = Path(p).read_bytes()
            data = base64.b64encode(raw).decode("ascii")
            wide = ' class="wide"' if _aspect(raw) >= WIDE_ASPECT else ""
            body.append(
                f'<figure{wide}><img alt="{html.escape(_plain(caption))}" '
                f'src="data:image/png;base64,{data}"><figcaption>{_inline(caption)}</figcaption>'
                "</figure>"
            )
        if s.code:
            body.append(f"<pre>{html.escape(s.code.rstrip())}</pre>")
    page = (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        f"<title>{html.escape(title)}</title><style>"
        "body{font-family:system-ui,sans-serif;max-width:920px;margin:2em auto;padding:0 1em;"
        "line-height:1.5;color:#222}img{max-width:100%;border:1px solid #ddd}"
        "figure{margin:1.2em 0}figure img{display:block;height:auto}"
        "figure.wide{width:min(96vw,1600px);position:relative;left:50%;"
        "transform:translateX(-50%)}figure.wide img{width:100%}"
        "code{background:#f3f3f3;padding:0 .25em;border-radius:3px;font-size:.92em}"
        "figcaption{font-size:.9em;color:#555;margin-top:.3em}pre{background:#f6f6f6;padding:.6em;"
        "overflow-x:auto}table{border-collapse:collapse;margin:.5em 0}"
        "td,th{border:1px solid #ccc;padding:.2em .6em;text-align:right}"
        "th{background:#f0f0f0}td:first-child,th:first-child{text-align:left}"
        "</style></head><body>\n" + "\n".join(body) + "\n</body></html>\n"
    )
    md_path, html_path = out_dir / "report.md", out_dir / "report.html"
    write_text(md_path, "\n".join(md))
    write_text(html_path, page)
    return [md_path, html_path]


#: Figures at least this much wider than high (three panels side by side) use the
#: full width of the window instead of the text column.
WIDE_ASPECT = 1.8
_CODE = re.compile(r"`([^`\n]+)`")


def _inline(text: str) -> str:
    """Escaped HTML of a line of text, with `backticks` shown as code."""
    return _CODE.sub(r"<code>\1</code>", html.escape(text))


def _plain(text: str) -> str:
    """The text without backticks (for alt texts)."""
    return text.replace("`", "")


def _caption(number: int, section: Section, index: int) -> str:
    """The caption sentence of a figure: given, or its number and the section title."""
    if index < len(section.captions):
        text = section.captions[index].strip()
    else:
        text = section.title.strip()
        if len(section.figures) > 1:
            text += f", part {index + 1} of {len(section.figures)}"
    text = f"Figure {number}. {text[:1].upper()}{text[1:]}"
    return text if text.endswith((".", "!", "?")) else text + "."


def _aspect(png: bytes) -> float:
    """Width over height of a PNG image (1 if it cannot be read)."""
    if png[:8] != b"\x89PNG\r\n\x1a\n" or len(png) < 24:
        return 1.0
    width, height = int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")
    return width / height if height else 1.0


def _md_table(rows: Sequence[Sequence[str]]) -> list[str]:
    head, *data = rows
    lines = ["| " + " | ".join(head) + " |", "|" + "|".join(" --- " for _ in head) + "|"]
    return lines + ["| " + " | ".join(r) + " |" for r in data]


def _html_table(rows: Sequence[Sequence[str]]) -> str:
    head, *data = rows
    out = ["<table><tr>" + "".join(f"<th>{_inline(c)}</th>" for c in head) + "</tr>"]
    out += ["<tr>" + "".join(f"<td>{_inline(c)}</td>" for c in r) + "</tr>" for r in data]
    return "".join(out) + "</table>"
