"""Ring-downs against the modal backbone: the estimators, the slow-decay view, one mode.

Exact free decays (`simulate_ring_down`, an impulse into a linear mode) read back by
`analyze_ring_down` (analytic signal and peak tracking) and compared (`RingDown.compare`)
with `modal_backbone`: with what a slow decay shows (ω₁, ζ_d) and with the quasi-static
secant quantities (ω, ζ). For one mass the single-mode view is exact, and the
difference is the estimator's and the slow-decay view's; for the 3-mass chain of NLvib's
example (springs 1, joints on q1 and q2 − q1) it adds the single-mode assumption's error:
the other modes the joints excite, and the deflection shape changing with the amplitude.
The chain's joints are softer here (k_t = 0.5, μN = 0.02, dampers 0.001·K) so that they
slide for many periods of the decay (with k = 20, μN = 1 the decay passes the sliding
range in a few periods, inside the trimmed start). Prints the median and
largest differences where a joint slides (its amplitude beyond 1.2 thresholds), and the
share of windows within twice the stated errors. CPU time (time.process_time)::

    PYTHONPATH=src python benchmarks/study_ring_down.py
"""

from __future__ import annotations

import time

import numpy as np

import presliding as ps


def study(name, st, mode, amplitude, duration, coordinate, threshold, band=None):
    t0 = time.process_time()
    motion = ps.simulate_ring_down(st, mode, amplitude, duration, samples_per_period=64)
    bb = ps.modal_backbone(st, mode, np.geomspace(1e-4, 3 * amplitude, 1500))
    print(f"\n{name} (mode {mode}, modal amplitude {amplitude}, coordinate {coordinate}): "
          f"{motion.n_events} events")  # fmt: skip
    print(f"{'method':>8} {'windows':>8} {'median |Δζ|':>12} {'max |Δζ|':>10} "
          f"{'median |Δω|/ω':>14} {'max':>9} {'in 2σ':>6} {'secant: median |Δζ|':>19} "
          f"{'|Δω|/ω':>9}")  # fmt: skip
    for method in ("hilbert", "peaks"):
        rd = ps.analyze_ring_down(motion, coordinate=coordinate, method=method, band=band)
        cmp = rd.compare(bb, coordinate)
        # where a joint slides: its displacement amplitude beyond 1.2 thresholds
        joints = ps.modal_backbone(st, mode, cmp["modal_amplitude"]).joint_amplitude
        sl = np.max(np.abs(joints), axis=1) > 1.2 * threshold
        dz, dw = np.abs(cmp["damping"][sl]), np.abs(cmp["frequency"][sl])
        within = (cmp["damping_within"] & cmp["frequency_within"])[sl].mean()
        print(f"{method:>8} {int(sl.sum()):8d} {np.median(dz):12.2e} {dz.max():10.2e} "
              f"{np.median(dw):14.2e} {dw.max():9.2e} {within:6.2f} "
              f"{np.median(np.abs(cmp['quasi_static_damping'][sl])):19.2e} "
              f"{np.median(np.abs(cmp['quasi_static_frequency'][sl])):9.2e}")  # fmt: skip
    print(f"  {time.process_time() - t0:.1f} s CPU")


if __name__ == "__main__":
    one = ps.JointedStructure(1.0, 10.0, [[1.0]], [ps.PIFriction(0.0, [2.0], threshold=[0.05])],
                              damping=0.01)  # fmt: skip
    study("one mass, a Jenkins joint", one, 0, 1.0, 150.0, 0, 0.05)
    k = np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 2]])
    w = np.array([[1.0, -1.0], [0.0, 1.0], [0.0, 0.0]])
    jenkins = ps.PIFriction(0.0, [0.5], breakaway=[0.02])
    chain = ps.JointedStructure(np.eye(3), k, w, [jenkins, jenkins], damping=0.001 * k)
    for coordinate in (0, 2):
        study("3-mass chain, two Jenkins joints", chain, 0, 2.0, 600.0, coordinate, 0.04)
