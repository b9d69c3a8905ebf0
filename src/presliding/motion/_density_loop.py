"""The fused implicit time loop of a mass with a density μ: Newton and commit in one pass.

Each step solves, for the distance x > 0 travelled in direction s (see
`presliding.motion._implicit_density` for the inclusion),

    φ(x) = (m/h² + σ/h)·x + s·(F_el(y + s·x) − F_el(y)) − b = 0,

with the memory of the general PI operator (`presliding.hysteresis._general_pi`)
held in local variables across the whole loop: the last input, direction,
base and level count, and the stack of turning inputs. The level a reversal
opens is computed once per step; every Newton trial then costs one evaluation
of the primitives M1, T (`_trial`: the level reached by the trial input, in
closed form), and the commit (`_commit`) walks the levels the step wipes out
and sums the stops' dissipation, exactly as `_general_pi.advance_dissipating`
does for the same input (the same formulas in the same order, so the memory
and forces are those of the operator itself, bit for bit). No compiled call
with array arguments is made per step.

Steps are uniform and samples between grid points are read off the step that
contains them, as in `presliding.motion._implicit_loop`: the position moves
linearly along the step; the memory there is the operator's exact update of
the partial step (a copy is advanced, only at such samples).
"""

from __future__ import annotations

import math

import numpy as np

from presliding.hysteresis import _general_pi as gk
from presliding.hysteresis._density_primitives import _prim, _unpack
from presliding.hysteresis._jit import JitFlags, njit
from presliding.motion._implicit_loop import BLOCK, fill_applied

_JIT: JitFlags = {"cache": True, "nogil": True}
_INLINE: JitFlags = {"cache": True, "nogil": True, "inline": "always"}
_EPS = 2.220446049250313e-16
_MAX_ITER = 200


@njit(**_INLINE)
def _trial(yv, s, last, base_t, n_t, pend, p_out, p_m1, p_p, stack, kind, big_r, p1, p2, tab):
    """(F_el, dF/dy, outer) at the trial input yv reached from `last` in direction s; pure.

    ``base_t``, ``n_t`` and the pending level (``pend``: e = last, outer p_out,
    M1(outer) p_m1, P p_p) are the memory after the reversal the step opens.
    ``outer`` is the radius where the level reached is wiped out (inf on the
    virgin branch): F_el is smooth in yv as long as 0.5·|yv − e| stays below it.
    """
    top = n_t + 1 if pend else n_t
    e = base_t
    outer = math.inf
    while top > 0:
        if top > n_t:
            e, outer = last, p_out
        else:
            e, outer = stack[top - 1, 0], stack[top - 1, 1]
        if 0.5 * abs(yv - e) < outer:
            break
        top = 0 if top == 1 else top - 2
    if top == 0:
        e = base_t
        outer = math.inf
        rho = abs(yv - base_t)
        m1, _, slope = _prim(kind, big_r, p1, p2, tab, rho, np.bool_(False))
        force = s * m1
    else:
        if top > n_t:
            m1o, p = p_m1, p_p
        else:
            m1o, p = stack[top - 1, 2], stack[top - 1, 3]
        rho = 0.5 * abs(yv - e)
        m1, _, slope = _prim(kind, big_r, p1, p2, tab, rho, np.bool_(False))
        force = s * (2.0 * m1 - m1o) + p
    if rho < big_r:
        force += (yv - e) * slope
    else:
        slope = 0.0
    return force, slope, e, outer


@njit(**_INLINE)
def _q_of(rho, m1, m2, m1r, m2r, big_r):  # pragma: no cover - compiled
    """Q(ρ) = ρ·M1(ρ) − M2(ρ) from the primitives at ρ (as `_general_pi._q`)."""
    if rho >= big_r:
        return (rho - big_r) * m1r + big_r * m1r - m2r
    return rho * m1 - m2


@njit(**_INLINE)
def _commit(yv, s, last, base, n, base_t, n_t, pend, p_out, p_m1, p_p, q_front, stack, kind,
            big_r, p1, p2, tab, m1r, m2r):  # fmt: skip  # pragma: no cover - compiled
    """Commit yv: returns (force, slope, dissipation, n, Q at the new front).

    `_walk` in its one-sample mode, with one evaluation of the primitives at the
    new front: Q(ρ) = ∫_0^ρ M1 at the old front is carried from the last commit
    (``q_front``). The stack must have room for the pending level (row n_t).
    """
    top = n_t + 1 if pend else n_t
    rho0 = 0.0
    q0 = 0.0  # Q(0)
    if not pend:
        rho0 = abs(last - base) if n == 0 else 0.5 * abs(last - stack[n - 1, 0])
        q0 = q_front
    diss = 0.0
    while top > 0:
        if top > n_t:
            e, outer = last, p_out
        else:
            e, outer = stack[top - 1, 0], stack[top - 1, 1]
        if 0.5 * abs(yv - e) < outer:
            break
        diss += 2.0 * (gk._q(outer, m1r, m2r, kind, big_r, p1, p2, tab) - q0)
        rho0 = outer if top == 1 else stack[top - 2, 1]
        q0 = gk._q(rho0, m1r, m2r, kind, big_r, p1, p2, tab)
        top = 0 if top == 1 else top - 2
    if top == 0:
        e = base_t
        rho = abs(yv - base_t)
        m1, m2, slope = _prim(kind, big_r, p1, p2, tab, rho, np.bool_(True))
        force = s * m1
        q_rho = _q_of(rho, m1, m2, m1r, m2r, big_r)
        if rho0 == math.inf:
            diss += m1r * abs(yv - last)
        else:
            diss += q_rho - q0
    else:
        if top > n_t:
            e, m1o, p = last, p_m1, p_p
            stack[n_t, 0] = last  # room made by the caller
            stack[n_t, 1] = p_out
            stack[n_t, 2] = p_m1
            stack[n_t, 3] = p_p
        else:
            e, m1o, p = stack[top - 1, 0], stack[top - 1, 2], stack[top - 1, 3]
        rho = 0.5 * abs(yv - e)
        m1, m2, slope = _prim(kind, big_r, p1, p2, tab, rho, np.bool_(True))
        force = s * (2.0 * m1 - m1o) + p
        q_rho = _q_of(rho, m1, m2, m1r, m2r, big_r)
        diss += 2.0 * (q_rho - q0)
    if rho < big_r:
        force += (yv - e) * slope
    else:
        slope = 0.0
    return force, slope, diss, top, q_rho


@njit(**_JIT)
def run_fused(  # pragma: no cover - compiled
    m, c1, sigma, head, stack, kind, par, tab, mu_max, v, last_dir, t0, t_end, n_steps,
    u_kind, u_t, u_val, u_mid, t_eval,
    o_y, o_v, o_a, o_fric, o_fel, o_eel, o_dis, o_vis, o_work, rev_t, rev_y,
):  # fmt: skip
    """n_steps equal implicit steps from t0 to t_end; samples at t_eval (sorted, in range).

    ``head``/``stack`` are the working memory (updated in place; the final stack
    is returned, it may have grown). ``mu_max`` bounds the density dμ/dr (inf
    for point masses: Newton then runs until it stagnates). ``last_dir`` is the trajectory's last
    direction (0: none), for counting reversals: their times and positions go
    to rev_t/rev_y (counted, not recorded, beyond their capacity). Samples at
    t0 get the initial state; their o_a/o_fric are left to the caller. Returns
    (stack, n_rev, rest_start (nan if moving at the end), v, last_dir,
    dissipated, work, viscous dissipation).

    No array is created or reassigned inside the step loop (that would cost
    reference counting every step): the stack grows between runs of steps.
    """
    big_r, p1, p2 = _unpack(par)
    m1r, m2r, _ = _prim(kind, big_r, p1, p2, tab, big_r, np.bool_(True))
    t_total = _prim(kind, big_r, p1, p2, tab, 0.0, np.bool_(False))[
        2
    ]  # μ([0, R]): slope after a reversal
    last, d, base, n = head[0], head[1], head[2], int(head[3])
    fel, slope = gk.force_at(last, head, stack, kind, par, tab)
    # The stops' dissipation telescopes along a level: from an anchor on the top level
    # it is anc_f·(Q(ρ) − Q(ρ_anchor)) (or M1(R)·|y − y_anchor| on a saturated branch of
    # an unbounded density), so it is evaluated only at samples and when the level changes
    dis_s, anc_f, q_anc, anc_y = _anchor(last, base, n, stack, 0.0, kind, big_r, p1, p2, tab,
                                         m1r, m2r)  # fmt: skip
    n_eval = t_eval.shape[0]
    h = (t_end - t0) / n_steps
    inv_h = 1.0 / h
    m_h = m * inv_h
    mh2 = m_h * inv_h + sigma * inv_h  # m/h² + σ/h
    # Newton ends after a step Δ whose error bound μ_max/(2·φ')·(1 + μ([0, R])/φ')²·Δ²
    # (φ' >= m/h² + σ/h) is below rounding: a bounded density, and the same level (φ is
    # smooth there; a wipe-out is a kink)
    curv = 0.5 * mu_max / mh2 * (1.0 + t_total / mh2) ** 2
    dis_c = vis = work = 0.0  # dis_c: the Coulomb element's dissipation
    cap = rev_t.shape[0]
    n_rev = 0
    rest_start = np.nan
    # the counters start as int64, not as the literal 0: a literal would compile
    # `_sample` and `fill_applied` a second time, for that literal argument
    ptr = np.int64(0)
    u_blk = np.empty(BLOCK)
    ie = np.int64(0)
    while ie < n_eval and t_eval[ie] <= t0:
        ie = _sample(ie, last, v, fel, _energy(last, d, base, n, stack, kind, par, tab), dis_s,
                     vis, work, o_y, o_v, o_fel, o_eel, o_dis, o_vis, o_work)  # fmt: skip
    i = np.int64(0)
    t_i = t0
    while i < n_steps:
        if n >= stack.shape[0]:  # room for the level a reversal opens
            stack = gk._grow(stack)
        while i < n_steps:
            t_next = t0 + (i + 1) * h if i + 1 < n_steps else t_end
            j_blk = i % BLOCK
            if j_blk == 0:
                ptr = fill_applied(u_blk, i, min(BLOCK, n_steps - i), u_kind, u_t, u_val,
                                   u_mid, t0, h, ptr)  # fmt: skip
            u = u_blk[j_blk]
            g = m_h * v + u - fel
            x = 0.0
            s = 0.0
            pend = False
            base_t, n_t, p_out, p_m1, p_p = base, n, 0.0, 0.0, 0.0
            if abs(g) <= c1:  # sticks: the position and the memory stay exactly as they are
                v_new = 0.0
                if rest_start != rest_start:
                    rest_start = t_i
            else:
                s = 1.0 if g > 0.0 else -1.0
                b = abs(g) - c1
                pend = s != d and d != 0.0
                if pend:
                    base_t, n_t, p_out, p_m1, p_p = gk._reversal_level(
                        last, d, base, n, stack, kind, big_r, p1, p2, tab
                    )
                # Newton from the tangent at the start (left of the root: φ is concave and
                # increasing), safeguarded by the bracket [0, b·h²/m]
                lo = 0.0
                hi = b / mh2
                x = b / (mh2 + (t_total if pend else slope))
                for _ in range(_MAX_ITER):
                    f_tr, sl, e_l, out_l = _trial(last + s * x, s, last, base_t, n_t, pend,
                                                  p_out, p_m1, p_p, stack, kind, big_r, p1, p2,
                                                  tab)  # fmt: skip
                    phi = mh2 * x + s * (f_tr - fel) - b
                    if phi < 0.0:
                        lo = x
                    elif phi > 0.0:
                        hi = x
                    else:
                        break
                    xn = x - phi / (mh2 + sl)
                    if not (xn > lo and xn < hi):  # also catches a NaN
                        xn = 0.5 * (lo + hi)
                    if xn == x or hi - lo <= 2.0 * _EPS * hi:
                        break
                    dx = xn - x
                    x = xn
                    if (
                        curv * dx * dx <= 0.25 * _EPS * xn
                        and 0.5 * abs(last + s * xn - e_l) < out_l
                    ):
                        break
                v_new = s * x * inv_h
            acc = (v_new - v) * inv_h
            if ie < n_eval and t_eval[ie] <= t_next:  # the dissipation before the step
                dis = dis_c + _stops(last, base, n, stack, dis_s, anc_f, q_anc, anc_y, kind, big_r,
                                     p1, p2, tab, m1r, m2r)  # fmt: skip
            while ie < n_eval and t_eval[ie] < t_next:  # samples inside the step
                th = (t_eval[ie] - t_i) * inv_h
                fel_p, eel_p, dpl_p = _partial(last, d, base, n, stack, kind, par, tab, fel, s,
                                               th * x)  # fmt: skip
                o_y[ie] = last + th * s * x
                o_v[ie] = v + th * (v_new - v)
                o_a[ie] = acc
                o_fric[ie] = u - m * acc
                o_fel[ie] = fel_p
                o_eel[ie] = eel_p
                o_dis[ie] = dis + th * c1 * x + dpl_p
                o_vis[ie] = vis + th * sigma * x * x * inv_h
                o_work[ie] = work + th * u * s * x
                ie += 1
            if x != 0.0:
                y_new = last + s * x
                if not pend and (n == 0 or 0.5 * abs(y_new - stack[n - 1, 0]) < stack[n - 1, 1]):
                    # on the same level: the force in closed form, the dissipation left to
                    # the anchor
                    e = base if n == 0 else stack[n - 1, 0]
                    if n == 0:
                        rho = abs(y_new - base)
                        m1, _, slope = _prim(kind, big_r, p1, p2, tab, rho, np.bool_(False))
                        fel = s * m1
                    else:
                        rho = 0.5 * abs(y_new - e)
                        m1, _, slope = _prim(kind, big_r, p1, p2, tab, rho, np.bool_(False))
                        fel = s * (2.0 * m1 - stack[n - 1, 2]) + stack[n - 1, 3]
                    if rho < big_r:
                        fel += (y_new - e) * slope
                    else:
                        slope = 0.0
                else:  # a new level or a wipe-out: close the anchor, commit, anchor again
                    dis_s = _stops(last, base, n, stack, dis_s, anc_f, q_anc, anc_y, kind, big_r,
                                   p1, p2, tab, m1r, m2r)  # fmt: skip
                    front = abs(last - base) if n == 0 else 0.5 * abs(last - stack[n - 1, 0])
                    q_front = 0.0
                    if not pend and front < math.inf:
                        q_front = gk._q(front, m1r, m2r, kind, big_r, p1, p2, tab)
                    fel, slope, dplastic, n, _ = _commit(
                        y_new, s, last, base, n, base_t, n_t, pend, p_out, p_m1, p_p, q_front,
                        stack, kind, big_r, p1, p2, tab, m1r, m2r,
                    )  # fmt: skip
                    dis_s, anc_f, q_anc, anc_y = _anchor(
                        y_new, base_t, n, stack, dis_s + dplastic, kind, big_r, p1, p2, tab, m1r,
                        m2r,
                    )  # fmt: skip
                base = base_t
                if s != last_dir:
                    if last_dir != 0.0:
                        if n_rev < cap:
                            rev_t[n_rev] = t_i
                            rev_y[n_rev] = last
                        n_rev += 1
                    last_dir = s
                last = y_new
                d = s
                dis_c += c1 * x
                vis += sigma * x * x * inv_h
                work += u * s * x
                rest_start = np.nan
            v = v_new
            if ie < n_eval and t_eval[ie] <= t_next:  # samples on the grid point
                eel = _energy(last, d, base, n, stack, kind, par, tab)
                dis = dis_c + _stops(last, base, n, stack, dis_s, anc_f, q_anc, anc_y, kind, big_r,
                                     p1, p2, tab, m1r, m2r)  # fmt: skip
                while ie < n_eval and t_eval[ie] <= t_next:
                    o_a[ie] = acc
                    o_fric[ie] = u - m * acc
                    ie = _sample(ie, last, v, fel, eel, dis, vis, work, o_y, o_v, o_fel, o_eel,
                                 o_dis, o_vis, o_work)  # fmt: skip
            t_i = t_next
            i += 1
            if n >= stack.shape[0]:
                break
    head[0], head[1], head[2], head[3] = last, d, base, n
    dis = dis_c + _stops(last, base, n, stack, dis_s, anc_f, q_anc, anc_y, kind, big_r, p1, p2, tab,
                         m1r, m2r)  # fmt: skip
    return stack, n_rev, rest_start, v, last_dir, dis, work, vis


@njit(**_JIT)
def _anchor(last, base, n, stack, dis_s, kind, big_r, p1, p2, tab, m1r, m2r):  # pragma: no cover
    """(dissipation, factor, Q, y) of an anchor at the front of the top level: factor 2 on a
    level, 1 on the virgin branch, 0 on a saturated branch of an unbounded density (linear)."""
    if n > 0:
        front = 0.5 * abs(last - stack[n - 1, 0])
        return dis_s, 2.0, gk._q(front, m1r, m2r, kind, big_r, p1, p2, tab), last
    front = abs(last - base)
    if front == math.inf:
        return dis_s, 0.0, 0.0, last
    return dis_s, 1.0, gk._q(front, m1r, m2r, kind, big_r, p1, p2, tab), last


@njit(**_JIT)
def _stops(last, base, n, stack, dis_s, anc_f, q_anc, anc_y, kind, big_r, p1, p2, tab, m1r,
           m2r):  # fmt: skip  # pragma: no cover - compiled
    """The stops' dissipation up to `last`, from the anchor on the top level."""
    if anc_f == 0.0:
        return dis_s + m1r * abs(last - anc_y)
    front = abs(last - base) if n == 0 else 0.5 * abs(last - stack[n - 1, 0])
    return dis_s + anc_f * (gk._q(front, m1r, m2r, kind, big_r, p1, p2, tab) - q_anc)


@njit(**_JIT)
def _energy(last, d, base, n, stack, kind, par, tab):  # pragma: no cover - compiled
    """½∫ f² dμ of the memory held in the loop's local variables."""
    hd = np.empty(4)
    hd[0], hd[1], hd[2], hd[3] = last, d, base, n
    return gk.elastic_energy(hd, stack, kind, par, tab)


@njit(**_JIT)
def _partial(last, d, base, n, stack, kind, par, tab, fel, s, x):  # pragma: no cover
    """F_el, ½∫ f² dμ and the stops' dissipation after moving x in direction s (a copy)."""
    if x == 0.0:
        return fel, _energy(last, d, base, n, stack, kind, par, tab), 0.0
    hd = np.empty(4)
    hd[0], hd[1], hd[2], hd[3] = last, d, base, n
    st = stack.copy()
    force, _, diss, st = gk.advance_dissipating(last + s * x, hd, st, kind, par, tab)
    return force, gk.elastic_energy(hd, st, kind, par, tab), diss


@njit(**_JIT)
def _sample(ie, y, v, fel, eel, dis, vis, work, o_y, o_v, o_fel, o_eel, o_dis, o_vis,
            o_work):  # fmt: skip  # pragma: no cover - compiled
    o_y[ie] = y
    o_v[ie] = v
    o_fel[ie] = fel
    o_eel[ie] = eel
    o_dis[ie] = dis
    o_vis[ie] = vis
    o_work[ie] = work
    return ie + 1
