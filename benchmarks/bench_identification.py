"""Identification benchmark: timings and the figures on measured data.

Prints
* the paper's 7-parameter output-error fit (m, F_c, c1, k2..k5 with equal
  break-away c_j = (F_c − c1)/4) on 10,000 samples of simulated data, from the
  default start: the best and median wall time of several runs, and the largest
  relative parameter error;
* over noise seeds: how many fits converge with the truth inside the 95 %
  intervals, are flagged not identifiable, or converge wrongly, with and
  without the multi-start and rigid-limit check;
* fit_presliding and fit_motion timings on synthetic data;
* when ../shared/data is present: EMPS parameters against the published IDIM-LS
  reference, the residual with and without presliding elements (estimation and
  validation file), and the tribometer NRMSE on held-back cycles.

Run: python benchmarks/bench_identification.py
"""

from __future__ import annotations

import statistics
import time
from pathlib import Path

import numpy as np

from presliding import PIFriction
from presliding.identification.fit_motion import fit_motion, predict_motion_force
from presliding.identification.fit_presliding import fit_presliding
from presliding.identification.fit_response import fit_response
from presliding.identification.fit_result import fit_statistics
from presliding.identification.problem._pi_regression import reversal_indices
from presliding.measurement.measurement import Measurement
from presliding.motion import simulate
from presliding.signals import piecewise_linear

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"
REFERENCE = {"mass": 95.11, "viscous": 203.5, "coulomb": 20.39, "offset": -3.16}


def timed(fn, repeat: int = 5):
    fn()  # compile and warm up
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return out, min(times), statistics.median(times)


def bench_response() -> None:
    k = np.array([4000.0, 2000.0, 1000.0, 500.0])
    model = PIFriction(0.3, k, breakaway=[(1.0 - 0.3) / 4] * 4)
    t = np.arange(10_000) * 1e-4
    u = np.select([t < 0.15, t < 0.35, t < 0.5], [2.0, -2.0, 2.0], 0.0)
    res = simulate(model, 2.0, applied_force=(t, u), initial_velocity=0.05,
                   initial_state="saturated", t_eval=t)  # fmt: skip
    meas = Measurement(t, position=res.position, velocity=res.velocity, applied_force=u)
    truth = {"mass": 2.0, "coulomb_level": 1.0, "coulomb": 0.3,
             **{f"stiffness_{j + 1}": float(x) for j, x in enumerate(k)}}  # fmt: skip
    for fit_initial, label in ((False, "7 parameters"), (True, "7 + initial velocity")):
        fit, best, med = timed(lambda fi=fit_initial: fit_response(meas, fit_initial=fi))
        err = max(abs(fit.parameters[n] / v - 1) for n, v in truth.items())
        print(f"fit_response, 10,000 samples, {label}: best {best:.3f} s, "
              f"median {med:.3f} s, {fit.n_evaluations} evaluations, status {fit.status}, "
              f"max rel. error {err:.1e}")  # fmt: skip


def bench_response_noise(noise: float = 0.003, seeds: int = 6) -> None:
    """Outcome over noise seeds with and without the multi-start and rigid-limit check."""
    k = [4000.0, 2000.0, 1000.0, 500.0]
    truth = {"mass": 2.0, "coulomb_level": 1.0, "coulomb": 0.3,
             **{f"stiffness_{j + 1}": x for j, x in enumerate(k)}}  # fmt: skip
    model = PIFriction(0.3, k, breakaway=[0.7 / 4] * 4)
    t = np.arange(3000) * 2.5e-4
    u = np.select([t < 0.15, t < 0.35, t < 0.5], [2.0, -2.0, 2.0], 0.0)
    res = simulate(model, 2.0, applied_force=(t, u), initial_velocity=0.05,
                   initial_state="saturated", t_eval=t)  # fmt: skip
    for multistart in (False, True):
        right = flagged = wrong = 0
        times = []
        for seed in range(seeds):
            rng = np.random.default_rng(seed)
            v = res.velocity + noise * np.ptp(res.velocity) * rng.standard_normal(t.shape)
            t0 = time.perf_counter()
            fit = fit_response(Measurement(t, velocity=v, applied_force=u), multistart=multistart)
            times.append(time.perf_counter() - t0)
            ci = fit.confidence_interval
            inside = all(ci[n][0] <= x <= ci[n][1] for n, x in truth.items())
            if fit.status != "converged":
                flagged += 1
            elif inside:
                right += 1
            else:
                wrong += 1
        print(f"fit_response, 3000 samples, velocity noise {100 * noise:g} % of range, "
              f"{seeds} seeds, multistart={multistart}: {right} converged with the truth in "
              f"the 95 % intervals, {flagged} flagged not identifiable, {wrong} wrongly "
              f"converged; median {statistics.median(times):.2f} s")  # fmt: skip


def bench_synthetic() -> None:
    model = PIFriction(0.3, [50.0, 20.0, 5.0], threshold=[0.01, 0.03, 0.1])
    path = piecewise_linear([0.0, 0.3, -0.3, 0.2, -0.1, 0.25, -0.3, 0.05] * 6, 1e-3)
    force, _ = model.force(path)
    fit, best, med = timed(lambda: fit_presliding(path, force, 3))
    print(f"fit_presliding, {path.size} samples, 3 elements: best {best:.3f} s, "
          f"median {med:.3f} s ({fit.status})")  # fmt: skip


def bench_emps() -> None:
    def load(name: str) -> Measurement:
        m = Measurement.from_mat(DATA / "emps" / name, position="qm", applied_force="vir",
                                 scale={"applied_force": "gtau"})  # fmt: skip
        return m.differentiate(cutoff=50.0, filter_forces=True)

    est, val = load("DATA_EMPS.mat"), load("DATA_EMPS_PULSES.mat")
    print("EMPS fit_motion(viscous=True, offset=True), 50 Hz zero-phase Butterworth:")
    for n in (0, 1, 2, 4):
        fit, best, _ = timed(lambda n=n: fit_motion(est, n, viscous=True, offset=True,
                                                    tolerance=1e-6), repeat=1)  # fmt: skip
        rms_val = fit_statistics(val.applied_force, predict_motion_force(fit, val))[0]
        p = fit.parameters
        line = (f"  N={n}: M {p['mass']:.2f} kg, Fv {p['viscous']:.1f} N s/m, "
                f"c1 {p['coulomb']:.2f} N, F_c {fit.model.coulomb_level:.2f} N, "
                f"offset {p['offset']:.3f} N; residual RMS {fit.residual_rms:.3f} N, "
                f"validation {rms_val:.3f} N ({best:.2f} s, {fit.status})")  # fmt: skip
        print(line)
        if n == 0:
            for name, ref in REFERENCE.items():
                print(f"    {name}: {p[name]:.3f} vs reference {ref} "
                      f"({100 * (p[name] / ref - 1):+.2f} %)")  # fmt: skip


def bench_tribometer() -> None:
    path = DATA / "tribometer" / "tribometer_loops.txt"
    normal = np.loadtxt(path, skiprows=1, usecols=(0, 1))
    full = normal[normal[:, 1] > 0.95 * np.median(normal[:, 1]), 0]
    m = Measurement.from_csv(path, "Time [s]", position="Position [mm]",
                             friction_force="Friction [uN]",
                             scale={"position": 1e-3, "friction_force": -1e-6},
                             ).window(full[0], full[-1])  # fmt: skip
    y, f = m.position, m.friction_force
    turns = reversal_indices(y, 2e-6)
    split = int(turns[2 * len(turns) // 3])
    burn = int(turns[0])
    for n in (2, 3, 4):
        fit, best, _ = timed(lambda n=n: fit_presliding(y[:split], f[:split], n, offset=True,
                                                        burn_in=burn), repeat=1)  # fmt: skip
        pred = fit.model.force(y)[0] + fit.parameters["offset"]
        _, nrmse, rel = fit_statistics(f[split:], pred[split:])
        print(f"tribometer, {n} elements: training NRMSE {100 * fit.nrmse:.2f} %, held-back "
              f"NRMSE {100 * nrmse:.2f} % (RMS/range), relative residual {100 * rel:.2f} % "
              f"({best:.2f} s, {fit.status}, F_c {fit.model.coulomb_level:.3f} N)")  # fmt: skip


if __name__ == "__main__":
    bench_response()
    bench_response_noise(0.003)
    bench_response_noise(0.001)
    bench_synthetic()
    if DATA.exists():
        bench_emps()
        bench_tribometer()
    else:
        print(f"measured data not found at {DATA}; skipped")
