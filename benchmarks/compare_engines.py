"""CPU of pooled fits on the same data through two or more versions of the fit engine.

Each engine is a ``src`` folder of the library (a git worktree of an older commit, say
``git worktree add ../old-engine 3345b9b~1``: the engine before the global search). Every
engine runs in a worker process of its own (``PYTHONPATH`` its ``src``, one BLAS thread),
started once and warmed up on each case (numba compiles or loads its kernels there); the
data are generated once here, with this checkout's library, and handed to every worker as
arrays. The repeats alternate between the engines (engine A, engine B, engine A, ...), so
that a busy machine slows both alike; each fit's CPU time is `time.process_time` inside the
worker around the one `fit_response` call.

The cases:

* ``stops s``: the pooled-fit benchmark (`bench_pooled_fit.py`, `_stops.stop_records`):
  20 records × 1000 samples, ``signal="both", initial_state="preload"``, data set s;
* ``servo ...``: the servo rig stand-in (`_stops.servo_stop_records`): 20 stops at 1 kHz of
  a rotary axis from steady turning under a small constant torque, a 10 000-count encoder;
  fitted with the defaults (``signal="both"``), with ``initial_state="preload"``, and with
  ``initial_state="preload", prune=True``.

Printed per case and engine: the median CPU seconds over the repeats (and their range),
the ratio to the first engine, the residual evaluations, the status, the cost ‖r‖² of the
fit (against the measured signals, the same for every engine), its residual RMS over the
noise floor and, for a pruned fit, its number of elements and the note.

Run::

    python benchmarks/compare_engines.py old=../old-engine/src now=src \\
        [--repeats 3] [--cases stops0,stops1,stops2,servo,servo-preload,servo-prune]

An engine given as ``label=path``; without any, this checkout's ``src`` alone.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ONE_THREAD = {v: "1" for v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                               "NUMBA_NUM_THREADS")}  # fmt: skip
CASES = {
    "stops0": ("stops", 0, {"signal": "both", "initial_state": "preload"}),
    "stops1": ("stops", 1, {"signal": "both", "initial_state": "preload"}),
    "stops2": ("stops", 2, {"signal": "both", "initial_state": "preload"}),
    "servo": ("servo", 0, {"signal": "both"}),
    "servo-preload": ("servo", 0, {"signal": "both", "initial_state": "preload"}),
    "servo-prune": ("servo", 0, {"signal": "both", "initial_state": "preload", "prune": True}),
}


# ---------------------------------------------------------------------- the worker
def worker() -> None:
    """Fits the data files it is sent (one JSON line each) and answers one JSON line each."""
    import time

    from presliding import Measurement, fit_response

    for line in sys.stdin:
        job = json.loads(line)
        data = np.load(job["path"])
        n = int(data["n"])
        records = [Measurement(data["t"], position=data["y"][i], velocity=data["v"][i],
                               applied_force=data["u"][i]) for i in range(n)]  # fmt: skip
        records = records[: job.get("records", n)]
        t0 = time.process_time()
        fit = fit_response(records, **job["options"])
        cpu = time.process_time() - t0
        r = np.asarray(fit.fitted) - np.asarray(fit.measured)
        k = [x for x in fit.parameters if x.startswith("stiffness_")]
        out = {"cpu": cpu, "nfev": int(fit.nfev), "status": fit.status, "cost": float(r @ r),
               "over": float(fit.search.residual_over_floor) if fit.search is not None
               else float("nan"), "elements": len(k),
               "shared": {x: float(v) for x, v in fit.parameters.items() if "_" not in x
                          or x.startswith(("stiffness", "coulomb"))},
               "notes": list(fit.notes)}  # fmt: skip
        print(json.dumps(out), flush=True)


class Engine:
    """A worker process running one engine."""

    def __init__(self, label: str, src: str) -> None:
        self.label, self.src = label, str(Path(src).resolve())
        env = {**os.environ, **ONE_THREAD, "PYTHONPATH": self.src}
        self.proc = subprocess.Popen(
            [sys.executable, str(Path(__file__).resolve()), "--worker"], env=env,
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
        )  # fmt: skip

    def fit(self, path: str, options: dict, records: int | None = None) -> dict:
        job = {"path": path, "options": options}
        if records is not None:
            job["records"] = records
        assert self.proc.stdin is not None and self.proc.stdout is not None
        self.proc.stdin.write(json.dumps(job) + "\n")
        self.proc.stdin.flush()
        line = self.proc.stdout.readline()
        if not line:
            raise RuntimeError(f"the engine {self.label!r} ({self.src}) stopped")
        return json.loads(line)

    def close(self) -> None:
        if self.proc.stdin is not None:
            self.proc.stdin.close()
        self.proc.wait()


# ---------------------------------------------------------------------- the parent
def save(design: str, seed: int, folder: str) -> str:
    """The records of a design as arrays in an npz file; its path."""
    sys.path.insert(0, str(HERE))
    from _stops import servo_stop_records, stop_records

    make = stop_records if design == "stops" else servo_stop_records
    records = make(seed, 20)[0]
    path = str(Path(folder) / f"{design}{seed}.npz")
    np.savez(path, n=len(records), t=records[0].time,
             y=np.array([m.position for m in records]), v=np.array([m.velocity for m in records]),
             u=np.array([m.applied_force for m in records]))  # fmt: skip
    return path


def _arguments(argv: list[str]) -> tuple[list[tuple[str, str]], int, list[str]]:
    engines, repeats, cases = [], 3, list(CASES)
    it = iter(argv)
    for a in it:
        if a == "--repeats":
            repeats = int(next(it))
        elif a == "--cases":
            cases = next(it).split(",")
        elif "=" in a:
            label, src = a.split("=", 1)
            engines.append((label, src))
        else:
            raise SystemExit(f"unknown argument {a!r} (engines as label=path/to/src)")
    unknown = [c for c in cases if c not in CASES]
    if unknown:
        raise SystemExit(f"unknown case(s) {unknown}; known: {', '.join(CASES)}")
    return engines or [("this", str(HERE.parent / "src"))], repeats, cases


def main(argv: list[str]) -> None:
    engines, repeats, cases = _arguments(argv)
    load = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as folder:
        paths = {}
        for case in cases:
            design, seed, _ = CASES[case]
            if (design, seed) not in paths:
                paths[design, seed] = save(design, seed, folder)
        workers = [Engine(label, src) for label, src in engines]
        try:
            for case in cases:  # compiled (or loaded from the cache) before any timing
                design, seed, options = CASES[case]
                for w in workers:
                    w.fit(paths[design, seed], {**options, "max_evaluations": 5}, records=2)
            rows = []
            for case in cases:
                design, seed, options = CASES[case]
                runs: dict[str, list[dict]] = {w.label: [] for w in workers}
                for _ in range(repeats):
                    for w in workers:
                        runs[w.label].append(w.fit(paths[design, seed], options))
                rows.append((case, runs))
                _print_case(case, runs)
        finally:
            for w in workers:
                w.close()
    _print_table(rows, [w.label for w in workers])
    print(f"load average (1 min) before / after: {load:.2f} / {os.getloadavg()[0]:.2f} on "
          f"{os.cpu_count()} cores; CPU seconds are process_time of the worker")  # fmt: skip


def _print_case(case: str, runs: dict[str, list[dict]]) -> None:
    first = None
    print(f"{case}:")
    for label, out in runs.items():
        cpu = [o["cpu"] for o in out]
        med = statistics.median(cpu)
        first = med if first is None else first
        last = out[-1]
        print(f"  {label:>8}: CPU {med:7.2f} s (range {min(cpu):.2f}..{max(cpu):.2f}) "
              f"= {med / first:5.2f} ×; {last['nfev']} evaluations, {last['status']}, "
              f"cost {last['cost']:.6g}, RMS/floor {last['over']:.3g}, "
              f"{last['elements']} elements", flush=True)  # fmt: skip
        shared = ", ".join(f"{x} {v:.4g}" for x, v in last["shared"].items())
        print(f"            {shared}")
        for note in last["notes"]:
            print(f"            note: {note}")


def _print_table(rows: list, labels: list[str]) -> None:
    head = "".join(f"{lab + ' s':>12}{'evals':>7}" for lab in labels)
    ratios = "".join(f"{lab + '/' + labels[0]:>14}" for lab in labels[1:])
    print(f"\n{'case':<15}{head}{ratios}")
    for case, runs in rows:
        meds = {lab: statistics.median(o["cpu"] for o in runs[lab]) for lab in labels}
        cells = "".join(f"{meds[lab]:>12.2f}{runs[lab][-1]['nfev']:>7d}" for lab in labels)
        rel = "".join(f"{meds[lab] / meds[labels[0]]:>14.2f}" for lab in labels[1:])
        print(f"{case:<15}{cells}{rel}")


if __name__ == "__main__":
    if sys.argv[1:] == ["--worker"]:
        worker()
    else:
        main(sys.argv[1:])
