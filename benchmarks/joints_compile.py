"""Compiling a slider network into one PI operator, and evaluating the result.

A bar of axial stiffness EA on a Coulomb foundation τ, discretised as a chain of
N springs and sliders (N = 1000 by default: 1001 nodes, 1001 sliders), is
compiled with `compile_network` (its exact virgin curve by the event-driven
active set, then the PI elements). The script prints

* the compile time of the N-node chain (target: <= 10 s on 2 cores), with the
  default check (the replay of a history with nested reversals runs by
  default for networks of at most 64 sliders) and, for a 200-node chain,
  with the replay forced;
* ns per sample of the compiled operator (``PIFriction.force``) against a
  ``PIFriction`` of N random elements built directly (the existing PI kernel)
  on the same input with many reversals, and their ratio, measured in the same
  run (median over repeats; each repeat calls until at least 0.1 s passed);
* the relative dissipation error of the chain against the bar's closed form
  D = 2F³/(3·EA·τ) at F = 0.6·τL::

    python benchmarks/joints_compile.py [--nodes 1000] [--samples 200000] [--repeats 5]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from _timing import seconds, through  # noqa: E402

from presliding import MicroslipBar, PIFriction, amplitude_response  # noqa: E402
from presliding.network import SliderNetwork, compile_network  # noqa: E402

EA, TAU, LENGTH = 2e6, 5e3, 0.4


def bar_chain(n: int) -> SliderNetwork:
    """N segments: springs EA·N/L, sliders τL/N (half at both ends)."""
    c = np.full(n + 1, TAU * LENGTH / n)
    c[[0, -1]] /= 2
    return SliderNetwork.chain(np.full(n, EA * n / LENGTH), c)


def reversing_input(n: int, scale: float, rng: np.random.Generator) -> np.ndarray:
    """A new turning point every 10 samples (random walk), every sample monotone to the next."""
    return through(np.cumsum(rng.normal(0.0, 0.3 * scale, n // 10 + 1)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nodes", type=int, default=1000)
    parser.add_argument("--samples", type=int, default=200_000)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    compile_network(bar_chain(10), 0)  # warm the compiled kernels

    net = bar_chain(args.nodes)
    start = time.perf_counter()
    model = compile_network(net, 0)
    t_compile = time.perf_counter() - start
    print(f"compile a {args.nodes + 1}-node chain ({net.n_sliders} sliders): {t_compile:.2f} s "
          f"(target <= 10 s){'' if t_compile <= 10 else '  MISSED'}")  # fmt: skip
    small = bar_chain(200)
    start = time.perf_counter()
    compile_network(small, 0, verify=True)
    print(f"compile a 201-node chain with the replay check: {time.perf_counter() - start:.2f} s")

    force = 0.6 * TAU * LENGTH
    grid = np.concatenate([model.threshold, [2 * model.threshold[-1]]])
    amp = float(np.interp(force, model.virgin_curve(grid), grid))
    exact = MicroslipBar(EA, TAU, LENGTH).loop_energy_at_force(force)
    err = amplitude_response(model, [amp]).dissipation[0] / exact - 1
    print(f"dissipation of the chain against 2F³/(3EAτ): relative error {err:.3e}")

    rng = np.random.default_rng(0)
    y = reversing_input(args.samples, float(model.threshold[-1]), rng)
    direct = PIFriction(model.coulomb, rng.uniform(0.5, 2.0, model.n_elements) * model.stiffness,
                        threshold=rng.permutation(model.threshold))  # fmt: skip
    model.force(y[:100]), direct.force(y[:100])
    t_comp = seconds(lambda: model.force(y), args.repeats)
    t_direct = seconds(lambda: direct.force(y), args.repeats)
    n = y.shape[0]
    print(f"evaluate, {model.n_elements} elements, {n} samples: compiled {1e9 * t_comp / n:.1f} "
          f"ns/sample, direct PIFriction {1e9 * t_direct / n:.1f} ns/sample, ratio "
          f"{t_comp / t_direct:.2f}")  # fmt: skip


if __name__ == "__main__":
    main()
