"""Implicit stepper of a mass with a continuous-density friction model (eqs. 10, 17).

Times `simulate` (method "implicit", the exact continuous operator inside every
step) on a forced motion that keeps moving and reversing (u = 1.5·F_c·sin(2t),
so no step is a cheap sticking step), and on the same motion with the midpoint
discretisation of the density into N = 1000 elements (the finite-element
stepper of `_implicit`), same step h. Prints ns per step (whole `simulate`
call over its steps, the Newton trials of each step included), the ratio and
the position difference between the two as a check, all from the same run
(best of the repeats)::

    python benchmarks/bench_motion_density.py [--steps 200000] [--repeats 5]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from presliding import Exponential, PIFriction, Uniform, simulate  # noqa: E402

N_ELEMENTS = 1000


def best_seconds(call, repeats: int) -> float:
    out = []
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        out.append(time.perf_counter() - start)
    return min(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=200_000)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    t_end = 20.0
    h = t_end / args.steps
    t_eval = np.linspace(0.0, t_end, 201)
    print(f"forced motion u = 1.5·F_c·sin(2t), {args.steps} steps of h = {h:.3g}")
    print(f"{'density':<24}{'exact ns/step':>15}{'N=1000 ns/step':>16}{'speed-up':>10}"
          f"{'max |dy| / max |y|':>20}{'reversals':>11}")  # fmt: skip
    for name, dens, cut in (
        ("uniform", Uniform(2.0, 1.0), None),
        ("exponential (R = inf)", Exponential(3.0, 0.4), 30 * 0.4),
    ):
        model = PIFriction(0.1 * dens.max_elastic_force, density=dens)
        disc = dens.discretize(N_ELEMENTS, cut)
        fe = PIFriction(model.coulomb, stiffness=disc.stiffness, threshold=disc.threshold)
        amp = 1.5 * model.coulomb_level

        def run(mod, amp=amp):
            return simulate(mod, 1.0, applied_force=lambda t: amp * np.sin(2.0 * t),
                            t_eval=t_eval, step=h, method="implicit")  # fmt: skip

        exact, approx = run(model), run(fe)  # compile / load the cache
        t_exact = best_seconds(lambda m=model: run(m), args.repeats)
        t_disc = best_seconds(lambda m=fe: run(m), args.repeats)
        diff = np.max(np.abs(exact.position - approx.position)) / np.max(np.abs(exact.position))
        ns_e, ns_d = 1e9 * t_exact / exact.n_events, 1e9 * t_disc / approx.n_events
        print(f"{name:<24}{ns_e:>15.1f}{ns_d:>16.1f}{t_disc / t_exact:>9.1f}x{diff:>20.2e}"
              f"{exact.n_reversals:>11d}")  # fmt: skip


if __name__ == "__main__":
    main()
