"""Probes of the neighbouring valleys after a search: moves from the best optimum.

The pooled residual of stops and loops has valleys next to the best one that
the starts need not reach (the shared parameters all start from one
regression start and its spread and global variants). Each probe is a start
made from the best optimum by one move, solved from there; the best of all is
kept, and every optimum a probe reaches is kept on the run, so that another
valley within the profile's threshold is reported (`_alternatives`).

The moves (elements of equal break-away force, stiffnesses ``k_names``):

* `engage_starts`: an element that carries almost no stiffness
  (k_j < `DEAD` × the largest) never engaged; F_c then sits where the
  engaged elements saturate, above the true level. The start re-engages it:
  k_j set to the median of the others and F_c lowered so that the force the
  engaged elements carried at saturation stays, c1 + (n − 1)·c, with
  c = (F_c − c1)/n. A second start keeps F_c. From the rigid corner (the
  stiffest element `CORNER` times the next) the corner element starts at
  `CORNER` times the next one: kept at k_1 ~ 1e15, the re-engaged starts let c1
  fall to 0 beside the near-rigid element, whose response then rings at MHz
  after each stop (~6e5 reversals per record and evaluation; 130 s of a
  300-sample fit).
* `corner_starts`: the rigid corner, the stiffest element more than `CORNER`
  times the next one (its break-away force joins c1): k_1 reduced to twice
  the next element's.
* `merge_starts`: the elements coalesced, which a model with more elements than
  the data need contains exactly (elements of one threshold act as one). A
  search can end instead in a valley where surplus elements hold break-away
  force at thresholds the records never reach (k → 0, or springs beyond the
  largest swing), while the elements that slide share what is left: F_c then
  counts force that never acts. The starts give every element the total
  stiffness's share, K/n (one threshold: the stiffness the records see at
  small amplitude kept), once with F_c kept (the force of all the elements
  sliding together kept) and once with F_c lowered to the reachable level;
  and, where the m < n elements that slide divide n, each of them
  split into n/m copies of its threshold (F_c lowered to c1 and their share).
* `split_starts`: the element split, the least determined direction: a
  tenth of the smaller stiffness moved between neighbouring elements, both
  ways (`SPLIT_SHARES`).

`solve_probes` solves them: with a budget, a probe whose short solve ended
within `REFINE_WITHIN` of the best's cost in another basin is solved on to
its own optimum (`other_valley`, the move of the quasi-static starts too);
a probe that only moves the split, close to the best already, is solved on
only when its short solve already went below the best (``within=1``). A
probe whose capped solve ended below the best in the same basin is solved on
too: the best is never a solve stopped on its cap (with a light stage's fine
encoder the main solve can stop on its step test a few 1e-4 of the cost above
the optimum that a probe then reaches, capped, in the same basin).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from presliding.identification.search._search import REFINE_WITHIN, TIE, cost, same_point
from presliding.identification.solve._least_squares import Solution

__all__ = [
    "CORNER",
    "DEAD",
    "SPLIT_SHARES",
    "corner_starts",
    "engage_starts",
    "merge_starts",
    "other_valley",
    "solve_probes",
    "split_starts",
]

#: share of the smaller stiffness moved between neighbouring elements by the split probes
SPLIT_SHARES = (0.1, -0.1)
#: an element whose stiffness is below this share of the largest never engaged
DEAD = 0.01
#: the stiffest element this many times the next one: the rigid corner
CORNER = 20.0


def split_starts(values: Mapping[str, float], k_names: Sequence[str],
                 shares: Sequence[float] = SPLIT_SHARES) -> list[dict[str, float]]:  # fmt: skip
    """A share of the smaller stiffness moved between neighbouring elements, each way."""
    starts = []
    for a, b in itertools.pairwise(k_names):
        for share in shares:
            begin = dict(values)
            move = share * min(begin[a], begin[b])
            begin[a], begin[b] = begin[a] - move, begin[b] + move
            starts.append(begin)
    return starts


def engage_starts(values: Mapping[str, float], k_names: Sequence[str]) -> list[dict[str, float]]:
    """Starts with an element that never engaged re-engaged (module notes)."""
    k = [values[x] for x in k_names]
    n, largest = len(k), max(k, default=0.0)
    if n < 2 or not largest > 0 or "coulomb_level" not in values:
        return []
    ranked = sorted(k, reverse=True)
    cap = np.inf
    if ranked[1] > 0 and ranked[0] / ranked[1] >= CORNER:  # the rigid corner (`corner_starts`):
        cap = CORNER * ranked[1]  # its element starts at CORNER × the next one
    starts = []
    for j, x in enumerate(k_names):
        if k[j] >= DEAD * largest:
            continue
        engaged = {**values, **{y: min(values[y], cap) for y in k_names}}
        engaged[x] = float(np.median([min(k[i], cap) for i in range(n) if i != j]))
        c1, fc = values["coulomb"], values["coulomb_level"]
        lowered = {**engaged, "coulomb_level": c1 + (n - 1) / n * (fc - c1)}
        starts += [lowered, engaged]
    return starts


def corner_starts(values: Mapping[str, float], k_names: Sequence[str]) -> list[dict[str, float]]:
    """The stiffest element reduced to twice the next one's stiffness (the rigid corner)."""
    ranked = sorted(((values[x], x) for x in k_names), reverse=True)
    if len(ranked) < 2 or not ranked[1][0] > 0 or ranked[0][0] / ranked[1][0] < CORNER:
        return []
    return [{**values, ranked[0][1]: 2.0 * ranked[1][0]}]


def merge_starts(values: Mapping[str, float], k_names: Sequence[str], live: Sequence[int],
                 reachable: float) -> list[dict[str, float]]:  # fmt: skip
    """Starts with the elements coalesced (module notes); `live` the indices of the elements
    that slide in the data, `reachable` the F_c they and c1 reach."""
    k = np.array([values[x] for x in k_names], dtype=float)
    n, total = k.size, float(np.sum(k))
    if n < 2 or not total > 0 or "coulomb_level" not in values:
        return []
    one = {**values, **{x: total / n for x in k_names}}
    starts = [one]
    if values["coulomb"] < reachable < values["coulomb_level"]:
        starts.append({**one, "coulomb_level": float(reachable)})
    m = len(live)
    if 1 < m < n and n % m == 0:
        copies = np.repeat(k[list(live)] * m / n, n // m)  # each threshold kept: F_c lowered
        c1, fc = values["coulomb"], values["coulomb_level"]
        starts.append({**values, **{x: float(c) for x, c in zip(k_names, copies, strict=True)},
                       "coulomb_level": c1 + m / n * (fc - c1)})  # fmt: skip
    return starts


def other_valley(problem, solve: Callable[..., Solution], t: Solution, sol: Solution,
                 within: float = REFINE_WITHIN) -> Solution:  # fmt: skip
    """A short solve that ended within `within` × the best's cost in another basin, solved
    on to its own optimum (a second valley the intervals must not hide, `_alternatives`)."""
    near = np.isfinite(cost(t)) and cost(t) <= within * cost(sol)
    if t.status != "max_evaluations" or not near or same_point(problem, t.values, sol.values):
        return t
    return solve(t.values)


def solve_probes(
    problem,
    solve: Callable[..., Solution],
    starts: Sequence[dict[str, float]],
    best: Solution,
    budget: int | None = None,
    within: float = REFINE_WITHIN,
) -> tuple[Solution, list[Solution]]:
    """Each start solved (within `budget` evaluations, then on when its cost ended within
    `within` × the best's, `other_valley`); the best of all, and the probes' solutions."""
    probes = []
    for begin in starts:
        t = solve(begin) if budget is None else solve(begin, max_evaluations=budget)
        if budget is not None:
            t = other_valley(problem, solve, t, best, within)
            if t.status == "max_evaluations" and cost(t) < cost(best) * (1.0 - TIE):
                t = solve(t.values)  # a capped probe below the best: solved on to its optimum
        probes.append(t)
        if cost(t) < cost(best) * (1.0 - TIE):
            best = t
    return best, probes
