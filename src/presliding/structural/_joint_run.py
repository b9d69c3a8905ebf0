"""The event loop of a jointed structure with stop joints: pieces, events, samples, and the
exact state transition of perturbations (for shooting and Floquet multipliers).

The state is (q, q̇, x): x the plastic parts of the stops. At an event a stop reaching its
threshold while its joint moves outward starts to slide (x_j = g_c − s·r_j from then on;
the saltation of its row is δx_j = w_cᵀδq), and a sliding joint whose velocity reaches
zero sticks its sliding stops (no saltation: the vector field is continuous there).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from presliding.structural._joint_events import next_event
from presliding.structural._pieces import Model, Piece

FloatArray = NDArray[np.float64]

#: Relative tolerance of "at a threshold" (of the threshold and the joint's displacement).
AT_LIMIT = 1e-12


@dataclass
class Run:
    """The end of a run, its samples, and optionally its pieces and state transition."""

    t: float
    q: FloatArray
    v: FloatArray
    x: FloatArray
    sliding: FloatArray
    n_events: int = 0
    status: str = "success"
    transition: FloatArray | None = None
    derivative: FloatArray | None = None  # ∂(q, q̇, x)(t_end)/∂p at fixed end time
    pieces: list[tuple[Piece, float]] = field(default_factory=list)
    samples: dict[str, FloatArray] = field(default_factory=dict)
    slid: NDArray[np.bool_] | None = None  # per stop: slid at least once in the run


def start_modes(model: Model, q: FloatArray, v: FloatArray,
                x: FloatArray) -> tuple[FloatArray, FloatArray, NDArray[np.bool_]]:  # fmt: skip
    """(x, sliding, projected): x put within its thresholds (|e_j| <= r_j), and the stops at a
    threshold whose joint moves outward marked sliding."""
    g = model.w.T @ q
    gd = model.w.T @ v
    e = g[model.owner] - x
    side = np.sign(e)
    at = np.abs(e) >= model.er * (1.0 - AT_LIMIT)
    x = np.where(at, g[model.owner] - side * model.er, x)
    out = side * gd[model.owner]
    sliding = np.where(at & (out > 0), side, 0.0)
    return x, sliding, at


def run(model: Model, t0: float, q0: FloatArray, v0: FloatArray, x0: FloatArray, t_end: float,
        *, samples: FloatArray | None = None, transition: bool = False, keep: bool = False,
        max_events: int = 100_000, d_force: NDArray[np.complex128] | None = None,
        d_omega: float = 0.0) -> Run:  # fmt: skip
    """Run from t0 to t_end (absolute times: the forcing's phase). With `transition`, the
    state transition ∂Z(t_end)/∂Z(t0) and, for `d_force` (dF̂/dp) and `d_omega` (dΩ/dp),
    the derivative ∂Z(t_end)/∂p at fixed times."""
    n, n_e = model.n, model.n_e
    beyond = np.abs((model.w.T @ q0)[model.owner] - x0) > model.er * (1.0 + AT_LIMIT)
    x, sliding, _ = start_modes(model, q0, v0, x0)
    out = Run(t=t0, q=q0.copy(), v=v0.copy(), x=x, sliding=sliding)
    out.slid = sliding != 0
    total = deriv = None
    if transition:
        deriv = np.zeros(2 * n + n_e)
        total = np.eye(2 * n + n_e)
        rows = np.flatnonzero((sliding != 0) | beyond)  # x_j = g_c − s·r_j there
        total[2 * n + rows] = 0.0
        total[2 * n + rows, :n] = model.w[:, model.owner[rows]].T
    sm = _Samples(samples, n, model.n_c)
    while True:
        piece = Piece(model, out.t, out.q, out.v, out.x, out.sliding)
        horizon = t_end - out.t
        ev = next_event(piece, horizon) if horizon > 0 else None
        tau = horizon if ev is None else ev[0]
        q, v, _ = piece.state(np.array([tau]))
        q, v = q[0], v[0]
        x = piece.elements(tau, q)
        sm.fill(piece, out.t, out.t + tau, last=ev is None)
        if keep:
            out.pieces.append((piece, tau))
        if total is not None and deriv is not None:
            step = piece.transition(tau)
            total = step @ total
            if d_force is not None or d_omega != 0.0:
                df = np.zeros(n, complex) if d_force is None else d_force
                deriv = step @ deriv + piece.parameter_derivative(tau, df, d_omega)
        out.q, out.v, out.x = q, v, x
        out.t = t_end if ev is None else out.t + tau
        if ev is None:
            break
        switched = _apply(model, piece, out, ev)
        if total is not None and deriv is not None and switched.size:  # δx_j = w_cᵀ·δq
            total[2 * n + switched] = model.w[:, model.owner[switched]].T @ total[:n]
            deriv[2 * n + switched] = model.w[:, model.owner[switched]].T @ deriv[:n]
        out.slid[switched] = True
        out.n_events += 1
        if out.n_events >= max_events:
            out.status = "event_limit"
            break
    out.transition, out.derivative = total, deriv
    out.samples = sm.arrays()
    return out


def _apply(model: Model, piece: Piece, st: Run, ev: tuple[float, int, int]) -> NDArray[np.intp]:
    """Apply an event to the state; the stops that started to slide."""
    _, c, kind = ev
    mine = model.owner == c
    g, gd, gdd = piece.contacts(np.array([ev[0]]))
    g_c, gd_c, gdd_c = float(g[0, c]), float(gd[0, c]), float(gdd[0, c])
    if kind == 0:  # the joint comes to rest: its sliding stops stick unless it turns outward
        s = float(np.sign(np.sum(st.sliding[mine])))
        if not s * gdd_c > 0.0:
            st.sliding = np.where(mine, 0.0, st.sliding)
        return np.empty(0, dtype=np.intp)
    e = g_c - st.x
    slack = AT_LIMIT * (model.er + abs(g_c))
    reach = mine & (st.sliding == 0) & (kind * e >= model.er - slack)
    st.x = np.where(reach, g_c - kind * model.er, st.x)
    outward = kind * gd_c > 0.0 or (gd_c == 0.0 and kind * gdd_c > 0.0)
    if not outward:  # touched at an extremum: the stop stays elastic at its threshold
        return np.empty(0, dtype=np.intp)
    st.sliding = np.where(reach, float(kind), st.sliding)
    return np.flatnonzero(reach)


class _Samples:
    """Samples of q, q̇, q̈ and the joints' displacements and forces at given times."""

    def __init__(self, times: FloatArray | None, n: int, n_c: int) -> None:
        self.time = np.empty(0) if times is None else times
        t = self.time.shape[0]
        self.q, self.v, self.a = np.zeros((t, n)), np.zeros((t, n)), np.zeros((t, n))
        self.g, self.lam = np.zeros((t, n_c)), np.zeros((t, n_c))
        self.filled = 0

    def fill(self, piece: Piece, t0: float, t1: float, last: bool) -> None:
        i0 = self.filled
        i1 = int(np.searchsorted(self.time, t1, side="right" if last else "left"))
        if i1 <= i0:
            return
        tau = self.time[i0:i1] - t0
        q, v, a = piece.state(tau)
        g, _, _ = piece.contacts(tau)
        md = piece.model
        x = np.where(piece.sliding != 0, piece.x0 + (g - piece.g0)[:, md.owner], piece.x0)
        force = np.where(piece.sliding != 0, piece.sliding * md.er, g[:, md.owner] - x) * md.ek
        lam = np.zeros((tau.shape[0], md.n_c))
        for c in range(md.n_c):
            lam[:, c] = force[:, md.owner == c].sum(axis=1)
        sl = slice(i0, i1)
        self.q[sl], self.v[sl], self.a[sl], self.g[sl], self.lam[sl] = q, v, a, g, lam
        self.filled = i1

    def arrays(self) -> dict[str, FloatArray]:
        k = self.filled
        return {"time": self.time[:k], "position": self.q[:k], "velocity": self.v[:k],
                "acceleration": self.a[:k], "joint_displacement": self.g[:k],
                "joint_force": self.lam[:k]}  # fmt: skip
