"""`simulate_network`: exact event-driven motion of a structure with friction contacts.

    M·q̈ + C·q̇ + K·q + W·λ = f(t),   λ_c = c1_c·σ_c + F_el,c(g_c) + σ_v,c·ġ_c,  σ_c ∈ Sign(ġ_c)

Between events every contact sticks (w_cᵀq̇ = 0, a constraint) or slides in a fixed
direction with a fixed set of elastic elements, and the force is constant: the
motion is a closed form (modes of the constrained system, or a matrix exponential
when damped; `presliding.network._piece`). Events (`presliding.network._events`): a
contact velocity reaching zero, a stuck contact's Coulomb force reaching c1 (its
break-away), an element reaching its threshold, a change of f. At each event the
contacts at rest decide stick or slip together by one box-constrained QP over the
Delassus matrix G = W_Zᵀ M⁻¹ W_Z (`presliding.network._contact_problem`). With a
redundant stick set (W_S without full column rank) the motion is unique but the
contact forces are not: the result says so (``forces_unique`` False, the message),
and reports the distribution that leaves the largest margin to slip.

A stuck contact's displacement g_c is held exactly (bit for bit); a structure whose
contacts all stick and that has no free coordinate keeps q exactly.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_count,
    as_real_scalar,
    as_signal,
    as_state_vector,
    check_time_span,
    check_type,
    fmt,
)
from presliding.network._events import scan
from presliding.network._exact_run import Network, RunState
from presliding.network.results import NetworkResult, NetworkState, build_result
from presliding.network.structure import NetworkStructure

__all__ = ["simulate_network"]

FloatArray = NDArray[np.float64]


def simulate_network(
    structure: NetworkStructure,
    t_end: float,
    initial_position: ArrayLike | None = None,
    initial_velocity: ArrayLike | None = None,
    initial_state: str | NetworkState = "relaxed",
    t_eval: ArrayLike | None = None,
    *,
    t_start: float | None = None,
    max_events: int = 1_000_000,
) -> NetworkResult:
    """Simulate a structure with friction contacts exactly (events in closed form).

    Parameters
    ----------
    structure : NetworkStructure
        M, C, K, the contacts W with one `PIFriction` each, and the force f(t).
    t_end : float
        End time [s] (> t_start).
    initial_position, initial_velocity : array_like, shape (n,), optional
        q(t_start) [m], q̇(t_start) [m/s]; zeros by default, or those of
        `initial_state` when it is a `NetworkState`.
    initial_state : "relaxed" or NetworkState
        "relaxed": no element deformed. A `NetworkState` (a result's
        ``final_state``) continues a run: position, velocity, deformations, modes and
        time are taken from it.
    t_eval : array_like, optional
        Increasing sample times in [t_start, t_end]; default 1001 uniform samples.
    t_start : float, optional
        Start time; 0, or the state's time.
    max_events : int
        Stop (status "event_limit") after this many events.

    Returns
    -------
    NetworkResult

    Examples
    --------
    The friction oscillator m = k = 1, c1 = 1 from x0 = 12, v0 = 6 rests at 15 − √205:

    >>> from presliding import PIFriction
    >>> s = NetworkStructure(1.0, 1.0, [[1.0]], [PIFriction(1.0)])
    >>> res = simulate_network(s, 30.0, [12.0], [6.0])
    >>> bool(abs(res.position[-1, 0] - (15 - 205**0.5)) < 1e-12)
    True
    """
    check_type("structure", structure, NetworkStructure)
    net = Network(structure)
    n, n_c = structure.n_coordinates, structure.n_contacts
    max_events = as_count("max_events", max_events, minimum=1)
    if isinstance(initial_state, NetworkState):
        if initial_state.deformation.shape != net.cts.k.shape or initial_state.position.shape != (
            n,
        ):
            raise ValueError(
                "`initial_state` must belong to this structure (same coordinates and elements);"
                f" got {initial_state.position.shape[0]} coordinates and "
                f"{initial_state.deformation.shape[0]} elements."
            )
        t0 = initial_state.time if t_start is None else as_real_scalar("t_start", t_start)
        q0 = initial_state.position.copy() if initial_position is None else as_state_vector(
            "initial_position", initial_position, n)  # fmt: skip
        v0 = initial_state.velocity.copy() if initial_velocity is None else as_state_vector(
            "initial_velocity", initial_velocity, n)  # fmt: skip
        e0 = initial_state.deformation.copy()
        g0 = initial_state.contact_displacement.copy()
        s0 = initial_state.mode.copy()
        last0 = initial_state.last_direction.copy()
        if not np.array_equal(q0, initial_state.position):
            g0 = q0 @ net.w
        if not np.array_equal(v0, initial_state.velocity):
            s0 = np.sign(v0 @ net.w)
    elif isinstance(initial_state, str) and initial_state == "relaxed":
        t0 = 0.0 if t_start is None else as_real_scalar("t_start", t_start)
        q0 = np.zeros(n) if initial_position is None else as_state_vector(
            "initial_position", initial_position, n)  # fmt: skip
        v0 = np.zeros(n) if initial_velocity is None else as_state_vector(
            "initial_velocity", initial_velocity, n)  # fmt: skip
        e0 = np.zeros(net.cts.k.shape[0])
        g0 = q0 @ net.w
        s0 = np.sign(v0 @ net.w)
        last0 = np.zeros(n_c)
    else:
        raise ValueError(f"`initial_state` must be 'relaxed' or a NetworkState; got "
                         f"{fmt(initial_state)}.")  # fmt: skip
    t_end = as_real_scalar("t_end", t_end)
    if not t_end > t0:
        raise ValueError(f"`t_end` must be after the start time {t0!r}; got {fmt(t_end)}.")
    check_time_span("t_end", t_end, t_end - t0)
    if t_eval is None:
        times = np.linspace(t0, t_end, 1001)
    else:
        times = as_signal("t_eval", t_eval)
        if np.any(np.diff(times) < 0) or times[0] < t0 or times[-1] > t_end:
            raise ValueError(
                f"`t_eval` must be nondecreasing within [t_start, t_end] = [{t0!r}, {t_end!r}];"
                f" got values from {times[0]!r} to {times[-1]!r}."
            )
    zeros = np.zeros(n_c)
    st = RunState(t=t0, q=q0, v=v0, g=g0, e=e0, s=s0.astype(float), last=last0.astype(float),
                  coulomb=zeros.copy(), hysteretic=zeros.copy(), viscous=zeros.copy())  # fmt: skip
    out = _Samples(times, n, n_c, net.cts.k.shape[0])
    e_initial = _mechanical_energy(net, st.q, st.v, st.e)
    status, message = _run(structure, net, st, t_end, out, max_events)
    return build_result(structure, net, st, out, status, message, e_initial, t0)


def _mechanical_energy(net: Network, q: FloatArray, v: FloatArray, e: FloatArray) -> float:
    return float(0.5 * v @ net.m @ v + 0.5 * q @ net.k @ q + 0.5 * np.sum(net.cts.k * e * e))


class _Samples:
    """The sampled arrays, filled piece by piece."""

    def __init__(self, times: FloatArray, n: int, n_c: int, n_e: int) -> None:
        t = times.shape[0]
        self.time = times
        self.filled = 0
        z = np.zeros
        self.q, self.v, self.a, self.f = z((t, n)), z((t, n)), z((t, n)), z((t, n))
        self.g, self.gd, self.lam, self.fel, self.mode = (z((t, n_c)) for _ in range(5))
        self.coulomb, self.hysteretic, self.viscous = z((t, n_c)), z((t, n_c)), z((t, n_c))
        self.kinetic, self.potential, self.elastic, self.damping, self.work = (
            z(t) for _ in range(5)
        )


def _record(net: Network, pc: Any, info: Any, st: RunState, out: _Samples, t1: float,
            last: bool) -> None:  # fmt: skip
    i0 = out.filled
    i1 = int(np.searchsorted(out.time, t1, side="right" if last else "left"))
    if i1 <= i0:
        return
    tau = out.time[i0:i1] - st.t
    vals = net.contact_values(pc, info, st, tau)
    en = net.add_energy(pc, info, st, tau, vals)
    sl = slice(i0, i1)
    q = st.q + vals["dq"] if pc.dim else np.broadcast_to(st.q, vals["dq"].shape)
    out.q[sl], out.v[sl], out.a[sl] = q, vals["v"], vals["a"]
    out.f[sl] = pc.f
    out.g[sl] = st.g + vals["dg"]
    out.gd[sl], out.lam[sl], out.fel[sl] = vals["gd"], vals["lam"], vals["fel"]
    out.mode[sl] = st.s
    out.coulomb[sl], out.hysteretic[sl], out.viscous[sl] = (
        en["coulomb"], en["hysteretic"], en["viscous"])  # fmt: skip
    out.damping[sl], out.work[sl] = en["damping"], en["work"]
    v = vals["v"]
    out.kinetic[sl] = 0.5 * np.einsum("ti,ij,tj->t", v, net.m, v)
    out.potential[sl] = 0.5 * np.einsum("ti,ij,tj->t", q, net.k, q)
    e = st.e + np.where(info["elastic"], vals["dg"][:, net.cts.owner], 0.0)
    out.elastic[sl] = 0.5 * (e * e) @ net.cts.k
    out.filled = i1


def _run(structure: NetworkStructure, net: Network, st: RunState, t_end: float, out: _Samples,
         max_events: int) -> tuple[str, str]:  # fmt: skip
    ft, fv = structure.forcing_times, structure.forcing_values
    iu = max(int(np.searchsorted(ft, st.t, side="right")) - 1, 0)
    forced: dict[int, float] = {}
    prev: FloatArray | None = None
    while True:
        f = np.asarray(fv[iu])
        net.decide(st, f, forced)
        if prev is None:
            st.transitions.extend((st.t, c, float(st.s[c])) for c in range(st.s.shape[0]))
            st.last = np.where(st.s != 0.0, st.s, st.last)
        else:
            _note_transitions(st, prev)
        prev = st.s.copy()
        t_next = float(ft[iu + 1]) if iu + 1 < ft.shape[0] else np.inf
        t1 = min(t_next, t_end)
        pc, info = net.piece(st, f)
        if info["redundant"]:
            st.redundant = True
        found = scan(net.event_functions(pc, info, st), t1 - st.t, pc.omega_max)
        at_end = found is None and t1 >= t_end
        tau, trig = (t1 - st.t, None) if found is None else found
        _record(net, pc, info, st, out, st.t + tau, at_end)
        forced = net.advance(pc, info, st, tau, trig)
        if found is None:
            st.t = t1  # exactly
            if at_end:
                return "success", _message(st, out)
            iu += 1
        st.n_events += 1
        if st.n_events >= max_events:
            return "event_limit", (
                f"the event limit max_events={max_events} was reached at t = {st.t!r} s; the "
                "samples after it are missing (zeros are not written: arrays are cut)."
            )


def _note_transitions(st: RunState, before: FloatArray) -> None:
    for c in np.flatnonzero(st.s != before):
        st.transitions.append((st.t, int(c), float(st.s[c])))
        if st.s[c] != 0.0:
            if st.last[c] != 0.0 and st.s[c] != st.last[c]:
                st.reversals.append((st.t, int(c), float(st.g[c])))
            st.last[c] = st.s[c]


def _message(st: RunState, out: _Samples) -> str:
    text = f"simulated to t = {st.t!r} s in {st.n_events} events"
    if st.redundant:
        text += (
            "; the contact forces are not unique (redundant contacts stuck together: W_S has "
            "dependent columns); the motion is unique, the forces shown are the minimum-norm "
            "distribution, or where it exceeds c1 the one that leaves the largest margin to slip"
        )
    return text + "."
