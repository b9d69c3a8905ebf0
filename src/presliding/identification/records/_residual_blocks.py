"""A pooled fit's residual as the adequacy tests read it: blocks, noise models, candidates.

`residual_blocks` cuts the residual of a record-pooled fit at its optimum into
one `_adequacy.Block` per record and compared signal, each with the noise
model the data give (`_noise_floor`): a position's white variance and quantum
(a record that hardly moves takes the others' quantum: one encoder); a velocity
that is the difference quotient of the position carries the position's noise
through the quotient D (its whiteness read on the position's residual, where
that noise is white, with the positions' own sensitivity J_y to the parameters,
`position_sensitivity`, when the position is not compared: the parameters' error
J_y·Δθ, slow there, is no sign of a model that is wrong); a measured velocity
its own. The independence test correlates each block with the applied force,
the model's velocity and its sign (for a quasi-static fit: the force, the
model's position increments and their sign).

`candidates` gives the residual's directions of the mechanisms the model may
lack (`_adequacy.score_causes`): an asymmetry by direction (c1 and the
thresholds a factor 1 + ε larger for sliding in −y, linearised along the fitted
motion as the extra force it exerts there), a force offset, a viscous force
σ·ẏ, the applied force one sample later, and one more element (a small
stiffness at each of a few thresholds); each is one simulation of every record
on a sibling problem with that mechanism added at zero, at the optimum.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Mapping
from dataclasses import replace
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from presliding.identification.judge._adequacy import (
    Adequacy,
    Block,
    Candidate,
    assess,
    score_causes,
)
from presliding.identification.judge._noise_floor import shared_quanta, shows_noise, white_variance
from presliding.identification.problem._model_spec import ModelSpec
from presliding.identification.records._pooled_problem import PooledProblem
from presliding.identification.records._pooled_record import difference_matrix

FloatArray = NDArray[np.float64]

__all__ = ["candidates", "pooled_adequacy", "position_sensitivity", "residual_blocks"]

#: thresholds tried for one more element, geometric between these shares of the largest swing
ELEMENT_RANGE = (1e-3, 0.5)
#: how many of them
ELEMENT_TRIES = 8
#: the small amount of each mechanism its direction is taken over (relative)
STEP = 1e-6


def still(x: FloatArray, q: float) -> NDArray[np.bool_]:
    """Samples of a quantised signal equal to a neighbour (it did not move by a quantum)."""
    out = np.zeros(x.shape[0], dtype=bool)
    if q > 0 and x.shape[0] > 1:
        same = np.diff(x) == 0
        out[1:] |= same
        out[:-1] |= same
    return out


def _row_slices(problem: PooledProblem) -> dict[tuple[int, str], slice]:
    """The residual rows of each (record, signal): velocity before position."""
    out, seen = {}, set()
    for i, rows in problem.rows:
        signal = "velocity" if problem.w_v and i not in seen else "position"
        seen.add(i)
        out[(i, signal)] = rows
    return out


def residual_blocks(problem: PooledProblem, values: Mapping[str, float], jacobian: Any = None,
                    covariance: Any = None, positions: Any = None) -> list[Block]:  # fmt: skip
    """The blocks of the pooled residual at `values` (module notes), with the fit's
    `jacobian` (weighted rows, every parameter) and parameter `covariance` when given;
    `positions`: ∂y/∂θ of the simulated positions (S, same columns), the path
    sensitivity of a velocity block that is the quotient of an uncompared position."""
    p = np.array([values[x] for x in problem.names], dtype=float)[None]
    o_y, o_v, status, _ = problem.simulate(p)
    if np.any(status != 0):
        return []
    recs = problem.records
    q_y = shared_quanta([r.position for r in recs])
    q_v = shared_quanta([r.velocity for r in recs])
    quasi = not problem.w_v and not np.any(o_v)
    slices = _row_slices(problem)

    def rows(i: int, signal: str) -> Any:
        if jacobian is None:
            return None
        w = problem.w_v if signal == "velocity" else problem.w_y
        return np.asarray(jacobian[slices[(i, signal)]]) / w

    out = []
    for i, rec in enumerate(recs):
        a, b = int(problem.t_off[i]), int(problem.t_off[i + 1])
        y_res, v_res = o_y[0, a:b] - rec.position, o_v[0, a:b] - rec.velocity
        var_y = white_variance(rec.position, q_y[i])
        still_y = still(rec.position, q_y[i])
        if quasi:
            motion = np.gradient(o_y[0, a:b])
            regressors = {"the applied force": rec.applied_force, "the motion": motion,
                          "the direction of motion": np.sign(motion)}  # fmt: skip
        else:
            regressors = {"the applied force": rec.applied_force, "the velocity": o_v[0, a:b],
                          "the direction of motion": np.sign(o_v[0, a:b])}  # fmt: skip
        if problem.w_v:
            jv = rows(i, "velocity")
            if rec.difference:
                d = difference_matrix(rec.time, rec.difference)
                jp = None if positions is None or problem.w_y else positions[a:b]
                out.append(Block(i, "velocity", v_res, var_y, d, q_y[i], still_y,
                                 None if problem.w_y else y_res, regressors,
                                 not problem.w_y, jv, jp, covariance))  # fmt: skip
            else:
                white = not (problem.w_y and rec.measured_position)
                out.append(Block(i, "velocity", v_res, white_variance(rec.velocity, q_v[i]),
                                 None, q_v[i], still(rec.velocity, q_v[i]), None, regressors,
                                 white, jv, jv, covariance))  # fmt: skip
        if problem.w_y:
            jy = rows(i, "position")
            out.append(Block(i, "position", y_res, var_y, None, q_y[i], still_y, None,
                             regressors, True, jy, jy, covariance))  # fmt: skip
    return out


def _measured(block: Block, problem: PooledProblem) -> bool:
    """Whether the block's noise model rests on measurable noise (`shows_noise`)."""
    rec = problem.records[block.record]
    signal = rec.position if block.quotient is not None or block.signal == "position" else (
        rec.velocity)  # fmt: skip
    return block.quantum > 0 or shows_noise(signal, block.noise)


def floor_cost(problem: PooledProblem, blocks: list[Block]) -> float:
    """‖r‖² the noise alone would leave in the weighted residual, from the blocks' models."""
    total = 0.0
    for blk in blocks:
        w = problem.w_v if blk.signal == "velocity" else problem.w_y
        total += w * w * blk.noise * blk.noise_scale() * blk.residual.shape[0]
    return total


def _sibling(problem: PooledProblem, spec: ModelSpec | None = None, *, offset: bool | None = None,
             viscous: bool | None = None, records: Any = None) -> PooledProblem:  # fmt: skip
    """The same problem with another model, offset, viscous term or records."""
    from presliding.identification.records._quasi_static_problem import QuasiStaticProblem

    suffix = problem.nuisance("initial_position", 0) != "initial_position"
    off = ("offset" in problem.shared) if offset is None else offset
    recs = problem.records if records is None else records
    if isinstance(problem, QuasiStaticProblem):
        return QuasiStaticProblem(recs, spec or problem.spec, problem.initial_state, offset=off,
                                  suffix=suffix)  # fmt: skip
    return PooledProblem(recs, spec or problem.spec, (problem.w_v, problem.w_y),
                         problem.initial_state, offset=off, suffix=suffix,
                         viscous=("viscous" in problem.shared) if viscous is None else viscous,
                         velocity=problem.velocity)  # fmt: skip


def candidates(problem: PooledProblem, values: Mapping[str, float],
               residual: FloatArray) -> list[Candidate]:  # fmt: skip
    """The residual's directions of the mechanisms the model may lack (module notes)."""
    vals = dict(values)
    scale = max(abs(problem.spec.coulomb_level(vals)), 1e-300)
    out: list[Candidate] = []

    def direction(sib: PooledProblem, extra: Mapping[str, float], base: Mapping[str, float]):
        q0 = {**vals, **base}
        q1 = {**q0, **extra}
        r0 = sib.residuals(np.array([[q0[x] for x in sib.names]], dtype=float))[0]
        r1 = sib.residuals(np.array([[q1[x] for x in sib.names]], dtype=float))[0]
        return r1 - r0

    quasi = not problem.w_v
    step = STEP * scale
    sided = _sided_force(problem, vals)
    if sided is not None:  # c1 and the thresholds 1 + ε times larger for sliding in −y
        extra = [replace(r, applied_force=r.applied_force + step * h)
                 for r, h in zip(problem.records, sided, strict=True)]  # fmt: skip
        j = (_sibling(problem, records=extra).residuals(
            np.array([[vals[x] for x in problem.names]], dtype=float))[0]
            - residual[: problem.n_res]) / step  # fmt: skip
        out.append(
            Candidate(
                "asymmetry",
                j,
                lambda e: (
                    "an asymmetry by direction: the residual asks for friction "
                    f"{100 * abs(e):.2g} % "
                    f"{'stronger' if e > 0 else 'weaker'} in −y than in +y (c1 and the break-away "
                    "forces); fit it with `asymmetric=True` (command line `--asymmetric`)"
                ),
            )
        )
    if "offset" not in problem.shared:
        sib = _sibling(problem, offset=True)
        j = direction(sib, {"offset": step}, {"offset": 0.0}) / step
        out.append(Candidate("offset", j, lambda e: (
            f"a force offset of {-e:.3g} (an asymmetry by direction acts alike while sliding): "
            "fit it with `offset=True`, or `asymmetric=True` (command line "
            "`--asymmetric`)")))  # fmt: skip
    if not quasi and "viscous" not in problem.shared:
        speed = max(float(np.max(np.abs(r.velocity))) for r in problem.records) or 1.0
        step = STEP * scale / speed
        sib = _sibling(problem, viscous=True)
        j = direction(sib, {"viscous": step}, {"viscous": 0.0}) / step
        out.append(Candidate("velocity", j, lambda e: (
            f"a velocity dependence: the residual asks for a viscous force σ·ẏ with σ = "
            f"{e:.3g} beyond the Coulomb element's sign; fit it with `viscous=True`")))  # fmt: skip
    later = [replace(r, applied_force=np.concatenate([r.applied_force[:1], r.applied_force[:-1]]))
             for r in problem.records]  # fmt: skip
    j = (
        _sibling(problem, records=later).residuals(
            np.array([[vals[x] for x in problem.names]], dtype=float)
        )[0]
        - residual[: problem.n_res]
    )
    dt = float(np.median(np.diff(problem.records[0].time))) if problem.records[0].time.size > 1 \
        else 0.0  # fmt: skip
    out.append(Candidate("delay", j, lambda e: (
        f"a delay between force and motion: the force fits better shifted by {abs(e):.2g} "
        f"sample(s) ({abs(e) * dt:.3g} s) {'earlier' if e < 0 else 'later'} (it was "
        f"recorded {'late' if e < 0 else 'early'})")))  # fmt: skip
    out += _element_candidates(problem, vals)
    return [c for c in out if c.direction.shape == (problem.n_res,)]


def _sided_force(problem: PooledProblem, vals: Mapping[str, float]) -> list[FloatArray] | None:
    """Per record, the force by which friction grows for sliding in −y when c1 and every
    threshold there grow by a factor 1 + ε, over ε, along the fitted motion: c1 while sliding
    in −y, and k_j·r_j for each element last dragged that way (`_pi_regression`'s sides).
    Friction larger in −y pushes the mass towards +y: an extra applied force of this size."""
    from presliding.identification.problem._pi_regression import stop_basis

    c1, k, r = problem.spec.bank(vals)
    p = np.array([[vals[x] for x in problem.names]], dtype=float)
    o_y, _, status, _ = problem.simulate(p)
    if np.any(status != 0):
        return None
    out = []
    for i in range(problem.n_rec):
        y = np.ascontiguousarray(o_y[0, problem.t_off[i] : problem.t_off[i + 1]])
        step = np.diff(y, prepend=y[0])
        last = np.where(step != 0, np.arange(y.shape[0]), 0)
        np.maximum.accumulate(last, out=last)
        direction = np.sign(step[last])
        h = c1 * (direction < 0).astype(float)
        if k.shape[0]:
            _, sides = stop_basis(y)(np.minimum(r, 1e300))
            h = h + (sides < 0).astype(float) @ (k * np.minimum(r, 1e300))
        out.append(np.asarray(h, dtype=float))
    return out


def _element_candidates(problem: PooledProblem, vals: dict[str, float]) -> list[Candidate]:
    """One element more, of a small stiffness, at each of a few thresholds."""
    spec = problem.spec
    if spec.density is not None:
        return []
    c1, k, r = spec.bank(vals)
    n = spec.n
    swing = max(float(np.ptp(rec.position)) for rec in problem.records) or 1.0
    wider = ModelSpec(n + 1, False, None, spec.cells)
    sib = _sibling(problem, wider)
    base = {"coulomb": c1}
    order = np.argsort(r)
    for j, idx in enumerate(order):
        base[f"stiffness_{j + 1}"] = float(k[idx])
        base[f"breakaway_{j + 1}"] = float(k[idx] * r[idx])
    k_small = STEP * max(float(np.sum(k)), spec.coulomb_level(vals) / swing)
    tries = np.geomspace(ELEMENT_RANGE[0] * swing, ELEMENT_RANGE[1] * swing, ELEMENT_TRIES)
    own = {x: vals[x] for x in problem.names if problem.record_of.get(x) is not None}
    shared: dict[str, float] = {x: vals[x] for x in ("mass", "offset", "viscous") if x in vals}
    rows = []
    for rn in [None, *tries]:
        q: dict[str, float] = {
            **shared,
            **own,
            **base,
            f"stiffness_{n + 1}": k_small if rn else 0.0,
            f"breakaway_{n + 1}": k_small * rn if rn else 0.0,
        }
        rows.append([q[x] for x in sib.names])
    res = sib.residuals(np.array(rows, dtype=float))
    out = []
    for rn, r1 in zip(tries, res[1:], strict=True):
        out.append(Candidate("elements", (r1 - res[0]) / k_small, _more_elements(float(rn))))
    return out


def pooled_adequacy(problem: Any, sol: Any) -> Adequacy | None:
    """The residual tests of a record-pooled fit's optimum, with the likely cause when they
    fail (`_adequacy`); `problem` the fit's `FitProblem`, `sol` its `Solution`."""
    rec: PooledProblem = problem.records
    x = np.array([sol.values[n] for n in problem.names], dtype=float)
    jac = problem.jacobian(x)
    jac = (jac.toarray() if hasattr(jac, "toarray") else np.asarray(jac))[: rec.n_res]
    keep = [j for j, n in enumerate(problem.names) if n not in problem.fixed]
    jac = np.where(np.isfinite(jac), jac, 0.0)[:, keep]
    cov = None if sol.covariance is None else np.asarray(sol.covariance)[np.ix_(keep, keep)]
    free = [problem.names[j] for j in keep]
    paths = position_sensitivity(problem, sol.values, free) if cov is not None and any(
        r.difference for r in rec.records) and rec.w_v and not rec.w_y else None  # fmt: skip
    blocks = residual_blocks(rec, sol.values, jac, cov, paths)
    if not blocks:
        return None
    blocks = [b for b in blocks if _measured(b, rec)]
    if not blocks:  # noise-free data: no noise model to judge the residual against
        return None
    result = assess(blocks, rec.n_rec)
    if result.passed:
        return result
    r = np.asarray(sol.residual, dtype=float)[: rec.n_res]
    found = candidates(rec, sol.values, r) if rec.names_causes else []
    return result.with_cause(score_causes(r, jac, found, floor_cost(rec, blocks)))


def position_sensitivity(problem: Any, values: Mapping[str, float],
                         free: list[str]) -> FloatArray | None:  # fmt: skip
    """∂y/∂θ (S, len(free)) of the simulated positions at `values` by central differences
    within the bounds: the path of a velocity compared through the difference quotient of
    a position that is not compared is that position's residual, whose share of the
    parameters' error, J_y·Δθ, the whiteness test allows for. One batched simulation; the
    records' own parameters move together (the j-th of every record in one set: each acts
    on its own record's rows alone), as in the fit's structured Jacobian."""
    from types import SimpleNamespace

    from presliding.identification.records._pooled_jacobian import difference_steps

    rec: PooledProblem = problem.records
    x = np.array([values[n] for n in free], dtype=float)
    lo = np.array([problem.bounds.get(n, (-np.inf, np.inf))[0] for n in free], dtype=float)
    hi = np.array([problem.bounds.get(n, (-np.inf, np.inf))[1] for n in free], dtype=float)
    typical = rec.typical(cast(Any, SimpleNamespace(free=free)))
    up, down = difference_steps(x, lo, hi, typical, True)
    owner = [rec.record_of.get(n) for n in free]
    group: list[int] = []  # the set each column moves in
    seen: Counter[int] = Counter()
    for i in owner:
        group.append(len(group) if i is None else -1 - seen[i])
        if i is not None:
            seen[i] += 1
    labels = sorted(set(group))
    base = np.array([values[n] for n in rec.names], dtype=float)
    sets = np.repeat(base[None], 2 * len(labels), axis=0)
    for j, n in enumerate(free):
        g = labels.index(group[j])
        sets[2 * g, rec.names.index(n)] += up[j]
        sets[2 * g + 1, rec.names.index(n)] -= down[j]
    o_y, _, status, _ = rec.simulate(sets)
    if np.any(status != 0):
        return None
    out = np.zeros((rec.t_all.shape[0], len(free)))
    for j, i in enumerate(owner):
        span = up[j] + down[j]
        if not span > 0:
            continue
        g = labels.index(group[j])
        rows = slice(None) if i is None else slice(int(rec.t_off[i]), int(rec.t_off[i + 1]))
        out[rows, j] = (o_y[2 * g, rows] - o_y[2 * g + 1, rows]) / span
    return out


def _more_elements(threshold: float) -> Callable[[float], str]:
    """The text naming too few elements, one more at `threshold` [its stiffness]."""
    return lambda e: (f"too few elements: one more element of threshold {threshold:.3g} "
                      f"(stiffness {e:.3g}) would take up the structure; fit more elements "
                      "(or `n_elements='auto'`)")  # fmt: skip
