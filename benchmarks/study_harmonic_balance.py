"""Exact periodic responses against harmonic balance (HB): the truncation error.

Two classic cases, each solved exactly (`frequency_response`: shooting on the event
solver, every orbit periodic to 1e-12) and by a small alternating frequency–time HB
(tests/structural/_harmonic_balance.py, 512 samples per period) with H harmonics:

* a 1-DOF Jenkins oscillator: m = k = 1, a Jenkins joint k_t = 3, μN = 0.5, c = 0.1,
  force 0.4·cos Ωt;
* NLvib's chain of three masses with two Jenkins joints (k = 20, μN = 1; springs 1,
  dampers 0.02, force cos Ωt on mass 2; NLvib's example uses H = 7).

For each H it prints the largest relative error of the peak amplitude (max − min)/2
over the curve and at the resonance peak, and of the first harmonic's amplitude (HB's
own first harmonic against the orbit's exact one). Then the 1-DOF oscillator's peaks at
three force levels (c = 0.02) against its closed-form backbones: the secant
ω² = (k·a + F_J(a))/a of the quasi-static modal analysis and the first harmonic
ω₁² = k + k_t·h(r/a) (the describing function). CPU time (time.process_time)::

    PYTHONPATH=src python benchmarks/study_harmonic_balance.py
"""

from __future__ import annotations

import math
import os
import sys
import time
from pathlib import Path

import numpy as np

import presliding as ps

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from tests.structural._harmonic_balance import HarmonicBalance

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def compare(name, st, force, freq_range, hb_args, harmonics, points=40):
    t0 = time.process_time()
    fr = ps.frequency_response(st, force, freq_range, step=0.02)
    t_exact = time.process_time() - t0
    idx = np.unique(np.linspace(0, fr.frequency.shape[0] - 1, points).astype(int))
    peak = int(np.argmax(fr.amplitude.max(axis=1)))
    idx = np.unique(np.r_[idx, peak])
    print(f"\n{name}: {fr.frequency.shape[0]} exact orbits in {t_exact:.1f} s CPU "
          f"(largest residual {fr.residual.max():.1g}); HB at {idx.shape[0]} of them")  # fmt: skip
    print(f"{'H':>3} {'max |A_HB/A − 1|':>17} {'at the peak':>12} {'max |Q1_HB/Q1 − 1|':>19} "
          f"{'HB not solved':>14} {'CPU [s]':>8}")  # fmt: skip
    for h in harmonics:
        hb = HarmonicBalance(*hb_args, force, h, samples=512)
        t0 = time.process_time()
        guess, err_a, err_q, err_peak, failed = None, 0.0, 0.0, math.nan, 0
        for i in idx:
            coef, ok = hb.solve(float(fr.frequency[i]), guess)
            if not ok:
                coef, ok = hb.solve(float(fr.frequency[i]))
            if not ok:  # fsolve did not converge there: counted, not compared
                failed += 1
                continue
            guess = coef
            amp = hb.amplitude(coef)
            first = np.hypot(coef[1], coef[h + 1])
            e_a = np.max(np.abs(amp / fr.amplitude[i] - 1))
            err_a = max(err_a, e_a)
            err_q = max(err_q, float(np.max(np.abs(first / fr.first_harmonic[i] - 1))))
            if i == peak:
                err_peak = e_a
        print(f"{h:3d} {err_a:17.3e} {err_peak:12.3e} {err_q:19.3e} {failed:14d} "
              f"{time.process_time() - t0:8.1f}")  # fmt: skip


def backbones() -> None:
    k, kt = 1.0, 3.0
    st = ps.JointedStructure(1.0, k, [[1.0]], [ps.PIFriction(0.0, [kt], breakaway=[0.5])],
                             damping=0.02)  # fmt: skip
    print("\n1-DOF Jenkins oscillator, c = 0.02: resonance peaks against the backbones")
    print(f"{'force':>6} {'Ω_peak':>9} {'A_peak':>9} {'ω₁(A) (DF)':>11} {'ω(A) secant':>12}")
    for f in (0.05, 0.1, 0.2):
        fr = ps.frequency_response(st, [f], (1.0, 2.4), step=0.02)
        i = int(np.argmax(fr.amplitude[:, 0]))
        a = float(fr.amplitude[i, 0])
        bb = ps.modal_backbone(st, 0, [a])
        print(f"{f:6.2f} {fr.frequency[i]:9.5f} {a:9.5f} {bb.harmonic_frequency[0]:11.5f} "
              f"{bb.frequency[0]:12.5f}")  # fmt: skip


if __name__ == "__main__":
    one = ps.JointedStructure(1.0, 1.0, [[1.0]], [ps.PIFriction(0.0, [3.0], breakaway=[0.5])],
                              damping=0.1)  # fmt: skip
    compare("1-DOF Jenkins oscillator", one, [0.4], (0.8, 2.6),
            (1.0, 0.1, 1.0, [[1.0]], [(3.0, 0.5 / 3.0)]), (1, 3, 5, 7, 9))  # fmt: skip
    kmat = np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 2]])
    w = np.array([[1.0, -1.0], [0.0, 1.0], [0.0, 0.0]])
    jenkins = ps.PIFriction(0.0, [20.0], breakaway=[1.0])
    chain = ps.JointedStructure(np.eye(3), kmat, w, [jenkins, jenkins], damping=0.02 * kmat)
    compare("NLvib 3-mass chain, two Jenkins joints", chain, [0.0, 1.0, 0.0], (0.5, 2.0),
            (np.eye(3), 0.02 * kmat, kmat, w, [(20.0, 0.05), (20.0, 0.05)]), (1, 3, 7))  # fmt: skip
    backbones()
