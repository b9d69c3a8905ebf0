"""The Stribeck curve's start values: eq. 17 with a Stribeck column, as one regression.

Over the records' first slides (where every element slides and the friction is the
Stribeck curve s(v) = F_C + (F_S − F_C)·exp(−(v/v_s)²), plus σ·v), eq. 17
integrated in time,

    m·(v − v_0) + F_C·∫sign v dt + (F_S − F_C)·∫sign v·exp(−(v/v_s)²) dt (+ σ·∫v dt)
        (+ offset·t) = ∫u dt,

is linear in m, F_C, the drop F_S − F_C (>= 0), σ and the offset for a given v_s:
bounded linear least squares on a geometric grid of v_s (from a fiftieth of the
records' largest speed to twice it) gives each v_s its residual, and the best v_s
with its coefficients is the start (variable projection over v_s). Free records
(u = 0) give it per unit mass: the mass is then held at its given value.
"""

from __future__ import annotations

import numpy as np

from presliding.identification.records import _response_tools as rt
from presliding.identification.records._pooled_record import Record
from presliding.identification.records._pooled_start import _moving_rows

#: the grid of v_s over the records' largest speed
GRID = np.geomspace(0.02, 2.0, 15)


def stribeck_start(records: list[Record], mass: float | None, offset: bool,
                   viscous: bool) -> dict[str, float] | None:  # fmt: skip
    """``mass``, ``coulomb_level`` F_C, ``stribeck_drop``, ``stribeck_velocity`` (and
    ``viscous``, ``offset``) of the best v_s on the grid (module notes); None when the
    rows do not determine them."""
    from scipy.optimize import lsq_linear
    from threadpoolctl import threadpool_limits

    rows = [_moving_rows(r, first_run=True) for r in records]
    top = max(float(np.max(np.abs(v))) for _, _, v, _ in rows)
    if not top > 0:
        return None
    best: tuple[float, float, np.ndarray] | None = None
    for vs in GRID * top:
        blocks, rhs = [], []
        for t, _, v, u in rows:
            cols = [
                rt.integral(t, np.sign(v)),
                rt.integral(t, np.sign(v) * np.exp(-((v / vs) ** 2))),
            ]
            cols += ([rt.integral(t, v)] if viscous else []) + ([t - t[0]] if offset else [])
            b = rt.integral(t, u)
            if mass is None:
                cols.insert(0, v - v[0])
            else:
                b = b - mass * (v - v[0])
            blocks.append(np.column_stack(cols))
            rhs.append(b)
        mat, b = np.vstack(blocks), np.concatenate(rhs)
        if mat.shape[0] <= mat.shape[1]:
            return None
        lower = np.zeros(mat.shape[1])
        if offset:
            lower[-1] = -np.inf
        scale = np.linalg.norm(mat, axis=0)
        scale[scale == 0] = 1.0
        with threadpool_limits(limits=1, user_api="blas"):
            x = lsq_linear(mat / scale, b, bounds=(lower, np.inf)).x / scale
        cost = float(np.sum((mat @ x - b) ** 2))
        if best is None or cost < best[0]:
            best = (cost, float(vs), x)
    assert best is not None
    _, vs, x = best
    lead = int(mass is None)
    m = float(x[0]) if mass is None else float(mass)
    if not m > 0:
        return None
    out = {"mass": m, "coulomb_level": float(x[lead]), "stribeck_drop": float(x[lead + 1]),
           "stribeck_velocity": vs}  # fmt: skip
    if viscous:
        out["viscous"] = float(x[lead + 2])
    if offset:
        out["offset"] = float(x[-1])
    return out if out["coulomb_level"] > 0 else None
