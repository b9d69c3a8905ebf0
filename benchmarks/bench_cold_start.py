"""Cold and warm ``presliding demo`` in one run: the first-run cost of compiling the kernels.

Each round runs the README's first command, ``presliding demo``, in fresh
subprocesses: once with ``NUMBA_CACHE_DIR`` pointing to a new empty folder
(cold: every kernel is compiled), then twice more with the same folder (warm:
every kernel loads from the cache). The ratio cold / warm of each round is
measured under the same machine load; the script prints the median and the
range over the rounds (wall time, the target's measure, and CPU time of the
demo's processes, which other work on a shared machine disturbs less),
against the target of issue 17 (a cold demo in at most 3x its warm time on a
2-core machine).

With ``--one-core`` the demo runs pinned to one core (its second compiling
process is then not started), which shows what that process contributes.
``--profile`` also lists, for one cold run, the kernels the demo compiles and
the seconds each takes (numba's compile events; nested compiles indented).

    python benchmarks/bench_cold_start.py [--rounds 3] [--one-core] [--profile]
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

TARGET = 3.0

PROFILE = r"""
import sys, time
from numba.core import event
stack, rows, t0 = [], [], time.perf_counter()

class Timer(event.Listener):
    def on_start(self, ev):
        stack.append([ev.data["dispatcher"], time.perf_counter(), 0.0])

    def on_end(self, ev):
        disp, start, inner = stack.pop()
        took = time.perf_counter() - start
        if stack:
            stack[-1][2] += took
        name = f"{disp.py_func.__module__}.{disp.py_func.__qualname__}"
        rows.append((start - t0, len(stack), name, took, took - inner))

event.register("numba:compile", Timer())
from presliding.cli import main
code = main(sys.argv[1:])
top = sum(r[3] for r in rows if r[1] == 0)
print(f"{len(rows)} compilations, {top:.1f} s in top-level compiles (this process)")
print(f"{'start s':>8} {'total s':>8} {'own s':>7}  kernel")
for start, depth, name, took, own in rows:
    if took >= 0.1:
        print(f"{start:8.2f} {took:8.2f} {own:7.2f}  {'  ' * depth}{name}")
sys.exit(code)
"""


def cpu_name() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


def children_cpu() -> float:
    """CPU seconds (user + system) of every finished child process so far."""
    use = resource.getrusage(resource.RUSAGE_CHILDREN)
    return use.ru_utime + use.ru_stime


def run_demo(
    cache: Path, out: Path, one_core: bool, code: str | None = None
) -> tuple[float, float]:
    """Wall and CPU seconds of one ``presliding demo`` in a new process using the cache
    folder (CPU: the demo and the processes it waited for)."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    args = ["-c", code] if code else ["-m", "presliding"]
    cmd = [sys.executable, *args, "demo", "--quiet", "--overwrite", "-o", str(out)]

    def pin() -> None:
        if one_core:
            os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})

    start, cpu = time.perf_counter(), children_cpu()
    done = subprocess.run(cmd, env=env, preexec_fn=pin, capture_output=code is None, text=True)
    took, cpu = time.perf_counter() - start, children_cpu() - cpu
    if done.returncode != 0:
        raise SystemExit(f"presliding demo failed:\n{done.stderr}")
    return took, cpu


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=3, help="cold + warm rounds (median)")
    parser.add_argument("--one-core", action="store_true", help="pin the demo to one core")
    parser.add_argument("--profile", action="store_true", help="list compile times once")
    args = parser.parse_args()
    import numba

    print(f"CPU: {cpu_name()}; {os.cpu_count()} cores; numba {numba.__version__}")
    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    work = Path(tempfile.mkdtemp(prefix="presliding-cold-"))
    try:
        if args.profile:
            print("\ncold run, kernels compiled (>= 0.1 s):")
            run_demo(work / "profile-cache", work / "out", args.one_core, PROFILE)
            print()
        colds, warms, ratios, cpu_ratios = [], [], [], []
        for i in range(args.rounds):
            cache = work / f"cache-{i}"
            cache.mkdir()
            cold, cold_cpu = run_demo(cache, work / "out", args.one_core)
            again = [run_demo(cache, work / "out", args.one_core) for _ in "ab"]
            warm = statistics.median(w for w, _ in again)
            warm_cpu = statistics.median(c for _, c in again)
            colds.append(cold)
            warms.append(warm)
            ratios.append(cold / warm)
            cpu_ratios.append(cold_cpu / warm_cpu)
            print(f"round {i + 1}: cold {cold:6.2f} s, warm {warm:5.2f} s, ratio {cold / warm:.2f}"
                  f" (CPU time: cold {cold_cpu:6.2f} s, warm {warm_cpu:5.2f} s, ratio "
                  f"{cold_cpu / warm_cpu:.2f})")  # fmt: skip
    finally:
        shutil.rmtree(work, ignore_errors=True)

    def summary(x: list[float]) -> str:
        return f"{statistics.median(x):.2f} ({min(x):.2f}–{max(x):.2f})"

    ok = statistics.median(ratios) <= TARGET
    print(f"\ncold {summary(colds)} s; warm {summary(warms)} s")
    print(f"cold / warm {summary(ratios)}; target <= {TARGET}: {'met' if ok else 'MISSED'}")
    print(f"cold / warm in CPU time {summary(cpu_ratios)} (less disturbed by other work)")
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
