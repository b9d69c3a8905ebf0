"""Checks after an output-error fit (`fit_response`): starts, polish, flags.

`rigid_check` refits with the stiffest element rigid and reports
"not_identifiable" when the data cannot tell the two fits apart;
`bound_check` reports "at_bound" when a parameter sits on its lower bound;
`stiffest_first` and `smallest_threshold_first` relabel interchangeable elements; `spread_start` and
`polish_initial_velocity` give the search a second start and a start from rest.
"""

from __future__ import annotations

import itertools
from dataclasses import replace
from typing import Any

import numpy as np

from presliding.identification.solve._least_squares import Solution, complete

_BOUND = 1e-8  # a parameter below this fraction of its scale sits on its bound 0
#: a rigid refit whose cost after `judge`'s evaluations is this many times t²·s² above the
#: fit's is not refitted further (`rigid_check`; on the pooled stops the rest of a 30-evaluation
#: refit lowered that excess by about 1 % of it)
CLEAR = 4.0
_NUISANCE = ("initial_velocity", "initial_position", "preload_fraction")


def cost(sol: Solution) -> float:
    """Sum of squared residuals (inf for a failed fit)."""
    return float(sol.residual @ sol.residual) if sol.status != "failed" else np.inf


def polish_initial_velocity(sol, solve, fixed, tied, v) -> Solution:
    """Refit with the initial velocity on its bound 0 when it ends next to it.

    Near an active bound the trust region shrinks the steps of that parameter
    and the fit stops early; a start from rest is common, so it is tried exactly
    and kept when it fits at least as well.
    """
    x = "initial_velocity"
    snapped = x in sol.at_bounds  # left on the bound by the solver: polish all the same
    if x in fixed or x in tied or sol.status == "failed" or (sol.values[x] == 0.0 and not snapped):
        return sol
    if abs(sol.values[x]) > 1e-6 * float(np.max(np.abs(v))):
        return sol
    alt = solve(sol.values, extra={x: 0.0})
    rounding = 1e-20 * v.size * float(np.max(v * v))  # costs equal to rounding: keep the bound
    return alt if cost(alt) <= cost(sol) + rounding else sol


def split_coalesced(sol: Solution, solve, k_names: list[str], ratio: float = 1.1) -> Solution:
    """Refit from a split start when two elements of equal break-away force coalesced.

    Interchangeable elements with (nearly) equal stiffnesses sit on the
    symmetric saddle, where the Jacobian cannot tell them apart; a start with
    the pair spread by 1.7 each way breaks the symmetry. Kept if it fits better.
    Where the pair is still coalesced after it (the symmetric point is the
    optimum, not a saddle: short records whose swings hardly cross the two
    thresholds), `coalesced_split` says so, after the fit's other checks.
    """
    if sol.status == "failed" or len(k_names) < 2:
        return sol
    ranked = sorted(((sol.values[x], x) for x in k_names), reverse=True)
    for (ka, xa), (kb, xb) in itertools.pairwise(ranked):
        if kb > 0 and ka / kb < ratio:
            start = {**sol.values, xa: 1.7 * ka, xb: kb / 1.7}
            alt = solve(start)
            return alt if cost(alt) < cost(sol) else sol
    return sol


#: two stiffnesses of equal break-away force within this relative difference: one point
#: of the symmetric pair (the solver's resolution on that flat direction)
COALESCED = 1e-3
#: the split d = (k_a − k_b)/2 tried, as shares of S/2 (S = k_a + k_b), until the cost rises
#: beyond the likelihood-ratio threshold (`coalesced_split`)
SPLIT_STEPS = (0.1, 0.2, 0.3, 0.4, 0.55, 0.7, 0.85, 1.0)


def coalesced_split(sol: Solution, solve, k_names: list[str], level: float = 0.95) -> Solution:
    """The split of two coalesced elements of equal break-away force, made honest.

    Why. With equal break-away forces c = (F_c − c1)/N, two elements of equal
    stiffness have the same threshold r = c/k (eq. 6): their columns of the
    Jacobian are the same, to first order, along the split k_a − k_b at fixed
    sum. The cost there is not a quadratic of the split (it rises through the
    kink where one of the two starts to slide first), so the linearised errors
    of the pair describe nothing: on 300-sample stops they came out ±21 N/m for
    a pair fitted at 1486/1486 whose truth is 2000/1000 (z of 24, a wrong
    ``converged``), while the same point reached from the truth gave |ρ| = 1.

    The check, for an optimum whose pair agrees to `COALESCED` (after the split
    refit came back to it): the split d = (k_a − k_b)/2 held at shares
    `SPLIT_STEPS` of S/2 with the sum S held and every other free parameter
    refitted, until the cost rises above t²·s² (the profile's likelihood-ratio
    bound of `rigid_check`). The pair's standard errors are infinite (no curvature
    describes the kink), its intervals span the split the data allow (stiffer
    element [S/2, S/2 + d], the softer [S/2 − d, S/2], the first d that rose
    above the bound; S/2 each way where none did), and the fit is
    ``not_identifiable``: the records determine the pair's sum, and a model with
    one element fewer describes them as well (rule ``profile`` of `_status`).
    """
    from scipy import stats

    if sol.status not in ("converged", "not_identifiable", "at_bound"):
        return sol
    v = sol.values
    ranked = sorted(((v[x], x) for x in k_names if x in sol.free), reverse=True)
    pair = next(((a, b) for a, b in itertools.pairwise(ranked)
                 if b[0] > 0 and a[0] - b[0] <= COALESCED * a[0]), None)  # fmt: skip
    dof = sol.residual.shape[0] - len(sol.free)
    c0 = cost(sol)
    if pair is None or dof < 1 or not np.isfinite(c0) or not c0 > 0:
        return sol
    (ka, xa), (kb, xb) = pair
    half = 0.5 * (ka + kb)
    limit = float(stats.t.ppf(0.5 + level / 2, dof)) ** 2 * c0 / dof
    reach = half
    for share in SPLIT_STEPS:
        d = share * half
        held = {xa: half + d, xb: half - d}
        alt = solve({**v, **held}, extra=held, errors=False)
        rise = cost(alt) - c0
        if rise > limit:
            reach = d
            break
    se = {**sol.standard_error, xa: np.inf, xb: np.inf}
    ci = dict(sol.confidence_interval)
    (lo_a, hi_a), (lo_b, hi_b) = ci[xa], ci[xb]  # the pair is interchangeable: both ends
    ci[xa] = (min(lo_a, lo_b, half), max(hi_a, hi_b, half + reach))
    ci[xb] = (min(lo_a, lo_b, half - reach), max(hi_a, hi_b, half))
    cov = sol.covariance
    if cov is not None:  # an undetermined parameter's variance is infinite
        cov, names = np.array(cov, dtype=float), list(v)
        for x in (xa, xb):
            cov[names.index(x), names.index(x)] = np.inf
    bound = (
        f"rises above t²·s² only at a split of ±{reach:.4g}"
        if reach < half
        else "stays within t²·s² for every split up to one element of stiffness 0"
    )
    first, second = sorted((xa, xb), key=k_names.index)  # the labels may be put in order
    message = (
        f"the data do not determine the split of {first} and {second}: the two coalesced "
        f"(both {half:.6g}; elements of equal break-away force and equal stiffness act as "
        f"one), their sum {ka + kb:.6g} is determined; with the sum held the cost "
        f"{bound}, so a model with one element fewer describes the records as well; the "
        "intervals span that split"
    )
    old = sol.message if sol.status == "not_identifiable" else ""
    return replace(sol, status="not_identifiable", standard_error=se, confidence_interval=ci,
                   covariance=cov, message="; ".join(x for x in (message, old) if x))  # fmt: skip


def escape_corner(sol: Solution, solve, k_names: list[str], ratio: float = 20.0) -> Solution:
    """Refit from the spread start when the stiffest element went (almost) rigid.

    The rigid corner (k_1 → ∞, its break-away force joining c1) is a local
    minimum that a start can fall into although the data hold a better fit with
    c1 and k_1 separate; a start moved off the corner (`spread_start` of the
    solution) finds that one when it exists. Kept only if it fits better.
    """
    if sol.status == "failed" or len(k_names) < 2 or "coulomb_level" not in sol.values:
        return sol
    k = sorted((sol.values[x] for x in k_names), reverse=True)
    if not k[1] > 0 or k[0] / k[1] < ratio:
        return sol
    alt = solve(spread_start(sol.values, k_names))
    return alt if cost(alt) < cost(sol) else sol


#: the stiffnesses of the restarts from the Coulomb corner, as shares of the corner's
COULOMB_RESTARTS = (0.1, 0.01)


def escape_coulomb(sol: Solution, solve, k_names: list[str]) -> Solution:
    """Refit from starts off the Coulomb corner when the elements carry no force.

    With c1 at or above F_c the elements of equal break-away force carry nothing:
    the residual does not depend on their stiffnesses, no gradient leads back, and the
    fit stays a Coulomb-friction fit at 2 × the noise floor (5 kHz stops: a regression
    start 16 times too stiff, every threshold below the records' swings, slid into it).
    The restarts: `spread_start` of the corner (c1/F_c at most 3/5) with every stiffness
    scaled by `COULOMB_RESTARTS` (thresholds 10 and 100 times wider). The best is kept.
    """
    v = sol.values
    if sol.status == "failed" or len(k_names) < 1 or "coulomb_level" not in v:
        return sol
    if v["coulomb"] < v["coulomb_level"]:
        return sol
    best, level = sol, v["coulomb"]  # the model's F_c: the parameter F_c lies below it
    for share in COULOMB_RESTARTS:
        moved = {**v, "coulomb_level": level, **{x: share * v[x] for x in k_names}}
        alt = solve(spread_start(moved, k_names))
        if cost(alt) < cost(best):
            best = alt
    return best


def spread_start(start: dict[str, float], k_names: list[str]) -> dict[str, float]:
    """The regression start moved off the rigid corner: c1/F_c in [1/4, 3/5], k_1 ≤ 2·k_2."""
    s = dict(start)
    fc = s["coulomb_level"]
    s["coulomb"] = fc * min(max(s["coulomb"] / fc, 0.25), 0.6)
    k = sorted((s[x] for x in k_names), reverse=True)
    if len(k) > 1:
        k[0] = min(k[0], 2.0 * k[1])
    s.update(zip(k_names, k, strict=True))
    return s


def rigid_check(
    sol, solve, problem, names, fixed, tied, level, refine=None, retried=False, judge=None
) -> Solution:
    """Refit with the smallest-threshold element rigid; flag it if that fits as well.

    `refine` (a solver without an evaluation cap), when given, carries a
    rigid refit that already fits as well on to convergence, so that the
    intervals span both fits in full. When the rigid refit fits clearly
    better, the fit was a local minimum: it is refitted from there (once).
    `judge` (a solver of fewer evaluations than `solve`), when given, refits first:
    a refit whose cost after it is still `CLEAR` × t²·s² above the fit's keeps the
    fit as it is (the rest of a capped refit lowers it by a small part of that);
    otherwise the refit is made with `solve` from the same start.
    """
    from scipy import stats

    values = dict(sol.values)
    if not problem.equal:  # put the smallest threshold first
        r = [values[c] / values[k] for k, c in zip(problem.k_names, problem.c_names, strict=True)]
        j = int(np.argmin(r))
        for a, b in ((problem.k_names[0], problem.k_names[j]),
                     (problem.c_names[0], problem.c_names[j])):  # fmt: skip
            values[a], values[b] = values[b], values[a]
    extra = {"stiffness_1": values["stiffness_1"]}
    if not problem.equal:
        extra["breakaway_1"] = values["breakaway_1"]
    cost_free = cost(sol)
    dof = sol.residual.shape[0] - (len(names) - len(fixed) - len(tied))
    if dof < 1:
        return sol
    s2 = cost_free / dof
    q2 = float(stats.t.ppf(0.5 + level / 2, dof)) ** 2
    if judge is not None and not retried:  # a refit far above after a few evaluations
        first = judge(values, rigid=True, extra=extra)
        if cost(first) - cost_free > CLEAR * q2 * s2:  # the same when it converged
            return sol
    alt = solve(values, rigid=True, extra=extra)
    cost_rigid = cost(alt)
    if not np.isfinite(cost_rigid):
        return sol
    excess = (cost_rigid - cost_free) / s2 if s2 > 0 else np.inf
    if excess <= q2 and refine is not None:
        alt = refine(alt.values, rigid=True, extra=extra)
        cost_rigid = cost(alt)
        excess = (cost_rigid - cost_free) / s2 if s2 > 0 else np.inf
    if excess < -q2 and not retried:  # the rigid limit fits better: a local minimum
        stiff = 100.0 * max(alt.values[x] for x in problem.k_names[1:]) if len(
            problem.k_names) > 1 else 100.0 * alt.values["stiffness_1"]  # fmt: skip
        free = (refine or solve)({**alt.values, "stiffness_1": stiff})  # near the rigid fit
        if cost(free) < cost_free:
            return rigid_check(free, solve, problem, names, fixed, tied, level, refine, True)
    if excess > q2:
        return sol
    alt = complete(alt)  # a refit's covariance deferred by `solve`, computed now
    ci = dict(sol.confidence_interval)
    for x in names:
        if x in alt.confidence_interval and x not in extra and x not in fixed:
            (a, b), (c, d) = ci[x], alt.confidence_interval[x]
            ci[x] = (min(a, c, alt.values[x]), max(b, d, alt.values[x]))
    ci["stiffness_1"] = (ci["stiffness_1"][0], np.inf)
    se = {**sol.standard_error, "stiffness_1": np.inf}
    message = (
        "the data do not separate the Coulomb element from the stiffest element: with that "
        f"element rigid (k → ∞, coulomb = {alt.values['coulomb']:.6g}) the cost rises by only "
        f"{excess:.3g}·s² ≤ t² = {q2:.3g} (profile bound at {100 * level:g} %); the intervals "
        "span both fits"
    )
    return replace(sol, status="not_identifiable", message=message, confidence_interval=ci,
                   standard_error=se)  # fmt: skip


def bound_check(sol, start, names, fixed, tied, equal_breakaway) -> Solution:
    """Status "at_bound" when a model parameter sits on its lower bound 0."""
    if sol.status not in ("converged", "not_identifiable"):
        return sol
    free = [x for x in names if x not in fixed and x not in tied]
    val = sol.values
    k_max = max([val[x] for x in names if x.startswith("stiffness_")], default=0.0)
    c_max = max([val[x] for x in names if x.startswith("breakaway_")], default=0.0)
    scale = {
        "mass": abs(start["mass"]),
        "coulomb_level": abs(start.get("coulomb_level", 0.0)),
        "coulomb": val.get("coulomb_level", val["coulomb"] + c_max),
        "coulomb_level_negative": abs(start.get("coulomb_level_negative", 0.0)),
        "coulomb_negative": max(val["coulomb"], val.get("coulomb_negative", 0.0)),
    }
    at = []
    for x in free:
        ref = scale.get(x, k_max if x.startswith("stiffness_") else c_max)
        if x.startswith(_NUISANCE) or x in ("offset", "viscous", "viscous_negative"):
            continue  # a record's start, an offset or no viscous friction: not a model bound
        if val[x] <= _BOUND * ref:
            at.append(f"{x} = 0")
    if equal_breakaway and "coulomb" in free and val["coulomb"] >= val["coulomb_level"]:
        at.append(
            "coulomb >= coulomb_level: the elements carry no force, the model is Coulomb "
            "friction with F_c = coulomb (n_elements=0 fits it as such)"
        )
    if at:
        message = (
            f"the solution sits on a bound ({', '.join(at)}), where the linearised intervals "
            f"do not hold; {sol.message}"
        )
        return replace(sol, status="at_bound", message=message)
    if "initial_velocity" in free and val.get("initial_velocity") == 0.0:
        sol = replace(sol, message=sol.message + "; initial_velocity sits on its bound 0")
    return sol


def consistent_level(sol: Solution, spec: Any) -> Solution:
    """F_c in the parameters equal to the model's `coulomb_level` (eq. 9).

    With c1 at or above the parameter F_c the elements carry no force and the
    model's F_c is c1 (plus their vanishing break-away forces): the parameter
    is set to the model's value, so the two never disagree.
    """
    if not spec.has_level_parameter or spec.n == 0 or sol.status == "failed":
        return sol
    model = spec.model(sol.values)  # PIFriction: F_c⁻ of an asymmetric model; a rate family: one
    sides = hasattr(model, "coulomb_levels")
    level, below = model.coulomb_levels if sides else (model.coulomb_level, 0.0)
    if level == sol.values["coulomb_level"]:
        return sol
    values = {**sol.values, "coulomb_level": float(level)}
    if (
        getattr(spec, "negative", None) is not None
    ):  # the negative side's level the same way (ρ kept)
        values[spec.negative] = float(below)
    return replace(sol, values=values)


def smallest_threshold_first(sol: Solution, k_names: list[str], c_names: list[str]) -> Solution:
    """Relabel free elements (k_j, c_j) by increasing threshold r_j = c_j/k_j (eq. 6)."""
    # an element whose stiffness sits on its bound 0 never yields: its threshold is infinite
    r = [sol.values[c] / sol.values[k] if sol.values[k] > 0 else np.inf
         for k, c in zip(k_names, c_names, strict=True)]  # fmt: skip
    order = np.argsort(r, kind="stable")
    rename = {}
    for i, j in enumerate(order):
        rename[k_names[int(j)]], rename[c_names[int(j)]] = k_names[i], c_names[i]
    return relabelled(sol, rename)


def stiffest_first(sol: Solution, k_names: list[str]) -> Solution:
    """Relabel the elements of equal break-away force by decreasing stiffness.

    They are interchangeable, so only the sorted set is meaningful.
    """
    order = np.argsort([-sol.values[x] for x in k_names], kind="stable")
    return relabelled(sol, {k_names[int(j)]: k_names[i] for i, j in enumerate(order)})


def relabelled(sol: Solution, rename: dict[str, str]) -> Solution:
    """`sol` with its parameters renamed (`rename`: old name → new name, a permutation of
    interchangeable elements): values, errors, intervals, bounds reached and the covariance
    (rows and columns in the order of `values`) move together. A solve whose covariance was
    deferred is completed first (its errors belong to the old labels)."""
    rename = {a: b for a, b in rename.items() if a != b}
    if not rename:
        return sol
    sol = complete(sol)

    def relabel(d: dict) -> dict:
        out = dict(d)
        out.update({rename[x]: d[x] for x in rename if x in d})
        return out

    cov = sol.covariance
    if cov is not None:
        names = list(sol.values)
        old = {b: a for a, b in rename.items()}  # new name → the name it had
        idx = [names.index(old.get(n, n)) for n in names]
        cov = np.asarray(cov)[np.ix_(idx, idx)]
    return replace(
        sol,
        values=relabel(sol.values),
        standard_error=relabel(sol.standard_error),
        confidence_interval=relabel(sol.confidence_interval),
        at_bounds=tuple(rename.get(x, x) for x in sol.at_bounds),
        covariance=cov,
    )
