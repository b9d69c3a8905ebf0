"""Speed of a pooled output-error fit: 20 records × 1000 samples, 7 shared + 3 per record.

The records are stops on a servo drive (`_stops.py`): a slide decelerated by
a force, then free until rest; position quantised to 1 µm with 0.2 µm noise,
velocity its difference quotient; each record with its own initial position,
velocity and preload. The fit (`fit_response(records, signal="both",
initial_state="preload")`) identifies m, F_c, c1, k_1..k_4 (shared) and
y0, v0 and the preload of each record (60 more): 67 parameters, 40 000
residuals. Every evaluation simulates all records in one compiled call; a
Jacobian costs one more call for all its columns (grouped by the sparsity
structure: 7 shared columns + 3 record columns).

Target: at most 5 s on the 2-core machine, with the default options
(two starts compared and the rigid-limit check, profile intervals where the
Wald interval is doubtful). Printed: the median and range of repeated runs,
their ratio to the target, the same without the multi-start, the evaluations,
the largest error of the shared parameters, the time of the profile step
(`identification._profile`) with the parameters it profiled, and the cost of the
global nuisance search (`identification._nuisance_search.search_nuisance`, every
call the adaptive search and the probe along eq. 17's scale make: the records' own
parameters on a grid, all candidates in one compiled call, then polished): its
time, its share of the fit's time in the same run, its calls and its residual
evaluations (the adaptive search's).

The load average before and after is printed: on a shared machine the times
scale with it, the ratios of the same run much less.

The search's path, and so its time, varies with the data: the default fit is also timed
once on further data sets of the same design (seeds 1, 2, ...), with their median, mean
and largest time.

Run: python benchmarks/bench_pooled_fit.py [repeats] [data sets]
"""

from __future__ import annotations

import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _stops import TRUTH, stop_records
from _timing import accumulating

from presliding import fit_response
from presliding.identification import fit_result
from presliding.identification.search import _scale_probe, _search

TARGET = 5.0


_PROFILE_TIME = [0.0]
_NUISANCE = [0.0, 0]  # time, calls


fit_result.profile_solution = accumulating(fit_result.profile_solution, _PROFILE_TIME)
_search.search_nuisance = accumulating(_search.search_nuisance, _NUISANCE)
_scale_probe.search_nuisance = accumulating(_scale_probe.search_nuisance, _NUISANCE)


def run(records, **kw):
    _PROFILE_TIME[0] = 0.0
    _NUISANCE[:] = [0.0, 0]
    t0 = time.perf_counter()
    fit = fit_response(records, signal="both", initial_state="preload", **kw)
    return fit, time.perf_counter() - t0


def main(repeats: int = 5, sets: int = 3) -> None:
    records, _, sims = stop_records(0, 20)
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"records: {len(records)} × {records[0].n_samples} samples; reversals per record "
          f"{min(s.n_reversals for s in sims)}..{max(s.n_reversals for s in sims)}")  # fmt: skip
    run(records[:2], max_evaluations=5)  # compile and warm up
    medians = {}
    for label, kw in (("default (multi-start, rigid check)", {}),
                      ("single start", {"multistart": False})):  # fmt: skip
        times, fit, profile, nuisance, calls = [], None, [], [], 0
        for _ in range(repeats):
            fit, dt = run(records, **kw)
            times.append(dt)
            profile.append(_PROFILE_TIME[0])
            nuisance.append(_NUISANCE[0])
            calls = _NUISANCE[1]
        free = len(fit.parameters) - len(fit.fixed)
        err = max(abs(fit.parameters[k] / v - 1) for k, v in TRUTH.items())
        med = statistics.median(times)
        medians[label] = med
        print(f"{label}: median {med:.2f} s (range {min(times):.2f}..{max(times):.2f} s over "
              f"{repeats} runs) = {med / TARGET:.2f} × the {TARGET:g} s target; "
              f"{free} free parameters, {fit.nfev} evaluations, status {fit.status}; largest "
              f"relative error of the shared parameters {100 * err:.2f} %")  # fmt: skip
        profiled = [k for k, v in fit.interval_method.items() if v == "profile"]
        print(f"  profile step: median {statistics.median(profile):.2f} s; profiled: "
              f"{', '.join(profiled) or 'none'}")  # fmt: skip
        share = statistics.median(n / t for n, t in zip(nuisance, times, strict=True))
        spent = fit.search.search_evaluations if fit.search is not None else 0
        print(f"  global nuisance search: median {statistics.median(nuisance):.2f} s = "
              f"{100 * share:.0f} % of the fit; {calls} call(s), {spent} residual "
              "evaluations (each grid of candidates one compiled call)")  # fmt: skip
    default, single = medians.values()
    print(f"default / single start: {default / single:.2f} (same run)")
    times = [medians["default (multi-start, rigid check)"]]
    for seed in range(1, sets):  # other data sets of the same design: the search's path varies
        fit, dt = run(stop_records(seed, 20)[0])
        times.append(dt)
        print(f"data set {seed}: default fit {dt:.2f} s, {fit.nfev} evaluations, status "
              f"{fit.status}")  # fmt: skip
    if sets > 1:
        print(f"default fit over {sets} data sets: median {statistics.median(times):.2f} s, mean "
              f"{statistics.mean(times):.2f} s, largest {max(times):.2f} s = "
              f"{max(times) / TARGET:.2f} × the target")  # fmt: skip
    after = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"load average (1 min) before / after: {load:.2f} / {after:.2f} on {os.cpu_count()} "
          "cores (the times scale with it on a shared machine)")  # fmt: skip


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 5, int(sys.argv[2]) if len(sys.argv) > 2 else 3)
