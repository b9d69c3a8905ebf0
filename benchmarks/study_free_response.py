"""Free responses (u = 0): per-unit-mass fits when the motion reverses at least twice.

Without an applied force, eq. 17 determines only F/m; `fit_response` then
holds m = 1 and reports per unit mass (forces in N/kg). Here a mass of 2 kg
with c1 = 0.05 N and two elements (k = 3000, 600 N/m, c = 0.3 N each) is
released at 0.06–0.12 m/s from a preloaded memory; only records with at least
two reversals are kept. Position: 1 µm quantum, 0.2 µm noise; velocity its
difference quotient. Per seed, three records are fitted together and each
alone (signal "both", a preload per record). Printed: how many fits converge
with every per-unit-mass parameter determined (finite intervals), how many
hold the truth in their 95 % intervals, and the median relative error.

Run: python benchmarks/study_free_response.py [seeds]
"""

from __future__ import annotations

import sys
import time
from collections import Counter

import numpy as np

from presliding import Measurement, PIFriction, fit_response, preloaded_state, simulate

MASS = 2.0
MODEL = PIFriction(0.05, [3000.0, 600.0], breakaway=[0.3, 0.3])
TRUTH = {"coulomb_level": 0.65 / MASS, "coulomb": 0.05 / MASS, "stiffness_1": 3000.0 / MASS,
         "stiffness_2": 600.0 / MASS}  # fmt: skip


def record(rng):
    t = np.arange(800) * 1e-3
    while True:
        d = rng.choice([-1.0, 1.0])
        state = preloaded_state(MODEL, d * rng.uniform(0.2, 1.0) * MODEL.max_elastic_force,
                                direction=d)  # fmt: skip
        res = simulate(MODEL, MASS, initial_velocity=d * rng.uniform(0.06, 0.12),
                       initial_state=state, t_eval=t)  # fmt: skip
        if res.n_reversals >= 2:
            break
    y = 1e-6 * np.round((res.position + 2e-7 * rng.standard_normal(t.shape)) / 1e-6)
    return Measurement(t, position=y, velocity=np.gradient(y, t)), res.n_reversals


def judge(fit):
    determined = all(np.isfinite(fit.standard_error[k]) for k in TRUTH)
    inside = all(fit.confidence_interval[k][0] <= v <= fit.confidence_interval[k][1]
                 for k, v in TRUTH.items())  # fmt: skip
    err = max(abs(fit.parameters[k] / v - 1) for k, v in TRUTH.items())
    return fit.status, determined, inside, err, "per unit mass" in fit.message


def main(seeds: int = 20) -> None:
    t0 = time.perf_counter()
    rows = {"pooled (3 records)": [], "single record": []}
    reversals = Counter()
    for seed in range(seeds):
        rng = np.random.default_rng(500 + seed)
        recs = [record(rng) for _ in range(3)]
        reversals.update(n for _, n in recs)
        records = [m for m, _ in recs]
        rows["pooled (3 records)"].append(
            judge(fit_response(records, 2, signal="both", initial_state="preload"))
        )
        for m in records:
            rows["single record"].append(
                judge(fit_response(m, 2, signal="both", initial_state="preload"))
            )
    print(f"free responses, {seeds} seeds ({time.perf_counter() - t0:.0f} s); reversals per "
          f"record: {dict(sorted(reversals.items()))}")  # fmt: skip
    for label, res in rows.items():
        status = Counter(r[0] for r in res)
        ok = sum(r[0] == "converged" and r[1] for r in res)
        inside = sum(r[2] for r in res)
        per_mass = sum(r[4] for r in res)
        print(f"  {label}: {len(res)} fits, status {dict(status)}; converged with every "
              f"parameter determined {ok}/{len(res)}; truth inside the 95 % intervals "
              f"{inside}/{len(res)}; median largest relative error "
              f"{100 * np.median([r[3] for r in res]):.2f} %; said per unit mass "
              f"{per_mass}/{len(res)}")  # fmt: skip


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:2]))
