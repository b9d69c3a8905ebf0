"""The result of a parameter sweep (`presliding.sweep.sweep`): values, status, plot, report.

`SweepResult.to_pandas` and `SweepResult.to_xarray` hand the values to pandas and
xarray, which are optional (the ``pandas`` and ``xarray`` extras) and imported
only when those methods are called.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from presliding._display import result_html, short_repr, summarise
from presliding._interop import require
from presliding._validation import check_type

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    import xarray as xr
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

    def to_pandas(self, names: Sequence[str] | None = None) -> pd.DataFrame:
        """The values as a pandas DataFrame, one row per point.

        Parameters
        ----------
        names : sequence of str, optional
            Column names of the per-point values: one name for one value per
            point, or one per entry of a row. Default ``"value"``, or
            ``"value_0"``, ``"value_1"``, ... for rows.

        Returns
        -------
        pandas.DataFrame
            For a product grid, indexed by a MultiIndex of the axes (first axis
            varying slowest, as in ``values.ravel()``), so ``df["value"].unstack()``
            gives the 2-D map; for a table, the grid's columns first, then the
            values. A boolean column ``failed`` marks the points of `failed`.
            ``df.attrs`` holds ``success``, ``status``, ``message``, ``backend``,
            ``elapsed`` [s] and ``units`` (empty: the grid's units are the caller's).
        """
        pd = _optional("pandas", "to_pandas")
        columns = self._named_values(names)
        columns["failed"] = self.failed.ravel()
        if self.kind == "product":
            index = pd.MultiIndex.from_product(list(self.grid.values()), names=list(self.grid))
            frame = pd.DataFrame(columns, index=index)
        else:
            frame = pd.DataFrame({**self.grid, **columns})
        frame.attrs.update(self._attrs(), success=self.success, units={"elapsed": "s"})
        return frame

    def to_xarray(self, names: Sequence[str] | None = None) -> xr.Dataset:
        """The values as an xarray Dataset on the grid's coordinates.

        Parameters
        ----------
        names : sequence of str, optional
            Names of the per-point values, as for `to_pandas`; each becomes a data
            variable.

        Returns
        -------
        xarray.Dataset
            For a product grid, one dimension per axis with the axis values as
            coordinates; for a table, one dimension ``point`` with the grid's
            columns as coordinates along it. Data variables: the values (one per
            name) and ``failed``; ``attrs`` holds ``status``, ``message``,
            ``backend`` and ``elapsed``.
        """
        xr = _optional("xarray", "to_xarray")
        if self.kind == "product":
            dims = tuple(self.grid)
            coords: dict[str, Any] = dict(self.grid)
        else:
            dims = ("point",)
            coords = {name: ("point", col) for name, col in self.grid.items()}
        data = {
            name: (dims, column.reshape(self.shape))
            for name, column in self._named_values(names).items()
        }
        data["failed"] = (dims, self.failed)
        return xr.Dataset(data, coords=coords, attrs=self._attrs())

    def _named_values(self, names: Sequence[str] | None) -> dict[str, np.ndarray]:
        """The per-point values as flat columns, by name."""
        n = int(np.prod(self.shape))
        flat = self.values.reshape(n, -1)
        width = flat.shape[1]
        per_point = self.values.shape[len(self.shape) :]
        if names is None:
            names = ["value"] if not per_point else [f"value_{j}" for j in range(width)]
        else:
            names = (
                [names] if isinstance(names, str) else list(check_type("names", names, Sequence))
            )
            if (
                len(names) != width
                or len(set(names)) != width
                or not all(isinstance(name, str) and name for name in names)
            ):
                raise ValueError(
                    f"`names` must be {width} distinct non-empty strings, one per value of a "
                    f"point; got {names!r}."
                )
            clash = set(names) & ({"failed"} | set(self.grid))
            if clash:
                raise ValueError(
                    f"`names` must not repeat a grid name or 'failed'; got {sorted(clash)}."
                )
        return {name: flat[:, j] for j, name in enumerate(names)}

    def to_dict(self) -> dict[str, Any]:
        """The grid, values, failed points and the run's summary as plain values."""
        return {
            "grid": dict(self.grid), "values": self.values, "failed": self.failed,
            "kind": self.kind, "shape": self.shape, "status": self.status,
            "success": self.success, "message": self.message, "backend": self.backend,
            "n_workers": self.n_workers, "n_chunks": self.n_chunks, "elapsed": self.elapsed,
        }  # fmt: skip

    def _attrs(self) -> dict[str, Any]:
        return {
            "status": self.status,
            "message": self.message,
            "backend": self.backend,
            "elapsed": self.elapsed,
        }

    def __repr__(self) -> str:
        return short_repr(self, ("kind", "shape", "grid", "values", "failed", "backend",
                                 "n_workers", "n_chunks", "elapsed"))  # fmt: skip

    def _repr_html_(self) -> str:
        """The status, the run and the grid's axes, for notebooks."""
        n = int(np.prod(self.shape))
        figures = [("points", f"{n} ({self.kind}, shape {self.shape})", ""),
                   ("failed points", str(int(np.sum(self.failed))), ""),
                   ("values", summarise(self.values), ""),
                   ("run", f"{self.n_chunks} chunks {where_run(self.backend, self.n_workers)}",
                    ""),
                   ("elapsed", f"{self.elapsed:.3f}", "s")]  # fmt: skip
        rows = [(name, arr.size, f"{np.min(arr):.6g}", f"{np.max(arr):.6g}")
                for name, arr in self.grid.items()]  # fmt: skip
        return result_html(self, figures, (("grid", "values", "min", "max"), rows))

    def report(self) -> str:
        """A readable summary of the grid, the run and the values."""
        lines = [f"sweep: {self.status} ({self.message})"]
        for name, arr in self.grid.items():
            lines.append(f"  {name}: {arr.size} values in [{np.min(arr):.6g}, {np.max(arr):.6g}]")
        n = int(np.prod(self.shape))
        lines.append(
            f"  {n} points ({self.kind}) in {self.n_chunks} chunks "
            f"{where_run(self.backend, self.n_workers)}: {self.elapsed:.3f} s"
        )
        ok = self.values[~self.failed]
        if ok.size and np.issubdtype(ok.dtype, np.number):
            lines.append(f"  values in [{np.min(ok):.6g}, {np.max(ok):.6g}]")
        return "\n".join(lines)


def _optional(module: str, method: str) -> Any:
    """Import an optional dependency, or say which extra installs it (`require`)."""
    return require(module, f"`SweepResult.{method}()`")


def where_run(backend: str, workers: int) -> str:
    """Where a sweep ran, in words."""
    if backend == "serial":
        return "in this process"
    if backend == "processes":
        return f"on {workers} local worker processes"
    if backend == "executor":
        return f"on a given executor ({workers} workers)"
    return f"on {workers} Dask workers"
