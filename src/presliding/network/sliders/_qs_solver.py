"""The event-driven active-set solution of a quasi-static slider network.

Without inertia, equilibrium of the free nodes F (all but the
displacement-driven nodes D and the ground) reads

    K_FF·x_F + K_FD·u + B_F·f = p_F,       f_s ∈ [−c_s, c_s],

with f the slider forces, B the slider incidence (d_s = b_sᵀx) and p the
applied forces. Each input increment is Moreau's sweeping process (the
minimiser of ½Σk(Δx)² + Σc|Δd| − Δpᵀx). For an input linear in the parameter
s the rates are constant between events, so the response is piecewise
linear: at a state, the rates solve the convex rate problem

    min ½vᵀK_FF v + (K_FD u̇ − ṗ)ᵀv   s.t. ḋ_s = 0 for sticking sliders,
                                        sign(f_s)·ḋ_s >= 0 at |f_s| = c_s,

whose multipliers are the force rates ḟ; it is solved exactly by an active
set (Murty's least-index pivoting on the sliders at their limits). An event
is a sticking slider whose force reaches ±c; the time to it is exact. Sliders
between driven nodes or the ground only (no free node) take ±c at once when
their ends move apart.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse import csgraph
from scipy.sparse.linalg import splu

from presliding.network.sliders.slider_network import GROUND, SliderNetwork

FloatArray = NDArray[np.float64]

_DENSE_LIMIT = 300  # KKT systems up to this size are solved densely


@dataclass
class Path:
    """Breakpoints of the piecewise-linear response (samples included)."""

    s: list[float] = field(default_factory=list)
    x: list[FloatArray] = field(default_factory=list)  # positions of every node (ground excluded)
    force: list[FloatArray] = field(default_factory=list)  # reactions at the driven nodes
    slider: list[FloatArray] = field(default_factory=list)
    force_rate: list[FloatArray] = field(default_factory=list)  # dR/ds on the piece ending here


class EventLimit(RuntimeError):
    """More events than allowed; ``path`` and ``events`` hold the solution so far."""

    def __init__(self, path: Path, events: int) -> None:
        super().__init__(f"more than {events - 1} events")
        self.path, self.events = path, events


class EventSolver:
    """Exact quasi-static evolution of a `SliderNetwork` under driven nodes."""

    def __init__(self, network: SliderNetwork, displacement_nodes: Any, force_nodes: Any) -> None:
        n = network.n_total
        sn, k, ln, c = network.expanded()
        self.n = n
        self.drv = np.asarray(displacement_nodes, dtype=np.int64)
        driven = np.zeros(n, dtype=bool)
        driven[self.drv] = True
        self.free = np.flatnonzero(~driven)
        self.fnodes = np.asarray(force_nodes, dtype=np.int64)
        pos_free = np.full(n, -1)
        pos_free[self.free] = np.arange(self.free.shape[0])
        self.force_pos = pos_free[self.fnodes]
        rows, cols, vals = [], [], []
        for (a, b), kk in zip(sn, k, strict=True):
            for i, j, v in ((a, a, kk), (b, b, kk), (a, b, -kk), (b, a, -kk)):
                if i != GROUND and j != GROUND:
                    rows.append(i)
                    cols.append(j)
                    vals.append(v)
        kmat = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
        br, bc, bv = [], [], []
        for s, (a, b) in enumerate(ln):
            for node, v in ((a, 1.0), (b, -1.0)):
                if node != GROUND:
                    br.append(node)
                    bc.append(s)
                    bv.append(v)
        bmat = sp.csr_matrix((bv, (br, bc)), shape=(n, ln.shape[0]))
        self.c = c.astype(np.float64)
        self.kff = kmat[self.free][:, self.free].tocsc()
        self.kfd = kmat[self.free][:, self.drv].tocsc()
        self.kdf = kmat[self.drv][:, self.free].tocsc()
        self.kdd = kmat[self.drv][:, self.drv].toarray()
        bf = bmat[self.free].tocsc()
        self.internal = np.asarray(abs(bf).sum(axis=0)).ravel() > 0
        self.bf = bf[:, self.internal].tocsc()
        self.bd_int = bmat[self.drv][:, self.internal].toarray()
        self.bd_all = bmat[self.drv].toarray()
        self.bd_ext = self.bd_all[:, ~self.internal]
        self.c_int = self.c[self.internal]
        self.c_ext = self.c[~self.internal]
        self._pins()
        self._check(sn, ln, driven)

    # ------------------------------------------------------------------ checks
    def _check(self, spring_nodes: Any, slider_nodes: Any, driven: Any) -> None:
        """Every free node held by springs; no closed loop of sliders."""
        n = self.n
        anchor = n  # the ground and the driven nodes as one node

        def node(i: int) -> int:
            return anchor if i == GROUND or driven[i] else int(i)

        a = [node(i) for i in spring_nodes[:, 0]]
        b = [node(i) for i in spring_nodes[:, 1]]
        graph = sp.csr_matrix((np.ones(len(a)), (a, b)), shape=(n + 1, n + 1))
        _, labels = csgraph.connected_components(graph, directed=False)
        loose = [int(i) for i in self.free if labels[i] != labels[anchor]]
        if loose:
            raise ValueError(
                f"every node that is not displacement-driven must be held by springs to the "
                f"ground or to a driven node; node {loose[0]} is not (it would have no unique "
                f"equilibrium)."
            )
        parent = list(range(n + 1))

        def find(i: int) -> int:
            while parent[i] != i:
                parent[i] = parent[parent[i]]
                i = parent[i]
            return i

        for s, (p, q) in enumerate(slider_nodes):
            i, j = find(node(p)), find(node(q))
            if i == j and (node(p) != anchor or node(q) != anchor):
                raise ValueError(
                    f"the sliders must not form a closed loop with one another, the ground and "
                    f"the driven nodes; slider {s} (nodes {int(p)}, {int(q)}) closes one."
                )
            parent[i] = j

    # ------------------------------------------------------------------ rates
    def _pins(self) -> None:
        """Sliders from a free node to the ground or a driven node pin that node when sticking."""
        bf = self.bf.tocsc()
        n_int = bf.shape[1]
        self.pin_node = np.full(n_int, -1, dtype=np.int64)
        self.pin_coef = np.zeros(n_int)
        for s in range(n_int):
            rows = bf.indices[bf.indptr[s] : bf.indptr[s + 1]]
            if rows.shape[0] == 1:
                self.pin_node[s] = rows[0]
                self.pin_coef[s] = bf.data[bf.indptr[s]]
        self.kff_r = self.kff.tocsr()
        self.bf_r = bf.tocsr()
        kc = self.kff.tocoo()
        self.k_coo = (kc.row.astype(np.int64), kc.col.astype(np.int64), kc.data)
        bc = bf.tocoo()
        self.b_coo = (bc.row.astype(np.int64), bc.col.astype(np.int64), bc.data)

    def _solve(self, work: Any, base_v: FloatArray, base_d: FloatArray) -> tuple[Any, Any]:
        """(v_F, ḟ of the sticking sliders in `work`), the pinned nodes eliminated."""
        nf, n_int = self.free.shape[0], work.shape[0]
        pinned = work & (self.pin_node >= 0)
        cons = np.flatnonzero(work & (self.pin_node < 0))
        pin = self.pin_node[pinned]
        v = np.zeros(nf)
        v[pin] = -base_d[pinned] / self.pin_coef[pinned]
        pos = np.arange(nf)
        free_mask = np.ones(nf, dtype=bool)
        free_mask[pin] = False
        unp = np.flatnonzero(free_mask)
        pos[unp] = np.arange(unp.shape[0])
        pos[pin] = -1
        nu, nc = unp.shape[0], cons.shape[0]
        cpos = np.full(n_int, -1)
        cpos[cons] = nu + np.arange(nc)
        rhs = np.concatenate([(base_v - self.kff_r @ v)[unp], -(base_d + self.bf_r.T @ v)[cons]])
        kr, kc, kv = self.k_coo
        mk = (pos[kr] >= 0) & (pos[kc] >= 0)
        br, bc, bv = self.b_coo
        mb = (pos[br] >= 0) & (cpos[bc] >= 0)
        rows = np.concatenate([pos[kr[mk]], pos[br[mb]], cpos[bc[mb]]])
        cols = np.concatenate([pos[kc[mk]], cpos[bc[mb]], pos[br[mb]]])
        vals = np.concatenate([kv[mk], bv[mb], bv[mb]])
        if nu + nc == 0:
            sol = rhs
        elif nu + nc <= _DENSE_LIMIT:
            kkt = np.zeros((nu + nc, nu + nc))
            kkt[rows, cols] = vals
            sol = np.linalg.solve(kkt, rhs)
        else:
            kkt = sp.csc_matrix((vals, (rows, cols)), shape=(nu + nc, nu + nc))
            sol = splu(kkt).solve(rhs)
        v[unp] = sol[:nu]
        fdot = np.zeros(n_int)
        fdot[cons] = sol[nu:]
        resid = base_v - self.kff_r @ v - self.bf_r @ fdot
        fdot[pinned] = resid[pin] / self.pin_coef[pinned]
        return v, fdot

    def rates(
        self, f_int: FloatArray, slipping: Any, udot: FloatArray, pdot: FloatArray
    ) -> tuple[FloatArray, FloatArray, Any]:
        """(v_F, ḟ of the internal sliders, slipping set) at the state, for the input rates."""
        n_int = f_int.shape[0]
        sat = np.abs(f_int) >= self.c_int
        sgn = np.sign(f_int)
        work = ~(slipping & sat)
        base_v = -(self.kfd @ udot)
        if self.fnodes.shape[0]:
            np.add.at(base_v, self.force_pos, pdot)
        base_d = self.bd_int.T @ udot
        for _ in range(4 * n_int + 20):
            v, fdot = self._solve(work, base_v, base_d)
            g = fdot[work]
            ddot = self.bf.T @ v + base_d
            tol_f = 1e-11 * (np.max(np.abs(g)) if g.shape[0] else 0.0)
            tol_d = 1e-11 * (np.max(np.abs(ddot)) if n_int else 0.0)
            bad = (work & sat & (fdot * sgn > tol_f)) | (~work & (ddot * sgn < -tol_d))
            if not bad.any():
                return v, fdot, ~work
            i = int(np.argmax(bad))
            work[i] = not work[i]
        raise RuntimeError("the active set of the rate problem did not settle (degenerate network)")

    def next_event(
        self, f_int: FloatArray, fdot: FloatArray, slipping: Any
    ) -> tuple[int, float, Any]:
        """(slider, time, its limit ±c) of the first sticking slider to reach its limit."""
        target = np.where(fdot > 0, self.c_int, -self.c_int)
        at_limit = (np.abs(f_int) >= self.c_int) & (fdot * np.sign(f_int) >= 0)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            tau = np.where(
                (fdot != 0) & ~slipping & ~at_limit,
                np.maximum((target - f_int) / fdot, 0.0),
                np.inf,
            )
        which = int(np.argmin(tau)) if tau.shape[0] else -1
        return which, (float(tau[which]) if which >= 0 else np.inf), target

    # ------------------------------------------------------------------ run
    def run(
        self,
        u: FloatArray,
        p: FloatArray,
        max_events: int,
        record_positions: bool = True,
    ) -> tuple[Path, int]:
        """Evolve from the relaxed state through the samples u[k] (T, nD), p[k] (T, nP)."""
        nf = self.free.shape[0]
        x_f = np.zeros(nf)
        uu = np.zeros(self.drv.shape[0])
        pp = np.zeros(self.fnodes.shape[0])
        f = np.zeros(self.c.shape[0])
        slipping = np.zeros(int(self.internal.sum()), dtype=bool)
        path = Path()
        events = 0
        self._record(path, -1.0, x_f, uu, f, np.zeros(uu.shape), record_positions)
        prev_u, prev_p = uu.copy(), pp.copy()
        for k in range(u.shape[0]):
            udot, pdot = u[k] - prev_u, p[k] - prev_p
            s, s1 = float(k - 1), float(k)
            if udot.any():  # sliders between driven nodes and the ground take ±c at once
                dd = self.bd_ext.T @ udot
                f_ext = f[~self.internal]
                jump = (dd != 0) & (f_ext != self.c_ext * np.sign(dd))
                if jump.any():
                    f_ext[jump] = self.c_ext[jump] * np.sign(dd[jump])
                    f[~self.internal] = f_ext
                    self._record(path, s, x_f, uu, f, np.zeros(uu.shape), record_positions)
            if not (udot.any() or pdot.any()):
                self._record(path, s1, x_f, uu, f, np.zeros(uu.shape), record_positions)
                prev_u, prev_p = u[k], p[k]
                continue
            while s < s1:
                f_int = f[self.internal]
                v, fdot, slipping = self.rates(f_int, slipping, udot, pdot)
                rdot = self.kdf @ v + self.kdd @ udot + self.bd_int @ fdot
                which, t_ev, target = self.next_event(f_int, fdot, slipping)
                ds = min(t_ev, s1 - s)
                x_f = x_f + v * ds
                f_int = np.clip(f_int + fdot * ds, -self.c_int, self.c_int)
                if t_ev < s1 - s:
                    f_int[which] = target[which]
                    slipping[which] = True  # the likely next active set
                    uu, pp, s = uu + udot * ds, pp + pdot * ds, s + ds
                else:
                    uu, pp, s = u[k].copy(), p[k].copy(), s1
                f[self.internal] = f_int
                self._record(path, s, x_f, uu, f, rdot, record_positions)
                events += 1
                if events > max_events:
                    raise EventLimit(path, events)
            prev_u, prev_p = u[k], p[k]
        return path, events

    def _record(
        self, path: Path, s: float, x_f: Any, uu: Any, f: Any, rdot: Any, positions: bool
    ) -> None:
        path.s.append(s)
        if positions:
            x = np.zeros(self.n)
            x[self.free] = x_f
            x[self.drv] = uu
            path.x.append(x)
        force = self.kdf @ x_f + self.kdd @ uu + self.bd_all @ f
        path.force.append(force)
        path.slider.append(f.copy())
        path.force_rate.append(np.asarray(rdot, dtype=np.float64).copy())
