"""The EMPS benchmark on its own metric (Janot, Gautier and Brunot, 2019).

Fits the inverse dynamic model of the Electro-Mechanical Positioning System on
``DATA_EMPS.mat`` and predicts the force of the cross-test record
``DATA_EMPS_PULSES.mat``, scored as the benchmark scores its IDIM-LS reference:

* motor force u = gtau·vir;
* position low-passed by a zero-phase 4th-order Butterworth filter at 100 Hz,
  velocity and acceleration by central differences, the first 49 samples
  (the differentiation's edge) left out;
* the measured and the predicted force decimated by 10 as MATLAB's ``decimate``
  does (zero-phase order-8 Chebyshev type I anti-aliasing, every 10th sample
  ending at the last);
* relative error 100·‖u − û‖/‖u‖ of the decimated forces.

The cross-test record is scored on gtau·vir, as the benchmark's cross-test
script does: its force pulses ``pulses_N`` are part of the controller output
vir already (adding them as a separate force makes every model worse).

Published IDIM-LS figures: 4.08 % (identification) and 5.98 % (cross-test) with
symmetric friction, 3.11 % (identification) with asymmetric friction. Every
model here is fitted by ``fit_motion`` on the full-rate samples (the figures
are of the decimated forces, as published).

Run from the repository root (the data sit in ../shared/data/emps)::

    python benchmarks/emps.py [DATA_FOLDER]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
from scipy import signal

import presliding as ps
from presliding.identification.fit_motion import predict_motion_force

DATA = Path(__file__).resolve().parents[2] / "shared" / "data" / "emps"
#: the benchmark's published IDIM-LS relative errors [%]
PUBLISHED = {("symmetric", "identification"): 4.08, ("symmetric", "cross-test"): 5.98,
             ("asymmetric", "identification"): 3.11}  # fmt: skip
CUTOFF = 100.0  # Hz, the benchmark's Butterworth cut-off (5·20 Hz)
EDGE = 49  # samples left out at the start (MATLAB's n_border = 50, one-based)
DECIMATION = 10  # round(0.8·500/40)
ELEMENTS = 4


def load(path: Path) -> ps.Measurement:
    """One EMPS record with the benchmark's force, filter and differentiation."""
    m = ps.Measurement.from_mat(path, position="qm", applied_force="vir",
                                scale={"applied_force": "gtau"})  # fmt: skip
    m = m.differentiate(CUTOFF, order=4)
    return m.window(start=float(m.time[EDGE]))


def decimate(x: np.ndarray, q: int = DECIMATION) -> np.ndarray:
    """MATLAB's ``decimate(x, q)``: order-8 Chebyshev type I low-pass (0.05 dB ripple, cut-off
    0.8·Nyquist/q) run forwards and backwards, then every q-th sample ending at the last."""
    b, a = signal.cheby1(8, 0.05, 0.8 / q)
    smooth = signal.filtfilt(b, a, x, padlen=3 * (max(len(a), len(b)) - 1))
    return smooth[(x.shape[0] - 1) % q :: q]


def relative_error(measured: np.ndarray, predicted: np.ndarray) -> float:
    """100·‖u − û‖/‖u‖ of the decimated forces [%]."""
    u, u_hat = decimate(measured), decimate(predicted)
    return float(100.0 * np.linalg.norm(u - u_hat) / np.linalg.norm(u))


def fit(identification: ps.Measurement, n_elements: int, asymmetric: bool) -> ps.FitResult:
    """The inverse model: mass, Coulomb, viscous, offset (symmetric) and elements."""
    return ps.fit_motion(identification, n_elements, viscous=True, offset=not asymmetric,
                         asymmetric=asymmetric)  # fmt: skip


def table(folder: Path = DATA) -> list[tuple[str, int, float, float, ps.FitResult]]:
    """(friction, elements, identification %, cross-test %, fit) for the four models."""
    ident = load(folder / "DATA_EMPS.mat")
    cross = load(folder / "DATA_EMPS_PULSES.mat")
    rows = []
    for asymmetric in (False, True):
        for n in (0, ELEMENTS):
            res = fit(ident, n, asymmetric)
            e_id = relative_error(ident.applied_force, predict_motion_force(res, ident))
            e_x = relative_error(cross.applied_force, predict_motion_force(res, cross))
            rows.append(("asymmetric" if asymmetric else "symmetric", n, e_id, e_x, res))
    return rows


def main(folder: Path = DATA) -> int:
    if not (folder / "DATA_EMPS.mat").exists():
        print(f"EMPS data not found in {folder}")
        return 1
    start = time.perf_counter()
    rows = table(folder)
    print(f"{'friction':<11} {'elements':>8} {'identification %':>17} {'cross-test %':>13}"
          f"   published (ident. / cross)")  # fmt: skip
    for kind, n, e_id, e_x, _ in rows:
        pub = "" if n else " / ".join(
            f"{PUBLISHED[(kind, s)]:.2f}" if (kind, s) in PUBLISHED else "–"
            for s in ("identification", "cross-test"))  # fmt: skip
        print(f"{kind:<11} {n:>8} {e_id:>17.2f} {e_x:>13.2f}   {pub}")
    for kind, n, _, _, res in rows:
        values = ", ".join(f"{k} {v:.4g}" for k, v in res.parameters.items())
        print(f"{kind}, {n} elements: {res.status}; {values}")
        if res.asymmetry is not None:  # the sides tested against the symmetric fit
            a = res.asymmetry
            print(f"  asymmetry {a.verdict}: F = {a.statistic:.4g}, p = {a.p_value:.3g}, "
                  f"ΔAIC {a.delta_aic:+.4g}, ΔBIC {a.delta_bic:+.4g}")  # fmt: skip
    print(f"({time.perf_counter() - start:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main(Path(sys.argv[1]) if len(sys.argv) > 1 else DATA))
