"""Helpers of the pooled `fit_response`: entry checks, bounds, pruning, record bootstrap.

Pruning. Element j can slide after a reversal only if a swing of the motion
(the travel between two turning points) exceeds 2·r_j (Masing's rule); an
element with k_j → 0 or 2·r_j beyond the largest swing of the fitted motion
never slides in the data, so its break-away force is a level the data never
reach. Elements with k_j → 0 are dropped; those beyond the swing act as linear
springs over the data, indistinguishable from one another, and are merged
into one (the stiffnesses added). ``prune=True`` refits once without them,
from the optimum (`Pruning.start`); the refit says which of its own elements
never slide in turn (kept). The reachable Coulomb level is
c1 + Σ_j k_j·min(r_j, s) with s half the largest swing (c1 + φ(s) for a
density): the largest friction force the model produces over the travel seen.

Bootstrap. The records are resampled with replacement (each copy keeps its own
nuisance parameters) and refitted from the pooled optimum; the standard
deviation and the percentile interval of each shared parameter are reported,
and the result's interval becomes the union of the HAC and percentile
intervals (its standard error the larger of the two), so that neither a too
short bandwidth nor too few records makes it optimistic.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from presliding._validation import (
    as_choice,
    as_count,
    as_list,
    as_nonnegative_scalar,
    as_positive_scalar,
    as_real_scalar,
    fmt,
)
from presliding.identification.intervals._profile import profile_solution
from presliding.identification.problem import _pi_regression as pr
from presliding.identification.problem._fit_options import check_varies
from presliding.identification.records import _pooled_problem as pp
from presliding.identification.records._pooled_record import VELOCITY, Record, as_record
from presliding.identification.solve._least_squares import Solution, solve_least_squares
from presliding.measurement.measurement import Measurement

NEED = {"velocity": ("velocity",), "position": ("position",), "both": ("velocity", "position")}


def check_records(
    records: Any, signal: str, signals: tuple[str, ...], velocity: str = "auto"
) -> list[Record]:
    """The records as a checked list (each a Measurement with the signals compared);
    `velocity` says how a record's velocity is compared (`_pooled_problem.as_record`)."""
    if isinstance(records, Measurement):
        found = [records]
    elif isinstance(records, Sequence) and not isinstance(records, (str, bytes)):
        found = list(records)
        for i, m in enumerate(found):
            if not isinstance(m, Measurement):
                raise TypeError(f"`records[{i}]` must be a Measurement; got {type(m).__name__}.")
        if not found:
            raise ValueError("`records` must hold at least one Measurement; got none.")
    else:
        raise TypeError(
            f"`records` must be a Measurement or a sequence of them; got {type(records).__name__}."
        )
    signal = as_choice("signal", signal, signals)
    single = isinstance(records, Measurement)
    for i, m in enumerate(found):
        m.require(*NEED[signal], purpose=f"fit_response(signal={signal!r})")
        which = "velocity" if m.velocity is not None else "position"
        check_record(m, which, "records" if single else f"records[{i}]")
    velocity = as_choice("velocity", velocity, VELOCITY)
    if velocity == "difference":
        for i, m in enumerate(found):
            if m.position is None:
                raise ValueError(
                    "`velocity='difference'` compares the difference quotient of the position; "
                    f"got a record without a position (record {i})."
                )
    return [as_record(m, velocity) for m in found]


def check_quasi_static_records(records: Any) -> list[Record]:
    """The records of a quasi-static fit as a checked list (position and applied force)."""
    found = [records] if isinstance(records, Measurement) else as_list("records", records)
    if not found:
        raise ValueError("`records` must hold at least one Measurement; got none.")
    for i, m in enumerate(found):
        if not isinstance(m, Measurement):
            raise TypeError(f"`records[{i}]` must be a Measurement; got {type(m).__name__}.")
        _, force = m.require("position", "applied_force", purpose="fit_quasi_static")
        label = "records" if isinstance(records, Measurement) else f"records[{i}]"
        check_record(m, "position", label)
        check_varies("applied_force" if label == "records" else f"{label}.applied_force", force)
    return [as_record(m) for m in found]


#: fewest samples of a record: its own start (up to 3 parameters), the velocity's difference
#: quotient and the noise floor's second differences
MIN_RECORD_SAMPLES = 8


def check_record(m: Measurement, which: str, label: str) -> None:
    """A record long enough for the fit and moving: refused naming it (`label`) otherwise.

    A 3-sample record ended ``max_evaluations`` (its noise floor and its own start cannot
    be had from it), and a record that never moves was refused without saying which."""
    n = m.time.shape[0]
    if n < MIN_RECORD_SAMPLES:
        raise ValueError(
            f"`{label}` must have at least {MIN_RECORD_SAMPLES} samples (its own start, the "
            f"velocity's difference quotient and the noise floor need them); got {n}."
        )
    signal = getattr(m, which)
    if not np.ptp(signal) > 0:
        raise ValueError(
            f"`{label}` must move: its {which} is constant ({fmt(float(signal[0]))}), a record "
            "that never moves holds nothing to fit (leave it out)."
        )


def check_model_values(spec: Any, fixed: dict, tied: dict, initial: Mapping | None) -> None:
    """Fixed and start values in the model's domain; ties of model parameters positive."""

    def positive(x: object) -> bool:
        return x in ("mass", "coulomb_level") or (isinstance(x, str) and spec.positive(x))

    if initial is not None and not isinstance(initial, Mapping):
        raise TypeError(
            f"`initial` must be a mapping of parameter names to start values; "
            f"got {type(initial).__name__}."
        )
    for label, values in (("fixed", fixed), ("initial", initial or {})):
        for x, v in values.items():
            name = f"{label}[{x!r}]"
            if positive(x):
                as_positive_scalar(name, v)
            elif x in ("coulomb", "coulomb_negative"):
                as_nonnegative_scalar(name, v)
            else:
                as_real_scalar(name, v)
    for x, spec_ in tied.items():
        if positive(x) and not isinstance(spec_, str):
            as_positive_scalar(f"tied[{x!r}][1]", spec_[1])


def initial_bounds(problem: pp.PooledProblem, initial_state: str) -> dict[str, tuple]:
    """Bounds of the per-record parameters (a saturated start moves in its direction)."""
    out: dict[str, tuple] = {}
    for i in range(problem.n_rec):
        d = problem.direction[i]
        out[problem.nuisance("initial_position", i)] = (-np.inf, np.inf)
        v = (-np.inf, np.inf)
        if initial_state != "preload":
            v = (0.0, np.inf) if d > 0 else ((-np.inf, 0.0) if initial_state == "saturated" else v)
        out[problem.nuisance("initial_velocity", i)] = v
        if initial_state == "preload":
            out[problem.nuisance("preload_fraction", i)] = (-1.0, 1.0)
    return out


# ---------------------------------------------------------------------- pruning
#: the end of a fit's note on its elements that never slide (`Pruning.note`) ...
DROPS = " (prune=True drops them)"
#: ... and of the refit's of ``prune=True``, which refits once (`_response_plan._prune`)
LEFT = " in turn, in the model refitted without the others: kept (prune=True refits once)"


@dataclass
class Pruning:
    """Elements that never slide in the fitted motion (module notes)."""

    dead: list[int]
    swing: float
    reachable: float
    effective: int | None
    reasons: dict[int, str] = field(default_factory=dict)
    spring: int | None = None  # the never-sliding element the others merge into

    def derived(self, spec: Any) -> dict[str, float]:
        out = {"largest_swing": self.swing, "reachable_coulomb_level": self.reachable}
        if self.effective is not None:
            out["effective_elements"] = float(self.effective)
        return out

    def note(self, spec: Any) -> str:
        which = ", ".join(f"{j + 1} ({self.reasons[j]})" for j in self.dead)
        return (
            f"element(s) {which} never slide in the data: effective N = {self.effective}, "
            f"reachable F_c = {self.reachable:.6g} (largest swing {self.swing:.3g})"
        )

    def start(self, values: dict[str, float], problem: pp.PooledProblem) -> dict[str, float]:
        """Start values of the refit without the dead elements (renumbered).

        The springs merged into one add their stiffnesses and (break-away forces free)
        their break-away forces to it: the spring the data see stays, and so does the force
        of the elements while they all slide (a record that starts sliding, saturated or
        preloaded, carries every element's break-away force until its first reversal). With
        equal break-away forces F_c is kept for that reason: the elements left share it.
        """
        spec = problem.spec
        alive = [j for j in range(spec.n) if j not in self.dead]
        out = {x: v for x, v in values.items() if x not in (*spec.k_names, *spec.c_names)}
        _, k, r = spec.bank(values)
        merged = [j for j in self.dead if "merged" in self.reasons[j]]
        for new, j in enumerate(alive):
            extra = merged if j == self.spring else []
            out[f"stiffness_{new + 1}"] = float(k[j] + np.sum(k[extra]))
            if not spec.equal:
                out[f"breakaway_{new + 1}"] = float(k[j] * r[j] + np.sum(k[extra] * r[extra]))
        return out


def prune_elements(problem: pp.PooledProblem, sol: Solution, spec: Any) -> Pruning:
    """The elements that never slide, the largest swing and the reachable F_c."""
    values = sol.values
    full = np.array([values[x] for x in problem.names])
    o_y = problem.simulate(full)[0][0]
    swing = 0.0
    for i in range(problem.n_rec):
        y = o_y[problem.t_off[i] : problem.t_off[i + 1]]
        turns = pr.reversal_indices(np.ascontiguousarray(y), 0.0)
        if turns.shape[0]:
            marks = np.concatenate([y[turns], [y[-1]]])
            swing = max(swing, float(np.max(np.abs(np.diff(marks)))) if marks.size > 1 else 0.0)
    c1, k, r = spec.bank(values)
    half = 0.5 * swing
    if spec.density is not None:
        dens = spec.friction_density(values)
        return Pruning([], swing, c1 + float(dens.virgin_curve(half)), None)
    reasons = {}
    total = float(np.sum(k)) if k.size else 0.0
    springs = [j for j in range(spec.n) if k[j] > 1e-9 * total and 2.0 * r[j] >= swing]
    keep = min(springs, key=lambda j: r[j]) if springs else None
    for j in range(spec.n):
        if k[j] <= 1e-9 * total:
            reasons[j] = "k → 0"
        elif keep is not None and j in springs and j != keep:  # springs ⇒ keep is set
            reasons[j] = f"2·r beyond the largest swing: a spring there, merged into {keep + 1}"
    reachable = c1 + float(np.sum(k * np.minimum(r, half)))
    return Pruning(sorted(reasons), swing, reachable, spec.n - len(reasons), reasons, keep)


# ---------------------------------------------------------------------- bootstrap
#: Most bootstrap refits a fit accepts (each is a full fit: 10,000 settle the ends of a 95 %
#: interval far beyond what the records can tell, and already take hours on large records).
MAX_BOOTSTRAP = 10_000


def _duration(seconds: float) -> str:
    """A time span in words for a progress line: 40 s, 12 min, 3.5 h."""
    if seconds < 90:
        return f"{seconds:.0f} s"
    return f"{seconds / 60:.0f} min" if seconds < 5400 else f"{seconds / 3600:.1f} h"


def record_bootstrap(
    sol: Solution,
    problem: pp.PooledProblem,
    settings: dict[str, Any],
    n_resamples: int,
    seed: int | None,
) -> tuple[Solution, dict[str, tuple[float, float, float]], int]:
    """Record-level bootstrap of the shared parameters (module notes)."""
    seed = None if seed is None else as_count("seed", seed)
    rng = np.random.default_rng(seed)
    fixed, tied, box = settings["fixed"], settings["tied"], settings["bounds"]
    shared_free = [x for x in problem.shared if x not in fixed and x not in tied]
    draws, count = [], 0
    shown = settings.get("progress")
    began = time.perf_counter()
    for b in range(n_resamples):
        if shown is not None:  # with an estimate of the time left from the resamples so far
            left = (time.perf_counter() - began) / b * (n_resamples - b) if b else None
            eta = "" if left is None else f", about {_duration(left)} left"
            shown.stage(f"bootstrap: resample {b + 1} of {n_resamples}{eta}")
        idx = rng.integers(0, problem.n_rec, problem.n_rec)
        recs = [problem.records[i] for i in idx]
        sub = problem.subset(recs)
        rename = {}
        for new, old in enumerate(idx):
            for kind in problem.kinds:
                rename[sub.nuisance(kind, new)] = problem.nuisance(kind, int(old))
        start = {x: sol.values[rename.get(x, x)] for x in sub.names}
        sub_fixed = {x: fixed[rename.get(x, x)] for x in sub.names if rename.get(x, x) in fixed}
        sub_tied = {x: v for x, v in tied.items() if x in problem.shared}
        sub_box = {x: box[rename.get(x, x)] for x in sub.names}
        sub.set_typical(start)
        out = solve_least_squares(
            sub.residual(), start, fixed=sub_fixed, tied=sub_tied, bounds=sub_box,
            free_jacobian=sub.free_jacobian(), residual_size=sub.n_res, level=settings["level"],
            step_limit=sub.step_limit, method="lm",
            max_evaluations=settings["max_evaluations"], tolerance=settings["tolerance"],
            gradient_tolerance=settings["gradient_tolerance"], progress=shown,
        )  # fmt: skip
        count += out.n_evaluations
        if out.status in ("converged", "not_identifiable", "max_evaluations"):
            draws.append([out.values[x] for x in shared_free])
    if len(draws) < 2:
        return sol, {}, count
    arr = np.array(draws)
    alpha = 1.0 - sol.level
    lo, hi = np.quantile(arr, [alpha / 2, 1 - alpha / 2], axis=0)
    boot = {x: (float(np.std(arr[:, j], ddof=1)), float(lo[j]), float(hi[j]))
            for j, x in enumerate(shared_free)}  # fmt: skip
    if not sol.interval_method:  # the profile intervals first, then joined with the bootstrap
        sol = profile_solution(sol, "auto")
    se, ci = dict(sol.standard_error), dict(sol.confidence_interval)
    for x, (b_se, b_lo, b_hi) in boot.items():
        se[x] = max(se[x], b_se)
        ci[x] = (min(ci[x][0], b_lo), max(ci[x][1], b_hi))
    message = f"{sol.message}; intervals joined with a {len(draws)}-resample record bootstrap"
    return replace(sol, standard_error=se, confidence_interval=ci, message=message), boot, count


# ---------------------------------------------------------------------- residual set-up
def signal_weights(signal: str, recs: list[Record], weights: Any) -> tuple[float, float]:
    """Weights of the velocity and position residuals (0: not compared)."""
    extra = {"velocity": 1.0, "position": 1.0}
    if weights is not None:
        if not isinstance(weights, Mapping):
            raise TypeError(f"`weights` must be a mapping of signal names; got {fmt(weights)}.")
        for key, val in weights.items():
            as_choice("weights", key, ("velocity", "position"))
            extra[key] = as_positive_scalar(f"weights[{key!r}]", val)
    wv = wy = 0.0
    if signal in ("velocity", "both"):
        rv = float(np.sqrt(np.mean(np.concatenate([r.velocity for r in recs]) ** 2)))
        wv = extra["velocity"] / (rv if signal == "both" and rv > 0 else 1.0)
    if signal in ("position", "both"):
        dev = np.concatenate([r.position - np.mean(r.position) for r in recs])
        ry = float(np.sqrt(np.mean(dev**2)))
        if signal == "both" and not ry > 0:
            raise ValueError("`position` must vary for signal='both'; got constant records.")
        wy = extra["position"] / (ry if signal == "both" else 1.0)
    return wv, wy


def nuisance_only(sol: Solution, problem: pp.PooledProblem, fixed: Mapping) -> Solution:
    """A fit whose undetermined parameters are all records' own keeps "converged".

    The shared (physical) parameters are determined; a record whose start the
    data cannot pin down (its preload and position enter only together) is
    said in the message, with its infinite intervals.
    """
    if sol.status != "not_identifiable":
        return sol
    loose = [x for x, se in sol.standard_error.items() if np.isinf(se) and x not in fixed]
    if not loose or any(problem.record_of.get(x) is None for x in loose):
        return sol
    records = sorted({i + 1 for x in loose if (i := problem.record_of.get(x)) is not None})
    more = f" and {len(records) - 8} more" if len(records) > 8 else ""
    message = (
        f"converged; the data do not determine the own parameters of record(s) "
        f"{', '.join(map(str, records[:8]))}{more}"
        " (infinite intervals); the shared parameters are "
        "determined"
    )
    return replace(sol, status="converged", message=message)


def record_starts(problem: pp.PooledProblem, start: dict[str, float],
                  fractions: tuple[float, ...] = (-0.6, 0.0, 0.6)) -> dict[str, float]:  # fmt: skip
    """Each record's own start (position, preload) fitted alone, the shared values held.

    Preloads start from several fractions (the residual of a preload is not
    convex); the best fit of each record is kept. Cheap: one record at a time.
    """
    out = dict(start)
    for i, rec in enumerate(problem.records):
        sub = problem.subset([rec], suffix=False)
        best, best_cost = None, np.inf
        for frac in fractions:
            begin = {x: start[x] for x in problem.shared}
            for kind in sub.kinds:
                begin[kind] = (
                    frac if kind == "preload_fraction" else start[problem.nuisance(kind, i)]
                )
            begin = {x: begin[x] for x in sub.names}
            sub.set_typical(begin)
            bounds = {"preload_fraction": (-1.0, 1.0)} if "preload_fraction" in sub.kinds else {}
            fit = solve_least_squares(
                sub.residual(), begin, fixed={x: start[x] for x in problem.shared},
                bounds=bounds, free_jacobian=sub.free_jacobian(), tolerance=1e-6,
                max_evaluations=60, step_limit=sub.step_limit, method="lm",
            )  # fmt: skip
            c = float(fit.residual @ fit.residual) if fit.status != "failed" else np.inf
            if c < best_cost:
                best, best_cost = fit, c
        if best is not None:
            for kind in sub.kinds:
                out[problem.nuisance(kind, i)] = best.values[kind]
    return out
