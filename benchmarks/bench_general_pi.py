"""Exact general PI operator (eq. 10) against an N = 1000 discretisation of μ.

On one input with many reversals (a random walk of turning points plus a
decaying oscillation, every sample monotone to the next), the script times

* the exact continuous operator (``GeneralPIOperator.apply``, closed-form
  primitives, memory of dominant turning points), for a uniform and an
  untruncated exponential density;
* the midpoint discretisation with N = 1000 elements (``PIOperator.apply``,
  the compiled stop-sum kernel) on the same input,

and prints ns per sample, the speed ratio and the discretisation error
max|F_N − F_exact| / F_m, all measured in the same run (median over repeats;
each repeat calls until at least 0.1 s passed)::

    python benchmarks/bench_general_pi.py [--samples 200000] [--repeats 5]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402

import numpy as np  # noqa: E402
from _timing import seconds, through  # noqa: E402

from presliding import Exponential, GeneralPIOperator, PIOperator, Uniform  # noqa: E402

N_ELEMENTS = 1000


def reversing_input(n: int, rng: np.random.Generator) -> np.ndarray:
    """Many reversals: every 10 samples a new turning point (random walk), then a ring-down."""
    turns = np.cumsum(rng.normal(0.0, 0.4, n // 20))
    ring = turns[-1] + 0.8 * np.cos(np.linspace(0, 200 * np.pi, n // 20)) * np.linspace(
        1, 0, n // 20
    )
    return through(np.concatenate([turns, ring]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=200_000)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    y = reversing_input(args.samples, np.random.default_rng(7))
    reversals = int(np.sum(np.diff(np.sign(np.diff(y))) != 0))
    print(f"input: {y.shape[0]} samples, {reversals} reversals")
    header = f"{'density':<24}{'exact ns/sample':>17}{'N=1000 ns/sample':>18}{'speed-up':>10}"
    print(header + f"{'N=1000 error/F_m':>18}")
    for name, dens, cut in (
        ("uniform", Uniform(2.0, 1.0), None),
        ("exponential (R = inf)", Exponential(3.0, 0.4), 30 * 0.4),
    ):
        exact_op = GeneralPIOperator(dens)
        disc = dens.discretize(N_ELEMENTS, cut)
        disc_op = PIOperator(disc.threshold, disc.stiffness)
        exact, _ = exact_op.apply(y)  # compile / load the cache
        approx, _ = disc_op.apply(y)
        t_exact = seconds(lambda op=exact_op: op.apply(y), args.repeats)
        t_disc = seconds(lambda op=disc_op: op.apply(y), args.repeats)
        err = np.max(np.abs(approx - exact)) / dens.max_elastic_force
        ns_e, ns_d = 1e9 * t_exact / y.shape[0], 1e9 * t_disc / y.shape[0]
        print(f"{name:<24}{ns_e:>17.1f}{ns_d:>18.1f}{t_disc / t_exact:>9.1f}x{err:>18.2e}")
    print("target: exact at least as fast as N = 1000 (speed-up >= 1), and exact where it is not")


if __name__ == "__main__":
    main()
