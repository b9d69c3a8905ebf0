"""The probe along the scale of eq. 17: the mass and every force scaled together.

In a free motion (u = 0) eq. 17, m·ÿ + c1·sign(ẏ) + Σ k_j (y − x_j) = 0, is
unchanged when the mass, F_c, c1, σ and every stiffness (the element forces
k_j·(y − x_j); the thresholds r_j = c_j/k_j stay) are multiplied by one
factor s. Only the applied force fixes that scale, in the short forced part
of a stop. The pooled residual of stops is therefore nearly flat along the
scale, with a staircase of local minima on it: each record's own block
(initial position, velocity, preload fraction) compensates the wrong scale in
its forced part, and on a wrong scale its best block sits in another basin
than on the true one. A local solve from such a minimum does not leave it
(mass and forces 18–27 % low at a cost 19–21 % above the true valley's, a
residual the noise-floor rule cannot tell from the floor); neither does a
move of the shared parameters alone with the blocks kept, since the blocks
belong to the wrong scale. The search's solve stops there short of a minimum,
on a kink: the probe runs where that is so (`_probe_gate`).

`scale_probe` moves along the scale from the best optimum: the shared model
parameters multiplied by each factor of `SCALES` (up and down), every
record's block searched again globally for the scaled values (the nuisance
grid and its polish, `_nuisance_search`), a short solve of everything (judged
after `JUDGE` evaluations: one still above `REFINE_WITHIN` × the best's cost
ends there, the others are solved on from where the judge left them) and,
only when that short solve already went below the best (a step onto a lower
stair does: measured on the study's stops), the solve on to its optimum
(`_probes.other_valley`), the blocks searched once more for the shared values
it reached and solved again (the alternation of the search). A step that does
not lower the cost costs one nuisance search and one short solve (`JUDGE`
evaluations when it is not heading below the best). A
step that lowers the cost becomes the best and the probe steps on in the same
direction, since the staircase can take more than one step to its foot (each
step's solve moves little along the scale: it ends on the stair next to the
scaled start); a step after a move that does not lower the cost overshot, and
the step is halved in log, tried either way, while above `FINEST` (`ROUNDS`
rounds at most). A step whose solve slid back along the scale towards the
best it started from, by more than `RETURNED` of the step (in log of the
mass), ends the probe: the scale is then fixed by the descent itself, the foot
between the scaled start and the old best, not by a stair next to the start
(on the search study's 40 seeds and the 20-record benchmark, no step after
such a move lowered the cost; on the benchmark's first data set the step on
and the four halvings after it took half the probe's time). From the true
valley both first steps fail: two steps.

A record's own parameter that the nuisance search left on a bound of its range
(a preload fraction of ±1: memory saturated, a grid end) is held during the
step's solves (`on_bound`). A step that went below the best releases them: the
blocks searched again where its solve ended, then one solve of everything from
them (or from where it ended, when the search found nothing better); a step
that did not is dropped as it is. Released from where the held solve ended,
the 20-record benchmark's steps solved 173 and 226 evaluations on (a preload
held on its bound was not the record's best); from the blocks searched again,
8, at the same final cost. Near saturation a preload is often invisible in the record (its
column a 1e-4 of the others'), and the solver's column scaling then gives it a
step thousands of times its trust box: clipped there, every trial step moves the
preload by the box's 0.25 and raises the cost, the damping grows until the step
is negligible, and the solve ends `converged` where it began (5 kHz stops: the
step from mass 1.53 up to 1.91 ended so, 9 evaluations, 1 % above the true
valley, and the probe stopped with mass and forces 23 % low). Held, the step's
solve descends to mass 1.90 below the old best, the next step's slides back to
the foot at the true scale.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from functools import partial

import numpy as np

from presliding.identification.records._pooled_problem import PooledProblem
from presliding.identification.search._nuisance_search import search_nuisance
from presliding.identification.search._probes import other_valley
from presliding.identification.search._search import REFINE_WITHIN, SAME_OPTIMUM, cost
from presliding.identification.solve._least_squares import Solution

__all__ = [
    "FINEST",
    "JUDGE",
    "RETURNED",
    "ROUNDS",
    "SCALES",
    "on_bound",
    "scale_probe",
    "scaled",
    "scaled_names",
]

#: factors of one step along the scale, up first then down (symmetric in log)
SCALES = (1.25, 0.8)
#: rounds of steps along the scale at most (a move that lowers the cost is a round: the
#: staircase can take several to its foot; the halvings end at `FINEST`, two at most)
ROUNDS = 12
#: the finest step: a step that overshot is halved (in log) while above this factor
FINEST = 1.05
#: evaluations after which a step's short solve is judged: one still above `REFINE_WITHIN`
#: × the best's cost is not heading below it and ends there (measured on the study's stops:
#: the steps that went below the best were within 4 % of it after 10 evaluations, the
#: rejected ones 44–127 % above it)
JUDGE = 10
#: a step whose solve came back towards the best by more than this share of the step (in
#: log of the mass) found the foot between them: the probe ends there (module notes)
RETURNED = 0.5


def scaled_names(problem: PooledProblem, fixed: Mapping[str, float],
                 tied: Mapping[str, object] | None = None) -> list[str]:  # fmt: skip
    """The parameters eq. 17's scale moves: the mass, σ and the discrete model's forces and
    stiffnesses. Empty when one of them is fixed or tied (the scale is then pinned) or the
    model is a density (its parameters mix forces and thresholds)."""
    spec = problem.spec
    if spec.density is not None or "mass" not in problem.shared:
        return []
    names = ["mass", *spec.names, *(["viscous"] if "viscous" in problem.shared else [])]
    if any(x in fixed or x in (tied or {}) for x in names):
        return []
    return names


def scaled(values: Mapping[str, float], names: Sequence[str], factor: float) -> dict[str, float]:
    """`values` with the parameters `names` multiplied by `factor`."""
    out = dict(values)
    for x in names:
        out[x] = factor * values[x]
    return out


def _inside(values: Mapping[str, float], bounds: Mapping[str, tuple[float, float]]) -> bool:
    for x, v in values.items():
        lo, hi = bounds.get(x, (-float("inf"), float("inf")))
        if not lo <= v <= hi:
            return False
    return True


def _step(
    problem: PooledProblem,
    solve: Callable[..., Solution],
    best: Solution,
    names: Sequence[str],
    factor: float,
    fixed: Mapping[str, float],
    bounds: Mapping[str, tuple[float, float]],
    budget: int,
    tied: Mapping[str, object] | None = None,
) -> tuple[Solution | None, int]:
    """One step along the scale (module notes); None when it leaves the bounds."""
    begin = scaled(best.values, names, factor)
    if not _inside({x: begin[x] for x in names}, bounds):
        return None, 0
    values, _, spent = search_nuisance(problem, begin, fixed, bounds)
    held = on_bound(problem, values, {**fixed, **(tied or {})}, bounds)  # (module notes)
    step_solve = partial(solve, extra=held) if held else solve
    t = step_solve(values, max_evaluations=min(JUDGE, budget))  # judged early (module notes)
    if t.status == "max_evaluations" and budget > JUDGE:
        if not cost(t) < REFINE_WITHIN * cost(best):
            return t, spent
        t = step_solve(t.values, max_evaluations=budget - JUDGE)  # heading below: solved on
    t = other_valley(problem, step_solve, t, best, within=1.0)
    if t.status == "failed" or not cost(t) < cost(best):
        return t, spent
    if t.status == "max_evaluations" and not held:  # below the best: never kept on its cap
        t = solve(t.values)
    again, c, ev = search_nuisance(problem, t.values, fixed, bounds)
    spent += ev
    if held:  # released: every parameter free, from the blocks searched again when better
        return solve(again if c < cost(t) else t.values), spent
    if c < cost(t) * (1.0 - SAME_OPTIMUM):
        other = solve(again)
        t = other if cost(other) < cost(t) else t
    return t, spent


def on_bound(problem: PooledProblem, values: Mapping[str, float], held: Mapping[str, object],
             bounds: Mapping[str, tuple[float, float]]) -> dict[str, float]:  # fmt: skip
    """The records' own parameters (not in `held`: fixed or tied) that sit on a bound of
    their range in `values`, a preload fraction of ±1 (memory saturated): held during a
    step's solve (module notes)."""
    out = {}
    for x in problem.names:
        if problem.record_of[x] is None or x in held:
            continue
        lo, hi = bounds.get(x, (-float("inf"), float("inf")))
        if not lo < values[x] < hi:
            out[x] = values[x]
    return out


def _returned(best: Solution, moved: Solution, factor: float) -> bool:
    """Whether a step's solve came back towards `best` by more than `RETURNED` of the step
    (in log of the mass): the solve slid down along the scale to the foot between the
    scaled start and the best (module notes)."""
    travel = np.log(moved.values["mass"] / best.values["mass"]) / np.log(factor)
    return bool(travel < 1.0 - RETURNED)


def scale_probe(
    problem: PooledProblem,
    solve: Callable[..., Solution],
    best: Solution,
    names: Sequence[str],
    fixed: Mapping[str, float],
    bounds: Mapping[str, tuple[float, float]],
    budget: int,
    scales: Sequence[float] = SCALES,
    rounds: int = ROUNDS,
    tied: Mapping[str, object] | None = None,
) -> tuple[Solution, list[Solution], int]:
    """Steps along eq. 17's scale from `best` (module notes): the best of all, every
    step's solution and the residual evaluations of the nuisance searches."""
    steps: list[Solution] = []
    spent = 0
    directions, factor = list(scales), None
    for _ in range(rounds):
        improved: tuple[Solution, float] | None = None
        for f in directions:
            t, ev = _step(problem, solve, best, names, f, fixed, bounds, budget, tied=tied)
            spent += ev
            if t is None:
                continue
            steps.append(t)
            if cost(t) < cost(best) * (1.0 - SAME_OPTIMUM):
                improved = (t, f)
                break
        if improved is not None:
            settled = _returned(best, *improved)
            best, factor = improved
            if settled:
                break  # the solve slid back to the foot between the start and the best
            directions = [factor]
            continue
        if factor is None or abs(np.log(factor)) < 2 * np.log(FINEST):
            break  # no step lowered the cost, or the step cannot be halved again
        factor = float(np.sqrt(factor))  # overshot: half the step (in log), either way
        directions = [factor, 1.0 / factor]
    return best, steps, spent
