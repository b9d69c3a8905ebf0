"""`compile_structure`: a structure with joints loaded along one vector as one exact PI operator.

Quasi-statically, K·q + W·λ = P·b: a structure of stiffness K (n × n) with joints
c = 1..n_c, each a finite-element PI model (eq. 8) λ_c = c1_c·σ_c + Σ_j k_j·e_j of its
relative displacement g_c = w_cᵀq, is loaded by a force P·b along one load vector b
(for a modal analysis b = M·φ). Its work-conjugate displacement is u = bᵀq. Driven
through u (P the multiplier of bᵀq = u; the same path as the force-driven one where
P(u) increases), the response is piecewise linear: between events every joint's
Coulomb element is rigid (stuck) or slipping, every stop elastic or sliding, and the
rates solve one linear system. Events are a stuck joint's force reaching its Coulomb
level and a stop reaching its threshold.

When the structure is order-preserving along b (every joint moves one way while u
moves one way, and everything reverses when u reverses), P(u) is a linear spring
plus a PI operator (Krejčí et al., Phys. Rev. E 90, 032822, 2014, for networks
driven through one input): P = k_∞·u + c1 + Σ_j k_j·min(u, r_j) on the virgin curve,
the exact breakpoints r_j and slope drops k_j of the virgin curve being the elements.
The check as in `compile_network`: every joint's direction is watched along the virgin
curve (and in every replayed segment), and for up to 64 sliders the structure is
replayed over a history with nested reversals against the compiled operator.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import LinAlgError, LinAlgWarning, solve

from presliding._validation import as_list, as_real_array, check_type, fmt
from presliding.friction import PIFriction
from presliding.network.reduction.compile import VERIFY_RTOL, verification_history

__all__ = ["CompiledStructure", "compile_structure"]

FloatArray = NDArray[np.float64]

#: Relative size below which a rate counts as zero (of the largest rate of its kind).
RATE_TOL = 1e-10


@dataclass(frozen=True, eq=False)
class CompiledStructure:
    """A structure loaded along one vector: P(u) = k_∞·u + F(u), F a PI operator.

    Attributes
    ----------
    linear_stiffness : float
        k_∞ >= 0 [N/m, or the load's units], the stiffness once every joint element slides.
    friction : PIFriction or None
        The hysteretic part F (its c1 = 0: the stuck structure moves along the load);
        None when no joint slides under this load (P = k_∞·u).
    load : ndarray, shape (n,)
        The load vector b.
    """

    linear_stiffness: float
    friction: PIFriction | None
    load: FloatArray = field(repr=False)
    breakpoints: FloatArray = field(repr=False)
    deflections: FloatArray = field(repr=False)
    deflection_rates: FloatArray = field(repr=False)

    @property
    def initial_stiffness(self) -> float:
        """dP/du right after every reversal: k_∞ + Σ k_j [N/m]."""
        extra = 0.0 if self.friction is None else self.friction.initial_stiffness
        return self.linear_stiffness + extra

    def virgin_curve(self, displacement: ArrayLike) -> Any:
        """P on the virgin curve at u (from the relaxed state)."""
        u = as_real_array("displacement", displacement)
        extra = 0.0 if self.friction is None else self.friction.virgin_curve(u)
        return self.linear_stiffness * u + extra

    def force(self, displacement: ArrayLike) -> FloatArray:
        """P along a history u (from the relaxed state)."""
        u = np.asarray(as_real_array("displacement", displacement), dtype=np.float64)
        extra = 0.0 if self.friction is None else np.asarray(self.friction.force(u)[0])
        return np.asarray(self.linear_stiffness * u + extra)

    def deflection(self, displacement: ArrayLike) -> FloatArray:
        """q on the virgin curve at u (odd in u), shape (len(u), n) [m]."""
        u = np.atleast_1d(as_real_array("displacement", displacement)).reshape(-1)
        a = np.abs(u)
        i = np.searchsorted(self.breakpoints, a, side="right") - 1
        q = self.deflections[i] + self.deflection_rates[i] * (a - self.breakpoints[i])[:, None]
        return np.asarray(np.sign(u)[:, None] * q)


class _Joints:
    """The joints' elements flattened: owner contact, stiffness, threshold; Coulomb levels."""

    def __init__(self, friction: list[PIFriction]) -> None:
        ks: list[FloatArray] = []
        rs: list[FloatArray] = []
        owner, c1 = [], []
        for c, model in enumerate(friction):
            check_type(f"friction[{c}]", model, PIFriction)
            if not model.is_discrete:
                raise ValueError(
                    f"`friction[{c}]` must have finite elements (eq. 8) for an exact "
                    f"compilation, not a density; got {model.density!r}."
                )
            if not model.is_symmetric:
                raise ValueError(
                    f"`friction[{c}]` must be symmetric (one level both ways) for the loops to "
                    f"be Masing loops; got {model!r}."
                )
            if model.coulomb == 0.0 and model.n_elements == 0:
                raise ValueError(f"`friction[{c}]` must hold c1 > 0 or an element; got none.")
            ks.append(np.asarray(model.stiffness, dtype=np.float64))
            rs.append(np.asarray(model.threshold, dtype=np.float64))
            owner.append(np.full(model.n_elements, c, dtype=np.int64))
            c1.append(model.coulomb)
        self.k = np.concatenate(ks) if ks else np.empty(0)
        self.r = np.concatenate(rs) if rs else np.empty(0)
        self.owner = np.concatenate(owner) if owner else np.empty(0, dtype=np.int64)
        self.c1 = np.array(c1, dtype=np.float64)


@dataclass
class _State:
    """The quasi-static state: q, joint forces, P, u and the elements' plastic parts."""

    q: FloatArray
    lam: FloatArray
    x: FloatArray  # plastic offset of each stop (e_j = g_owner − x_j)
    stuck: Any  # bool per joint: its Coulomb element rigid
    slip: FloatArray  # per joint: the Coulomb element's slip direction (0: none)
    sliding: FloatArray  # per stop: its sliding direction (0: elastic)
    moved: FloatArray  # per joint: its direction in this segment (0: not moved yet)
    p: float = 0.0
    u: float = 0.0
    direction: float = 0.0  # of the last segment (0: none yet)


class _Loaded:
    """The structure, its joints and the load: rate solves, segments, the virgin curve."""

    def __init__(self, k: FloatArray, w: FloatArray, joints: _Joints, b: FloatArray) -> None:
        self.kmat, self.w, self.j, self.b = k, w, joints, b
        self.n, self.n_c = w.shape

    def relaxed(self) -> _State:
        n_c, n_e = self.n_c, self.j.k.shape[0]
        return _State(q=np.zeros(self.n), lam=np.zeros(n_c), x=np.zeros(n_e),
                      stuck=self.j.c1 > 0, slip=np.zeros(n_c), sliding=np.zeros(n_e),
                      moved=np.zeros(n_c))  # fmt: skip

    def elastic_force(self, st: _State) -> FloatArray:
        e = (self.w.T @ st.q)[self.j.owner] - st.x
        return np.bincount(self.j.owner, self.j.k * e, minlength=self.n_c).astype(np.float64)

    def rates(self, st: _State, d: float) -> tuple[FloatArray, FloatArray, float]:
        """dq, dλ, dP per unit of u moved in direction d, the active sets held."""
        kt = np.bincount(self.j.owner, self.j.k * (st.sliding == 0), minlength=self.n_c)
        comp = ~st.stuck
        wc = self.w[:, comp]
        k_t = self.kmat + (wc * kt[comp]) @ wc.T
        wr = self.w[:, st.stuck]
        n, m = self.n, wr.shape[1]
        a = np.zeros((n + m + 1, n + m + 1))
        a[:n, :n], a[:n, n : n + m], a[:n, -1] = k_t, wr, self.b  # unknown −dP: symmetric
        a[n : n + m, :n], a[-1, :n] = wr.T, self.b
        rhs = np.zeros(n + m + 1)
        rhs[-1] = d
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("error", LinAlgWarning)
                sol = solve(a, rhs, assume_a="sym", check_finite=False)
        except (LinAlgError, LinAlgWarning, np.linalg.LinAlgError):
            raise ValueError(
                f"`stiffness` and `contacts` must hold the structure while it is loaded along "
                f"`load`: at u = {st.u!r} (P = {st.p!r}) it can move without a force (the rate "
                f"equations are singular), so no operator is returned."
            ) from None
        dq = sol[:n]
        dlam = kt * (self.w.T @ dq)
        dlam[st.stuck] = sol[n : n + m]
        return dq, dlam, -float(sol[-1])

    def _check_rates(self, st: _State, dg: FloatArray, dlam: FloatArray,
                     before: tuple[FloatArray, FloatArray] | None) -> None:  # fmt: skip
        """Every joint moves one way while u does; after a reversal (`before`: the Coulomb
        slip and stop directions that held), every element that slid unloads."""
        tol = RATE_TOL * max(float(np.max(np.abs(dg), initial=0.0)), 1e-300)
        moving = np.abs(dg) > tol
        bad = moving & (st.moved != 0) & (np.sign(dg) != st.moved)
        bad |= ~st.stuck & (st.slip != 0) & (st.slip * dg < -tol)
        stops = (st.sliding != 0) & (st.sliding * dg[self.j.owner] < -tol)
        if before is not None:
            slip, sliding = before
            tol_l = RATE_TOL * max(float(np.max(np.abs(dlam), initial=0.0)), 1e-300)
            bad |= st.stuck & (slip * dlam > tol_l)
            stops |= sliding * dg[self.j.owner] > tol
        bad[self.j.owner[stops]] = True
        if bad.any():
            c = int(np.argmax(bad))
            raise ValueError(
                f"`load` does not load the structure in an order-preserving way: joint {c} "
                f"reverses (or keeps sliding after a reversal) at u = {st.u!r} while u moves one "
                f"way, so its response is not one PI operator (the loops are not Masing loops); "
                f"none is returned."
            )
        st.moved = np.where(moving & (st.moved == 0), np.sign(dg), st.moved)

    def segment(self, st: _State, target: float, points: list[tuple[Any, ...]]) -> None:
        """Move u monotonically to `target` (inf: until nothing more slides), recording
        (u, P, dP/du) at the start and after every event."""
        d = 1.0 if target > st.u else -1.0
        before: tuple[FloatArray, FloatArray] | None = None
        if d != st.direction:  # a reversal: every element unloads, all rigid or elastic
            before = (st.slip, st.sliding)
            st.stuck = self.j.c1 > 0
            st.slip = np.where(st.stuck, 0.0, st.slip)
            st.sliding = np.zeros_like(st.sliding)
            st.moved = np.zeros(self.n_c)
            st.direction = d
        for _ in range(4 * (self.j.k.shape[0] + self.n_c) + 10):
            dq, dlam, dp = self.rates(st, d)
            dg = self.w.T @ dq
            self._check_rates(st, dg, dlam, before)
            before = None
            points.append((st.u, st.p, d * dp, st.q, d * dq))
            step, hit_c, hit_e = self._next_event(st, dg, dlam, abs(target - st.u))
            if not np.isfinite(step):
                return
            st.q = st.q + dq * step
            st.lam = st.lam + dlam * step
            st.p, st.u = st.p + dp * step, st.u + d * step
            st.x = st.x + np.where(st.sliding != 0, dg[self.j.owner] * step, 0.0)
            if hit_c is None and hit_e is None:  # the target
                st.u = target
                points.append((st.u, st.p, d * dp, st.q, d * dq))
                return
            g = self.w.T @ st.q
            if hit_e is not None:
                s = np.sign(dg[self.j.owner[hit_e]])
                st.sliding[hit_e] = s
                st.x[hit_e] = g[self.j.owner[hit_e]] - s * self.j.r[hit_e]
            if hit_c is not None:
                st.slip[hit_c] = np.sign(dlam[hit_c])
                st.stuck[hit_c] = False
            comp = ~st.stuck
            st.lam[comp] = (self.j.c1 * st.slip + self.elastic_force(st))[comp]
        raise RuntimeError("the quasi-static path did not end: more events than elements allow")

    def _next_event(self, st: _State, dg: FloatArray, dlam: FloatArray,
                    remaining: float) -> tuple[float, Any, Any]:  # fmt: skip
        j = self.j
        with np.errstate(divide="ignore", invalid="ignore"):
            fel = self.elastic_force(st)
            m = st.lam - fel
            tol_l = RATE_TOL * max(float(np.max(np.abs(dlam), initial=0.0)), 1e-300)
            to_c = np.where(dlam > tol_l, (j.c1 - m) / dlam,
                            np.where(dlam < -tol_l, (-j.c1 - m) / dlam, np.inf))  # fmt: skip
            to_c = np.where(st.stuck, np.maximum(to_c, 0.0), np.inf)
            e = (self.w.T @ st.q)[j.owner] - st.x
            rate = dg[j.owner]
            tol_g = RATE_TOL * max(float(np.max(np.abs(dg), initial=0.0)), 1e-300)
            to_e = np.where(rate > tol_g, (j.r - e) / rate,
                            np.where(rate < -tol_g, (-j.r - e) / rate, np.inf))  # fmt: skip
            to_e = np.where((st.sliding == 0) & ~st.stuck[j.owner], np.maximum(to_e, 0.0), np.inf)
        step = min(float(np.min(to_c, initial=np.inf)), float(np.min(to_e, initial=np.inf)))
        if remaining <= step:
            return (remaining, None, None) if np.isfinite(remaining) else (np.inf, None, None)
        near = step + 1e-12 * max(step, abs(st.u), 1e-300)
        hit_c = np.flatnonzero(to_c <= near)
        hit_e = np.flatnonzero(to_e <= near)
        return step, (hit_c if hit_c.size else None), (hit_e if hit_e.size else None)


def _structure(stiffness: Any, contacts: Any, friction: Any, load: Any) -> _Loaded:
    k = as_real_array("stiffness", stiffness)
    k = k.reshape(1, 1) if k.ndim == 0 else (np.diag(k) if k.ndim == 1 else k)
    if k.ndim != 2 or k.shape[0] != k.shape[1]:
        raise ValueError(f"`stiffness` must be a square matrix (n, n); got shape {k.shape}.")
    n = k.shape[0]
    scale = float(np.max(np.abs(k), initial=0.0))
    if not np.allclose(k, k.T, rtol=0.0, atol=1e-12 * scale):
        raise ValueError(f"`stiffness` must be symmetric; got {fmt(k)}.")
    w = as_real_array("contacts", contacts)
    if w.ndim == 1 and n == 1:
        w = w.reshape(1, -1)
    if w.ndim != 2 or w.shape[0] != n or w.shape[1] == 0:
        raise ValueError(f"`contacts` must have shape ({n}, n_c), n_c >= 1; got {w.shape}.")
    models = as_list("friction", friction)
    if len(models) != w.shape[1]:
        raise ValueError(
            f"`friction` must hold one model per contact ({w.shape[1]}); got {len(models)}."
        )
    b = as_real_array("load", load).reshape(-1)
    if b.shape != (n,) or not np.any(b != 0.0):
        raise ValueError(f"`load` must be a nonzero vector of shape ({n},); got {fmt(b)}.")
    return _Loaded(0.5 * (k + k.T), np.ascontiguousarray(w), _Joints(models), b)


def _from_curve(points: list[tuple[Any, ...]]) -> tuple[float, FloatArray, FloatArray, Any]:
    """(k_∞, k_j, r_j, (u, q, dq/du)) of a virgin curve recorded as (u, P, slope, q, dq/du)
    at its breakpoints."""
    u = np.array([p[0] for p in points])
    first = np.r_[True, np.diff(u) > 0]  # one slope per breakpoint: the one after it
    last = np.r_[np.flatnonzero(first)[1:] - 1, len(points) - 1]
    u = u[first]
    slope = np.array([points[i][2] for i in last])
    shape = (u, np.array([points[i][3] for i in last]), np.array([points[i][4] for i in last]))
    scale = float(np.max(np.abs(slope)))
    drops = slope[:-1] - slope[1:]
    if np.any(drops < -1e-9 * scale) or slope[-1] < -1e-9 * scale:
        raise ValueError(
            "`load` gives a virgin curve that is not concave with a nonnegative final slope, "
            "so it is not a linear spring plus a PI operator; none is returned."
        )
    keep = drops > 1e-12 * scale
    k_inf = float(slope[-1]) if slope[-1] > 1e-12 * scale else 0.0  # rounding of a 0
    return k_inf, drops[keep], u[1:][keep], shape


def compile_structure(
    stiffness: ArrayLike,
    contacts: ArrayLike,
    friction: Sequence[PIFriction],
    load: ArrayLike,
    *,
    verify: bool | None = None,
) -> CompiledStructure:
    """The exact operator u ↦ P of a structure with joints loaded along one vector.

    Parameters
    ----------
    stiffness : array_like, shape (n, n)
        K, symmetric [N/m] (semidefinite: the joints may hold the structure).
    contacts : array_like, shape (n, n_c)
        W: joint c acts on g_c = w_cᵀq.
    friction : sequence of PIFriction, length n_c
        One symmetric finite-element model per joint (eq. 8), c1 >= 0 (c1 = 0: a joint
        of stops only, an Iwan joint; c1 > 0: a Coulomb contact, rigid until it slips).
    load : array_like, shape (n,)
        b: the force is P·b, the conjugate displacement u = bᵀq.
    verify : bool, optional
        Replay the structure over a history with ten nested reversals against the
        compiled operator and raise if they differ by more than 1e-9 of the force range.
        Default (None): for joints with at most 64 sliders. The joints' directions are
        checked on every call.

    Returns
    -------
    CompiledStructure
        P(u) = k_∞·u + F(u), F a `PIFriction` from the exact virgin curve.

    Raises
    ------
    ValueError
        A joint that reverses while u moves one way (not order-preserving), a
        structure that moves without a force, a failed verification.

    Examples
    --------
    A mass on a spring of 3 N/m and a Jenkins joint (20 N/m, slips at 1 N):

    >>> jenkins = PIFriction(0.0, [20.0], breakaway=[1.0])
    >>> op = compile_structure([[3.0]], [[1.0]], [jenkins], [1.0])
    >>> op.linear_stiffness, op.friction.stiffness.tolist(), op.friction.threshold.tolist()
    (3.0, [20.0], [0.05])
    """
    net = _structure(stiffness, contacts, friction, load)
    st = net.relaxed()
    points: list[tuple[Any, ...]] = []
    net.segment(st, np.inf, points)
    k_inf, k, r, (u, q, dq) = _from_curve(points)
    model = PIFriction(0.0, k, threshold=r) if k.shape[0] else None
    out = CompiledStructure(k_inf, model, net.b, u, q, dq)
    n_sliders = int(net.j.k.shape[0] + np.count_nonzero(net.j.c1))
    if verify is None:
        verify = n_sliders <= 64
    if verify:
        _verify(net, out)
    return out


def replay(net: _Loaded, history: FloatArray) -> tuple[FloatArray, FloatArray]:
    """(u, P) at every event of the structure driven through u along `history`."""
    st = net.relaxed()
    points: list[tuple[Any, ...]] = []
    for target in history[1:]:
        net.segment(st, float(target), points)
    return np.array([p[0] for p in points]), np.array([p[1] for p in points])


def _verify(net: _Loaded, out: CompiledStructure) -> None:
    if out.friction is None:
        return  # every joint stays stuck: nothing to replay
    history = verification_history(out.friction)
    u, p = replay(net, history)
    pi = out.force(np.r_[0.0, u])[1:]
    scale = max(float(np.max(np.abs(p))), 1e-300)
    dev = float(np.max(np.abs(p - pi))) / scale
    if dev > VERIFY_RTOL:
        raise ValueError(
            f"`load` does not load the structure as its compiled operator says: deviation "
            f"{dev:.3g} of the force range over a history with nested reversals (the structure "
            f"is not order-preserving along it); none is returned."
        )
