"""`quasi_static_network`: the exact response of a slider network to driven nodes.

Nodes are displacement-driven (a prescribed path) or force-driven (an applied
force path); the inputs are linear between samples, and the network starts
relaxed (every node at 0, every spring at rest, every slider force 0) with
every input at 0, moving linearly to the first sample. The response is
piecewise linear with breakpoints where a slider sticks or slips, found
exactly by the event-driven active-set solution of `_qs_solver`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import NDArray
from threadpoolctl import threadpool_limits

from presliding._display import fill_attrs
from presliding._interop import require
from presliding._validation import as_count, as_signal, check_type, fmt
from presliding.hysteresis._results import ResultMixin
from presliding.network.sliders._qs_solver import EventLimit, EventSolver, Path
from presliding.network.sliders.slider_network import SliderNetwork

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["QuasiStaticNetworkResult", "quasi_static_network"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass(frozen=True, eq=False)
class QuasiStaticNetworkResult(ResultMixin):
    """The path of every node of a quasi-static slider network.

    Attributes
    ----------
    sample : ndarray, shape (T,)
        The sample index k of the inputs (the response between samples is
        piecewise linear; its breakpoints are below).
    positions : ndarray, shape (T, n_nodes)
        Node positions at the samples [m].
    forces : ndarray, shape (T, n_driven)
        The force the drive applies at each displacement-driven node [N]
        (springs plus sliders attached to it).
    slider_forces : ndarray, shape (T, n_sliders)
        Slider forces f in [−c, c] [N], sliders then the sliders of the stops.
    breakpoints : ndarray, shape (E,)
        The input parameter s of every breakpoint (samples included; −1 is the
        relaxed start, k the sample k; a repeated s is a force jump of a slider
        between driven nodes or the ground).
    breakpoint_positions : ndarray, shape (E, n_nodes)
    breakpoint_forces : ndarray, shape (E, n_driven)
    displacement_nodes, force_nodes : ndarray of int
    n_events : int
        Pieces of the exact solution.
    network : SliderNetwork
    status : str
        'success', or 'event_limit' (more than ``max_events`` pieces: the arrays
        stop at the last sample reached).
    message : str
    """

    sample: FloatArray
    positions: FloatArray
    forces: FloatArray
    slider_forces: FloatArray
    breakpoints: FloatArray
    breakpoint_positions: FloatArray
    breakpoint_forces: FloatArray
    displacement_nodes: IntArray
    force_nodes: IntArray
    n_events: int
    network: SliderNetwork = field(repr=False)
    status: str = "success"
    message: str = ""
    _rows: ClassVar[str] = "sample"

    @property
    def success(self) -> bool:
        """True when every sample was reached."""
        return self.status == "success"

    def __repr__(self) -> str:
        return (
            f"QuasiStaticNetworkResult(samples={self.sample.shape[0]}, "
            f"events={self.n_events}, status={self.status!r})"
        )

    def report(self) -> str:
        """A readable summary."""
        lines = [
            f"quasi-static response of {self.network!r}: {self.status}",
            self.message,
            f"samples: {self.sample.shape[0]}, breakpoints: {self.breakpoints.shape[0]}, "
            f"pieces: {self.n_events}",
        ]
        for j, node in enumerate(self.displacement_nodes):
            x, f = self.positions[:, node], self.forces[:, j]
            lines.append(
                f"  node {node} (displacement-driven): x in [{x.min():.6g}, {x.max():.6g}] m, "
                f"force in [{f.min():.6g}, {f.max():.6g}] N"
            )
        for node in self.force_nodes:
            x = self.positions[:, node]
            lines.append(f"  node {node} (force-driven): x in [{x.min():.6g}, {x.max():.6g}] m")
        return "\n".join(lines)

    def to_pandas(self) -> Any:
        """A DataFrame indexed by sample: positions ``x<node>`` and forces ``force<node>``."""
        pd = require("pandas", "`to_pandas()`")

        cols: dict[str, Any] = {
            f"x{i}": self.positions[:, i] for i in range(self.positions.shape[1])
        }
        for j, node in enumerate(self.displacement_nodes):
            cols[f"force{node}"] = self.forces[:, j]
        frame = pd.DataFrame(cols, index=pd.Index(self.sample, name="sample"))
        units = {c: ("m" if c.startswith("x") else "N") for c in cols}
        return fill_attrs(frame, self, units={**units, "sample": "index"})

    def plot(self, ax: Axes | None = None) -> Axes:
        """Force against displacement at the first driven node, through every breakpoint."""
        from presliding.plotting import new_axes

        ax = new_axes(ax)
        if self.displacement_nodes.shape[0]:
            node = int(self.displacement_nodes[0])
            ax.plot(self.breakpoint_positions[:, node], self.breakpoint_forces[:, 0])
            ax.set_ylabel(f"force at node {node} [N]")
        else:
            node = int(self.force_nodes[0])
            ax.plot(self.breakpoints, self.breakpoint_positions[:, node])
            ax.set_ylabel(f"position of node {node} [m]")
        ax.set_xlabel(
            f"position of node {node} [m]" if self.displacement_nodes.shape[0] else "sample [-]"
        )
        ax.grid(True, alpha=0.3)
        return ax


def _drives(name: str, value: Any, n_nodes: int) -> tuple[list[int], list[FloatArray]]:
    if value is None:
        return [], []
    check_type(name, value, dict)
    nodes, paths = [], []
    for node, path in value.items():
        if isinstance(node, bool) or not isinstance(node, (int, np.integer)):
            raise TypeError(f"`{name}` must map node indices to paths; got key {fmt(node)}.")
        if not 0 <= int(node) < n_nodes:
            raise ValueError(f"`{name}` must drive nodes 0..{n_nodes - 1}; got node {fmt(node)}.")
        nodes.append(int(node))
        paths.append(as_signal(f"{name}[{node}]", path))
    return nodes, paths


def driven_inputs(
    network: SliderNetwork, displacement: Any, force: Any
) -> tuple[IntArray, FloatArray, IntArray, FloatArray]:
    """Checked (displacement nodes, u (T, nD), force nodes, p (T, nP))."""
    check_type("network", network, SliderNetwork)
    dn, du = _drives("displacement", displacement, network.n_nodes)
    fn, fp = _drives("force", force, network.n_nodes)
    if not dn and not fn:
        raise ValueError("`displacement` or `force` must drive at least one node; got neither.")
    both = set(dn) & set(fn)
    if both:
        raise ValueError(
            f"a node is driven by `displacement` or by `force`, not both; got node {min(both)}."
        )
    lengths = {p.shape[0] for p in du + fp}
    if len(lengths) > 1:
        raise ValueError(
            f"every input path must have the same length; got lengths {sorted(lengths)}."
        )
    t = lengths.pop()
    u = np.column_stack(du) if du else np.zeros((t, 0))
    p = np.column_stack(fp) if fp else np.zeros((t, 0))
    return np.array(dn, dtype=np.int64), u, np.array(fn, dtype=np.int64), p


def quasi_static_network(
    network: SliderNetwork,
    *,
    displacement: dict[int, Any] | None = None,
    force: dict[int, Any] | None = None,
    max_events: int = 1_000_000,
) -> QuasiStaticNetworkResult:
    """Exact quasi-static response of a slider network to displacement- and force-driven nodes.

    Each input increment solves Moreau's sweeping process (the minimiser of
    ½Σk(Δx)² + Σc|Δd| − Δpᵀx over the free nodes); for inputs linear between
    samples the response is piecewise linear and its breakpoints (a slider
    sticks or starts to slip) are found exactly by an event-driven active set.

    Parameters
    ----------
    network : SliderNetwork
    displacement : dict {node: array_like, shape (T,)}, optional
        Prescribed positions of displacement-driven nodes [m].
    force : dict {node: array_like, shape (T,)}, optional
        Applied forces at force-driven nodes [N].
    max_events : int
        Most pieces of the solution (the status says when it is reached).

    Returns
    -------
    QuasiStaticNetworkResult

    Examples
    --------
    A stop (spring 100 N/m in series with a 1 N slider) pulled to 2 cm and back:

    >>> net = SliderNetwork(1, stops=[(0, -1, 100.0, 1.0)])
    >>> res = quasi_static_network(net, displacement={0: [0.02, 0.0]})
    >>> [round(float(f), 12) for f in res.forces[:, 0]]
    [1.0, -1.0]
    """
    dn, u, fn, p = driven_inputs(network, displacement, force)
    max_events = as_count("max_events", max_events, minimum=1)
    solver = EventSolver(network, dn, fn)
    status, message = "success", "every sample reached; the breakpoints are exact."
    try:
        with threadpool_limits(1):  # small dense solves: threads only cost
            path, events = solver.run(u, p, max_events)
    except EventLimit as stop:
        path, events = stop.path, stop.events
        status = "event_limit"
        message = (
            f"the event limit (max_events={max_events}) was reached at input parameter "
            f"s = {path.s[-1]:.6g}: the arrays stop at the last sample reached."
        )
    return _result(network, solver, path, events, dn, fn, u.shape[0], status, message)


def _result(
    network: SliderNetwork,
    solver: EventSolver,
    path: Path,
    events: int,
    dn: IntArray,
    fn: IntArray,
    t: int,
    status: str,
    message: str,
) -> QuasiStaticNetworkResult:
    s = np.array(path.s)
    x = np.array(path.x)[:, : network.n_nodes]
    forces = np.array(path.force).reshape(s.shape[0], dn.shape[0])
    slider = np.array(path.slider).reshape(s.shape[0], -1)
    idx = np.searchsorted(s, np.arange(t, dtype=np.float64), side="left")
    idx = idx[idx < s.shape[0]]
    idx = idx[s[idx] == np.arange(idx.shape[0])]
    return QuasiStaticNetworkResult(
        sample=np.arange(idx.shape[0], dtype=np.float64),
        positions=x[idx],
        forces=forces[idx],
        slider_forces=slider[idx],
        breakpoints=s,
        breakpoint_positions=x,
        breakpoint_forces=forces,
        displacement_nodes=dn,
        force_nodes=fn,
        n_events=events,
        network=network,
        status=status,
        message=message,
    )
