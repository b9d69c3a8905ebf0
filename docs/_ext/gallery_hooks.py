"""Hooks of the example gallery (sphinx-gallery), named by string in ``conf.py``.

The example scripts save their figure themselves, to the path given as their
first argument: `example_argv` gives each one a path next to its page, and
`saved_figure_scraper` shows that PNG on the page.
"""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any


def _figure_path(script_vars: dict[str, Any]) -> Path:
    return Path(script_vars["target_file"]).with_suffix(".figure.png")


def example_argv(gallery_conf: dict[str, Any], script_vars: dict[str, Any]) -> list[str]:
    """The argument list of an example: where to write its figure."""
    return [str(_figure_path(script_vars))]


def saved_figure_scraper(
    block: Any, block_vars: dict[str, Any], gallery_conf: dict[str, Any]
) -> str:
    """The figure an example wrote, moved among the gallery's images."""
    from sphinx_gallery.scrapers import figure_rst

    made = _figure_path(block_vars)
    if not made.exists():
        return ""
    target = Path(next(block_vars["image_path_iterator"]))
    shutil.move(str(made), target)
    return figure_rst([str(target)], gallery_conf["src_dir"])
