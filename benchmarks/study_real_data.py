"""Leave-one-window-out cross-validation on the measured data of ../shared/data.

EMPS (Janot et al. 2019, a prismatic joint in closed loop): the estimation
file is cut into windows of 3 s; the windows are pooled records of an
output-error fit (`fit_response(..., viscous=True, offset=True, signal="both")`,
one presliding element; mass, σ, F_c, c1, k and the force offset shared; each
window with its own initial position and velocity) and each window is
predicted by the fit of the others (`cross_validate`). The parameters of the
fit on all windows are printed next to the published IDIM-LS reference.

Tribometer (displacement-driven loops, force measured): the run after the
load ramp is cut into windows of eight cycles; for each window, the virgin
curve is fitted to the loops of the others (`fit_virgin_curve`, Masing's rule)
and the held-out window's force is predicted from its displacement (the
memory wiped by its first two reversals; the force offset taken from the
other windows); the Masing check of each window against that virgin curve is
listed too.

Run: python benchmarks/study_real_data.py
"""

from __future__ import annotations

import itertools
import time
from pathlib import Path

import numpy as np

from presliding import Measurement, cross_validate, fit_virgin_curve, masing_check
from presliding.identification.problem._pi_regression import reversal_indices

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"
REFERENCE = {"mass": 95.11, "viscous": 203.5, "coulomb_level": 20.39, "offset": -3.16}


def emps(window: float = 3.0) -> None:
    path = DATA / "emps" / "DATA_EMPS.mat"
    if not path.exists():
        print(f"EMPS: no data at {path}")
        return
    full = Measurement.from_mat(path, "t", position="qm", applied_force="vir",
                                scale={"applied_force": "gtau"})  # fmt: skip
    starts = np.arange(1.0, full.time[-1] - window, window)
    records = []
    for a in starts:
        m = full.window(a, a + window - 1e-3)
        records.append(Measurement(m.time, position=m.position,
                                   velocity=np.gradient(m.position, m.time),
                                   applied_force=m.applied_force))  # fmt: skip
    labels = [f"{a:.0f}–{a + window:.0f} s" for a in starts]
    t0 = time.perf_counter()
    cv = cross_validate(records, labels=labels, n_elements=1, viscous=True, offset=True,
                        signal="both", initial_state="saturated")  # fmt: skip
    fit = cv.result
    print(f"EMPS, {len(records)} windows of {window:g} s ({time.perf_counter() - t0:.0f} s): "
          f"fit on all windows {fit.status}")  # fmt: skip
    for name, ref in REFERENCE.items():
        value = fit.parameters.get(name, fit.derived.get(name))
        lo, hi = fit.confidence_interval.get(name, (np.nan, np.nan))
        print(f"  {name:14s} {value:10.4g}  [{lo:.4g}, {hi:.4g}]   reference {ref:g}")
    print(f"  c1 {fit.parameters['coulomb']:.4g} N, k {fit.parameters['stiffness_1']:.4g} N/m")
    print(cv.report())


def tribometer(cycles: int = 8) -> None:
    path = DATA / "tribometer" / "tribometer_loops.txt"
    if not path.exists():
        print(f"tribometer: no data at {path}")
        return
    m = Measurement.from_csv(
        path,
        "Time [s]",
        position="Position [mm]",
        friction_force="Friction [uN]",
        scale={"friction_force": -1.0},
    )
    m = m.window(8.0, 210.0)  # fmt: skip
    y, f, t = m.position, m.friction_force, m.time
    turns = reversal_indices(np.ascontiguousarray(y), 1e-6)
    bounds = turns[:: 2 * cycles]
    windows = [(int(a), int(b)) for a, b in itertools.pairwise(bounds)]
    print(f"tribometer, {len(windows)} windows of {cycles} cycles (t = {t[0]:.0f}..{t[-1]:.0f} s):")
    print(f"  {'window':>14s}  {'NRMSE %':>8s}  {'Masing check':>14s}")
    scores = []
    for i, (a, b) in enumerate(windows):
        others = [w for j, w in enumerate(windows) if j != i]
        fit = fit_virgin_curve([y[p:q] for p, q in others], [f[p:q] for p, q in others], 3,
                               loops=True, reversal_tolerance=1e-6)  # fmt: skip
        model = fit.model
        offset = float(np.mean(np.concatenate(
            [f[p:q] - model.force(y[p:q])[0] for p, q in others])))  # fmt: skip
        pred = model.force(y[a:b])[0] + offset
        skip = reversal_indices(np.ascontiguousarray(y[a:b]), 1e-6)[1]  # memory wiped
        res = f[a:b][skip:] - pred[skip:]
        nrmse = float(np.sqrt(np.mean(res**2)) / np.ptp(f[a:b][skip:]))
        check = masing_check(model, (y[a:b], f[a:b]), reversal_tolerance=1e-6)
        scores.append(nrmse)
        print(f"  {t[a]:6.0f}–{t[b - 1]:4.0f} s  {100 * nrmse:8.2f}  {check.status:>8s} "
              f"({100 * check.discrepancy:.2f} %)")  # fmt: skip
    print(f"  median NRMSE {100 * np.median(scores):.2f} %, largest {100 * max(scores):.2f} %")


if __name__ == "__main__":
    tribometer()
    emps()
