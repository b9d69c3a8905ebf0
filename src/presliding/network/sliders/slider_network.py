"""`SliderNetwork`: nodes joined by springs, Coulomb sliders and stops, without inertia.

A quasi-static frictional network: linear springs between nodes (or to the
ground), rigid-plastic Coulomb sliders (force in [−c, c], relative motion only
at |force| = c) and stops (a spring in series with a slider, eq. 5) between
nodes or to the ground. Node ``GROUND`` (−1) is the fixed ground. A stop is
expanded into a spring and a slider joined at an internal node numbered after
the user's nodes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_count,
    as_parameter_vector,
    check_same_length,
    check_size,
    fmt,
)

__all__ = ["GROUND", "SliderNetwork"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: The node index of the fixed ground.
GROUND = -1

#: Numbers a network needs per element (spring, slider or stop), checked before it is
#: built: its rows and their checks (13 measured while a chain is built), the expanded
#: form (12) and the quasi-static solver's sparse matrices.
FOOTPRINT = 32


def _check_elements(name: str, count: int) -> None:
    check_size(name, f"{count:,} elements", float(FOOTPRINT) * count, what="numbers")


def _rows_in(value: Any) -> int:
    if value is None:
        return 0
    shape = value.shape if isinstance(value, np.ndarray) else None
    if shape is None:
        try:
            return len(value)
        except TypeError:
            return 1
    return int(shape[0]) if len(shape) else 1


def _rows(name: str, value: Any, width: int) -> FloatArray:
    arr = np.asarray(value if value is not None else np.empty((0, width)), dtype=np.float64)
    if arr.size == 0:
        return np.empty((0, width))
    if arr.ndim == 1 and arr.shape[0] == width:
        arr = arr.reshape(1, width)
    if arr.ndim != 2 or arr.shape[1] != width:
        raise ValueError(f"`{name}` must be rows of {width} numbers; got shape {arr.shape}.")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"`{name}` must be finite; got {fmt(arr)}.")
    return arr


def _nodes(name: str, cols: FloatArray, n_nodes: int) -> IntArray:
    nodes = cols.astype(np.int64)
    if np.any(nodes != cols) or np.any(nodes < GROUND) or np.any(nodes >= n_nodes):
        bad = cols[(nodes != cols) | (nodes < GROUND) | (nodes >= n_nodes)][0]
        raise ValueError(
            f"`{name}` must join nodes 0..{n_nodes - 1} or the ground ({GROUND}); got node "
            f"{fmt(bad)}."
        )
    same = nodes[:, 0] == nodes[:, 1]
    if same.any():
        i = int(np.argmax(same))
        raise ValueError(f"`{name}` row {i} joins node {nodes[i, 0]} to itself.")
    return nodes


@dataclass(frozen=True, eq=False)
class SliderNetwork:
    """Springs, Coulomb sliders and stops between nodes and the ground (no masses).

    Parameters
    ----------
    n_nodes : int
        Number of nodes (>= 1), numbered 0..n_nodes−1; −1 (``GROUND``) is the ground.
    springs : array_like, shape (m, 3), optional
        Rows (node_a, node_b, stiffness k > 0 [N/m]).
    sliders : array_like, shape (s, 3), optional
        Rows (node_a, node_b, slip force c > 0 [N]): rigid until the force
        reaches c, then slipping (Coulomb).
    stops : array_like, shape (q, 4), optional
        Rows (node_a, node_b, stiffness k > 0 [N/m], slip force c > 0 [N]): an
        elasto-plastic element (eq. 5), a spring from node_a in series with a
        slider to node_b.

    Notes
    -----
    Every node that is not displacement-driven must be held by springs (a
    path of springs to the ground or to a displacement-driven node), so that
    each load increment has one solution; and the sliders must not form a
    closed loop with one another and the ground.
    """

    n_nodes: int
    springs: FloatArray = field(default_factory=lambda: np.empty((0, 3)))
    sliders: FloatArray = field(default_factory=lambda: np.empty((0, 3)))
    stops: FloatArray = field(default_factory=lambda: np.empty((0, 4)))

    def __post_init__(self) -> None:
        n = as_count("n_nodes", self.n_nodes, minimum=1)
        count = sum(_rows_in(x) for x in (self.springs, self.sliders, self.stops))
        _check_elements("springs, sliders and stops", n + count)
        sp = _rows("springs", self.springs, 3)
        sl = _rows("sliders", self.sliders, 3)
        st = _rows("stops", self.stops, 4)
        _nodes("springs", sp[:, :2], n)
        _nodes("sliders", sl[:, :2], n)
        _nodes("stops", st[:, :2], n)
        for name, col in (("springs", sp[:, 2]), ("sliders", sl[:, 2]), ("stops", st[:, 2])):
            as_parameter_vector(f"{name} (stiffness or slip force column)", col, allow_empty=True)
        as_parameter_vector("stops (slip force column)", st[:, 3], allow_empty=True)
        if sl.shape[0] + st.shape[0] == 0:
            raise ValueError("`sliders` or `stops` must hold at least one element; got none.")
        for name, arr in (("springs", sp), ("sliders", sl), ("stops", st)):
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        object.__setattr__(self, "n_nodes", n)

    @classmethod
    def chain(cls, stiffness: ArrayLike, slip_force: ArrayLike) -> SliderNetwork:
        """Nodes 0..N in a row: springs k_i between nodes i−1 and i, sliders c_i to ground.

        Parameters
        ----------
        stiffness : array_like, shape (N,)
            k_i > 0 [N/m], i = 1..N.
        slip_force : array_like, shape (N + 1,)
            c_i >= 0 [N] of the sliders at nodes 0..N (0: no slider there).

        Examples
        --------
        A bar of axial stiffness EA and length L on a Coulomb foundation τ,
        N segments: springs EA·N/L, sliders τL/N inside and τL/(2N) at both
        ends (the end weights make the dissipation converge as O(N⁻²))::

            c = np.full(N + 1, tau * L / N); c[[0, -1]] /= 2
            SliderNetwork.chain(np.full(N, EA * N / L), c)
        """
        _check_elements("stiffness", 2 * _rows_in(stiffness))
        k = as_parameter_vector("stiffness", stiffness)
        c = as_parameter_vector("slip_force", slip_force, positive=False)
        if c.shape[0] != k.shape[0] + 1:
            raise ValueError(
                f"`slip_force` must have one entry more than `stiffness` (one per node); got "
                f"{c.shape[0]} and {k.shape[0]}."
            )
        i = np.arange(1, k.shape[0] + 1, dtype=np.float64)
        springs = np.column_stack([i - 1, i, k])
        nodes = np.arange(k.shape[0] + 1, dtype=np.float64)
        keep = c > 0
        sliders = np.column_stack([nodes[keep], np.full(int(keep.sum()), -1.0), c[keep]])
        return cls(k.shape[0] + 1, springs, sliders)

    # ------------------------------------------------------------ expanded form
    @property
    def n_total(self) -> int:
        """Nodes including the internal node of every stop."""
        return self.n_nodes + self.stops.shape[0]

    def expanded(self) -> tuple[IntArray, FloatArray, IntArray, FloatArray]:
        """(spring nodes, stiffnesses, slider nodes, slip forces), stops expanded."""
        st = self.stops
        inner = self.n_nodes + np.arange(st.shape[0], dtype=np.int64)
        st_nodes = st[:, :2].astype(np.int64)
        spring_nodes = np.vstack([self.springs[:, :2].astype(np.int64),
                                  np.column_stack([st_nodes[:, 0], inner])])  # fmt: skip
        slider_nodes = np.vstack([self.sliders[:, :2].astype(np.int64),
                                  np.column_stack([inner, st_nodes[:, 1]])])  # fmt: skip
        k = np.concatenate([self.springs[:, 2], st[:, 2]])
        c = np.concatenate([self.sliders[:, 2], st[:, 3]])
        check_same_length(spring_nodes=spring_nodes[:, 0], stiffness=k)
        return spring_nodes, k, slider_nodes, c

    @property
    def n_sliders(self) -> int:
        """Sliders, those inside the stops included."""
        return self.sliders.shape[0] + self.stops.shape[0]

    def __repr__(self) -> str:
        return (
            f"SliderNetwork(n_nodes={self.n_nodes}, springs={self.springs.shape[0]}, "
            f"sliders={self.sliders.shape[0]}, stops={self.stops.shape[0]})"
        )

    def _repr_html_(self) -> str:
        from presliding._display import result_html

        def span(values: FloatArray) -> str:
            if values.size == 0:
                return "none"
            lo, hi = float(np.min(values)), float(np.max(values))
            return f"{lo:.6g}" if lo == hi else f"{lo:.6g} … {hi:.6g}"

        st = self.stops
        rows = [("nodes", str(self.n_nodes), ""), ("springs", str(self.springs.shape[0]), ""),
                ("sliders", str(self.sliders.shape[0]), ""), ("stops", str(st.shape[0]), ""),
                ("spring stiffness", span(self.springs[:, 2]), "N/m"),
                ("slip force", span(np.concatenate([self.sliders[:, 2], st[:, 3]])), "N"),
                ("stop stiffness", span(st[:, 2]), "N/m")]  # fmt: skip
        return result_html(self, rows, title="SliderNetwork", show_model=False)
