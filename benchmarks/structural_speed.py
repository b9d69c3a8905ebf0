"""Speed targets of the structural layer, CPU time (time.process_time).

* a modal backbone (`modal_backbone`) of a 100-DOF modal model with 10 discrete Iwan
  joints (Segalman's density in 20 cells each) over 50 amplitudes: target <= 1 s;
* a frequency response curve (`frequency_response`) of NLvib's 3-mass chain with two
  Jenkins joints (k = 20, μN = 1; springs 1, dampers 0.02, the force on mass 2) over
  Ω = 0.5..2 rad/s with at least 200 orbits: target <= 60 s.

Both from a cold start of the layer (numba is not used by these paths), and each result's
size and largest residual printed::

    PYTHONPATH=src python benchmarks/structural_speed.py
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import time  # noqa: E402

import numpy as np  # noqa: E402

import presliding as ps  # noqa: E402


def backbone() -> None:
    rng = np.random.default_rng(0)
    n, n_c = 100, 10
    w = 2 * np.pi * np.sort(rng.uniform(10, 2000, n))
    w[0] = 2 * np.pi * 50
    phi = rng.normal(size=(n, n_c)) * 0.1
    phi[0] = 1.0 + 0.2 * rng.random(n_c)  # the first mode moves every joint one way
    cells = ps.SegalmanIwan(1e5, 100.0, -0.5, 0.1).discretize(20)
    joint = ps.PIFriction(0.0, cells.stiffness, threshold=cells.threshold)
    st = ps.JointedStructure.modal(w, phi, joint, damping_ratios=0.001)
    a = np.geomspace(1e-6, 1e-1, 50)
    t0 = time.process_time()
    bb = ps.modal_backbone(st, 0, a)
    cpu = time.process_time() - t0
    print(f"backbone, 100-DOF modal model, 10 joints x {cells.stiffness.shape[0]} elements, "
          f"50 amplitudes: {cpu:.3f} s CPU (target <= 1 s); ω from {bb.frequency[0]:.6g} to "
          f"{bb.frequency[-1]:.6g} rad/s, ζ up to {bb.damping_ratio.max():.4g}")  # fmt: skip


def nlvib_chain() -> ps.JointedStructure:
    k = np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 2]])
    w = np.array([[1.0, -1.0], [0.0, 1.0], [0.0, 0.0]])
    jenkins = ps.PIFriction(0.0, [20.0], breakaway=[1.0])
    return ps.JointedStructure(np.eye(3), k, w, [jenkins, jenkins], damping=0.02 * k)


def frequency_response() -> None:
    st = nlvib_chain()
    t0 = time.process_time()
    fr = ps.frequency_response(st, [0.0, 1.0, 0.0], (0.5, 2.0), step=0.01)
    cpu = time.process_time() - t0
    print(f"frequency response, 3-DOF chain, 2 Jenkins joints, Ω 0.5–2 rad/s: "
          f"{fr.frequency.shape[0]} orbits in {cpu:.1f} s CPU (target: 200 orbits <= 60 s), "
          f"status {fr.status}, largest residual {fr.residual.max():.2g}, "
          f"{int((~fr.stable).sum())} unstable")  # fmt: skip


if __name__ == "__main__":
    backbone()
    frequency_response()
