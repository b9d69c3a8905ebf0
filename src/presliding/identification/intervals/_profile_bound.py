"""Intervals around a parameter whose column vanishes on its bound: its one-sided profile.

A record's preload fraction saturated in the direction of its first motion (f·d = 1) changes
the motion only while its unsaturated elements load up: over a distance ∝ 1 − |f|, with a
friction deficit ∝ 1 − |f|, so the residual moves as (1 − |f|)² and its column vanishes on the
bound. The Jacobian there sees neither the preload (its Wald half width spans its range) nor
that moving it inward absorbs a change of the record's other parameters: their Wald
intervals, and their profiles with the preload held on the bound (the Gauss–Newton step of
a parameter with a zero column and gradient is zero), come out far too short. In the pooled
stops study an initial velocity sat 28 standard errors (of 1.3e-5 m/s) from the truth, where
holding it at the truth and re-optimising moves the preload inward to 0.66 and raises the
cost by a few profile thresholds only.

Such a parameter p (free, on a finite bound or within `NEAR_FLAT` of it, where it is put on
the bound if that costs nothing, its Wald half width t·SE_p at least its range, or its error
infinite: `_normal_equations.flat_on_bound`) is profiled inward from the bound: the walk of
`_profile_walk` (continuation from the bound, secant steps, regula falsi), with steps in
units of its range (`STEP`) instead of its Wald half width, to where P(p) = χ²(p) − χ²_min
reaches the threshold of `_normal_equations.carried_threshold`: the largest of the other
free parameters' P_j = t²·SE_j²/h_jj, h = (JᵀJ)⁻¹ without p (the largest HAC inflation of
the fit; t²·s² for independent residuals). Its own is a ratio of two variances that the
vanishing column sends to infinity, each cut by a different rank tolerance: any number. Its
interval is [end, bound] ("profile"), and the second optima (`_alternatives`) read that
threshold for it and for the parameters below.

Every point solved on the way with P within that threshold holds the re-optimised values
of all the other parameters: a point of the confidence region at that level. Each other
parameter θ_j gets the hull of its Wald interval and the values it takes at those points
(the last one interpolated at the end): the range the data allow it while p moves over its
interval (``interval_method`` "partner", where that widens it). Its standard error becomes
the larger of its own and the new interval's width over 2·t, its covariance row and column
scaled alike (a Wald error read at the bound says nothing of the partner's move). Those
values lie inside θ_j's own profile interval at that threshold (P_j(θ_j) ≤ P(p) there), so
the interval is never longer than that profile's, and never shorter than Wald.
"""

from __future__ import annotations

import numpy as np

from presliding.identification.intervals._profile_walk import (
    FloatArray,
    Walker,
    interval_end,
)

__all__ = ["ACCURACY", "STEP", "partner_intervals", "widen"]

#: The walk's unit step (its "half width"), as a share of the parameter's range: the first
#: point is half of it inward from the bound, later steps no longer than the distance walked.
STEP = 0.125
#: The accuracy of the end, in units of that step: 1 % of the range (a preload's interval
#: needs no more, and each further digit costs a re-optimisation of every parameter).
ACCURACY = 0.04


def partner_intervals(walk: Walker) -> tuple[tuple[float, float], dict[int, tuple[float, float]]]:
    """The walk inward from the bound of `walk.j` (module notes): its interval, and for every
    other free parameter (by index) the range of its values at the points solved within the
    threshold, the last one interpolated at the end."""
    prof, j = walk.prof, walk.j
    v = float(walk.x[j])
    side = -1 if prof.upper[j] - v <= v - prof.lower[j] else 1  # inward from the nearer
    bound = float(prof.upper[j] if side < 0 else prof.lower[j])
    span = float(prof.upper[j] - prof.lower[j])
    end = interval_end(walk, side, STEP * span)
    end = float(np.clip(end, prof.lower[j], prof.upper[j]))
    crit = walk.root**2
    points = sorted(walk.solved.items(), key=lambda kv: side * (kv[0] - v))
    inside: list[tuple[float, FloatArray]] = []
    beyond: tuple[float, FloatArray] | None = None
    for theta, (p, z) in points:
        if side * (theta - end) > 0 or not np.isfinite(p):
            if beyond is None and np.isfinite(p):
                beyond = (theta, z)
            continue
        if p - walk.low <= crit * (1.0 + 1e-9):
            inside.append((theta, z))
    ranges: dict[int, tuple[float, float]] = {}
    if not inside:
        return (min(v, end, bound), max(v, end, bound)), ranges
    zs = [z for _, z in inside]
    last_theta, last_z = inside[-1]
    if beyond is not None and beyond[0] != last_theta:
        w = (end - last_theta) / (beyond[0] - last_theta)
        zs.append(last_z + float(np.clip(w, 0.0, 1.0)) * (beyond[1] - last_z))
    arr = np.array(zs)
    for col, i in enumerate(walk.keep):
        ranges[int(i)] = (float(np.min(arr[:, col])), float(np.max(arr[:, col])))
    return (min(v, end, bound), max(v, end, bound)), ranges


def widen(value: float, name: str, rng: tuple[float, float], ci: dict, se: dict,
          quantile: float) -> bool:  # fmt: skip
    """Join `rng` to the interval of `name` in `ci` and raise its error in `se` to at least
    the new interval's width over 2·t (module notes); True where that widened it."""
    lo, hi = ci[name]
    new = (min(lo, rng[0]), max(hi, rng[1]))
    if new == (lo, hi):
        return False
    ci[name] = new
    se[name] = max(float(se[name]), 0.5 * (new[1] - new[0]) / quantile)
    return True
