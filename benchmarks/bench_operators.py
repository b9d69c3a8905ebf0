"""Speed of the PI operator kernel (eq. 4 with the play update of eq. 3).

For banks of N = 5, 100 and 1000 elements, drives the compiled kernel
``_kernels.stop_sum`` along a random displacement path and prints

* element updates per second (N·T / time),
* nanoseconds per time step (median, and the best run),
* the same for ``PIOperator.apply`` (validation, state and direction included),
* the ratio to a plain numpy implementation measured in the same run: one
  vectorised numpy step per time sample (over fewer samples, scaled per step).

Every figure is the median over repeated runs; each run repeats the call until
it has lasted at least 0.1 s. Run it on an otherwise idle machine::

    python benchmarks/bench_operators.py [--repeats 7]
"""

from __future__ import annotations

import os

# one core: keep numpy's BLAS single-threaded for a fair comparison
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import platform  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402

import numpy as np  # noqa: E402

from presliding import PIOperator  # noqa: E402
from presliding.hysteresis import _kernels  # noqa: E402

#: bank size -> time steps per kernel call (fewer steps for larger banks)
CASES = {5: 1_000_000, 100: 200_000, 1000: 100_000}
#: time steps for the numpy baseline (one numpy step per sample is slow)
NUMPY_STEPS = {5: 20_000, 100: 20_000, 1000: 5_000}
#: targets on one core of a 2-core x86-64 (AVX2) machine (issue 8; wall clock here,
#: see benchmarks/bench_kernels.py for CPU-time figures on a shared machine)
TARGET_UPDATES_PER_S = {100: 3.6e9, 1000: 4.5e9}
TARGET_NS_PER_STEP = {5: 4.5}
MIN_RUN_S = 0.1


def bank(n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Thresholds spread over two decades and positive weights."""
    return 10 ** rng.uniform(-2.0, 0.0, n), 10 ** rng.uniform(0.0, 2.0, n)


def path(n_time: int, rng: np.random.Generator) -> np.ndarray:
    """A random walk whose moves make some elements stick and others slide."""
    return np.cumsum(rng.normal(0.0, 0.05, n_time))


def time_run(call: Callable[[], object]) -> float:
    """Seconds per call, from one run that repeats the call for at least MIN_RUN_S."""
    reps, start = 0, time.perf_counter()
    while True:
        call()
        reps += 1
        elapsed = time.perf_counter() - start
        if elapsed >= MIN_RUN_S:
            return elapsed / reps


def median_time(call: Callable[[], object], repeats: int) -> tuple[float, float]:
    """(median, best) seconds per call over `repeats` runs."""
    call()  # compile / warm up
    runs = [time_run(call) for _ in range(repeats)]
    return statistics.median(runs), min(runs)


def numpy_pi(y: np.ndarray, r: np.ndarray, w: np.ndarray, x: np.ndarray, out: np.ndarray) -> None:
    """Plain numpy: one vectorised play update and weighted sum per time sample."""
    lo = np.empty_like(r)
    hi = np.empty_like(r)
    f = np.empty_like(r)
    for t in range(y.shape[0]):
        yt = y[t]
        np.subtract(yt, r, out=lo)
        np.add(yt, r, out=hi)
        np.maximum(x, lo, out=x)
        np.minimum(x, hi, out=x)
        np.subtract(yt, x, out=f)
        out[t] = w @ f


def bench(n: int, n_time: int, repeats: int, rng: np.random.Generator) -> dict[str, float]:
    r, w = bank(n, rng)
    y = path(n_time, rng)
    out = np.empty(n_time)
    x = np.empty(n)

    def kernel() -> None:
        x[:] = y[0]
        _kernels.stop_sum(y, r, w, x, out)

    kernel_s, kernel_best_s = median_time(kernel, repeats)
    op = PIOperator(r, w)
    apply_s, _ = median_time(lambda: op.apply(y), repeats)

    n_np = NUMPY_STEPS[n]
    x_np = np.full(n, y[0])
    out_np = np.empty(n_np)
    numpy_s, _ = median_time(
        lambda: numpy_pi(y[:n_np], r, w, x_np.copy(), out_np), max(3, repeats // 2)
    )

    # the two implementations agree (same play update, sums within rounding)
    kernel()
    x_np = np.full(n, y[0])
    numpy_pi(y[:n_np], r, w, x_np, out_np)
    ref = np.empty(n_np)
    x_k = np.full(n, y[0])
    _kernels.stop_sum(y[:n_np], r, w, x_k, ref)
    assert np.array_equal(x_k, x_np), "kernel and numpy play states differ"
    assert np.allclose(ref, out_np, rtol=0, atol=1e-12 * float(w @ r))

    ns_step = kernel_s / n_time * 1e9
    return {
        "n": n,
        "steps": n_time,
        "updates_per_s": n * n_time / kernel_s,
        "ns_per_step": ns_step,
        "best_ns_per_step": kernel_best_s / n_time * 1e9,
        "apply_ns_per_step": apply_s / n_time * 1e9,
        "numpy_ns_per_step": numpy_s / n_np * 1e9,
        "speedup": (numpy_s / n_np * 1e9) / ns_step,
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=7, help="runs per figure (median)")
    args = parser.parse_args()

    load = os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, {platform.processor() or ''}")
    print(f"load average before: {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")
    print(f"median of {args.repeats} runs, each >= {MIN_RUN_S} s\n")
    header = (
        f"{'N':>5} {'T':>9} {'updates/s':>11} {'ns/step':>9} {'(best)':>7} {'apply ns/step':>14} "
        f"{'numpy ns/step':>14} {'x numpy':>8}  target"
    )
    print(header)
    print("-" * len(header))
    rng = np.random.default_rng(2024)
    ok = True
    for n, n_time in CASES.items():
        res = bench(n, n_time, args.repeats, rng)
        target = ""
        if n in TARGET_UPDATES_PER_S:
            met = res["updates_per_s"] >= TARGET_UPDATES_PER_S[n]
            target = f">= {TARGET_UPDATES_PER_S[n]:.0e} updates/s: {'met' if met else 'MISSED'}"
            ok &= met
        if n in TARGET_NS_PER_STEP:
            met = res["ns_per_step"] <= TARGET_NS_PER_STEP[n]
            target = f"<= {TARGET_NS_PER_STEP[n]:g} ns/step: {'met' if met else 'MISSED'}"
            ok &= met
        print(
            f"{n:>5} {n_time:>9.0e} {res['updates_per_s']:>11.3e} {res['ns_per_step']:>9.2f} "
            f"{res['best_ns_per_step']:>7.2f} "
            f"{res['apply_ns_per_step']:>14.2f} {res['numpy_ns_per_step']:>14.1f} "
            f"{res['speedup']:>8.0f}  {target}"
        )
    load = os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3
    print(f"\nload average after: {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")
    print("all targets met" if ok else "some targets missed (is the machine busy?)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
