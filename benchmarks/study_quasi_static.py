"""Torque-driven presliding loops: quasi-static fits of held-out loops, Masing check with creep.

A joint with presliding friction (c1 = 0.05 N m, three elements of 0.15 N m,
F_c = 0.5 N m) is driven by slow torque sines of decaying amplitude around a
preload, each record from a memory that reverses at its preload
(`preloaded_state`); its angle is measured with a 10 nrad quantum and 3 nrad
noise. For each seed, 6 records are cross-validated (`cross_validate(...,
fit="quasi-static")`): each loop predicted by the fit of the others. Printed:
the median, 90th percentile and largest NRMSE of the held-out loops, the share
within 2 %, and the held-out reversal counts.

Masing check: the same loops with creep added (a viscoelastic element in
series: dθ_c/dt = (g·u − θ_c)/τ, compliance g, τ = 0.5 s) are compared with the
branches predicted from the virgin curve of a virgin-curve fit to the loops
without creep (`fit_virgin_curve(..., loops=True)`); the share of records each
is flagged in is printed.

Run: python benchmarks/study_quasi_static.py [seeds]
"""

from __future__ import annotations

import sys
import time

import numpy as np

from presliding import (
    Measurement,
    PIFriction,
    cross_validate,
    fit_virgin_curve,
    masing_check,
    preloaded_state,
    quasi_static_response,
)

MODEL = PIFriction(0.05, [2e4, 6e3, 2e3], breakaway=[0.15, 0.15, 0.15])
QUANTUM, NOISE = 1e-8, 3e-9


def loops(seed: int, n: int = 6, creep: float = 0.0):
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 8.0, 800)
    out = []
    for _ in range(n):
        amp, f0, d = rng.uniform(0.3, 0.42), rng.uniform(-0.05, 0.05), rng.choice([-1.0, 1.0])
        u = f0 + d * amp * np.sin(2 * np.pi * 0.25 * t) * np.exp(-0.08 * t)
        state = preloaded_state(MODEL, f0, direction=-d, position=rng.uniform(-1e-5, 1e-5))
        y = quasi_static_response(MODEL, u, state).position
        if creep:
            tau, dt = 0.5, t[1] - t[0]
            yc = np.zeros_like(y)
            for i in range(1, t.shape[0]):
                yc[i] = yc[i - 1] + dt * (creep * u[i] - yc[i - 1]) / tau
            y = y + yc
        y = QUANTUM * np.round((y + NOISE * rng.standard_normal(y.shape)) / QUANTUM)
        out.append(Measurement(t, position=y, applied_force=u))
    return out


def main(seeds: int = 10) -> None:
    t0 = time.perf_counter()
    nrmse, exact, held = [], 0, 0
    flagged = {"no creep": 0, "creep": 0}
    records_seen = 0
    for seed in range(seeds):
        recs = loops(seed)
        cv = cross_validate(recs, fit="quasi-static")
        nrmse += [p.nrmse for p in cv.predictions]
        for p in cv.predictions:
            if p.reversals_match is not None:
                held += 1
                exact += p.reversals_match
        virgin = fit_virgin_curve([r.position for r in recs], [r.applied_force for r in recs], 3,
                                  loops=True, reversal_tolerance=None)  # fmt: skip
        compliance = 1.0 / MODEL.initial_stiffness  # creep as large as the presliding itself
        for label, data in (("no creep", recs), ("creep", loops(seed, creep=compliance))):
            for r in data:
                check = masing_check(virgin, (r.position, r.applied_force))
                flagged[label] += not check.passed
        records_seen += len(recs)
    arr = np.array(nrmse)
    elapsed = time.perf_counter() - t0
    print(f"quasi-static cross-validation, {seeds} seeds × 6 loops ({elapsed:.0f} s):")
    print(f"  held-out NRMSE: median {100 * np.median(arr):.3f} %, 90th percentile "
          f"{100 * np.quantile(arr, 0.9):.3f} %, largest {100 * arr.max():.3f} %; within 2 %: "
          f"{100 * np.mean(arr <= 0.02):.1f} %")  # fmt: skip
    print(f"  held-out reversal counts exact: {exact}/{held}")
    print(f"  Masing check flags: {flagged['no creep']}/{records_seen} loops without creep, "
          f"{flagged['creep']}/{records_seen} with creep")  # fmt: skip


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:2]))
