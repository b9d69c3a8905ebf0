"""Studies of the fit engine's search (local minima, noise floor, coverage, mirror, speed).

Data generated with the library (exact event method) with a 1 µm encoder,
0.2 µm noise, velocity from differences, per-record preload:

* ``stops``: pooled stops, each record's preload anywhere in ±0.8 F_m of either
  sign, initial velocities of both signs, random initial positions (8 records
  × 1000 samples, the model of `_stops.py`; the velocity is ``numpy.gradient`` of the
  quantised position, which `fit_response` detects and compares as such). Per seed: the
  status, the residual
  RMS over the noise floor, that ratio at the truth (the fit started from the
  true values), and whether each 95 % interval holds the truth. Printed: the
  share of fits at the noise floor (best cost within 5 % of the cost reached
  from the truth, or lower), the share of wrong ``converged`` (converged and
  not at the floor), coverage per parameter.
* ``loops``: the same for torque-driven loops with preload (`fit_quasi_static`).
* ``guide``: the user guide's 3-stop example (docs/user_guide/pooled_fits.rst):
  status and coverage of the two stiffnesses over seeds of encoder noise.

Every study of correctly specified data also prints the share of fits ``converged`` or
``not_identifiable`` (the residual tests of `_adequacy` must not cry wolf: target ≥ 90 %)
and how many passed those tests. Times are CPU times (time.process_time).
* ``mirror``: a pooled fit and the fit of its mirror image (y, v, u negated).
* ``speed``: 20 records × 1000 samples, one set per seed: time of the default
  fit and of its nuisance searches.

Coverage is printed per parameter (a record's own parameters pooled over
records) with its binomial standard error, the mean and spread of
z = (estimate − truth)/SE (a mean away from 0 is a bias, a spread above 1 a
standard error too small; formed where the error is finite, the seeds with
|z| > 5 counted and those with an infinite error, a parameter the fit reports
undetermined, counted apart) and the median relative width. Interchangeable
elements (equal break-away forces) are labelled stiffest first by the fits, and
the truths are listed in that order, so each is compared with its own element. With
PRESLIDING_STUDY_DUMP=path each fit's estimates, errors and intervals are
appended there as JSON lines, and its Jacobian and residual saved next to it
(``path.<design><seed>.npz``), so that covariance estimates can be compared
offline on the same fits.

Run: python benchmarks/identification_search.py [study] [seeds] [--seeds i,j,...]
(``--seeds 23,31`` runs those seed indices only, e.g. to check the seeds that failed;
``--first k`` starts at index k; ``--records N`` pools N stops per fit instead of 8).
"""

from __future__ import annotations

import json
import os
import sys
import time
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _stops import MASS, TRUTH, model, stop_records
from _timing import accumulating

from presliding import (
    Measurement,
    PIFriction,
    fit_quasi_static,
    fit_response,
    preloaded_state,
    quasi_static_response,
    simulate,
)

QUANTUM, NOISE = 1e-6, 2e-7
#: per-seed rows (estimates, SEs, intervals, truth) appended here when set
DUMP = os.environ.get("PRESLIDING_STUDY_DUMP")
OPTIONS = {"signal": "both", "initial_state": "preload"}
#: records per pooled fit of the ``stops`` study (``--records N`` changes it)
RECORDS = 8


def random_stop(rng: np.random.Generator, samples: int = 1000) -> tuple:
    fric = model()
    v0 = rng.choice([-1.0, 1.0]) * rng.uniform(0.02, 0.06)
    d = float(np.sign(v0))
    fraction = rng.uniform(-0.8, 0.8)
    y0 = rng.uniform(-1e-3, 1e-3)
    state = preloaded_state(fric, fraction * fric.max_elastic_force, direction=d, position=y0)
    t = np.arange(samples) * 1e-3
    u = np.where(t < rng.uniform(0.03, 0.08), -d * rng.uniform(0.1, 0.6), 0.0)
    res = simulate(fric, MASS, applied_force=(t, u), initial_position=y0, initial_velocity=v0,
                   initial_state=state, t_eval=t)  # fmt: skip
    y = QUANTUM * np.round((res.position + NOISE * rng.standard_normal(samples)) / QUANTUM)
    meas = Measurement(t, position=y, velocity=np.gradient(y, t), applied_force=u)
    return meas, {"initial_position": y0, "initial_velocity": v0, "preload_fraction": fraction}


def _cost(fit) -> float:
    r = fit.fitted - fit.measured
    return float(r @ r)


def _summary(label, statuses, at_floor, wrong, cover, seeds, elapsed, passed=None) -> None:
    print(f"{label}: {seeds} seeds, {elapsed:.0f} s")
    print(f"  statuses: {dict(statuses)}")
    honest = statuses["converged"] + statuses["not_identifiable"]
    print(f"  converged or not_identifiable: {honest}/{seeds} = {100 * honest / seeds:.0f} % "
          "(target >= 90 %: the residual tests must not cry wolf)")  # fmt: skip
    if passed is not None:
        print(f"  residual tests passed: {passed}/{seeds}")
    print(f"  at the noise floor: {at_floor}/{seeds} = {100 * at_floor / seeds:.0f} %")
    print(f"  wrong 'converged' (converged, not at the floor): {wrong}/{seeds}")
    coverage_table(cover)


def coverage_table(cover: dict) -> None:
    """Per parameter: coverage ± binomial SE, mean and spread of z, how many |z| > 5, how
    many have no z, relative width, share profiled.

    ``cover[name]`` lists (inside, z, relative width, profiled) per interval;
    z = (estimate − truth)/SE tells a bias (mean z ≠ 0) from a too-small SE
    (std z > 1); it is formed only where the fit reports a finite, positive error
    (an infinite one, a parameter the fit reports undetermined, or 0 is counted
    under ``no z``).
    """
    print(f"  {'parameter':<20}{'n':>5}{'coverage':>16}{'mean z':>9}{'std z':>8}{'|z|>5':>7}"
          f"{'no z':>7}{'width/|truth|':>15}{'profiled':>10}")  # fmt: skip
    for name, rows in cover.items():
        a = np.array(rows, dtype=float)
        n, p = len(a), float(np.mean(a[:, 0]))
        se = np.sqrt(p * (1 - p) / n)
        z = a[np.isfinite(a[:, 1]), 1]
        mean, spread = (np.mean(z), np.std(z)) if z.size else (np.nan, np.nan)
        print(f"  {name:<20}{n:>5}{100 * p:>9.1f} ± {100 * se:>4.1f}%{mean:>9.2f}"
              f"{spread:>8.2f}{int(np.sum(np.abs(z) > 5)):>7}{n - z.size:>7}"
              f"{np.median(a[:, 2]):>15.3g}{np.mean(a[:, 3]):>10.2f}")  # fmt: skip


def _entry(fit, name: str, value: float) -> tuple[float, float, float, float]:
    lo, hi = fit.confidence_interval[name]
    est, se = fit.parameters[name], fit.standard_error[name]
    # an infinite error (a parameter the fit reports undetermined) has no z: counted apart
    z = (est - value) / se if np.isfinite(se) and se > 0 else np.nan
    width = (hi - lo) / max(abs(value), 1e-12)
    return (
        float(lo <= value <= hi),
        float(z),
        float(width),
        float(fit.interval_method.get(name) == "profile"),
    )


def _dump(path, row) -> None:
    if path:
        with open(path, "a") as fh:
            fh.write(json.dumps(row) + "\n")


class _Capture:
    """Keeps the (Jacobian, residual, blocks, clusters) of every covariance the fits form,
    so that covariance estimates can be compared offline on the same fits (DUMP set)."""

    def __init__(self) -> None:
        import presliding.identification.solve._least_squares as lsq

        self.module, self.original, self.calls = lsq, lsq.fit_covariance, []

        def hook(jac, r, blocks=None, clusters=None, links=None):
            if blocks is not None:
                self.calls.append((np.array(jac), np.array(r), blocks, clusters))
            return self.original(jac, r, blocks, clusters, links)

        lsq.fit_covariance = hook

    def save(self, path: str, fit) -> None:
        """The call whose residual is the fit's own, as an npz next to the dump."""
        best = min(self.calls, key=lambda c: float(c[1] @ c[1]), default=None)  # the best fit
        self.calls = []
        if best is None or not path:
            return
        jac, r, blocks, clusters = best
        starts = [b.start if isinstance(b, slice) else int(b[0]) for b in blocks]
        stops = [b.stop if isinstance(b, slice) else int(b[-1]) + 1 for b in blocks]
        np.savez_compressed(path, jac=jac, r=r, starts=starts, stops=stops,
                            clusters=np.asarray(clusters))  # fmt: skip


def _row(design, seed, fit, truth, floor) -> dict:
    r = fit.fitted - fit.measured
    return {"design": design, "seed": seed, "status": fit.status, "floor": bool(floor),
            "n": int(r.size), "free": list(fit.var_names),
            "rho1": float(np.sum(r[1:] * r[:-1]) / np.sum(r * r)),
            "params": {k: [v, fit.parameters[k], fit.standard_error[k],
                           *fit.confidence_interval[k], fit.interval_method.get(k)]
                       for k, v in truth.items()}}  # fmt: skip


def _study(
    design: str, label: str, seeds, seed0: int, draw, shared: dict, fit_fn, ref_fn, detail
) -> None:
    """One design over seeds: draw records and their own parameters, fit, fit again from the
    truth (the noise floor), and tally statuses, the floor and coverage per parameter."""
    t0 = time.process_time()
    statuses, cover = Counter(), {}
    at_floor = wrong = passed = 0
    capture = _Capture() if DUMP else None
    chosen = list(range(seeds)) if isinstance(seeds, int) else list(seeds)
    for seed in chosen:
        pairs = draw(np.random.default_rng(seed0 + seed))
        records = [p[0] for p in pairs]
        if capture is not None:
            capture.calls = []
        fit = fit_fn(records)
        if capture is not None:
            capture.save(f"{DUMP}.{design}{seed}.npz", fit)
        truth = dict(shared)
        for i, (_, nu) in enumerate(pairs):
            truth.update({f"{k}_{i + 1}": v for k, v in nu.items()})
        ref = ref_fn(records, truth)
        floor = _cost(fit) <= 1.05 * _cost(ref)
        statuses[fit.status] += 1
        passed += fit.adequacy is not None and fit.adequacy.passed
        at_floor += floor
        wrong += fit.status == "converged" and not floor
        for name, value in truth.items():
            key = name if name in shared else name.rsplit("_", 1)[0]
            cover.setdefault(key, []).append(_entry(fit, name, value))
        _dump(DUMP, _row(design, seed, fit, truth, floor))
        print(
            f"  seed {seed}: {fit.status}, RMS/floor {fit.search.residual_over_floor:.2f} "
            f"(truth {ref.search.residual_over_floor:.2f}), {detail(fit)}",
            flush=True,
        )
    _summary(label, statuses, at_floor, wrong, cover, len(chosen), time.process_time() - t0,
             passed)  # fmt: skip


class _Timed:
    """Wall time of one step of the fit (a module function wrapped), per fit and in all."""

    def __init__(self, module: str, name: str) -> None:
        __import__(module)
        self.module, self.name = sys.modules[module], name
        self.original = getattr(self.module, name, None)
        self.last = self.total = 0.0
        self.fit = self.fits = 0.0
        if self.original is None:  # a version of the library without that step
            return

        def timed(*a, **k):
            t = time.perf_counter()
            try:
                return self.original(*a, **k)
            finally:
                self.last += time.perf_counter() - t

        setattr(self.module, name, timed)

    def wrap(self, fit_fn):
        def run(records):
            self.last, t = 0.0, time.perf_counter()
            out = fit_fn(records)
            self.fit, self.fits = time.perf_counter() - t, self.fits + 1
            self.total += self.last
            return out

        return run


def study_stops(seeds, n_records: int = RECORDS) -> None:
    """Pooled stops; per seed also the fit's wall time and that of its probe along eq. 17's
    scale (`_scale_probe`)."""
    probe = _Timed("presliding.identification.plans._response_plan", "scale_probe")
    _study(
        "stops", "pooled stops, random preloads", seeds, 5000,
        lambda rng: [random_stop(rng) for _ in range(n_records)], TRUTH,
        probe.wrap(lambda records: fit_response(records, **OPTIONS)),
        lambda records, truth: fit_response(records, **OPTIONS, initial=truth, multistart=False),
        lambda fit: f"mass {fit.parameters['mass']:.4g}, starts "
        f"{fit.n_starts_at_best}/{fit.n_starts}, fit {probe.fit:.1f} s of which the scale "
        f"probe {probe.last:.1f} s",
    )  # fmt: skip
    print(f"  scale probe: {probe.total / max(probe.fits, 1):.2f} s per fit on average")


LOOP_MODEL = PIFriction(0.05, [2e4, 6e3, 2e3], breakaway=[0.15, 0.15, 0.15])
LOOP_TRUTH = {"coulomb_level": 0.5, "coulomb": 0.05, "stiffness_1": 2e4, "stiffness_2": 6e3,
              "stiffness_3": 2e3}  # fmt: skip


def random_loop(rng: np.random.Generator, samples: int = 600) -> tuple:
    t = np.linspace(0.0, 4.0, samples)
    f0 = rng.uniform(-0.8, 0.8) * 0.25 * LOOP_MODEL.max_elastic_force  # |u| < F_c = 0.5
    d = rng.choice([-1.0, 1.0])
    amp = rng.uniform(0.25, 0.33)
    u = f0 + d * amp * np.sin(np.pi * t) * (1 - 0.1 * t / 4)
    y0 = rng.uniform(-1e-5, 1e-5)
    state = preloaded_state(LOOP_MODEL, f0, direction=-d, position=y0)
    y = quasi_static_response(LOOP_MODEL, u, state).position
    y = 1e-8 * np.round((y + 2e-9 * rng.standard_normal(samples)) / 1e-8)
    nuisance = {"initial_position": y0, "preload_fraction": f0 / LOOP_MODEL.max_elastic_force}
    return Measurement(t, position=y, applied_force=u), nuisance


def study_loops(seeds, n_records: int = 4) -> None:
    _study(
        "loops", "torque loops with preload", seeds, 7000,
        lambda rng: [random_loop(rng) for _ in range(n_records)], LOOP_TRUTH,
        lambda records: fit_quasi_static(records, 3),
        lambda records, truth: fit_quasi_static(records, 3, initial=LOOP_TRUTH),
        lambda fit: f"F_c {fit.parameters['coulomb_level']:.4g}",
    )  # fmt: skip


def guide_records(seed: int) -> list:
    truth = PIFriction(coulomb=0.3, stiffness=[4000.0, 1000.0], breakaway=[0.35, 0.35])
    rng = np.random.default_rng(seed)
    t = np.arange(600) * 1e-3
    out = []
    for v0 in (0.03, -0.045, 0.06):
        d = np.sign(v0)
        u = np.where(t < 0.05, -0.3 * d, 0.0)
        memory = preloaded_state(truth, 0.5 * d, direction=d)
        res = simulate(truth, 2.0, applied_force=(t, u), initial_velocity=v0,
                       initial_state=memory, t_eval=t)  # fmt: skip
        y = 1e-7 * np.round((res.position + 2e-8 * rng.standard_normal(600)) / 1e-7)
        out.append(Measurement(t, position=y, applied_force=u))
    return out


def study_guide(seeds: int) -> None:
    t0 = time.process_time()
    statuses, inside = Counter(), Counter()
    for seed in range(seeds):
        fit = fit_response(guide_records(seed), n_elements=2, signal="position",
                           initial_state="preload")  # fmt: skip
        statuses[fit.status] += 1
        for name, value in (("stiffness_1", 4000.0), ("stiffness_2", 1000.0), ("mass", 2.0)):
            lo, hi = fit.confidence_interval[name]
            inside[name] += lo <= value <= hi
    honest = statuses["converged"] + statuses["not_identifiable"]
    print(f"user guide 3 stops: converged or not_identifiable {honest}/{seeds}")
    print(f"user guide 3 stops: {seeds} seeds, {time.process_time() - t0:.0f} s; statuses "
          f"{dict(statuses)}; 95 % coverage " + ", ".join(
              f"{k} {100 * v / seeds:.0f} %" for k, v in inside.items()))  # fmt: skip


def study_mirror() -> None:
    records, _, _ = stop_records(3, 4)
    mirror = [Measurement(m.time, position=-m.position, velocity=-m.velocity,
                          applied_force=-m.applied_force) for m in records]  # fmt: skip
    for state in ("saturated", "preload"):
        a = fit_response(records, signal="both", initial_state=state)
        b = fit_response(mirror, signal="both", initial_state=state)
        worst = max(abs(b.parameters[k] / a.parameters[k] - 1) for k in TRUTH)
        print(f"mirror ({state}): statuses {a.status}/{b.status}; largest relative difference "
              f"of the shared parameters {worst:.2e}")  # fmt: skip


def study_speed(seeds: int = 6) -> None:
    """20 records × 1000 samples per seed: the fit's wall time and its nuisance searches'."""
    import presliding.identification.search._nuisance_search as ns

    fit_response(stop_records(0, 2)[0], **OPTIONS, max_evaluations=5)  # compile
    spent = [0.0]
    search_module = sys.modules["presliding.identification.search._search"]
    original = ns.search_nuisance
    search_module.search_nuisance = accumulating(original, spent)
    times = []
    probe = _Timed("presliding.identification.plans._response_plan", "scale_probe")
    for seed in range(seeds):
        records, _, _ = stop_records(seed, 20)
        spent[0] = 0.0
        t = time.perf_counter()
        fit = probe.wrap(lambda r: fit_response(r, **OPTIONS))(records)
        times.append(time.perf_counter() - t)
        print(f"20 × 1000, seed {seed}: {times[-1]:.2f} s (target 5 s), of which the nuisance "
              f"search {spent[0]:.2f} s, the scale probe {probe.last:.2f} s; status "
              f"{fit.status}, RMS/floor "
              f"{fit.search.residual_over_floor:.2f}, starts "
              f"{fit.n_starts_at_best}/{fit.n_starts}", flush=True)  # fmt: skip
    search_module.search_nuisance = original
    print(f"20 × 1000: median {np.median(times):.2f} s, max {max(times):.2f} s over {seeds} seeds")


def _seed_list(argv: list[str]) -> tuple[list[str], int | list[int]]:
    """The positional arguments, and the seed indices: ``--seeds i,j`` or ``--first k``
    (with the count, indices k … k + count − 1) or the count alone (0 … count − 1)."""
    args, chosen, first = [], None, 0
    it = iter(argv)
    for a in it:
        if a == "--seeds":
            chosen = [int(x) for x in next(it).split(",") if x]
        elif a == "--first":
            first = int(next(it))
        elif a == "--records":
            global RECORDS
            RECORDS = int(next(it))
        else:
            args.append(a)
    count = int(args[1]) if len(args) > 1 else 40
    if chosen is not None:
        return args, chosen
    return args, count if first == 0 else list(range(first, first + count))


def main() -> None:
    args, chosen = _seed_list(sys.argv[1:])
    study = args[0] if args else "all"
    seeds = chosen if isinstance(chosen, int) else len(chosen)
    if study in ("stops", "all"):
        study_stops(chosen, RECORDS)
    if study in ("loops", "all"):
        study_loops(chosen)
    if study in ("guide", "all"):
        study_guide(seeds)
    if study in ("mirror", "all"):
        study_mirror()
    if study in ("speed", "all"):
        study_speed(seeds if study == "speed" else 6)


if __name__ == "__main__":
    main()
