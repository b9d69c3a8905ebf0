"""Sphinx configuration of the presliding documentation.

Build (offline, warnings as errors)::

    pip install -e ".[docs]"
    sphinx-build -W -b html docs docs/_build/html

The example scripts in ``examples/`` become the gallery (sphinx-gallery): they
run during the build and their figures are shown. ``-D plot_gallery=0`` renders
them without running (what the test suite does: ``tests/test_docs.py``, the
examples themselves run in ``tests/test_examples.py``).

Links to numpy, scipy, matplotlib, Python, python-control, pandas, lmfit and pint go
through the inventories bundled in ``docs/_inventories/`` (written offline by
``docs/_ext/make_inventories.py``): the build downloads nothing. The changelog
page is made from ``CHANGELOG.md`` at every build.

The API reference is generated from ``__all__``: the pages ``api/<layer>.rst``
are written here at every build from each layer's ``__all__`` (and the root's),
so every public name is documented and a new one needs no edit of these files.
"""

from __future__ import annotations

import importlib
import re
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT / "src"))  # a source checkout builds without installing

import presliding  # noqa: E402

project = "presliding"
author = "presliding developers"
copyright = "presliding developers"
release = presliding.__version__
version = ".".join(release.split(".")[:2])

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
]

templates_path = ["_templates"]
exclude_patterns = ["_build", "auto_examples/*.ipynb", "auto_examples/*.py", "**.zip", "**.md5"]
source_suffix = {".rst": "restructuredtext"}
root_doc = "index"
nitpicky = False

# -- API reference -------------------------------------------------------------------
autosummary_generate = True
autosummary_imported_members = True
autodoc_typehints = "none"  # numpydoc's Parameters sections carry the types
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

#: The layers in the order data flows, with a line on what each holds.
LAYERS = {
    "hysteresis": "play and stop operators, PI operators, densities, the inverse operator",
    "friction": "PIFriction (eqs. 8-10) and the Coulomb, Dahl and LuGre baselines",
    "motion": "simulate a mass with friction (eqs. 12, 17), batches, free responses",
    "analysis": "when a free mass stops: eqs. 14-16, turning points, energy",
    "network": "structures with many friction contacts: exact stick/slip per contact",
    "measurement": "measured signals: readers, units, joins, windows, filters, derivatives",
    "identification": "fits to measurements (section 4)",
    "control": "python-control systems",
    "sweep": "parameter sweeps on local processes or Dask",
}
#: Modules of the shared ground with a reference page of their own.
SHARED = {
    "plotting": "plot functions behind every result's ``plot``",
    "model_io": "model files (TOML): read, write, build a model",
    "signals": "input paths: piecewise-linear displacements, the paper's Figure 3",
}


def _write_if_changed(path: Path, text: str) -> None:
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


def _api_pages() -> None:
    """One page per layer: an autosummary table of its public names.

    A name the root re-exports is documented as ``presliding.<name>`` (how it is
    imported); the layer's other public names as ``presliding.<layer>.<name>``.
    """
    root = set(presliding.__all__)
    documented: set[str] = set()
    for layer, summary in LAYERS.items():
        module = importlib.import_module(f"presliding.{layer}")
        names = sorted(module.__all__, key=str.lower)
        entries = [f"presliding.{n}" if n in root else f"presliding.{layer}.{n}" for n in names]
        documented.update(n for n in names if n in root)
        title = f"``presliding.{layer}``: {summary}"
        lines = [
            f".. _api-{layer}:",
            "",
            title,
            "=" * len(title),
            "",
            ".. currentmodule:: presliding",
            "",
            ".. autosummary::",
            "   :toctree: generated/",
            "   :nosignatures:",
            "",
            *(f"   {e.removeprefix('presliding.')}" for e in entries),
            "",
        ]
        _write_if_changed(DOCS / "api" / f"{layer}.rst", "\n".join(lines))
    for name, summary in SHARED.items():
        module = importlib.import_module(f"presliding.{name}")
        title = f"``presliding.{name}``: {summary}"
        lines = [
            f".. _api-{name}:",
            "",
            title,
            "=" * len(title),
            "",
            f".. automodule:: presliding.{name}",
            "   :no-members:",
            "   :no-index:",
            "",
            f".. currentmodule:: presliding.{name}",
            "",
            ".. autosummary::",
            "   :toctree: generated/",
            "   :nosignatures:",
            "",
            *(f"   {n}" for n in sorted(module.__all__, key=str.lower)),
            "",
        ]
        _write_if_changed(DOCS / "api" / f"{name}.rst", "\n".join(lines))
    rest = sorted((n for n in root - documented if not n.startswith("_")), key=str.lower)
    title = "Shared helpers at the package root"
    lines = [
        ".. _api-root:",
        "",
        title,
        "=" * len(title),
        "",
        "Names of ``presliding.__all__`` that belong to no layer.",
        "",
        ".. currentmodule:: presliding",
        "",
        ".. autosummary::",
        "   :toctree: generated/",
        "   :nosignatures:",
        "",
        *(f"   {n}" for n in rest),
        "",
    ]
    _write_if_changed(DOCS / "api" / "root.rst", "\n".join(lines))


_api_pages()

# -- Changelog: CHANGELOG.md as a page -------------------------------------------------
_LINK = re.compile(r"\[([^\]]+)\]\(([^)\s]+)\)")


def _inline(text: str) -> str:
    """Markdown inline markup as reST: `code`, **strong**, [text](url)."""
    text = re.sub(r"(?<!`)`([^`]+)`(?!`)", r"``\1``", text)
    text = re.sub(r"(?<![\w*])\*([^*\s][^*]*?)\*(?![\w*])", r"*\1*", text)
    text = _LINK.sub(lambda m: f"`{m.group(1)} <{m.group(2)}>`__", text)
    return text.replace("|", "\\|")


def _changelog_page() -> None:
    """docs/changelog.rst from CHANGELOG.md: headings, paragraphs and bullet lists (inline
    markup may run over several lines of a paragraph, so it is converted block by block)."""
    marks = {1: "=", 2: "-", 3: "~", 4: "^"}
    out: list[str] = [".. _changelog:", ""]
    block: list[str] = []
    for line in [*(ROOT / "CHANGELOG.md").read_text(encoding="utf-8").splitlines(), "# end"]:
        # "# end" closes the last block
        head = re.match(r"^(#{1,4}) (.*)$", line)
        if not head:
            block.append(line)
            continue
        out += [*_inline("\n".join(block)).splitlines(), ""]
        block = []
        if line != "# end":
            title = _inline(head.group(2)).replace("[", "").replace("]", "")
            out += [title, marks[len(head.group(1))] * len(title), ""]
    _write_if_changed(DOCS / "changelog.rst", "\n".join(out) + "\n")


_changelog_page()

# -- Links to other projects' documentation (bundled inventories: no download) ---------
_INV = DOCS / "_inventories"
_CONTROL_DOCS = "https://python-control.readthedocs.io/en/latest"
intersphinx_mapping = {
    "python": ("https://docs.python.org/3", str(_INV / "python.inv")),
    "numpy": ("https://numpy.org/doc/stable", str(_INV / "numpy.inv")),
    "scipy": ("https://docs.scipy.org/doc/scipy", str(_INV / "scipy.inv")),
    "matplotlib": ("https://matplotlib.org/stable", str(_INV / "matplotlib.inv")),
    "control": (
        _CONTROL_DOCS,
        str(_INV / "python-control.inv"),
    ),
    "pandas": ("https://pandas.pydata.org/docs", str(_INV / "pandas.inv")),
    "lmfit": ("https://lmfit.github.io/lmfit-py", str(_INV / "lmfit.inv")),
    "pint": ("https://pint.readthedocs.io/en/stable", str(_INV / "pint.inv")),
}
intersphinx_timeout = 1

# -- Gallery: the scripts of examples/ -------------------------------------------------
sys.path.insert(0, str(DOCS / "_ext"))  # gallery_hooks, named by string (a picklable config)

sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r".*\.py$",  # every example runs (unless plot_gallery=0)
    "reset_argv": "gallery_hooks.example_argv",
    "image_scrapers": ("gallery_hooks.saved_figure_scraper",),
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "matplotlib_animations": False,
    "show_memory": False,
    "min_reported_time": 10**9,
}

# -- Docstrings -----------------------------------------------------------------------
_BARS = re.compile(r"(?<![\\`|])\|(?=[^|\s`])([^|\n`]*?[^|\s\\`])\|(?![|_`])")


def _plain_bars(app, what, name, obj, options, lines):
    """|x| in docstrings is an absolute value or a norm, never a reST substitution.

    Before numpydoc reads them, each ``|...|`` pair on a line becomes literal bars.
    """
    for i, line in enumerate(lines):
        if "|" in line and not line.lstrip().startswith((">>>", "...")):
            lines[i] = _BARS.sub(lambda m: "\\|" + m.group(1) + "\\|", line)


def setup(app):
    app.connect("autodoc-process-docstring", _plain_bars, priority=100)


# -- HTML ------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"presliding {release}"
html_static_path: list[str] = []
html_theme_options = {
    "navigation_with_keys": False,
    "show_prev_next": True,
    "secondary_sidebar_items": ["page-toc"],
    "footer_start": ["copyright"],
    "footer_end": [],
    "header_links_before_dropdown": 6,
}
# The top navigation: the user guide, the examples, the API reference and the changelog; the
# sidebar lists the pages of each (none on the front page).
html_sidebars = {"**": ["sidebar-nav-bs"], "index": [], "changelog": []}
html_show_sourcelink = False
