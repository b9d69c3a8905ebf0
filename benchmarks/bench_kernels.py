"""Kernel figures at the machine limit (eqs. 4, 17): PI sum, fused batch loss, implicit stepper.

Prints, each against a reference measured in the same run:

1. the weighted stop sum (`_kernels.stop_sum`: time-blocked, with one-sided
   play updates for banks of 64 elements or more) for N = 5, 100, 1000 on a
   random walk (the input changes direction every other sample, the worst
   case for the per-step direction test), and for N = 1000 on a smooth decaying
   sine as well: element updates per second and ns per step, with the ratio to
   the straightforward kernel (`_kernels._stop_sum_short`) and to plain numpy
   (one vectorised step per sample);
2. the fused identification loss of a batch of B = 64 operators with N = 5
   (`_fused.batch_loss`, layout [N][B]) on one core and on all cores
   (`batch_loss_parallel`), against B calls of the straightforward kernel
   followed by a numpy loss;
3. the implicit stepper with stiction (`_implicit.run_implicit`), N = 5,
   against the same step written with the straightforward commit.

Timing on a shared machine: each figure is the median (and the best) of
``--repeats`` runs, each run repeating the call for >= 0.1 s. One-core
figures are given twice: wall clock, and the CPU time of the calling thread
(``time.thread_time``), which leaves out the time the thread waited for a
core while others ran; the load average is printed before and after. The
two-core figure is wall clock only (best and median), plus total CPU time of
the process for comparison. Run::

    python benchmarks/bench_kernels.py [--repeats 7]

To measure the code the AVX2+FMA reference machine kind gets on a host with
AVX-512, build for that target in a separate cache::

    NUMBA_CPU_NAME=haswell NUMBA_CPU_FEATURES=+fma NUMBA_CACHE_DIR=/tmp/nb-avx2 \\
        python benchmarks/bench_kernels.py
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import platform  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402

import numba as nb  # noqa: E402
import numpy as np  # noqa: E402

from presliding.hysteresis import _fused, _kernels  # noqa: E402
from presliding.motion import _implicit  # noqa: E402
from presliding.motion._run import implicit_grid  # noqa: E402

MIN_RUN_S = 0.1
STOP_CASES = [(5, 1_000_000, "walk"), (100, 200_000, "walk"), (1000, 100_000, "walk"),
              (1000, 100_000, "sine")]  # fmt: skip
NUMPY_STEPS = 20_000
TARGET_UPDATES = {100: 3.6e9, 1000: 4.5e9}
TARGET_NS = {5: 4.5}


def runs(call: Callable[[], object], repeats: int, clock: Callable[[], float]) -> list[float]:
    """Seconds per call for `repeats` runs, each repeating the call for >= MIN_RUN_S."""
    call()  # compile / warm up
    out = []
    for _ in range(repeats):
        reps, start = 0, clock()
        while True:
            call()
            reps += 1
            elapsed = clock() - start
            if elapsed >= MIN_RUN_S:
                break
        out.append(elapsed / reps)
    return out


def measure(call: Callable[[], object], repeats: int) -> dict[str, float]:
    """Median and best seconds per call, wall clock and thread CPU time."""
    wall = runs(call, repeats, time.perf_counter)
    cpu = runs(call, repeats, time.thread_time)
    return {
        "wall": statistics.median(wall),
        "wall_best": min(wall),
        "cpu": statistics.median(cpu),
        "cpu_best": min(cpu),
    }


def load() -> str:
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def verdict(ok: bool) -> str:
    return "met" if ok else "MISSED"


# ----------------------------------------------------------------------------- 1. stop sum
def numpy_pi(y, r, w, x, out) -> None:
    """Plain numpy: one vectorised play update and weighted sum per sample."""
    for t in range(y.shape[0]):
        np.minimum(np.maximum(x, y[t] - r, out=x), y[t] + r, out=x)
        out[t] = w @ (y[t] - x)


def bench_stop_sum(repeats: int, rng: np.random.Generator) -> bool:
    print("1. weighted stop sum (eq. 4), one core; CPU = thread CPU time, wall = wall clock")
    head = (
        f"{'N, input':>10} {'upd/s CPU med':>14} {'(best)':>9} {'ns/step CPU':>12} {'(best)':>7} "
        f"{'wall med':>9} {'(best)':>7} {'x straight':>11} {'x numpy':>8}  target"
    )
    print(head)
    ok = True
    for n, n_time, kind in STOP_CASES:
        r = 10 ** rng.uniform(-2.0, 0.0, n)
        w = 10 ** rng.uniform(0.0, 2.0, n)
        if kind == "walk":
            y = np.cumsum(rng.normal(0.0, 0.05, n_time))
        else:
            y = np.linspace(1.0, 0.1, n_time) * np.sin(np.linspace(0.0, 200.0, n_time))
        x = np.empty(n)
        out = np.empty(n_time)

        def fast(x=x, y=y, r=r, w=w, out=out) -> None:
            x[:] = y[0]
            _kernels.stop_sum(y, r, w, x, out)

        def straight(x=x, y=y, r=r, w=w, out=out) -> None:
            x[:] = y[0]
            _kernels._stop_sum_short(y, r, w, x, out)

        f = measure(fast, repeats)
        s = measure(straight, repeats)
        yn = y[:NUMPY_STEPS]
        npy = measure(
            lambda r=r, w=w, yn=yn: numpy_pi(yn, r, w, np.full(r.size, yn[0]), np.empty(yn.size)),
            3,
        )
        ns = f["cpu"] / n_time * 1e9
        upd = n * n_time / f["cpu"]
        target = ""
        if n in TARGET_UPDATES:
            target = f">= {TARGET_UPDATES[n]:.1e}: {verdict(upd >= TARGET_UPDATES[n])}"
            ok &= upd >= TARGET_UPDATES[n]
        if n in TARGET_NS:
            target = f"<= {TARGET_NS[n]} ns: {verdict(ns <= TARGET_NS[n])}"
            ok &= ns <= TARGET_NS[n]
        print(
            f"{f'{n}, {kind}':>10} {upd:>14.3e} {n * n_time / f['cpu_best']:>9.2e} {ns:>12.2f} "
            f"{f['cpu_best'] / n_time * 1e9:>7.2f} {f['wall'] / n_time * 1e9:>9.2f} "
            f"{f['wall_best'] / n_time * 1e9:>7.2f} {s['cpu'] / f['cpu']:>11.2f} "
            f"{npy['cpu'] / NUMPY_STEPS / (f['cpu'] / n_time):>8.0f}  {target}"
        )
    return ok


# ----------------------------------------------------------------------------- 2. fused loss
def bench_loss(repeats: int, rng: np.random.Generator) -> bool:
    n, n_batch, n_time = 5, 64, 100_000
    updates = n * n_batch * n_time
    r = 10 ** rng.uniform(-2.0, 0.0, (n, n_batch))
    w = 10 ** rng.uniform(0.0, 2.0, (n, n_batch))
    a = rng.normal(0.0, 1.0, n_batch)
    offset = np.zeros(n_batch)
    y = np.cumsum(rng.normal(0.0, 0.05, n_time))
    target = rng.normal(0.0, 1.0, n_time)
    x = np.empty((n, n_batch))
    loss = np.empty(n_batch)
    rows_r = [np.ascontiguousarray(r[:, b]) for b in range(n_batch)]
    rows_w = [np.ascontiguousarray(w[:, b]) for b in range(n_batch)]

    def fused(kernel) -> Callable[[], None]:
        def call() -> None:
            x[:] = y[0]
            loss[:] = 0.0
            kernel(y, y, target, r, w, a, offset, x, loss)

        return call

    def straight() -> None:
        out = np.empty(n_time)
        for b in range(n_batch):
            xb = np.full(n, y[0])
            _kernels._stop_sum_short(y, rows_r[b], rows_w[b], xb, out)
            e = out + a[b] * y - target
            loss[b] = e @ e

    print(
        f"\n2. fused identification loss, B = {n_batch}, N = {n}, T = {n_time:.0e} (layout [N][B])"
    )
    one = measure(fused(_fused.batch_loss), repeats)
    ref = measure(straight, max(3, repeats // 2))
    upd = updates / one["cpu"]
    print(
        f"   one core : {upd:.3e} updates/s CPU median (best {updates / one['cpu_best']:.3e}); "
        f"wall median {updates / one['wall']:.3e} (best {updates / one['wall_best']:.3e}); "
        f"x {ref['cpu'] / one['cpu']:.1f} vs B straightforward kernels + numpy loss  "
        f"target >= 3e9: {verdict(upd >= 3e9)}"
    )
    par = fused(_fused.batch_loss_parallel)
    wall = runs(par, repeats, time.perf_counter)
    proc = runs(par, repeats, time.process_time)
    best = updates / min(wall)
    print(
        f"   {nb.get_num_threads()} threads: {updates / statistics.median(wall):.3e} updates/s "
        f"wall median"
        f" (best {best:.3e}); total CPU of the process {statistics.median(proc) / one['cpu']:.2f}x"
        f" the one-core CPU time  target >= 5e9 (wall best): {verdict(best >= 5e9)}"
    )
    return upd >= 3e9 and best >= 5e9


# ----------------------------------------------------------------------------- 3. stepper
@nb.njit(fastmath={"nsz", "arcp", "contract"}, error_model="numpy")
def straight_stepper(m, c1, k, r, f, y, v, t_grid, u_mid):  # pragma: no cover
    """The implicit step with the straightforward `_commit` (no outputs recorded)."""
    ktot = 0.0
    for j in range(k.shape[0]):
        ktot += k[j]
    fel, kpos, kneg, _, dpos, dneg = _implicit._commit(k, r, f, 0.0)
    dis = 0.0
    for i in range(t_grid.shape[0] - 1):
        h = t_grid[i + 1] - t_grid[i]
        inv_h = 1.0 / h
        m_h = m * inv_h
        mh2 = m_h * inv_h
        g = m_h * v + u_mid[i] - fel
        if abs(g) <= c1:
            v = 0.0
            continue
        if g > 0.0:
            s, b, slope, dist = 1.0, g - c1, mh2 + ktot - kpos, dpos
        else:
            s, b, slope, dist = -1.0, -g - c1, mh2 + ktot - kneg, dneg
        d = b / slope
        if d >= dist:
            d = _implicit._newton_walk(mh2, k, r, f, s, b, slope, d)
        fel, kpos, kneg, dplastic, dpos, dneg = _implicit._commit(k, r, f, s * d)
        y += s * d
        v = s * d * inv_h
        dis += c1 * d + dplastic
    return y, v, dis


def bench_stepper(repeats: int) -> bool:
    m, c1 = 1.0, 0.3
    k = np.array([400.0, 200.0, 100.0, 50.0, 25.0])
    r = np.array([0.001, 0.002, 0.004, 0.008, 0.016])
    n = 1_000_000
    grid, out_idx = implicit_grid(0.0, 10.0, np.array([0.0, 10.0]), 10.0 / n)
    print(f"\n3. implicit stepper with stiction, N = 5, {n:.0e} steps of 1e-5 s, one core")
    ok = True
    for amp, regime in ((3.0, "reversing gross sliding"), (1.0, "presliding, stick-slip")):
        u = amp * np.sin(np.pi * 0.5 * (grid[1:] + grid[:-1]))
        o = [np.zeros(2) for _ in range(8)]
        rev = [np.zeros(1024) for _ in range(2)]

        def fast(u=u, o=o, rev=rev) -> None:
            _implicit.run_implicit(m, c1, k, r, np.zeros(5), 0.0, 0.0, 0.0, grid, u, out_idx,
                                   *o, *rev)  # fmt: skip

        f = measure(fast, repeats)
        s = measure(lambda u=u: straight_stepper(m, c1, k, r, np.zeros(5), 0.0, 0.0, grid, u), 3)
        ns = f["cpu"] / n * 1e9
        ok &= ns <= 18.0
        print(
            f"   {regime:24s}: {ns:6.2f} ns/step CPU median (best {f['cpu_best'] / n * 1e9:.2f}); "
            f"wall {f['wall'] / n * 1e9:.2f} (best {f['wall_best'] / n * 1e9:.2f}); "
            f"x {s['cpu'] / f['cpu']:.2f} vs a bare straightforward step (no outputs)  "
            f"target <= 18 ns: {verdict(ns <= 18)}"
        )
    return ok


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=7, help="runs per figure (median)")
    parser.add_argument("--only", choices=("stop", "loss", "stepper"), default=None)
    args = parser.parse_args()
    from numba.core import config

    cpu = config.CPU_NAME or "host"
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores; numba target cpu: {cpu}, "
          f"features: {config.CPU_FEATURES or 'host'}")  # fmt: skip
    print(
        f"load average before: {load()}; median (best) of {args.repeats} runs, "
        f"each >= {MIN_RUN_S} s\n"
    )
    rng = np.random.default_rng(2024)
    ok = True
    if args.only in (None, "stop"):
        ok &= bench_stop_sum(args.repeats, rng)
    if args.only in (None, "loss"):
        ok &= bench_loss(args.repeats, rng)
    if args.only in (None, "stepper"):
        ok &= bench_stepper(args.repeats)
    print(f"\nload average after: {load()}")
    print("all targets met" if ok else "some targets missed (is the machine busy?)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
