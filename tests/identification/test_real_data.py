"""Identification on the measured data of ../shared/data (skipped when it is absent)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from presliding.identification._pi_regression import reversal_indices
from presliding.identification.fit_motion import fit_motion, predict_motion_force
from presliding.identification.fit_presliding import fit_presliding
from presliding.identification.fit_result import fit_statistics
from presliding.identification.measurement import Measurement

DATA = Path(__file__).resolve().parents[3] / "shared" / "data"
EMPS = DATA / "emps"
TRIBOMETER = DATA / "tribometer" / "tribometer_loops.txt"
# published IDIM-LS reference of the EMPS benchmark (Janot et al. 2019)
REFERENCE = {"mass": 95.11, "viscous": 203.5, "coulomb": 20.39, "offset": -3.16}


def _emps(name: str) -> Measurement:
    path = EMPS / name
    if not path.exists():
        pytest.skip(f"measured data not found at {path}")
    m = Measurement.from_mat(path, position="qm", applied_force="vir",
                             scale={"applied_force": "gtau"})  # fmt: skip
    # band-limited differentiation as in the reference: zero-phase Butterworth low-pass
    # on the position, central differences; the force sees the same filter
    return m.differentiate(cutoff=50.0, filter_forces=True)


@pytest.fixture(scope="module")
def emps():
    return _emps("DATA_EMPS.mat"), _emps("DATA_EMPS_PULSES.mat")


def test_emps_matches_the_published_reference(emps):
    estimation, _ = emps
    res = fit_motion(estimation, viscous=True, offset=True)
    assert res.success
    for name in ("mass", "viscous", "coulomb"):
        assert res.parameters[name] == pytest.approx(REFERENCE[name], rel=0.03), name
    assert res.parameters["offset"] == pytest.approx(REFERENCE["offset"], abs=0.3)


def test_emps_presliding_elements_lower_the_residual_also_on_validation(emps):
    estimation, validation = emps
    plain = fit_motion(estimation, viscous=True, offset=True)
    with_pi = fit_motion(estimation, 1, viscous=True, offset=True, tolerance=1e-6)
    assert with_pi.residual_rms < 0.98 * plain.residual_rms
    # F_c of eq. 9 stays the reference's Coulomb force
    assert with_pi.model.coulomb_level == pytest.approx(REFERENCE["coulomb"], rel=0.05)
    u = validation.applied_force
    rms_plain = fit_statistics(u, predict_motion_force(plain, validation))[0]
    rms_pi = fit_statistics(u, predict_motion_force(with_pi, validation))[0]
    assert rms_pi < 0.98 * rms_plain


def test_emps_pulses_are_already_in_the_motor_force(emps):
    """gtau·vir carries the pulses: adding pulses_N (0/5) again only worsens the fit."""
    from scipy.io import loadmat

    estimation, validation = emps
    pulses = loadmat(EMPS / "DATA_EMPS_PULSES.mat")["pulses_N"].ravel().astype(float)
    predicted = predict_motion_force(fit_motion(estimation, viscous=True, offset=True), validation)
    rms = {
        s: fit_statistics(validation.applied_force + s * pulses, predicted)[0] for s in (-1, 0, 1)
    }
    assert rms[0] < rms[1] and rms[0] < rms[-1]


def test_tribometer_loops_fit_held_back_cycles():
    if not TRIBOMETER.exists():
        pytest.skip(f"measured data not found at {TRIBOMETER}")
    normal = np.loadtxt(TRIBOMETER, skiprows=1, usecols=(0, 1))
    full = normal[normal[:, 1] > 0.95 * np.median(normal[:, 1]), 0]  # skip load ramp and release
    m = Measurement.from_csv(
        TRIBOMETER, "Time [s]", position="Position [mm]", friction_force="Friction [uN]",
        scale={"position": 1e-3, "friction_force": -1e-6},
    ).window(full[0], full[-1])  # fmt: skip
    y, f = m.position, m.friction_force
    turns = reversal_indices(y, 2e-6)
    split = int(turns[2 * len(turns) // 3])  # the last third of the cycles is held back
    res = fit_presliding(y[:split], f[:split], 3, offset=True, burn_in=int(turns[0]))
    assert res.model is not None and res.status == "converged"
    predicted = res.model.force(y)[0] + res.parameters["offset"]
    _, nrmse, relative = fit_statistics(f[split:], predicted[split:])
    assert nrmse <= 0.05
    assert relative <= 0.06
    assert 2.0 < res.model.coulomb_level < 2.6  # |F/N| of about 0.45–0.5 at N ≈ 5 N
