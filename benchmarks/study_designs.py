"""Study of the pooled output-error fit on the designs users bring (one factor at a time).

The base design is the ``stops`` study of `identification_search.py` (the truth of
`_stops.py`: mass 2 kg, F_c = 1 N, c1 = 0.3 N, four elements of equal break-away
force, k = 4000/2000/1000/500 N/m; 8 records × 1000 samples at 1 kHz; a 1 µm
encoder with 0.2 µm noise; each record's preload anywhere in ±0.8 F_m of either
sign, both velocity signs, random starts). Each further design changes one factor:

* physical scale: ``light`` (0.05 kg, F_c 0.2 N; ``light_soft``/``light_stiff`` with
  the stiffnesses × 0.1 / × 10) and ``heavy`` (50 kg, F_c 40 N, stiffnesses × 40).
  The encoder quantum is 1/700 of the presliding range 2·c_j/k_min (the base
  design's ratio), the noise 0.2 quantum; the initial speeds give stopping times
  of the base design's 40–120 ms, the applied force 10–60 % of F_c;
* units: ``mm_ms`` (the base design in mm, ms, kg: forces × 1e-3, stiffnesses
  × 1e-6) and ``mm_s_g`` (mm, s, g: forces × 1e6, stiffnesses × 1e3). Each seed is
  also fitted in SI: the shared estimates mapped back must agree (relative
  difference printed) and the status must be the same;
* model order: ``n2``, ``n3`` (truth and fit with 2 and 3 elements), ``close``
  (k = 2000/1800/1600/1400 N/m);
* records: ``rec3``, ``rec20`` (3 and 20 records), ``short`` (300 samples);
* ``khz5``: 5 kHz sampling (0.5 s records);
* ``unequal``: break-away forces 0.05/0.1/0.2/0.35 N, fitted with
  ``equal_breakaway=False``;
* ``saturated``: no preload, records starting in steady sliding, fitted with
  ``initial_state="saturated"``.

Per design and seed: the status, the residual RMS over the noise floor, that ratio
for the fit started at the truth, whether each 95 % interval holds the truth.
Printed per design: the share at the floor (cost within 5 % of the fit from the
truth, or lower), wrong ``converged`` (converged and not at the floor, or an
interval missing the truth by more than 5 standard errors), coverage per parameter
(`identification_search.coverage_table`) and the mean time of the fit.

Run: python benchmarks/study_designs.py [--designs base,light,...] [--seeds N]
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from collections import Counter
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _stops import TRUTH
from identification_search import _cost, _entry, coverage_table

from presliding import Measurement, PIFriction, fit_response, preloaded_state, simulate


@dataclass(frozen=True)
class Design:
    """One pooled-stops design (SI values; `units` rescales records and truth)."""

    mass: float = TRUTH["mass"]
    coulomb_level: float = TRUTH["coulomb_level"]
    coulomb: float = TRUTH["coulomb"]
    stiffness: tuple[float, ...] = tuple(TRUTH[f"stiffness_{j}"] for j in range(1, 5))
    breakaway: tuple[float, ...] | None = None  # None: equal, (F_c − c1)/N each
    records: int = 8
    samples: int = 1000
    rate: float = 1e3
    preload: bool = True
    #: (length, time, mass) factors of the units the records are given in
    units: tuple[float, float, float] = (1.0, 1.0, 1.0)
    options: dict = field(default_factory=dict)

    def model(self) -> PIFriction:
        n = len(self.stiffness)
        c = self.breakaway or [(self.coulomb_level - self.coulomb) / n] * n
        return PIFriction(self.coulomb, list(self.stiffness), breakaway=list(c))

    def truth(self) -> dict[str, float]:
        out = {"mass": self.mass}
        if self.breakaway is None:
            out.update(coulomb_level=self.coulomb_level, coulomb=self.coulomb)
        else:
            out["coulomb"] = self.coulomb
        for j, k in enumerate(self.stiffness, 1):
            out[f"stiffness_{j}"] = k
        for j, c in enumerate(self.breakaway or (), 1):
            out[f"breakaway_{j}"] = c
        return out

    def fit_options(self) -> dict:
        opts = {"signal": "both", "n_elements": len(self.stiffness)}
        opts["initial_state"] = "preload" if self.preload else "saturated"
        if self.breakaway is not None:
            opts["equal_breakaway"] = False
        return {**opts, **self.options}


BASE = Design()
MM_MS, MM_S_G = (1e3, 1e3, 1.0), (1e3, 1.0, 1e3)
K = BASE.stiffness
DESIGNS = {
    "base": BASE,
    "light": replace(BASE, mass=0.05, coulomb_level=0.2, coulomb=0.06),
    "light_soft": replace(BASE, mass=0.05, coulomb_level=0.2, coulomb=0.06,
                          stiffness=tuple(0.1 * k for k in K)),
    "light_stiff": replace(BASE, mass=0.05, coulomb_level=0.2, coulomb=0.06,
                           stiffness=tuple(10 * k for k in K)),
    "heavy": replace(BASE, mass=50.0, coulomb_level=40.0, coulomb=12.0,
                     stiffness=tuple(40 * k for k in K)),
    "mm_ms": replace(BASE, units=MM_MS),
    "mm_s_g": replace(BASE, units=MM_S_G),
    "n2": replace(BASE, stiffness=(4000.0, 1000.0)),
    "n3": replace(BASE, stiffness=(4000.0, 2000.0, 1000.0)),
    "close": replace(BASE, stiffness=(2000.0, 1800.0, 1600.0, 1400.0)),
    "rec3": replace(BASE, records=3),
    "rec20": replace(BASE, records=20),
    "short": replace(BASE, samples=300),
    "khz5": replace(BASE, samples=2500, rate=5e3),
    "unequal": replace(BASE, breakaway=(0.05, 0.1, 0.2, 0.35)),
    "saturated": replace(BASE, preload=False),
}  # fmt: skip

#: the scale of each parameter in (length, time, mass) exponents
DIMENSIONS = {"mass": (0, 0, 1), "coulomb_level": (1, -2, 1), "coulomb": (1, -2, 1),
              "breakaway": (1, -2, 1), "stiffness": (0, -2, 1), "initial_position": (1, 0, 0),
              "initial_velocity": (1, -1, 0), "preload_fraction": (0, 0, 0)}  # fmt: skip


def factor(name: str, units: tuple[float, float, float]) -> float:
    """The factor that takes parameter `name` from SI to `units`."""
    base = name if name in DIMENSIONS else name.rsplit("_", 1)[0]
    e = DIMENSIONS[base]
    return float(np.prod([u**p for u, p in zip(units, e, strict=True)]))


def stop(design: Design, rng: np.random.Generator) -> tuple[Measurement, dict]:
    """One stop of `design` in SI: the measurement and its true nuisance values."""
    fric = design.model()
    decel = design.coulomb_level / design.mass
    d = rng.choice([-1.0, 1.0])
    v0 = d * decel * rng.uniform(0.04, 0.12)  # stopping in 40–120 ms
    fraction = rng.uniform(-0.8, 0.8) if design.preload else d
    span = 2 * max(c / k for c, k in zip(fric.breakaway, fric.stiffness, strict=True))
    quantum, noise = span / 700, 0.2 * span / 700
    y0 = rng.uniform(-1.5, 1.5) * span
    state = preloaded_state(fric, fraction * fric.max_elastic_force, direction=d, position=y0)
    t = np.arange(design.samples) / design.rate
    u = np.where(t < rng.uniform(0.03, 0.08), -d * rng.uniform(0.1, 0.6), 0.0)
    u = u * design.coulomb_level
    res = simulate(fric, design.mass, applied_force=(t, u), initial_position=y0,
                   initial_velocity=v0, initial_state=state, t_eval=t)  # fmt: skip
    y = quantum * np.round((res.position + noise * rng.standard_normal(t.size)) / quantum)
    meas = Measurement(t, position=y, velocity=np.gradient(y, t), applied_force=u)
    nuisance = {"initial_position": y0, "initial_velocity": v0}
    if design.preload:
        nuisance["preload_fraction"] = fraction
    return meas, nuisance


def in_units(meas: Measurement, units: tuple[float, float, float]) -> Measurement:
    length, time_, mass = units
    return Measurement(meas.time * time_, position=meas.position * length,
                       velocity=meas.velocity * length / time_,
                       applied_force=meas.applied_force * mass * length / time_**2)  # fmt: skip


def draw(design: Design, seed: int) -> tuple[list[Measurement], dict[str, float]]:
    """The records of one seed (in the design's units) and the truth (in the same units)."""
    rng = np.random.default_rng(9000 + seed)
    pairs = [stop(design, rng) for _ in range(design.records)]
    truth = design.truth()
    for i, (_, nu) in enumerate(pairs, 1):
        truth.update({f"{k}_{i}": v for k, v in nu.items()})
    truth = {k: v * factor(k, design.units) for k, v in truth.items()}
    return [in_units(p[0], design.units) for p in pairs], truth


def run(name: str, design: Design, seeds: int) -> dict:
    statuses, cover, times = Counter(), {}, []
    at_floor = wrong = 0
    caught: Counter = Counter()
    shared = design.truth()
    units = design.units != (1.0, 1.0, 1.0)
    agree = []
    for seed in range(seeds):
        records, truth = draw(design, seed)
        opts = design.fit_options()
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            t0 = time.perf_counter()
            try:
                fit = fit_response(records, **opts)
            except Exception as exc:  # a crash is a finding: count it, go on
                statuses[f"error {type(exc).__name__}"] += 1
                print(f"  seed {seed}: {type(exc).__name__}: {exc}", flush=True)
                continue
            times.append(time.perf_counter() - t0)
            ref = fit_response(records, **opts, initial=truth, multistart=False)
        for warning in w:
            caught[f"{warning.category.__name__}: {str(warning.message)[:80]}"] += 1
        floor = _cost(fit) <= 1.05 * _cost(ref)
        entries = {k: _entry(fit, k, v) for k, v in truth.items()}
        far = [k for k, e in entries.items() if not e[0] and abs(e[1]) > 5]
        bad = fit.status == "converged" and (not floor or bool(far))
        statuses[fit.status] += 1
        at_floor += floor
        wrong += bad
        for k, e in entries.items():
            cover.setdefault(k if k in shared else k.rsplit("_", 1)[0], []).append(e)
        extra = ""
        if units:  # the same records in SI: same status, same relative estimates
            si_records, _ = draw(replace(design, units=(1.0, 1.0, 1.0)), seed)
            si = fit_response(si_records, **opts)
            rel = max(abs(fit.parameters[k] / factor(k, design.units) / si.parameters[k] - 1)
                      for k in shared)  # fmt: skip
            agree.append((rel, si.status == fit.status))
            extra = f", SI fit {si.status} (largest relative difference {rel:.1e})"
        print(f"  seed {seed}: {fit.status}, RMS/floor {fit.search.residual_over_floor:.2f} "
              f"(truth {ref.search.residual_over_floor:.2f}), starts "
              f"{fit.n_starts_at_best}/{fit.n_starts}, {times[-1]:.1f} s"
              f"{', WRONG' if bad else ''}{', >5 SE: ' + ' '.join(far) if far else ''}"
              f"{extra}", flush=True)  # fmt: skip
    n = sum(statuses.values())
    print(f"{name}: {n} seeds; statuses {dict(statuses)}; at the floor {at_floor}/{n}; "
          f"wrong converged {wrong}/{n}; mean fit time "
          f"{np.mean(times) if times else float('nan'):.2f} s")  # fmt: skip
    if agree:
        print(f"  units: largest relative difference to SI {max(a[0] for a in agree):.1e}, "
              f"same status {sum(a[1] for a in agree)}/{len(agree)}")  # fmt: skip
    for text, count in caught.items():
        print(f"  warning ×{count}: {text}")
    if cover:
        coverage_table(cover)
    return {"at_floor": at_floor, "wrong": wrong, "n": n}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--designs", default=",".join(DESIGNS), help="comma-separated names")
    parser.add_argument("--seeds", type=int, default=5)
    args = parser.parse_args()
    names = [n for n in args.designs.split(",") if n]
    unknown = [n for n in names if n not in DESIGNS]
    if unknown:
        parser.error(f"unknown designs {unknown}; known: {', '.join(DESIGNS)}")
    for name in names:
        print(f"design {name}", flush=True)
        run(name, DESIGNS[name], args.seeds)


if __name__ == "__main__":
    main()
