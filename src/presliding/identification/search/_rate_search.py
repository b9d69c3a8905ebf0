"""The search of a rate-dependent family's fit (GMS, LuGre, Dahl): the PI fit, then a grid.

The rate families nest the PI model (GMS exactly; LuGre and Dahl through their
presliding stiffness and F_C), and their rate parameters (the Stribeck drop and speed,
the lag, the bristle stiffness) are what a local solve does not find: started with a
Stribeck curve in the wrong place, it turns the curve off (v_s → 0 or the drop → 0) and
stays there. So the search

1. fits the PI model to the same records with the same options (`fit_response`'s own
   search: the element structure, the records' own starts), unless the caller holds the
   elements' shape or turned the multistart off — then the problem's regression start
   stands in;
2. makes the family's base from it: its mass, σ, offset and every record's own start;
   GMS its c1 and elements, LuGre and Dahl F_C and a bristle stiffness σ0 = F_C/y½ from
   the travel y½ in which the elastic part of the PI virgin curve reaches F_m/2;
3. scores a grid of the rate parameters around that base — v_s over the records' speed,
   the drop as a share of F_C with F_C lowered by none, half or all of it, the lag
   (GMS), σ0 (LuGre, Dahl) — every candidate in one batched compiled call;
4. runs the adaptive multistart of `_search` from the best candidate, with the next two
   as its further starts (made only while the fit stays above the noise floor); values
   the caller gives in ``initial`` make the first start (on the base, clipped to the
   bounds), the grid's two best the further ones (they were overwritten by the PI fit's
   and the grid's values before: a start from the truth was not one).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np

from presliding.identification.problem._family_spec import FamilySpec
from presliding.identification.problem._model_spec import ModelSpec
from presliding.identification.search._search import adaptive_search

__all__ = ["base_values", "rate_search", "sample_interval", "typical_speed"]

#: the grid: v_s over the records' typical speed, the drop over F_C, the share of the drop
#: taken off F_C, the lag over the sample interval (GMS), σ0 over its base (LuGre, Dahl)
SPEEDS = (0.1, 0.25, 0.5, 1.0)
DROPS = (0.1, 0.3, 0.6)
LOWERED = (0.0, 0.5, 1.0)
LAGS = (0.0, 3.0)
STIFFNESSES = (1.0, 3.0)
DAHL_STIFFNESSES = (0.3, 1.0, 3.0, 10.0)
#: the further starts after the best candidate
FURTHER = 2


def typical_speed(recs: list[Any]) -> float:
    """The median of the records' largest speeds (m/s): the scale the Stribeck curve falls on."""
    top = [float(np.max(np.abs(r.velocity))) for r in recs]
    return float(np.median(top)) if max(top) > 0 else 1.0


def sample_interval(recs: list[Any]) -> float:
    """The median sample interval of the records (s)."""
    return float(np.median(np.concatenate([np.diff(r.time) for r in recs])))


def bristle_stiffness(pi_spec: ModelSpec, values: dict[str, float]) -> float:
    """σ0 = F_C/y½: y½ the travel in which the elastic part of the PI model's virgin curve
    reaches half its F_m (the Coulomb element, rigid, left out: a c1 above F_C/2 would put
    y½ at 0); Σ k_j where the elements carry nothing."""
    fc = pi_spec.coulomb_level(values)
    _, k, r = pi_spec.bank(values)
    fm = float(k @ np.minimum(r, 1e300)) if k.size else 0.0
    if not (k.size and fm > 0 and np.isfinite(fm)):
        return max(float(np.sum(k)), 1.0)
    travel = np.sort(np.concatenate([[0.0], r]))
    virgin = np.array([float(np.minimum(x, r) @ k) for x in travel])
    half = float(np.interp(0.5 * fm, virgin, travel))
    return fc / half if half > 0 else float(np.sum(k))


def base_values(spec: FamilySpec, start: dict[str, float], pi: dict[str, float],
          pi_spec: ModelSpec, free: set[str]) -> dict[str, float]:  # fmt: skip
    """The family's values from the PI fit `pi` where they are free (module notes, 2)."""
    out = dict(start)
    shared = {"mass", "viscous", "offset"} | {x for x in pi if x.startswith(
        ("initial_position", "initial_velocity", "preload_fraction"))}  # fmt: skip
    if spec.family == "gms":
        shared |= set(pi_spec.names)
    else:
        sigma0 = bristle_stiffness(pi_spec, pi)
        fc = pi_spec.coulomb_level(pi)
        pi = {**pi, "coulomb": fc, "stiffness": sigma0}
        shared |= {"coulomb", "stiffness"}
        if spec.family == "lugre":
            pi["damping"] = 0.1 * float(np.sqrt(sigma0 * pi["mass"]))
            shared.add("damping")
    out.update({x: float(pi[x]) for x in shared if x in free and x in pi and x in out})
    return out


def _candidates(spec: FamilySpec, base: dict[str, float], free: set[str], speed: float,
                dt: float) -> list[dict[str, float]]:  # fmt: skip
    """The grid of the rate parameters around `base` (module notes, 3)."""
    fc = spec.coulomb_level(base)
    out = []
    if spec.family == "dahl":
        for s0, low in itertools.product(DAHL_STIFFNESSES, (0.0, 0.1)):
            out.append({**base, "stiffness": base["stiffness"] * s0, "coulomb": fc * (1 - low)})
        return out
    tail = LAGS if spec.family == "gms" else STIFFNESSES
    for vs, drop, low, other in itertools.product(SPEEDS, DROPS, LOWERED, tail):
        cand = dict(base)
        cand["stribeck_velocity"] = vs * speed
        cand["stribeck_drop"] = drop * fc
        level = fc - low * drop * fc
        if spec.family == "gms":
            cand["lag_time"] = other * dt
            factor = level / fc  # c1 and the break-away forces with F_C
            cand["coulomb"] = base["coulomb"] * factor
            for x in ("coulomb_level", *spec.c_names):
                if x in cand:
                    cand[x] = base[x] * factor
        else:
            cand["coulomb"] = level
            cand["stiffness"] = base["stiffness"] * other
        out.append(cand)
    return [{x: (c[x] if x in free else base[x]) for x in base} for c in out]


def _pi_values(req: Any, spec: FamilySpec, run: Any, pi_fit: Callable[..., Any],
               pi_spec: ModelSpec) -> dict[str, float] | None:  # fmt: skip
    """The PI model's fit of the same records (module notes, 1), or None."""
    p = run.problem
    held = set(p.fixed) | set(p.tied)
    shaped = spec.family == "gms" and bool((set(pi_spec.names) - {"coulomb_level"}) & held)
    if not req.multistart or shaped:
        return None
    run.stage("search: the PI model's fit, the base of the family's start")
    own = {x: v for x, v in req.fixed.items() if x in ("mass", "offset", "viscous")}
    fit = pi_fit(
        req.records, n_elements=pi_spec.n, equal_breakaway=pi_spec.equal, signal=req.signal,
        velocity=req.velocity, weights=req.weights, initial_state=req.initial_state,
        fit_initial=req.fit_initial, viscous=req.viscous, offset=req.offset, fixed=own,
        level=req.level, tolerance=req.tolerance,
    )  # fmt: skip
    run.evaluations += fit.n_evaluations
    return None if fit.status == "failed" else dict(fit.parameters)


def rate_search(req: Any, spec: FamilySpec, pi_fit: Callable[..., Any],
                run: Any) -> tuple[Any, int, int, int]:  # fmt: skip
    """The search (module notes); returns (solution, starts, starts at the best, evaluations
    of the nuisance searches)."""
    p = run.problem
    rec = p.records
    free = {x for x in p.names if x not in p.fixed and x not in p.tied}
    pi_spec = spec.pi if spec.family == "gms" else ModelSpec(2, True, None, spec.cells)
    pi = _pi_values(req, spec, run, pi_fit, pi_spec)
    base = dict(p.initial) if pi is None else base_values(spec, dict(p.initial), pi, pi_spec, free)
    grid = _candidates(spec, base, free, typical_speed(req.recs), sample_interval(req.recs))
    grid = [{x: float(np.clip(c[x], *p.bounds[x])) for x in p.names} for c in grid]
    run.stage(f"search: {len(grid)} candidates of the rate parameters, one batched call")
    res = rec.residuals(np.array([[c[x] for x in p.names] for c in grid]))
    costs = np.sum(res * res, axis=1)
    costs[~np.isfinite(costs)] = np.inf
    order = [int(i) for i in np.argsort(costs, kind="stable")]
    run.evaluations += len(grid)
    starts = [grid[i] for i in order[: 1 + FURTHER]]
    if req.initial:  # the caller's start is the first, the grid's best the further ones
        own = {**base, **{x: float(v) for x, v in req.initial.items() if x in free}}
        starts = [{x: float(np.clip(own[x], *p.bounds[x])) for x in p.names}, *starts]

    def further() -> Iterator[tuple[dict[str, float], int]]:
        for start in starts[1 : 1 + FURTHER]:
            yield start, 0

    short = min(run.options.max_evaluations or 40, 12 + 2 * len(rec.shared))
    sol, n_starts, at_best, count = adaptive_search(rec, run.solve, starts[0], further,
                                                    p.fixed, p.bounds, short)  # fmt: skip
    return sol, n_starts, at_best, count
