"""Calibration of the joint fit: Segalman's four parameters from a noisy ring-down, 40 seeds.

A mass of 1 kg on a spring of 10 N/m with a Segalman joint (K_T = 2 N/m, F_S = 0.1 N,
χ = −0.3, β = 0.2) and viscous damping 0.01 N s/m rings down from a modal amplitude of
0.4 over 150 s. The joint is simulated exactly with its power law in 200 equal cells
(midpoint elements) and the point mass as its own element at φ_max; each seed adds
white noise (1e-4 m) to the displacement, reads the decay by peak tracking
(`analyze_ring_down`), fits the density with the viscous term (`fit_joint`), and counts
whether each 95 % interval covers the truth. Prints the coverage per parameter, the
median relative error and the CPU time (time.process_time).

    PYTHONPATH=src python benchmarks/study_joint_coverage.py [--seeds 40] [--method peaks]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import presliding as ps
from presliding.structural._joint_model import segalman_elements

TRUTH = {"stiffness": 2.0, "slip_force": 0.1, "exponent": -0.3, "mass_ratio": 0.2,
         "linear_stiffness": 10.0, "viscous": 0.01}  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=40)
    parser.add_argument("--method", default="peaks", choices=("peaks", "hilbert"))
    parser.add_argument("--noise", type=float, default=1e-4)
    args = parser.parse_args()
    seg = ps.SegalmanIwan(TRUTH["stiffness"], TRUTH["slip_force"], TRUTH["exponent"],
                          TRUTH["mass_ratio"])  # fmt: skip
    st = ps.JointedStructure(1.0, TRUTH["linear_stiffness"], [[1.0]],
                             [segalman_elements(seg, 200)], damping=TRUTH["viscous"])  # fmt: skip
    t0 = time.process_time()
    motion = ps.simulate_ring_down(st, 0, 0.4, 150.0, samples_per_period=32)
    t_sim = time.process_time() - t0
    covered = {k: 0 for k in TRUTH}
    errors: dict[str, list[float]] = {k: [] for k in TRUTH}
    statuses: dict[str, int] = {}
    t0 = time.process_time()
    for seed in range(args.seeds):
        rng = np.random.default_rng(seed)
        x = motion.position[:, 0] + args.noise * rng.normal(size=motion.time.shape[0])
        rd = ps.analyze_ring_down((motion.time, x), method=args.method)
        fit = ps.fit_joint(rd)
        statuses[fit.status] = statuses.get(fit.status, 0) + 1
        for k, v in TRUTH.items():
            lo, hi = fit.confidence_interval[k]
            covered[k] += int(lo <= v <= hi)
            errors[k].append(abs(fit.parameters[k] / v - 1))
    t_fit = time.process_time() - t0
    print(f"ring-down simulation (201 stops, {motion.n_events} events): {t_sim:.2f} s CPU")
    print(f"{args.seeds} seeds, {args.method}: {t_fit:.1f} s CPU ({t_fit / args.seeds:.2f} s "
          f"per seed); statuses {statuses}")  # fmt: skip
    print(f"{'parameter':>17} {'coverage':>9} {'median |rel. error|':>20}")
    for k in TRUTH:
        print(f"{k:>17} {covered[k] / args.seeds:9.3f} {np.median(errors[k]):20.3g}")


if __name__ == "__main__":
    main()
