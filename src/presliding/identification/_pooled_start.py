"""Start values of the pooled fits: eq. 17 as one regression over every record.

Eq. 17 integrated in time, record by record,

    m·(v − v_0) + ∫ (c1·sign v + Σ_g w_g·stop_g(y) + offset) dt = ∫ u dt,

needs no differentiation of a noisy velocity. The rows of all records are
stacked and bounded linear least squares gives m, c1, the offset and the
stiffnesses w_g of a geometric grid of stops (relaxed at each record's first
sample: only a start). The grid is a nonparametric virgin curve
G(s) = Σ_g w_g·min(s, r_g) of the elastic part, which `ModelSpec.start` turns
into the model's parameters. Free records (u = 0) determine everything only
per unit mass; the mass is then held at 1 (or its given value).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from presliding.identification import _pi_regression as pr
from presliding.identification import _response_tools as rt
from presliding.identification._model_spec import ModelSpec
from presliding.identification._pooled_problem import Record

FloatArray = NDArray[np.float64]


def pooled_start(
    records: list[Record],
    spec: ModelSpec,
    mass: float | None,
    offset: bool,
) -> dict[str, float]:
    """Start values of the shared parameters (``mass``, the model's, ``offset``)."""
    from scipy.optimize import lsq_linear
    from threadpoolctl import threadpool_limits

    span = max(float(np.ptp(r.position)) for r in records)
    steps = np.concatenate([np.abs(np.diff(r.position)) for r in records])
    steps = steps[steps > 0]
    quantum = float(np.min(steps)) if steps.size else 1e-5 * (span or 1.0)
    grid = pr.geometric_grid(2.0 * quantum, 0.5 * (span or 1.0), span or 1.0, 32)
    blocks, rhs = [], []
    for rec in records:
        t, y, v, u = rec.time, rec.position, rec.velocity, rec.applied_force
        cols = [np.sign(v), *pr.stop_basis(y)(grid)[0].T]
        if offset:
            cols.append(np.ones_like(t))
        cols = [rt.integral(t, c) for c in cols]
        b = rt.integral(t, u)
        if mass is None:
            cols.insert(0, v - v[0])
        else:
            b = b - mass * (v - v[0])
        blocks.append(np.column_stack(cols))
        rhs.append(b)
    mat, b = np.vstack(blocks), np.concatenate(rhs)
    n_col = mat.shape[1]
    lower = np.zeros(n_col)
    if offset:
        lower[-1] = -np.inf
    scale = np.linalg.norm(mat, axis=0)
    scale[scale == 0] = 1.0
    sol = None
    if mat.shape[0] > n_col and span > 0:
        with threadpool_limits(limits=1, user_api="blas"):  # a tall, thin problem
            sol = lsq_linear(mat / scale, b, bounds=(lower, np.inf)).x / scale
    lead = int(mass is None)
    m = (1.0 if mass is None else mass) if sol is None or mass is not None else float(sol[0])
    acc = float(np.mean([np.mean(np.abs(np.gradient(r.velocity, r.time))) for r in records]))
    if sol is None or not m > 0:
        m = 1.0 if mass is None else mass
        c1, weights, off = 0.5 * m * acc, np.zeros_like(grid), 0.0
    else:
        c1, weights = float(sol[lead]), sol[lead + 1 : lead + 1 + grid.shape[0]]
        off = float(sol[-1]) if offset else 0.0
    fc = c1 + float(weights @ grid)
    if not fc > 0:
        fc = m * acc or 1.0
    if not c1 > 0 or c1 >= fc:
        c1 = 0.5 * fc
    start = {"mass": float(m), **spec.start(fc, c1, grid, weights)}
    if offset:
        start["offset"] = off
    return start
