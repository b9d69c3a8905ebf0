"""The points of a sweep, described small enough to send anywhere, and one chunk's work.

A `Points` holds either the axes of a Cartesian product (a few 1-D arrays, however
many points they span) or the columns of a table. Chunks are index ranges with a
stride: chunk ``i`` of ``n_chunks`` holds the points ``i, i + n_chunks,
i + 2·n_chunks, ...`` (interleaving spreads expensive regions of the grid over all
chunks, so workers finish together). A worker builds its chunk's columns itself
from ``(points, i, n_chunks)``: nothing of size n_points travels with a task.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from presliding._validation import as_real_vector, check_size, fmt


@dataclass(frozen=True, eq=False)
class Points:
    """The points of a sweep: product axes or table columns (picklable, no mesh formed)."""

    kind: str  # "product" or "table"
    names: tuple[str, ...]
    arrays: tuple[np.ndarray, ...]  # the axes (product) or the columns (table)

    @property
    def shape(self) -> tuple[int, ...]:
        """The axes' lengths (product) or (n_points,) (table)."""
        if self.kind == "product":
            return tuple(a.shape[0] for a in self.arrays)
        return (self.arrays[0].shape[0],)

    @property
    def n_points(self) -> int:
        return int(np.prod(self.shape, dtype=np.int64))

    @property
    def nbytes(self) -> int:
        return sum(a.nbytes for a in self.arrays)

    def chunk(self, start: int, step: int) -> dict[str, np.ndarray]:
        """The columns of the points ``start, start + step, ...`` (contiguous float64)."""
        if self.kind == "table":
            pairs = zip(self.names, self.arrays, strict=True)
            return {n: np.ascontiguousarray(a[start::step]) for n, a in pairs}
        flat = np.arange(start, self.n_points, step, dtype=np.int64)
        index = np.unravel_index(flat, self.shape)
        return {n: a[i] for n, a, i in zip(self.names, self.arrays, index, strict=True)}

    def rows(self, start: int, step: int) -> Points:
        """The same points as `chunk`, as a table of their own (what a local worker is sent)."""
        cols = self.chunk(start, step)
        return Points("table", self.names, tuple(cols[n] for n in self.names))

    def point(self, flat: int) -> dict[str, float]:
        """The parameters of one point, by its flat index."""
        if self.kind == "table":
            return {n: float(a[flat]) for n, a in zip(self.names, self.arrays, strict=True)}
        index = np.unravel_index(flat, self.shape)
        return {n: float(a[i]) for n, a, i in zip(self.names, self.arrays, index, strict=True)}


def as_points(grid: Any) -> Points:
    """Validate a sweep's `grid`: a dict of 1-D axes (product) or a 1-D structured array."""
    if isinstance(grid, np.ndarray) and grid.dtype.names:
        if grid.ndim != 1 or grid.shape[0] == 0:
            raise ValueError(
                f"`grid` as a table must be a non-empty 1-D structured array; got shape "
                f"{grid.shape}."
            )
        names = tuple(grid.dtype.names)
        columns = tuple(as_real_vector(f"grid[{n!r}]", grid[n]) for n in names)
        return Points("table", names, columns)
    if not isinstance(grid, Mapping) or not grid:
        raise TypeError(
            "`grid` must be a non-empty dict of 1-D arrays (Cartesian product) or a "
            f"1-D structured array (table); got {fmt(grid)}."
        )
    axes = []
    for name, arr in grid.items():
        if not isinstance(name, str) or not name.isidentifier():
            raise ValueError(f"`grid` keys must be parameter names; got {fmt(name)}.")
        if np.ndim(arr) > 1:
            raise ValueError(f"`grid[{name!r}]` must be one-dimensional; got {np.shape(arr)}.")
        axes.append(as_real_vector(f"grid[{name!r}]", arr))
    # the values, the failure flags and each chunk's columns scale with the product
    n_points = math.prod(a.shape[0] for a in axes)
    check_size("grid", grid, n_points, what="grid points", item_bytes=8 * (len(axes) + 2))
    return Points("product", tuple(grid), tuple(axes))


def run_chunk(fn: Callable[..., Any], points: Points, start: int, step: int) -> tuple[bool, Any]:
    """Build a chunk's columns and call `fn` on them; runs in workers.

    Returns (True, values) or (False, text) when `fn` returned the wrong shape or
    type. Exceptions raised by `fn` propagate: the caller reports them (and Dask
    retries them first, when asked).
    """
    columns = points.chunk(start, step)
    n = next(iter(columns.values())).shape[0]
    out = np.asarray(fn(**columns))
    if out.ndim == 0 or out.shape[0] != n:
        return False, f"`fn` must return one value per point ({n}); got shape {out.shape}"
    if out.dtype.kind not in "biuf":
        return False, f"`fn` must return real numbers; got dtype {out.dtype}"
    return True, out


def describe_error(exc: BaseException) -> str:
    """The text a failed chunk reports: the exception's type and message."""
    return f"{type(exc).__name__}: {exc}"


__all__ = ["Points", "as_points", "describe_error", "run_chunk"]
