"""How the exact network path scales with the number of contacts (issue 36, item 2).

A chain of n masses (0.1 kg, springs 2e3 N/m) on n PI contacts (4 elements each), the last
mass pushed by a force that reverses every 20 ms, from a sine of initial velocities; the
event-driven `simulate_network` runs for `T` seconds. Printed per n: the events, the CPU time
(`time.process_time`, after a warm-up on the smallest chain), the CPU per event and its ratio
to the smallest chain's, and the peak resident memory of the process that ran it (each size
in a fresh process, so the peaks do not mix). The exact path is dense (its pieces are modes of
the full structure): sizes whose matrices do not fit are refused before allocating, and the
table says so.

Run: PYTHONPATH=src python benchmarks/network_scaling.py [--sizes 10,30,100,300,1000] [--t 0.02]
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time


def one(n: int, t_end: float) -> dict:
    import numpy as np

    from presliding import PIFriction
    from presliding.network import chain_structure, simulate_network

    model = PIFriction(0.2, [2e3, 1e3, 500.0, 200.0], [0.1, 0.1, 0.1, 0.1])
    times = np.arange(0.0, t_end + 0.02, 0.02)
    force = np.zeros((times.size, n))
    force[:, -1] = 2.0 * (-1.0) ** np.arange(times.size)
    try:
        s = chain_structure(n, 0.1, 2e3, model, forcing=(times, force))
    except ValueError as exc:
        return {"n": n, "refused": str(exc)}
    v0 = 0.3 * np.sin(np.arange(n))
    warm = chain_structure(3, 0.1, 2e3, model, forcing=(times, force[:, :3]))
    simulate_network(warm, t_end, None, v0[:3])  # loads (or compiles) the kernels
    t0 = time.process_time()
    res = simulate_network(s, t_end, None, v0, t_eval=[0.0, t_end])
    cpu = time.process_time() - t0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # MiB (Linux: KiB)
    return {"n": n, "events": int(res.n_events), "cpu": cpu, "peak_mib": peak,
            "status": res.status}  # fmt: skip


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", default="10,30,100,300,1000")
    parser.add_argument("--t", type=float, default=0.02, help="simulated seconds")
    parser.add_argument("--child", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(one(args.child, args.t)))
        return 0
    rows = []
    for n in (int(x) for x in args.sizes.split(",")):
        out = subprocess.run([sys.executable, __file__, "--child", str(n), "--t", str(args.t)],
                             capture_output=True, text=True, env=os.environ.copy())  # fmt: skip
        if out.returncode != 0:
            print(f"n = {n}: failed: {out.stderr.strip().splitlines()[-1:]}")
            continue
        rows.append(json.loads(out.stdout.strip().splitlines()[-1]))
    base = next((r["cpu"] / max(r["events"], 1) for r in rows if "cpu" in r), None)
    head = ("contacts", "events", "CPU s", "µs/event", "ratio", "peak MiB")
    print(" ".join(f"{h:>{w}}" for h, w in zip(head, (8, 7, 9, 9, 7, 9), strict=True)))
    for r in rows:
        if "refused" in r:
            print(f"{r['n']:>8} refused before allocating: {r['refused']}")
            continue
        per = r["cpu"] / max(r["events"], 1)
        ratio = per / base if base else float("nan")
        print(f"{r['n']:>8} {r['events']:>7} {r['cpu']:>9.3f} {1e6 * per:>9.0f} {ratio:>7.1f} "
              f"{r['peak_mib']:>9.0f}  {r['status']}")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
