"""Compiled batched motions of many records with GMS, LuGre or Dahl friction.

Task (p, i) of `rate_responses` simulates record i with parameter set p by the
implicit step of `presliding.motion._rate_step`, `n_sub` equal steps per sample
interval with the applied force held (zero-order hold) over the interval, and
writes the position and the step's velocity at every sample. A record simulated
by `presliding.simulate` with ``step = Δt/n_sub`` on its sample grid follows the
same steps.

The record's friction state at its first sample (``mode``): 0 relaxed; 1 the
branch family of `presliding.friction.preload` with force fraction·(its
saturated value) — GMS: the elements' forces of the PI branch family
(`preload_deformation`) times ŝ(|v0|), the elements saturated in the record's
direction slipping; LuGre: fraction·g(v0)/σ0; Dahl: fraction·F_c. A fraction of
±1 is steady sliding at v0 (the ``"saturated"`` start).
"""

from __future__ import annotations

import numba as nb
import numpy as np

from presliding.friction._gms_kernels import stribeck_factor
from presliding.friction.preload import preload_deformation
from presliding.hysteresis._jit import njit
from presliding.motion._rate_step import GMS, LUGRE, commit, solve_step

RELAXED, BRANCH = 0, 1
FAILED = -3


@njit(cache=True, error_model="numpy")
def start_state(family, par, k, c, v0, fraction, mode, direction, z, e):  # pragma: no cover
    """The friction state at a record's first sample (module notes), into z and e."""
    z[:] = 0.0
    e[:] = 0.0
    if mode == RELAXED:
        return
    if family == GMS:
        n = k.shape[0]
        r = np.empty(n)
        for j in range(n):
            r[j] = c[j] / k[j]
        preload_deformation(k, r, fraction, direction, True, z)
        shat = stribeck_factor(abs(v0), par[1], par[2], par[3])
        for j in range(n):
            if z[j] * direction >= r[j]:
                e[j] = direction
            z[j] = k[j] * z[j] * shat
        return
    if family == LUGRE:
        g = par[0] + (par[1] - par[0]) * np.exp(-((v0 / par[5]) ** 2))
        z[0] = fraction * g / par[2]
        return
    z[0] = fraction * par[0]


def _rate_responses(  # pragma: no cover - compiled
    family, par, k, c, mass, offset, y0, v0, fraction, mode, direction,
    t_all, t_off, u_all, n_sub, o_y, o_v, status,
):  # fmt: skip
    """Positions and velocities of every record for every parameter set.

    P parameter sets, R records, N GMS elements (1 for the other families), S
    samples in all: par (P, 6); k, c (P, N); mass, offset (P,); y0, v0, fraction
    (P, R); mode, direction (R,); t_all, u_all (S,), record i at t_off[i]:t_off[i+1].
    Outputs o_y, o_v (P, S); status (P, R): 0, or −3 where a step found no velocity.
    """
    n_par = mass.shape[0]
    n_rec = t_off.shape[0] - 1
    n_z = k.shape[1] if family == GMS else 1
    for task in nb.prange(n_par * n_rec):
        p = task // n_rec
        i = task % n_rec
        a, b = t_off[i], t_off[i + 1]
        z = np.empty(n_z)
        e = np.empty(n_z)
        kp, cp, pp = k[p], c[p], par[p]
        start_state(family, pp, kp, cp, v0[p, i], fraction[p, i], mode[i], direction[i], z, e)
        y = y0[p, i]
        v = v0[p, i]
        m = mass[p]
        o_y[p, a] = y
        o_v[p, a] = v
        status[p, i] = 0
        for q in range(a + 1, b):
            h = (t_all[q] - t_all[q - 1]) / n_sub
            u = u_all[q - 1] - offset[p]
            for _ in range(n_sub):
                delta = solve_step(family, pp, kp, cp, z, e, m, v, u, h)
                if not np.isfinite(delta):
                    status[p, i] = FAILED
                    break
                if delta != 0.0:
                    commit(family, pp, kp, cp, z, e, 1.0 if delta > 0.0 else -1.0, abs(delta), h)
                    y += delta
                v = delta / h
            if status[p, i] != 0:
                for rest in range(q, b):
                    o_y[p, rest] = y
                    o_v[p, rest] = v
                break
            o_y[p, q] = y
            o_v[p, q] = v


rate_responses_parallel = njit(cache=True, parallel=True, error_model="numpy")(_rate_responses)
rate_responses_serial = njit(cache=True, error_model="numpy")(_rate_responses)


def rate_responses(family, par, *args):
    """`_rate_responses`, in parallel for several parameter sets."""
    kernel = rate_responses_parallel if par.shape[0] > 1 else rate_responses_serial
    kernel(family, par, *args)
