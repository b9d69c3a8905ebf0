"""Compiled batched responses for the pooled output-error fit (eq. 17, many records).

`pooled_responses` simulates every record of a pooled fit for several parameter
sets in one compiled call: task (p, i) runs the exact event kernel
(`presliding.motion._event.run_events_sided`, equal sides) for parameter set p on record i, in
parallel over all tasks (``prange``), and writes position and velocity into
row p of flat output arrays, each record at its own offset. One call evaluates
the residual of every record; one more evaluates all the finite-difference
columns of a Jacobian.

Record memories: ``mode`` 0 relaxed, 1 on the branch from saturation in
−direction with elastic force fraction·F_m, 2 along the virgin curve
(`presliding.friction.preload`).

Asymmetric friction: c1n, sigman and rn are the Coulomb element, viscous coefficient
and thresholds of sliding in −y (`presliding.motion._event.run_events_sided`; the
memories by `preload_deformation_sided`). A symmetric fit passes the positive side's
arrays again: one compiled signature, and the motion of the symmetric kernel bit for bit.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from presliding.friction.preload import preload_deformation_sided
from presliding.hysteresis._jit import njit
from presliding.motion._event import run_events_sided

RELAXED, BRANCH, VIRGIN = 0, 1, 2


def _pooled_responses(  # pragma: no cover - compiled
    mass, c1, c1n, sigma, sigman, k, r, rn, offset, y0, v0, fraction, mode, direction,
    t_all, t_off, ut_all, uv_all, u_off, max_events, o_y, o_v, status, n_rev, damped,
):  # fmt: skip
    """Positions and velocities of every record for every parameter set.

    Parameters (P parameter sets, R records, N elements, S samples in all):
    mass, c1, c1n, sigma, sigman (viscous), offset (P,); k, r, rn (P, N); y0, v0,
    fraction (P, R); mode,
    direction (R,); t_all (S,) sample times, record i at t_off[i]:t_off[i+1];
    ut_all, uv_all the zero-order-hold pieces of u, record i at
    u_off[i]:u_off[i+1]. Outputs o_y, o_v (P, S); status, n_rev (P, R). ``damped``: None
    when every sigma and sigman is 0 (the damped pieces are then not compiled), else True.
    """
    n_par = mass.shape[0]
    n_rec = t_off.shape[0] - 1
    n_el = k.shape[1]
    for task in nb.prange(n_par * n_rec):
        p = task // n_rec
        i = task % n_rec
        a, b = t_off[i], t_off[i + 1]
        ua, ub = u_off[i], u_off[i + 1]
        t_eval = t_all[a:b]
        u_t = ut_all[ua:ub]
        u_val = uv_all[ua:ub] - offset[p]
        f = np.zeros(n_el)
        if mode[i] != RELAXED:
            preload_deformation_sided(k[p], r[p], rn[p], fraction[p, i], direction[i],
                                      mode[i] == BRANCH, f)  # fmt: skip
        s = 1.0 if v0[p, i] > 0.0 else (-1.0 if v0[p, i] < 0.0 else 0.0)
        last_dir = s
        if s == 0.0 and mode[i] == BRANCH:
            last_dir = direction[i]
        n_t = b - a
        scratch = np.empty((6, n_t))
        none = np.empty(0)  # no viscous record, no piece record
        rev = np.empty((2, 8))
        # the sided kernel itself, which `simulate` compiles already
        res = run_events_sided(
            mass[p], c1[p], c1n[p], k[p], r[p], rn[p], f, y0[p, i], v0[p, i], last_dir, u_t,
            u_val, t_eval, t_eval[n_t - 1], max_events, o_y[p, a:b], o_v[p, a:b], scratch[0],
            scratch[1], scratch[2], scratch[3], scratch[4], scratch[5], rev[0], rev[1],
            sigma[p], sigman[p], none, none, damped,
        )  # fmt: skip
        filled = res[1]
        for j in range(filled, n_t):  # only after an event limit: hold the last values
            o_y[p, a + j] = o_y[p, a + filled - 1] if filled > 0 else y0[p, i]
            o_v[p, a + j] = o_v[p, a + filled - 1] if filled > 0 else v0[p, i]
        status[p, i] = res[0]
        n_rev[p, i] = res[2]


def _assemble(o_y, o_v, index, w_v, w_y, data, out):  # pragma: no cover - compiled
    """out[p, i] = w_v[i]·o_v[p, index[i]] + w_y[i]·o_y[p, index[i]] − data[i]."""
    n_par, n_res = out.shape
    for p in range(n_par):
        for i in range(n_res):
            j = index[i]
            out[p, i] = w_v[i] * o_v[p, j] + w_y[i] * o_y[p, j] - data[i]


def _quotients(o_y, o_v, form, j0, j1, j2, ca, cb, cc):  # pragma: no cover - compiled
    """o_v[p, i] = the difference quotient of o_y[p] at the planned samples (`quotient_plan`):
    form 0: ca·y[j0] + cb·y[j1] + cc·y[j2]; form 1: (y[j1] − y[j0]) / ca."""
    n_par = o_y.shape[0]
    for p in range(n_par):
        for i in range(form.shape[0]):
            if form[i] == 0:
                o_v[p, i] = ca[i] * o_y[p, j0[i]] + cb[i] * o_y[p, j1[i]] + cc[i] * o_y[p, j2[i]]
            elif form[i] == 1:
                o_v[p, i] = (o_y[p, j1[i]] - o_y[p, j0[i]]) / ca[i]


def quotient_plan(t, offset, order, plan):
    """Fill `plan` (form, j0, j1, j2, ca, cb, cc; each (S,)) for the samples
    offset..offset + len(t) − 1: ``numpy.gradient(y, t, edge_order=order)`` of a record's
    positions written term by term, with numpy's coefficients and in its order of
    operations, so that the compiled quotient equals numpy's to the last bit. Samples left
    at form −1 keep their velocity."""
    form, j0, j1, j2, ca, cb, cc = plan
    n = t.shape[0]
    i = np.arange(n)
    sl = slice(offset, offset + n)
    dx = np.diff(t)
    uniform = bool((dx == dx[0]).all())
    inner = slice(offset + 1, offset + n - 1)
    j0[inner], j1[inner], j2[inner] = offset + i[:-2], offset + i[1:-1], offset + i[2:]
    if uniform:  # (f[2:] − f[:-2]) / (2·dx)
        form[inner], ca[inner] = 1, 2.0 * dx[0]
        j1[inner] = offset + i[2:]
    else:
        dx1, dx2 = dx[:-1], dx[1:]
        form[inner] = 0
        ca[inner] = -(dx2) / (dx1 * (dx1 + dx2))
        cb[inner] = (dx2 - dx1) / (dx1 * dx2)
        cc[inner] = dx1 / (dx2 * (dx1 + dx2))
    first, last = sl.start, sl.stop - 1
    if order != 2:  # one-sided at both ends
        form[first], j0[first], j1[first], ca[first] = 1, first, first + 1, dx[0]
        form[last], j0[last], j1[last], ca[last] = 1, last - 1, last, dx[-1]
        return
    d = dx[0]
    form[first], j0[first], j1[first], j2[first] = 0, first, first + 1, first + 2
    form[last], j0[last], j1[last], j2[last] = 0, last - 2, last - 1, last
    if uniform:
        ca[first], cb[first], cc[first] = -1.5 / d, 2.0 / d, -0.5 / d
        ca[last], cb[last], cc[last] = 0.5 / d, -2.0 / d, 1.5 / d
        return
    dx1, dx2 = dx[0], dx[1]
    ca[first] = -(2.0 * dx1 + dx2) / (dx1 * (dx1 + dx2))
    cb[first] = (dx1 + dx2) / (dx1 * dx2)
    cc[first] = -dx1 / (dx2 * (dx1 + dx2))
    dx1, dx2 = dx[-2], dx[-1]
    ca[last] = (dx2) / (dx1 * (dx1 + dx2))
    cb[last] = -(dx2 + dx1) / (dx1 * dx2)
    cc[last] = (2.0 * dx2 + dx1) / (dx2 * (dx1 + dx2))


def _forward_columns(res, base, gather, column, rows, step, data):  # pragma: no cover - compiled
    """The stored values of a forward-difference CSC Jacobian (`_pooled_jacobian`):
    data[k] = (res.flat[gather[k]] − base[rows[k]]) / step[column[k]], 0 where the
    difference or the quotient is not finite or the step is 0."""
    flat = res.ravel()
    for k in range(data.shape[0]):
        s = step[column[k]]
        d = flat[gather[k]] - base[rows[k]]
        if s == 0.0 or not np.isfinite(d):
            data[k] = 0.0
            continue
        v = d / s
        data[k] = v if np.isfinite(v) else 0.0


# Parallel forms for batches of parameter sets (a Jacobian); serial forms for one
# set, where a parallel region costs more than it saves on a busy machine.
pooled_responses_parallel = njit(cache=True, parallel=True)(_pooled_responses)
pooled_responses_serial = njit(cache=True)(_pooled_responses)
assemble = njit(cache=True)(_assemble)  # memory bound: serial is as fast
quotients = njit(cache=True)(_quotients)
forward_columns = njit(cache=True)(_forward_columns)


def pooled_responses(mass, *args):
    """`_pooled_responses`, in parallel for several parameter sets; the shapes of the
    parameter arrays checked first (a mismatch would read past an array in compiled code)."""
    c1, c1n, sigma, sigman, k, r, rn, offset = args[:8]
    check_sets("pooled", {"mass": mass, "c1": c1, "c1n": c1n, "sigma": sigma, "sigman": sigman,
                          "offset": offset}, {"k": k, "r": r, "rn": rn})  # fmt: skip
    kernel = pooled_responses_parallel if mass.shape[0] > 1 else pooled_responses_serial
    # its last argument: None when no set has a viscous term (the damped pieces are then
    # not compiled, `presliding.motion._event`)
    damped = True if np.any(sigma != 0.0) or np.any(sigman != 0.0) else None
    kernel(*(mass, *args, damped))


def check_sets(kernel: str, scalars: dict, banks: dict) -> None:
    """Every per-set array of one length P, every bank (P, N) of one shape, else ValueError
    (checked before a compiled kernel reads past an array)."""
    n_par = next(iter(scalars.values())).shape[0]
    shape = next(iter(banks.values())).shape
    if any(a.shape != (n_par,) for a in scalars.values()) or not (
        len(shape) == 2 and shape[0] == n_par and all(b.shape == shape for b in banks.values())
    ):  # fmt: skip
        got = ", ".join(f"{n} {a.shape}" for n, a in {**scalars, **banks}.items())
        raise ValueError(
            f"the {kernel} kernel's parameter arrays must share their sets and elements; got {got}."
        )
