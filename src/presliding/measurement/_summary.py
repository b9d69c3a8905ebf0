"""What a `Measurement` shows in a notebook: its samples, time span and each signal's range.

`NotebookView` gives `Measurement` its ``_repr_html_`` (`presliding._display.model_html`)
with the rows of `figures`: the number of samples, the time span and sampling step, the
axis, each signal present with its range and SI unit on that axis, and the file it was
read from.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from presliding._display import model_html

__all__ = ["NotebookView", "figures"]


class NotebookView:
    """The ``_repr_html_`` of `Measurement` (a mixin: the class stays within its size)."""

    def _repr_html_(self) -> str:
        return model_html(self, figures(self), parameters=False)


def figures(m: Any) -> list[tuple[str, str, str]]:
    """(name, value, unit) rows of the Measurement `m`."""
    step = f"{m.sampling_step:.6g}" + ("" if m.is_uniform else " (median; not uniform)")
    rows = [
        ("samples", str(m.n_samples), ""),
        ("time", f"{m.time[0]:.6g} … {m.time[-1]:.6g}", "s"),
        ("sampling step", step, "s"),
        ("axis", str(m.axis), ""),
    ]
    for name, values in m.signals().items():
        low, high = float(np.min(values)), float(np.max(values))
        quantity = "force" if name.endswith("force") else name
        rows.append((name, f"{low:.6g} … {high:.6g}", m.unit(quantity)))
    if m.source is not None and m.source.path:
        rows.append(("read from", str(m.source.path), ""))
    return rows
