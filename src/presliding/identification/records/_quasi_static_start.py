"""Start values of a quasi-static fit: eq. 8 as a regression, a density lifted above |u|.

`quasi_static_start` fits u = c1·sign(ẏ) + Σ_g w_g·stop_g(y) (+ offset) on the
samples where the position moves (there the balance holds with equality),
after each record's first reversal (an unknown earlier memory wiped out), and
turns the weights into the model's parameters. An asymmetric model is the
symmetric one of the mean levels under u − (F_c⁺ − F_c⁻)/2 (`ModelSpec`): its
start is that fit with an offset, the offset turned into the two sides. `lift_density` scales a
density's heights until its F_c exceeds every applied force (a start without
a quasi-static response could not begin).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from presliding.identification.problem import _pi_regression as pr
from presliding.identification.problem._model_spec import ModelSpec

__all__ = ["lift_density", "quasi_static_start"]


def quasi_static_start(recs: list, spec: ModelSpec, offset: bool) -> dict[str, float]:
    """Start values from eq. 8 as a regression on the moving samples (module notes)."""
    if spec.negative is None:
        return _regression_start(recs, spec, offset)
    start = _regression_start(recs, spec, True)  # the mean levels and their offset
    half = start.pop("offset")
    mean = spec.coulomb_level(start)
    half = min(max(half, -0.5 * mean), 0.5 * mean)  # F_c⁻/F_c⁺ within [1/3, 3]
    return spec.sided(start, (mean - half) / (mean + half))


def _regression_start(recs: list, spec: ModelSpec, offset: bool) -> dict[str, float]:
    """Eq. 8 as a regression: the symmetric model's start (with an offset when asked)."""
    from scipy.optimize import lsq_linear
    from threadpoolctl import threadpool_limits

    span = max(float(np.ptp(r.position)) for r in recs)
    steps = np.concatenate([np.abs(np.diff(r.position)) for r in recs])
    quantum = float(np.min(steps[steps > 0]))
    grid = pr.geometric_grid(max(2.0 * quantum, 1e-3 * span), 0.5 * span, span, 32)
    rows, rhs = [], []
    for r in recs:
        y, u = r.position, r.applied_force
        turns = pr.reversal_indices(np.ascontiguousarray(y), 2.0 * quantum)
        first_turn = int(turns[0]) if turns.size else 0
        dy = np.diff(y, prepend=y[0])
        moving = (np.abs(dy) > 0) & (np.arange(y.shape[0]) > first_turn)
        cols = [np.sign(dy), *pr.stop_basis(y)(grid)[0].T] + ([np.ones_like(y)] if offset else [])
        rows.append(np.column_stack(cols)[moving])
        rhs.append(u[moving])
    mat, b = np.vstack(rows), np.concatenate(rhs)
    lower = np.zeros(mat.shape[1])
    if offset:
        lower[-1] = -np.inf
    u_max = max(float(np.max(np.abs(r.applied_force))) for r in recs)
    if mat.shape[0] > mat.shape[1]:
        scale = np.linalg.norm(mat, axis=0)
        scale[scale == 0] = 1.0
        with threadpool_limits(limits=1, user_api="blas"):
            sol = lsq_linear(mat / scale, b, bounds=(lower, np.inf)).x / scale
        c1, weights = float(sol[0]), sol[1 : 1 + grid.shape[0]]
        off = float(sol[-1]) if offset else 0.0
    else:
        c1, weights, off = 0.1 * u_max, np.zeros_like(grid), 0.0
    fc = max(c1 + float(weights @ grid), 1.2 * u_max)
    c1 = min(max(c1, 0.02 * fc), 0.9 * fc)
    if not np.any(weights > 0):
        weights = np.zeros_like(grid)
        weights[len(grid) // 2] = (fc - c1) / grid[len(grid) // 2]
    start = spec.start(fc, c1, grid, weights)
    k_max = max([start[x] for x in spec.k_names], default=0.0)
    for x in spec.k_names:  # an element too soft to slide would blow the positions up
        start[x] = max(start[x], 0.02 * k_max)
    if offset:
        start["offset"] = off
    return start


def lift_density(spec: ModelSpec, start: dict[str, float], level: float,
                 fixed: Mapping[str, float]) -> dict[str, float]:  # fmt: skip
    """A density start whose F_c reaches `level`: its heights scaled (a start whose F_c
    is not above every |u| has no quasi-static response, and the solver could not begin)."""
    heights = [x for x in spec.names if x.startswith("height") and x not in fixed]
    fc = spec.coulomb_level(start)
    c1 = max(start.get("coulomb", 0.0), 0.0)
    if fc >= level or not heights or not fc > c1:
        return start
    if c1 >= 0.9 * level and "coulomb" not in fixed:
        c1 = start["coulomb"] = 0.5 * level
    factor = (level - c1) / (fc - c1)
    return {x: v * factor if x in heights else v for x, v in start.items()}


#: the further starts of a creep fit's time constant, as factors of its start (`creep_start`)
CREEP_TIMES = (0.1, 10.0)


def creep_start(recs: list, spec: ModelSpec, start: Mapping[str, float]) -> dict[str, float]:
    """Start values of the creep element (`CreepingFriction`): τ a tenth of the median
    record's duration, J a twentieth of the contact's compliance 1/Σ k_j at the start."""
    duration = float(np.median([r.time[-1] - r.time[0] for r in recs]))
    _, k, _ = spec.bank(start)
    total = float(np.sum(k))
    compliance = 0.05 / total if total > 0 else 0.0
    return {"creep_compliance": compliance, "creep_time": 0.1 * max(duration, 1e-300)}
