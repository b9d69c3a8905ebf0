"""Figures of a `NetworkResult`: contact motion, hysteresis per contact, stick/slip, energy."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from presliding._figures import new_axes, place_legend
from presliding._validation import as_choice

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

KINDS = ("time", "hysteresis", "timeline", "energy")


def _axes(ax: Axes | None) -> Axes:
    """`ax`, or the axes of a new figure with a constrained layout (the legend stays inside)."""
    return new_axes(ax)


def plot_network(res: Any, *, kind: str = "time", ax: Axes | None = None) -> Axes:
    """One figure of a network result on `ax` (new axes if None); returns the axes."""
    kind = as_choice("kind", kind, KINDS)
    ax = _axes(ax)
    n_c = res.contact_force.shape[1]
    if kind == "time":
        for c in range(n_c):
            ax.plot(res.time, res.contact_displacement[:, c], label=f"contact {c}")
        ax.set_xlabel("time [s]")
        ax.set_ylabel("contact displacement g [m]")
    elif kind == "hysteresis":
        for c in range(n_c):
            ax.plot(res.contact_displacement[:, c], res.contact_force[:, c], label=f"contact {c}")
        ax.set_xlabel("contact displacement g [m]")
        ax.set_ylabel("contact force λ [N]")
    elif kind == "timeline":
        t0, t1 = float(res.time[0]), float(res.time[-1])
        for c in range(n_c):
            ax.broken_barh([(t0, t1 - t0)], (c - 0.4, 0.8), color="tab:orange", alpha=0.5)
            spans = [(a, b - a) for a, b in res.stick_intervals[c]]
            if spans:
                ax.broken_barh(spans, (c - 0.4, 0.8), color="tab:blue")
        ax.set_yticks(np.arange(n_c))
        ax.set_xlabel("time [s]")
        ax.set_ylabel("contact (blue: stuck, orange: sliding)")
        return ax
    else:
        en = res.energy
        stored = en.kinetic + en.potential + en.elastic
        for name, values in (("stored", stored), ("Coulomb", en.coulomb.sum(axis=1)),
                             ("hysteretic", en.hysteretic.sum(axis=1)),
                             ("viscous", en.viscous.sum(axis=1)), ("damping", en.damping),
                             ("work of f", en.work)):  # fmt: skip
            ax.plot(res.time, values, label=name)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("energy [J]")
    place_legend(ax, fontsize="small")
    return ax
