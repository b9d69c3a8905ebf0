"""Coverage of the 95 % intervals over seeds: fit_presliding and a pooled fit_response.

Data generated with the library, noise drawn per seed:

- presliding: friction force against displacement on loops of decreasing
  amplitude (a two-element model with c1), Gaussian force noise of 1 % of the
  force range; fitted with two elements.
- pooled response: three records of the paper's model (m = 2 kg, F_c = 1 N,
  c1 = 0.3 N, four elements of equal break-away force), each decelerated by its
  own applied force from a start saturated in the direction of motion, velocity
  noise of 0.3 % of its range; fitted pooled (shared m, F_c, c1, k_j; each
  record's initial velocity).

For each parameter: the share of seeds whose interval holds the truth, for the
interval returned (profile likelihood where `interval_method` says so, Wald
elsewhere) and for the Wald interval value ± t·SE; and the statuses. Fits that
end `not_identifiable` are counted apart (their intervals are not claimed).

Run: python benchmarks/interval_coverage.py [seeds_presliding] [seeds_response]
"""

from __future__ import annotations

import sys
import time
from collections import Counter

import numpy as np
from scipy import stats

import presliding as ps
from presliding.identification import Measurement
from presliding.signals import piecewise_linear

PRESLIDING = ps.PIFriction(0.2, [2.0e5, 2.0e4], breakaway=[0.4, 0.3])
PRESLIDING_TRUTH = {"coulomb": 0.2, "stiffness_1": 2.0e5, "stiffness_2": 2.0e4,
                    "threshold_1": 2e-6, "threshold_2": 1.5e-5}  # fmt: skip

DT, N = 2.5e-4, 3000
T = np.arange(N) * DT
FORCES = [
    np.select([T < 0.15, T < 0.35, T < 0.5], [2.0, -2.0, 2.0], 0.0),
    np.select([T < 0.1, T < 0.3], [1.5, -1.2], 0.0),
    np.select([T < 0.2, T < 0.4], [-1.8, 1.6], 0.0),
]
RESPONSE = ps.PIFriction(0.3, [4000.0, 2000.0, 1000.0, 500.0], breakaway=[0.175] * 4)
RESPONSE_TRUTH = {"mass": 2.0, "coulomb_level": 1.0, "coulomb": 0.3, "stiffness_1": 4000.0,
                  "stiffness_2": 2000.0, "stiffness_3": 1000.0, "stiffness_4": 500.0}  # fmt: skip
V0 = [0.05, -0.04, 0.03]


def _presliding_fit(seed: int):
    y = piecewise_linear([0.0, 30e-6, -30e-6, 20e-6, -12e-6, 25e-6, -25e-6], 0.1e-6)
    f = PRESLIDING.force(y)[0]
    f = f + 0.01 * np.ptp(f) * np.random.default_rng(seed).standard_normal(f.shape)
    return ps.fit_presliding(y, f, 2), PRESLIDING_TRUTH


def _response_records():
    out = []
    for u, v0 in zip(FORCES, V0, strict=True):
        res = ps.simulate(RESPONSE, 2.0, applied_force=(T, u), initial_velocity=v0,
                          initial_state="saturated", t_eval=T)  # fmt: skip
        out.append((res.velocity, u))
    return out


def _response_fit(seed: int, clean):
    rng = np.random.default_rng(seed)
    recs = [Measurement(T, velocity=v + 0.003 * np.ptp(v) * rng.standard_normal(v.shape),
                        applied_force=u) for v, u in clean]  # fmt: skip
    truth = dict(RESPONSE_TRUTH)
    truth.update({f"initial_velocity_{i + 1}": v for i, v in enumerate(V0)})
    return ps.fit_response(recs, 4), truth


def _covers(fit, truth, name: str) -> tuple[bool, bool]:
    lo, hi = fit.confidence_interval[name]
    q = float(stats.t.ppf(0.5 + fit.confidence_level / 2, max(fit.nfree, 1)))
    v, se = fit.parameters[name], fit.standard_error[name]
    return bool(lo <= truth[name] <= hi), bool(abs(v - truth[name]) <= q * se)


def study(label: str, fits) -> None:
    print(f"\n{label}")
    statuses: Counter = Counter()
    hits: dict[str, list[tuple[bool, bool]]] = {}
    profiled: Counter = Counter()
    start = time.perf_counter()
    n = 0
    for fit, truth in fits:
        n += 1
        statuses[fit.status] += 1
        if fit.status == "not_identifiable":
            continue
        for name in truth:
            hits.setdefault(name, []).append(_covers(fit, truth, name))
            profiled[name] += fit.interval_method.get(name) == "profile"
    took = time.perf_counter() - start
    print(f"  {n} seeds, {took / max(n, 1):.1f} s per fit; statuses: {dict(statuses)}")
    print(f"  {'parameter':<22}{'returned':>10}{'Wald':>8}{'profiled':>10}")
    for name, h in hits.items():
        ret = np.mean([a for a, _ in h])
        wald = np.mean([b for _, b in h])
        print(f"  {name:<22}{100 * ret:>9.0f}%{100 * wald:>7.0f}%{profiled[name]:>7d}/{len(h)}")


def main() -> None:
    n_pre = int(sys.argv[1]) if len(sys.argv) > 1 else 40
    n_resp = int(sys.argv[2]) if len(sys.argv) > 2 else 40
    study("fit_presliding, two elements, 1 % force noise",
          (_presliding_fit(s) for s in range(n_pre)))  # fmt: skip
    clean = _response_records()
    study("fit_response, three pooled records, 0.3 % velocity noise",
          (_response_fit(s, clean) for s in range(n_resp)))  # fmt: skip


if __name__ == "__main__":
    main()
