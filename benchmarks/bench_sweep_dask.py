"""Benchmark: what a Dask sweep sends, and the speed-up of 2 local Dask workers.

Part 1, a 10^7-point grid on a LocalCluster of 2 worker processes (1 thread
each), an elementwise numpy function, as a product grid (two axes) and as a
table (a structured array of 10^7 rows):

``before``
    what `presliding.sweep` did until this release, rebuilt here: every chunk's
    columns are formed in this process and pickled into the task graph
    (``client.map(fn, chunks)``);
``after``
    `presliding.sweep.sweep`: the function and a product grid's axes are
    scattered to every worker once, a table's rows chunk by chunk (each row
    once), and each task carries two futures and an index range.

It prints the bytes in the task graph (cloudpickle of each task's arguments, as
the client sends them), the bytes scattered (the function and a product's axes
go to every worker, a table's rows once), the wall time
against a serial run in this process, and checks that the values agree.

Part 2, a sweep heavy enough to pay for itself: reversal counts of the free
motion by the exact energy analysis (`analysis.turning_points`, eqs. 13-16,
Python per point, one core), run serially in this process and on the 2 Dask
workers, in the same run.

Run:  python benchmarks/bench_sweep_dask.py [--points 10000000] [--heavy 8000] [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import cloudpickle
import numpy as np

from presliding import PIFriction
from presliding.analysis import turning_points
from presliding.sweep import sweep
from presliding.sweep._grid import as_points

STIFFNESS = np.array([200.0, 40.0, 10.0])
BREAKAWAY = np.array([0.3, 0.3, 0.4])  # F_m = 1
MIB = 2.0**20


def surface(ratio, velocity):
    """A cheap elementwise function: transfer and scheduling costs dominate."""
    return np.sin(3.0 * ratio) * np.exp(-0.1 * velocity**2) + ratio * velocity


def analysis_counts(ratio, velocity):
    """Reversal counts from the exact energy analysis, one point at a time (~0.3 ms each)."""
    out = np.empty(ratio.shape[0])
    for i in range(ratio.shape[0]):
        model = PIFriction(float(ratio[i]), STIFFNESS, BREAKAWAY)
        out[i] = turning_points(model, 1.0, float(velocity[i])).n_reversals
    return out


def _before_chunk(fn, columns):
    return fn(**columns)


def before(client, fn, grid, n_chunks):
    """The former way: chunk columns built here and pickled into the graph."""
    t0 = time.perf_counter()
    points = as_points(grid)
    chunks = [points.chunk(i, n_chunks) for i in range(n_chunks)]
    graph = sum(len(cloudpickle.dumps((fn, c))) for c in chunks)
    futures = client.map(_before_chunk, [fn] * n_chunks, chunks, pure=False)
    outs = client.gather(futures)
    values = np.empty(points.n_points)
    for i, out in enumerate(outs):
        values[i::n_chunks] = out
    return time.perf_counter() - t0, graph, values.reshape(points.shape)


def after(client, fn, grid, n_chunks, n_workers):
    """`sweep` itself; the graph's bytes measured on the way to the scheduler."""
    import distributed

    sent = []
    original = distributed.Client.map

    def spy(self, func, *iterables, **kwargs):
        sent.extend(len(cloudpickle.dumps(args)) for args in zip(*iterables, strict=True))
        return original(self, func, *iterables, **kwargs)

    distributed.Client.map = spy
    try:
        size = -(-as_points(grid).n_points // n_chunks)
        res = sweep(fn, grid, client, chunk_size=size)
    finally:
        distributed.Client.map = original
    assert res.success, res.message
    points = as_points(grid)
    if points.kind == "product":  # function and axes broadcast to every worker
        scattered = (len(cloudpickle.dumps(fn)) + points.nbytes) * n_workers
    else:  # function broadcast, each row sent once
        scattered = len(cloudpickle.dumps(fn)) * n_workers + points.nbytes
    return res.elapsed, sum(sent), scattered, res.values


def _median(values):
    return f"{statistics.median(values):7.2f} s ({min(values):.2f}-{max(values):.2f})"


def main() -> None:
    from distributed import Client, LocalCluster

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=10_000_000)
    parser.add_argument("--heavy", type=int, default=8_000, help="points of part 2")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    side = round(args.points**0.5)
    axes = {"ratio": np.linspace(0.05, 0.95, side), "velocity": np.linspace(0.2, 3.0, side)}
    table = np.empty(side * side, dtype=[("ratio", float), ("velocity", float)])
    mesh = np.meshgrid(axes["ratio"], axes["velocity"], indexing="ij")
    table["ratio"], table["velocity"] = mesh[0].ravel(), mesh[1].ravel()
    print(f"{os.cpu_count()} cores; median (range) of {args.repeat} runs")
    t_start = time.perf_counter()
    with (
        LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
            dashboard_address=None, memory_limit="6GiB",
        ) as cluster,
        Client(cluster) as client,
    ):  # fmt: skip
        client.wait_for_workers(2)
        startup = time.perf_counter() - t_start
        # import presliding on the workers and load the compiled kernels there
        sweep(analysis_counts, {"ratio": [0.5, 0.6], "velocity": [1.0]}, client)
        n_chunks = 8  # four per worker thread, as `sweep` sizes them by default
        print(f"\npart 1: {side * side:.3g} points, {n_chunks} chunks, 2 Dask workers")
        for name, grid in (("product grid", axes), ("table", table)):
            serial, t_before, t_after = [], [], []
            for _ in range(args.repeat):
                res = sweep(surface, grid, n_workers=1, chunk_size=-(-side * side // n_chunks))
                serial.append(res.elapsed)
                t, graph_before, v_before = before(client, surface, grid, n_chunks)
                t_before.append(t)
                t, graph_after, scattered, v_after = after(client, surface, grid, n_chunks, 2)
                t_after.append(t)
            same = np.array_equal(v_before, res.values) and np.array_equal(v_after, res.values)
            print(f"  {name}: serial {_median(serial)}")
            print(
                f"    before: graph {graph_before / MIB:9.2f} MiB, {_median(t_before)}, "
                f"x{statistics.median(serial) / statistics.median(t_before):.2f} vs serial"
            )
            print(
                f"    after:  graph {graph_after / 1024:9.2f} KiB, scattered "
                f"{scattered / MIB:.2f} MiB, {_median(t_after)}, "
                f"x{statistics.median(serial) / statistics.median(t_after):.2f} vs serial; "
                f"values equal: {same}"
            )
        n_ratio = 40
        heavy = {
            "ratio": np.linspace(0.05, 0.95, n_ratio),
            "velocity": np.linspace(0.2, 3.0, max(1, args.heavy // n_ratio)),
        }
        n_heavy = n_ratio * heavy["velocity"].size
        print(f"\npart 2: reversal counts by turning_points, {n_heavy} points")
        serial, dask = [], []
        for _ in range(args.repeat):
            ref = sweep(analysis_counts, heavy, n_workers=1)
            res = sweep(analysis_counts, heavy, client)
            assert np.array_equal(ref.values, res.values)
            serial.append(ref.elapsed)
            dask.append(res.elapsed)
        ratio = statistics.median(serial) / statistics.median(dask)
        print(f"  serial, this process:       {_median(serial)}")
        print(f"  2 Dask workers (warm):      {_median(dask)}   speed-up x{ratio:.2f}")
        print(f"  cluster start-up (once):    {startup:7.2f} s")


if __name__ == "__main__":
    main()
