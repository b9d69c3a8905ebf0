"""The result of a parameter sweep (`presliding.sweep.sweep`): values, status, plot, report."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes


@dataclass(frozen=True, eq=False)
class SweepResult:
    """Values of a sweep over a parameter grid.

    Attributes
    ----------
    grid : dict of str to ndarray
        For a product grid the axes (1-D arrays, one per parameter); for a
        table the columns (one entry per point).
    values : ndarray, shape ``shape`` + (per-point output shape)
        ``fn``'s values: for a product grid indexed like the axes, ``values[i, j]``
        at ``(axis_0[i], axis_1[j])``; for a table one row per point. Points of a
        failed chunk, and points for which ``fn`` returned only NaN or infinite
        values, hold NaN and are marked in `failed`.
    elapsed : float
        Wall time of the sweep [s], worker start-up included.
    n_workers : int
        Worker processes (local) or Dask workers used.
    status : {"ok", "failed"}
        "failed" when any point failed (see `failed`).
    message : str
        Where it ran, or how many chunks raised and how many points got no
        finite value, each with its first point.
    kind : {"product", "table"}
    backend : {"serial", "processes", "executor", "dask"}
    n_chunks : int
    failed : ndarray of bool, shape ``shape``
        Points whose chunk raised, and points whose value (every entry of a row)
        is NaN or infinite. A row with at least one finite entry is kept as
        returned: a row may carry its own validity flag next to a NaN.
    """

    grid: dict[str, NDArray[np.float64]]
    values: np.ndarray
    elapsed: float
    n_workers: int
    status: str
    message: str
    kind: str
    backend: str
    n_chunks: int
    failed: NDArray[np.bool_]

    @property
    def shape(self) -> tuple[int, ...]:
        """Shape of the grid: the axis lengths (product) or (n_points,) (table)."""
        return self.failed.shape

    @property
    def success(self) -> bool:
        """True when every point was evaluated (status "ok", no point in `failed`)."""
        return self.status == "ok"

    def plot(self, ax: Axes | None = None, **kwargs: Any) -> Axes:
        """A 2-D product grid as a colour map (first parameter on x), a 1-D one as a curve."""
        from presliding.plotting import plot_sweep

        per_point = self.values.shape[len(self.shape) :]
        if self.kind != "product" or len(self.shape) not in (1, 2) or per_point:
            raise ValueError(
                "`plot` needs a 1-D or 2-D product grid with one value per point; got a "
                f"{self.kind} grid of shape {self.shape} with per-point shape {per_point}."
            )
        names = list(self.grid)
        axes = [self.grid[n] for n in names]
        return plot_sweep(axes, self.values, names, ax=ax, **kwargs)

    def report(self) -> str:
        """A readable summary of the grid, the run and the values."""
        lines = [f"sweep: {self.status} ({self.message})"]
        for name, arr in self.grid.items():
            lines.append(f"  {name}: {arr.size} values in [{arr.min():.6g}, {arr.max():.6g}]")
        n = int(np.prod(self.shape))
        lines.append(
            f"  {n} points ({self.kind}) in {self.n_chunks} chunks "
            f"{where_run(self.backend, self.n_workers)}: {self.elapsed:.3f} s"
        )
        ok = self.values[~self.failed]
        if ok.size and np.issubdtype(ok.dtype, np.number):
            lines.append(f"  values in [{np.min(ok):.6g}, {np.max(ok):.6g}]")
        return "\n".join(lines)


def where_run(backend: str, workers: int) -> str:
    """Where a sweep ran, in words."""
    if backend == "serial":
        return "in this process"
    if backend == "processes":
        return f"on {workers} local worker processes"
    if backend == "executor":
        return f"on a given executor ({workers} workers)"
    return f"on {workers} Dask workers"
