"""Calibration study: pooled stops against single stops (servo-drive stops, section 4).

For each seed, 8 stops (`_stops.py`: forced deceleration, then free; 1 kHz,
1 µm encoder quantum, 0.2 µm noise, velocity from differences, a preload per
record) are fitted together (`fit_response(records, signal="both",
initial_state="preload")`). Printed:

* coverage: the share of (parameter, seed) cases whose 95 % interval holds the
  true value, over the 7 shared parameters (m, F_c, c1, k_1..k_4);
* held-out reversal counts: leave-one-record-out (`cross_validate`), the share
  of held-out records whose predicted reversal count equals the measured one
  (counted alike on both, `count_reversals`);
* single stops: each record fitted alone with the same options; how many come
  back converged (identified) against the pooled fits.

Run: python benchmarks/study_pooled_stops.py [seeds] [records]
"""

from __future__ import annotations

import sys
import time
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _stops import TRUTH, stop_records

from presliding import cross_validate, fit_response

OPTIONS = {"signal": "both", "initial_state": "preload"}


def main(seeds: int = 50, n_records: int = 8) -> None:
    t0 = time.perf_counter()
    inside = cases = 0
    per_param = Counter()
    exact = held = 0
    pooled_status, single_status = Counter(), Counter()
    for seed in range(seeds):
        records, _, _ = stop_records(1000 + seed, n_records)
        cv = cross_validate(records, **OPTIONS)
        fit = cv.result
        pooled_status[fit.status] += 1
        for name, value in TRUTH.items():
            lo, hi = fit.confidence_interval[name]
            ok = lo <= value <= hi
            inside += ok
            per_param[name] += ok
            cases += 1
        for p in cv.predictions:
            if p.reversals_match is not None:
                held += 1
                exact += p.reversals_match
        for rec in records:
            single_status[fit_response(rec, **OPTIONS).status] += 1
        if (seed + 1) % 10 == 0:
            print(f"  {seed + 1} seeds, {time.perf_counter() - t0:.0f} s", flush=True)
    print(f"pooled fits of {n_records} stops, {seeds} seeds ({time.perf_counter() - t0:.0f} s):")
    print(f"  95 % intervals hold the truth in {inside}/{cases} = {100 * inside / cases:.1f} % "
          "of the parameter × seed cases")  # fmt: skip
    print("  per parameter: " + ", ".join(f"{k} {100 * v / seeds:.0f} %"
                                         for k, v in per_param.items()))  # fmt: skip
    print(f"  held-out reversal counts exact in {exact}/{held} = {100 * exact / held:.1f} %")
    print(f"  pooled status: {dict(pooled_status)}")
    print(f"  single-stop fits: {dict(single_status)} "
          f"({single_status['converged']}/{sum(single_status.values())} identified)")  # fmt: skip


if __name__ == "__main__":
    args = [int(a) for a in sys.argv[1:3]]
    main(*args)
