"""First calls on an empty numba cache against warm ones: ``presliding demo``, ``simulate``,
``fit_response``.

Each round runs every entry point in fresh subprocesses: once with
``NUMBA_CACHE_DIR`` pointing to a new empty folder (cold: every kernel the call
needs is compiled), then twice more with the same folder (warm: every kernel
loads from the cache; the median of the two is the round's warm figure). Cold
and warm of a round run back to back, under the same machine load. The entry
points: ``demo`` is the README's first command, ``presliding demo``;
``simulate`` is the quickstart's first `simulate` (a mass with four elements
stopping from saturation); ``fit_response`` is the pooled fit of the user
guide (three stops, two elements, output error on the position), on records
simulated beforehand in this process (so the cold child compiles only what the
fit itself needs, as for measured data). For each it prints the CPU time (user
+ system, from ``resource.getrusage`` of the finished child: the whole process
and any process it waited for) and, for the two functions, the CPU time of the
call alone (``time.process_time`` around it in the child), with the ratio cold
/ warm and the target of issue 36: a first call in at most 3x the warm call's
CPU time plus 10 s. Wall times are printed beside them; on Linux also the CPU
seconds that other processes used during each cold run (from /proc/stat), to
tell a loaded machine apart.

The cold run of the first round also records every kernel numba compiles, in
every process of the tree (numba's ``"numba:compile"`` events, which it sends
only on cache misses, timed in CPU seconds; a kernel's own time leaves out the
kernels compiled while it was, which are listed on their own): the script prints
the most costly with their argument types. The listener is installed through a
``sitecustomize`` module on ``PYTHONPATH`` and adds a few calls per compiled
kernel. ``--no-profile`` leaves it out.

    python benchmarks/bench_cold_start.py [--entry demo simulate fit_response] [--rounds 1]
        [--no-profile] [--top 10]

With ``--network`` it measures the first `simulate_network` instead (see
``_cold_network.py``).
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

#: a first call may cost this many times the warm call's CPU time, plus `TARGET_PLUS` s
TARGET_TIMES = 3.0
TARGET_PLUS = 10.0
ENTRIES = ("demo", "simulate", "fit_response")

#: sitecustomize of the profiled cold run: every process of the tree writes the kernels
#: it compiled (CPU seconds) to COLD_START_PROFILE/<pid>.json at exit
SITECUSTOMIZE = r"""
import atexit, json, os, sys, time
_out = os.environ.get("COLD_START_PROFILE")
if _out:
    from numba.core import event
    _stack, _rows = [], []

    class _Timer(event.Listener):
        def on_start(self, ev):
            _stack.append([ev.data["dispatcher"], ev.data.get("args"), time.process_time(), 0.0])

        def on_end(self, ev):
            disp, args, start, inner = _stack.pop()
            took = time.process_time() - start
            if _stack:
                _stack[-1][3] += took
            func = disp.py_func
            _rows.append({"kernel": f"{func.__module__}.{func.__qualname__}",
                          "args": str(args), "took": took, "own": took - inner,
                          "nested": bool(_stack)})

    event.register("numba:compile", _Timer())

    _born = time.time()

    def _dump():
        name = " ".join(sys.argv[1:])[-30:] or "python"
        with open(os.path.join(_out, f"{os.getpid()}.json"), "w") as fh:
            json.dump({"rows": _rows, "cpu": time.process_time(), "argv": name,
                       "wall": time.time() - _born}, fh)

    atexit.register(_dump)
"""


# ---------------------------------------------------------------- the entry points (children)
def stage_model():  # the quickstart's stage
    import presliding as ps

    return ps.PIFriction(coulomb=0.3, stiffness=[2e4, 5e3, 1.5e3, 500.0], breakaway=[0.175] * 4)


def write_records(path: Path) -> None:
    """The user guide's three stops (pooled fits), simulated here and saved for the child."""
    import numpy as np

    import presliding as ps

    truth = ps.PIFriction(coulomb=0.3, stiffness=[4000.0, 1000.0], breakaway=[0.35, 0.35])
    t = np.arange(600) * 1e-3
    arrays = {"t": t}
    for i, v0 in enumerate((0.03, -0.045, 0.06)):
        d = np.sign(v0)
        u = np.where(t < 0.05, -0.3 * d, 0.0)
        memory = ps.preloaded_state(truth, 0.5 * d, direction=d)
        res = ps.simulate(truth, 2.0, applied_force=(t, u), initial_velocity=v0,
                          initial_state=memory, t_eval=t)  # fmt: skip
        arrays[f"y{i}"] = 1e-7 * np.round(res.position / 1e-7)
        arrays[f"u{i}"] = u
    np.savez(path, **arrays)


def child(entry: str, data: str) -> int:
    """Run one entry point in this (fresh) process; print the call's CPU seconds as JSON."""
    import numpy as np

    import presliding as ps

    if entry == "simulate":
        model = stage_model()
        start = time.process_time()
        res = ps.simulate(model, mass=1.0, initial_velocity=0.06, initial_state="saturated",
                          t_end=0.1)  # fmt: skip
        took = time.process_time() - start
        ok = res.success
    else:
        arrays = np.load(data)
        records = [ps.Measurement(arrays["t"], position=arrays[f"y{i}"],
                                  applied_force=arrays[f"u{i}"]) for i in range(3)]  # fmt: skip
        start = time.process_time()
        fit = ps.fit_response(records, n_elements=2, signal="position", initial_state="preload")
        took = time.process_time() - start
        ok = fit.success
    print(json.dumps({"call": took, "ok": bool(ok)}))
    return 0


# ---------------------------------------------------------------- the parent
def cpu_name() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


def children_cpu() -> float:
    """CPU seconds (user + system) of every finished child process so far (and of the
    processes they waited for)."""
    use = resource.getrusage(resource.RUSAGE_CHILDREN)
    return use.ru_utime + use.ru_stime


def machine_busy() -> float | None:
    """CPU seconds all processes of the machine have used since boot (None: not Linux)."""
    try:
        fields = Path("/proc/stat").read_text().split("\n", 1)[0].split()[1:]
        user, nice, system, _idle, _iowait, irq, softirq, steal = map(int, fields[:8])
        return (user + nice + system + irq + softirq + steal) / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError):
        return None


class Run:
    """One child process: wall and CPU seconds (whole process), the call's CPU seconds (the
    two functions), other processes' CPU seconds meanwhile."""

    def __init__(self, wall: float, cpu: float, call: float | None, others: float | None):
        self.wall, self.cpu, self.call, self.others = wall, cpu, call, others


def run_entry(entry: str, cache: Path, work: Path, profile: Path | None = None) -> Run:
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    if profile is not None:
        site = profile / "site"
        site.mkdir(parents=True, exist_ok=True)
        (site / "sitecustomize.py").write_text(SITECUSTOMIZE)
        path = os.pathsep.join(p for p in (str(site), env.get("PYTHONPATH")) if p)
        env.update(PYTHONPATH=path, COLD_START_PROFILE=str(profile))
    if entry == "demo":
        out = work / "demo-out"
        cmd = [sys.executable, "-m", "presliding", "demo", "--quiet", "--overwrite", "-o", str(out)]
    else:
        cmd = [sys.executable, __file__, "--child", entry, str(work / "records.npz")]
    start, cpu, busy = time.perf_counter(), children_cpu(), machine_busy()
    done = subprocess.run(cmd, env=env, capture_output=True, text=True)
    took, cpu, after = time.perf_counter() - start, children_cpu() - cpu, machine_busy()
    if done.returncode != 0:
        raise SystemExit(f"{entry} failed:\n{done.stderr}")
    call = None
    if entry != "demo":
        report = json.loads(done.stdout.strip().splitlines()[-1])
        if not report["ok"]:
            raise SystemExit(f"{entry}: the call did not succeed")
        call = report["call"]
    others = None if busy is None or after is None else max(after - busy - cpu, 0.0)
    return Run(took, cpu, call, others)


def load_note(run: Run) -> str:
    """Other processes' CPU seconds during a run and the cores they left to it."""
    if run.others is None:
        return ""
    left = (os.cpu_count() or 1) - run.others / run.wall
    return f"others {run.others:.1f} s CPU meanwhile ({left:.1f} cores left)"


def print_profile(folder: Path, top: int) -> None:
    """The kernels compiled in the profiled cold run, most costly first."""
    procs = [json.loads(p.read_text()) for p in sorted(folder.glob("*.json"))]
    rows = [r for p in procs for r in p["rows"]]
    print(f"\n  {len(rows)} compilations in {len(procs)} process(es)")
    for p in procs:
        own = sum(r["own"] for r in p["rows"])
        print(f"  {p['argv']:>30}: {p['cpu']:6.2f} s CPU in {p['wall']:6.2f} s, "
              f"{own:6.2f} s compiling ({len(p['rows'])} kernels)")  # fmt: skip
    by = collections.defaultdict(list)
    for r in rows:
        by[r["kernel"]].append(r)
    ranked = sorted(by.items(), key=lambda kv: -sum(r["own"] for r in kv[1]))
    print(f"  {'own CPU s':>9} {'with nested':>11} {'times':>5}  kernel (argument types)")
    for name, rs in ranked[:top]:
        own = sum(r["own"] for r in rs)
        took = sum(r["took"] for r in rs)
        print(f"  {own:9.2f} {took:11.2f} {len(rs):5d}  {name.removeprefix('presliding.')}")
        for r in rs[:3]:
            args = r["args"].replace("Array(float64, ", "f8[").replace(", aligned=True)", "]")
            print(f"{'':31}{args[:140]}{'...' if len(args) > 140 else ''}")
    print()


def median(values: list[float | None]) -> float | None:
    return None if None in values else statistics.median(values)


def target(warm: float) -> float:
    return TARGET_TIMES * warm + TARGET_PLUS


def summary(entry: str, what: str, pairs: list[tuple[float, float]]) -> bool:
    cold = statistics.median(c for c, _ in pairs)
    warm = statistics.median(w for _, w in pairs)
    ok = cold <= target(warm)
    print(f"{entry:>12} {what:<17} cold {cold:7.2f} s, warm {warm:6.2f} s, cold / warm "
          f"{cold / warm:5.2f}; target <= {TARGET_TIMES:g} x warm + {TARGET_PLUS:g} s = "
          f"{target(warm):.2f} s: {'met' if ok else 'MISSED'}")  # fmt: skip
    return ok


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--entry", nargs="+", choices=ENTRIES, default=list(ENTRIES))
    parser.add_argument("--rounds", type=int, default=1, help="cold + warm rounds (median)")
    parser.add_argument("--no-profile", action="store_true", help="no per-kernel table")
    parser.add_argument("--top", type=int, default=10, help="kernels listed (default 10)")
    parser.add_argument("--child", nargs=2, metavar=("ENTRY", "DATA"), help=argparse.SUPPRESS)
    parser.add_argument(
        "--network",
        action="store_true",
        help="the first simulate_network instead of the demo (_cold_network.py)",
    )
    args = parser.parse_args()
    if args.child:
        return child(*args.child)
    if args.network:
        from _cold_network import main as network_main

        return network_main(args.rounds)
    import numba

    print(f"CPU: {cpu_name()}; {os.cpu_count()} cores; numba {numba.__version__}")
    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    work = Path(tempfile.mkdtemp(prefix="presliding-cold-"))
    figures: dict[tuple[str, str], list[tuple[float, float]]] = collections.defaultdict(list)
    try:
        if "fit_response" in args.entry:
            write_records(work / "records.npz")
        for i in range(args.rounds):
            for entry in args.entry:
                cache = work / f"cache-{entry}-{i}"
                cache.mkdir()
                profile = None if args.no_profile or i else work / f"profile-{entry}"
                cold = run_entry(entry, cache, work, profile)
                again = [run_entry(entry, cache, work) for _ in "ab"]
                fields = ("wall", "cpu", "call")
                warm = Run(*(median([getattr(r, a) for r in again]) for a in fields), None)
                if cold.call is not None and warm.call is not None:
                    figures[(entry, "CPU, the call")].append((cold.call, warm.call))
                figures[(entry, "CPU, the process")].append((cold.cpu, warm.cpu))
                figures[(entry, "wall, the process")].append((cold.wall, warm.wall))
                call = "" if cold.call is None else (
                    f"; the call {cold.call:.2f} s cold, {warm.call:.2f} s warm")  # fmt: skip
                print(f"round {i + 1}, {entry}: process CPU cold {cold.cpu:.2f} s, warm "
                      f"{warm.cpu:.2f} s (wall {cold.wall:.2f} s, {warm.wall:.2f} s){call}; "
                      f"cold run: {load_note(cold)}")  # fmt: skip
                if profile is not None:
                    print_profile(profile, args.top)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print()
    for (entry, what), pairs in figures.items():
        summary(entry, what, pairs)
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
