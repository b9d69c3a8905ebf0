"""Study of the residual tests (issue 34): does a fit know when its model is wrong?

Data from `_misfits.py` (issue 34's review design: m = 1.5 kg, c1 = 0.2 N, F_c = 0.8 N,
three elements; six 800-sample sine-driven records from random preloads, 1 µm encoder,
0.2 µm noise), fitted with ``fit_response(records, N, signal="both",
initial_state="preload")`` (N = 3, or 0 and 1 for the too-few-elements classes). Per
class and seed: the status, the cause the message names, and whether a shared parameter
with a truth (mass, F_c, c1 and, where the model has them, the stiffnesses) lies outside
its 95 % interval. Printed per class:

* wrong converged: the share of fits called ``converged`` with a shared parameter outside
  its interval (target ≤ 5 %);
* names the model: the share ``model_inadequate`` (target ≥ 90 % for a misfit class);
* for the correctly specified classes (``none``, ``noise5``): the share ``converged`` or
  ``not_identifiable`` (target ≥ 90 %) and the coverage of each shared parameter;
* the causes named, and the CPU time per fit.

Run: python benchmarks/study_adequacy.py [seeds] [--classes none,n0,...] [--signal both]
"""

from __future__ import annotations

import argparse
import sys
import time
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _misfits as mf

from presliding import fit_response

#: shared parameters with a truth whatever the misfit (the stiffnesses only with elements)
SHARED = ("mass", "coulomb_level", "coulomb")
#: classes whose data the fitted model describes
CORRECT = ("none", "noise5")


def study(misfit: str, seeds: int, signal: str) -> None:
    statuses: Counter[str] = Counter()
    causes: Counter[str] = Counter()
    cover: dict[str, list[bool]] = {}
    wrong = 0
    cpu = 0.0
    truth = mf.truth()
    n = mf.n_elements(misfit)
    with_k = misfit in CORRECT or misfit.startswith(("delay", "viscous", "asymmetric"))
    names = [*SHARED] + ([f"stiffness_{j + 1}" for j in range(3)] if with_k else [])
    for seed in range(seeds):
        records = mf.records(seed, misfit)
        t0 = time.process_time()
        fit = fit_response(records, n, signal=signal, initial_state="preload")
        cpu += time.process_time() - t0
        outside = []
        for x in names:
            if x in fit.parameters:
                lo, hi = fit.confidence_interval[x]
                cover.setdefault(x, []).append(bool(lo <= truth[x] <= hi))
                if not lo <= truth[x] <= hi:
                    outside.append(x)
        statuses[fit.status] += 1
        cause = fit.adequacy.cause.name if fit.adequacy and fit.adequacy.cause else "-"
        causes[cause] += fit.status == "model_inadequate"
        wrong += fit.status == "converged" and bool(outside)
        print(f"  {misfit} seed {seed}: {fit.status}, cause {cause}, outside {outside}, "
              f"{time.process_time() - t0:.1f} s", flush=True)  # fmt: skip
    named = statuses["model_inadequate"]
    honest = statuses["converged"] + statuses["not_identifiable"]
    line = (
        f"{misfit}: {seeds} seeds, CPU {cpu:.0f} s ({cpu / seeds:.1f} s per fit); statuses "
        f"{dict(statuses)}; wrong converged {wrong}/{seeds} = {100 * wrong / seeds:.0f} %"
    )
    if misfit in CORRECT:
        line += f"; converged or not_identifiable {honest}/{seeds} = {100 * honest / seeds:.0f} %"
        line += "; coverage " + ", ".join(
            f"{x} {100 * np.mean(v):.0f} %" for x, v in cover.items())  # fmt: skip
    else:
        line += f"; names the model {named}/{seeds} = {100 * named / seeds:.0f} %"
        line += f"; causes {dict((k, v) for k, v in causes.items() if v)}"
    print(line, flush=True)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("seeds", nargs="?", type=int, default=40)
    parser.add_argument("--classes", default=",".join(mf.MISFITS))
    parser.add_argument("--signal", default="both")
    args = parser.parse_args()
    for misfit in args.classes.split(","):
        study(misfit, args.seeds, args.signal)


if __name__ == "__main__":
    main()
