"""Benchmark: a 10^5-point sweep of reversal counts, locally and on a Dask LocalCluster.

The map is the number of motion reversals of a free unit mass with PI friction
(eq. 12, N = 3 elements, F_m = 1), relaxed at the start, over the ratio c1/F_m
and the initial velocity, computed two ways:

``turning_points``
    the exact energy analysis (`presliding.analysis.stops`, eqs.
    13–16 walked reversal by reversal), one Python call per point (~0.3 ms):
    the motivating sweep, heavy enough for workers to pay off;
``simulate_batch``
    the exact event-driven batch (`presliding.simulate_batch`, one compiled
    thread per worker), about a microsecond per point: here start-up and
    transfer costs dominate.

Both must give the same counts; the benchmark checks that, and that every
backend returns the serial values exactly.

Run:  python benchmarks/bench_sweep.py [--points 100000] [--repeat 3]

Prints wall times for: serial in this process; the local default (a new pool
of worker processes on all cores per sweep, start-up included); a local pool
kept across sweeps (start-up excluded); and a LocalCluster with 1 and 2 workers
(cluster start-up excluded). Best of --repeat for simulate_batch, one run for
turning_points.
"""

from __future__ import annotations

import argparse
import os
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context

import numba as nb
import numpy as np

from presliding import PIFriction
from presliding.analysis import turning_points
from presliding.motion import simulate_batch
from presliding.sweep import sweep

STIFFNESS = np.array([200.0, 40.0, 10.0])
BREAKAWAY = np.array([0.3, 0.3, 0.4])  # F_m = 1


def analysis_counts(ratio: np.ndarray, velocity: np.ndarray) -> np.ndarray:
    """Reversal counts from the exact energy analysis, one point at a time."""
    out = np.empty(ratio.shape[0], dtype=np.int64)
    for i in range(ratio.shape[0]):
        model = PIFriction(float(ratio[i]), STIFFNESS, BREAKAWAY)
        res = turning_points(model, 1.0, float(velocity[i]))
        if res.status != "stopped":
            raise RuntimeError(f"point {i}: {res.message}")
        out[i] = res.n_reversals
    return out


def exact_counts(ratio: np.ndarray, velocity: np.ndarray) -> np.ndarray:
    """Exact reversal counts of the free motions (event method, one thread per worker)."""
    nb.set_num_threads(1)
    n = ratio.shape[0]
    res = simulate_batch(
        coulomb=ratio,  # F_m = 1
        stiffness=np.broadcast_to(STIFFNESS, (n, STIFFNESS.size)),
        breakaway=np.broadcast_to(BREAKAWAY, (n, BREAKAWAY.size)),
        initial_velocity=velocity,
        t_end=60.0,
        t_eval=[0.0, 60.0],
    )
    if not res.success or np.isinf(res.stop_time).any():
        raise RuntimeError(f"a motion did not stop within 60 s: {res.message}")
    return res.n_reversals


def _best(run, repeat):
    times, res = [], None
    for _ in range(repeat):
        res = run()
        assert res.status == "ok", res.message
        times.append(res.elapsed)
    return min(times), res


def _run_workload(name, fn, grid, repeat):
    from distributed import Client, LocalCluster

    fn(np.array([0.5]), np.array([1.0]))  # compile (or load the cache)
    print(f"workload {name}:")
    t_serial, serial = _best(lambda: sweep(fn, grid, n_workers=1), repeat)
    print(f"  serial (this process)           {t_serial:8.3f} s")
    t_local, local = _best(lambda: sweep(fn, grid), repeat)
    same = np.array_equal(local.values, serial.values)
    print(
        f"  local default ({local.n_workers} processes)     {t_local:8.3f} s   "
        f"x{t_serial / t_local:.2f} vs serial   equal values: {same}"
    )
    with ProcessPoolExecutor(os.cpu_count(), mp_context=get_context("forkserver")) as pool:
        sweep(fn, {"ratio": [0.5, 0.6], "velocity": [1.0]}, pool, chunk_size=1)  # start workers
        t_pool, pooled = _best(lambda: sweep(fn, grid, pool), repeat)
    same = np.array_equal(pooled.values, serial.values)
    print(
        f"  local pool kept ({pooled.n_workers} processes)   {t_pool:8.3f} s   "
        f"x{t_serial / t_pool:.2f} vs serial   equal values: {same}"
    )
    dask_times = {}
    for workers in (1, 2):
        with (
            LocalCluster(
                n_workers=workers,
                threads_per_worker=1,
                processes=True,
                host="127.0.0.1",
                dashboard_address=None,
            ) as cluster,
            Client(cluster) as client,
        ):
            sweep(fn, {"ratio": [0.5], "velocity": [1.0]}, client)  # warm the workers
            t, res = _best(lambda c=client: sweep(fn, grid, c), repeat)
            dask_times[workers] = t
            same = np.array_equal(res.values, serial.values)
            print(
                f"  LocalCluster, {workers} worker(s)        {t:8.3f} s   "
                f"x{t_serial / t:.2f} vs serial   equal values: {same}"
            )
    print(f"  LocalCluster 1 -> 2 workers: x{dask_times[1] / dask_times[2]:.2f}")
    return serial


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    n_ratio = 200
    n_vel = max(1, args.points // n_ratio)
    grid = {"ratio": np.linspace(0.05, 0.95, n_ratio), "velocity": np.linspace(0.2, 3.0, n_vel)}
    print(
        f"sweep of {n_ratio * n_vel} points (c1/F_m x v0), {os.cpu_count()} cores, "
        f"best of {args.repeat} (simulate_batch), 1 run (turning_points)"
    )
    batch = _run_workload(
        "simulate_batch (exact events, compiled)", exact_counts, grid, args.repeat
    )
    energy = _run_workload("turning_points (exact energy analysis)", analysis_counts, grid, 1)
    counts = np.bincount(energy.values.ravel())
    print("reversal counts over the map: " + ", ".join(f"{i}: {c}" for i, c in enumerate(counts)))
    print(f"turning_points and simulate_batch agree: {np.array_equal(energy.values, batch.values)}")


if __name__ == "__main__":
    main()
