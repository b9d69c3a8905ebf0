"""`simulate_network`: exact event-driven motion of a structure with friction contacts.

    M·q̈ + C·q̇ + K·q + W·λ = f(t),   λ_c = c1_c·σ_c + F_el,c(g_c) + σ_v,c·ġ_c,  σ_c ∈ Sign(ġ_c)

Between events every contact sticks (w_cᵀq̇ = 0, a constraint) or slides in a fixed
direction with a fixed set of elastic elements, and the force is constant: the
motion is a closed form (modes of the constrained system, or a matrix exponential
when damped; `presliding.network.events._piece`). Events (`presliding.network.events._events`): a
contact velocity reaching zero, a stuck contact's Coulomb force reaching c1 (its
break-away), an element reaching its threshold, a change of f. At each event the
contacts at rest decide stick or slip together by one box-constrained QP over the
Delassus matrix G = W_Zᵀ M⁻¹ W_Z (`presliding.network.events._contact_problem`). With a
redundant stick set (W_S without full column rank) the motion is unique but the
contact forces are not: the result says so (``forces_unique`` False, the message),
and reports the distribution that leaves the largest margin to slip.

A stuck contact's displacement g_c is held exactly (bit for bit); a structure whose
contacts all stick and that has no free coordinate keeps q exactly.
"""

from __future__ import annotations

import contextlib
import os
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_count,
    as_signal,
    check_size,
    check_type,
)
from presliding.network._start import check_samples, run_start
from presliding.network.events import _warm
from presliding.network.events._events import scan
from presliding.network.events._exact_kernel import ROW_LAYOUT, row_width, run_events
from presliding.network.events._exact_run import Network, RunState
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
    start = run_start(net.w, net.cts.k.shape[0], initial_position, initial_velocity,
                      initial_state, t_start, t_end)  # fmt: skip
    t0, t_end = start.t0, start.t_end
    if t_eval is None:
        times = np.linspace(t0, t_end, 1001)
    else:
        check_samples(t_eval, row_width(n, n_c))
        times = as_signal("t_eval", t_eval)
        if np.any(np.diff(times) < 0) or times[0] < t0 or times[-1] > t_end:
            raise ValueError(
                f"`t_eval` must be nondecreasing within [t_start, t_end] = [{t0!r}, {t_end!r}];"
                f" got values from {times[0]!r} to {times[-1]!r}."
            )
    zeros = np.zeros(n_c)
    st = RunState(t=t0, q=start.q.copy(), v=start.v.copy(), g=start.g.copy(), e=start.e.copy(),
                  s=start.s.copy(), last=start.last.copy(), coulomb=zeros.copy(),
                  hysteretic=zeros.copy(), viscous=zeros.copy())  # fmt: skip
    out = _Samples(times, n, n_c, net.cts.k.shape[0])
    e_initial = _mechanical_energy(net, st.q, st.v, st.e)
    compiled = _warm.ready()
    ran = _run_compiled(structure, net, st, t_end, out, max_events) if compiled else None
    if ran is None:  # redundant stick sets, ill-conditioned damped modes: the general loop
        st = RunState(t=t0, q=start.q, v=start.v, g=start.g, e=start.e, s=start.s,
                      last=start.last, coulomb=zeros.copy(), hysteretic=zeros.copy(),
                      viscous=zeros.copy())  # fmt: skip
        out = _Samples(times, n, n_c, net.cts.k.shape[0])
        ran = _run(structure, net, st, t_end, out, max_events)
        if not compiled:
            ran = (ran[0], ran[1].removesuffix(".") + _COLD)
    status, message = ran
    return build_result(structure, net, st, out, status, message, e_initial, t0)


def _run_compiled(structure: NetworkStructure, net: Network, st: RunState, t_end: float,
                  out: _Samples, max_events: int) -> tuple[str, str] | None:  # fmt: skip
    """The compiled event loop; None when it meets a redundant stick set or damped modes
    that are not well conditioned (the general loop runs instead)."""
    n, n_c = net.w.shape
    width = row_width(n, n_c)
    check_size("t_eval", out.time.shape[0], out.time.shape[0] * width)
    rec = np.zeros((out.time.shape[0], width))
    ft = np.ascontiguousarray(structure.forcing_times, dtype=np.float64)
    fv = np.ascontiguousarray(structure.forcing_values, dtype=np.float64)
    iu = max(int(np.searchsorted(ft, st.t, side="right")) - 1, 0)
    c = np.ascontiguousarray
    code, t, v, work, damp, events, filled, tr, rv, grouped, counts = run_events(
        float(st.t), st.q, st.v, st.g, st.e, st.s, st.last, st.coulomb, st.hysteretic,
        st.viscous, float(st.work), float(st.damping), iu, ft, fv, float(t_end),
        c(out.time, dtype=np.float64), rec, c(net.m), c(net.k), c(net.w), c(net.minv_w),
        net.cts.c1, net.cts.sigma, c(net.c), net.cts.k, net.cts.r, net.cts.owner,
        int(max_events),
    )  # fmt: skip
    if code == 2:
        return None
    st.cert.add(counts)
    st.t, st.v, st.work, st.n_events = float(t), v, float(work), int(events)
    st.damping = float(damp)
    st.redundant = bool(grouped)
    st.transitions = [(float(a), int(b), float(x)) for a, b, x in tr]
    st.reversals = [(float(a), int(b), float(x)) for a, b, x in rv]
    col = 0
    for name, size in ROW_LAYOUT:
        width = n if size == "n" else n_c if size == "c" else 1
        block = rec[:, col : col + width]
        setattr(out, name, np.ascontiguousarray(block[:, 0] if size == 1 else block))
        col += width
    out.filled = int(filled)
    if code == 0:
        return "success", _message(st, out, _GROUPED)
    return "event_limit", _limit_message(max_events, st.t)


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
        found = scan(net.event_functions(pc, info, st), t1 - st.t, pc.omega_max, st.cert)
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
            return "event_limit", _limit_message(max_events, st.t)


def _limit_message(max_events: int, t: float) -> str:
    return (
        f"the event limit max_events={max_events} was reached at t = {t!r} s; the "
        "samples after it are missing (zeros are not written: arrays are cut)."
    )


def _note_transitions(st: RunState, before: FloatArray) -> None:
    for c in np.flatnonzero(st.s != before):
        st.transitions.append((st.t, int(c), float(st.s[c])))
        if st.s[c] != 0.0:
            if st.last[c] != 0.0 and st.s[c] != st.last[c]:
                st.reversals.append((st.t, int(c), float(st.g[c])))
            st.last[c] = st.s[c]


_COLD = (
    "; the general loop ran (the same events): the compiled loop was not in numba's "
    "cache, and a second process is compiling it for the next runs."
)
_GENERAL = (
    "; the contact forces are not unique (redundant contacts stuck together: W_S has "
    "dependent columns); the motion is unique, the forces shown are the minimum-norm "
    "distribution, or where it exceeds c1 the one that leaves the largest margin to slip"
)
_GROUPED = (
    "; the contact forces are not unique (contacts with parallel columns of W stuck together, "
    "as one combined contact with c1 = Σ|α_c|·c1_c); the motion is unique, the forces shown "
    "share the combined Coulomb force in proportion to each contact's c1"
)


def _message(st: RunState, out: _Samples, redundant: str = _GENERAL) -> str:
    text = f"simulated to t = {st.t!r} s in {st.n_events} events"
    if st.redundant:
        text += redundant
    return text + "."


def compile_now() -> None:
    """Compile the event loop in this process (with the argument types of every call), so
    that it is cached (`presliding precompile`)."""
    from presliding.friction import PIFriction
    from presliding.network.structure import chain_structure

    before, _warm.BACKGROUND = _warm.BACKGROUND, False
    try:
        friction = PIFriction(0.2, [400.0, 150.0], [0.1, 0.15])
        chain = chain_structure(2, 1.0, 1000.0, friction, forcing=([0.0, 0.02], [[0, 0], [0, 1]]))
        simulate_network(chain, 0.05, initial_velocity=np.array([0.3, -0.2]))
    finally:
        _warm.BACKGROUND = before


def compile_main() -> int:
    """The second process of a cold cache (`presliding.network.events._warm`): compile at low
    priority, discard the result."""
    with contextlib.suppress(AttributeError, OSError):  # not on every platform
        os.nice(10)
    _warm.BACKGROUND = False  # never a third process
    compile_now()
    return 0
