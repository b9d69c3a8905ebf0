"""Axis kinds: rotary records (degrees, N m) are labelled rad, N m, kg m² everywhere."""

from __future__ import annotations

import numpy as np
import pytest

import presliding as ps
from presliding._axes import axis_unit, on_axis
from presliding.cli import main
from presliding.identification.fit_motion import fit_motion
from presliding.measurement.measurement import Measurement, common_axis
from presliding.model_io import model_to_toml

T = np.arange(3000) * 1e-3
W1, W2 = 2 * np.pi * 1.0, 2 * np.pi * 3.3
Q = 0.3 * np.sin(W1 * T) + 0.08 * np.sin(W2 * T)  # joint angle [rad]
QD = 0.3 * W1 * np.cos(W1 * T) + 0.08 * W2 * np.cos(W2 * T)
QDD = -0.3 * W1**2 * np.sin(W1 * T) - 0.08 * W2**2 * np.sin(W2 * T)
JOINT = ps.PIFriction(1.5, [300.0, 40.0], threshold=[0.002, 0.02])
INERTIA = 0.05  # kg m²


def _torque() -> np.ndarray:
    elastic, _ = JOINT.elastic_force(Q)
    return INERTIA * QDD + 1.5 * np.sign(QD) + elastic


def _joint_csv(tmp_path, deg=True, delimiter=","):
    path = tmp_path / "joint.csv"
    q = np.degrees(Q) if deg else Q
    unit = "deg" if deg else "rad"
    header = delimiter.join([
        "t [s]", f"q [{unit}]", f"qd [{unit}/s]", f"qdd [{unit}/s^2]", "tau [N m]"
    ])  # fmt: skip
    scale = np.degrees(1.0) if deg else 1.0
    np.savetxt(path, np.column_stack([T, q, QD * scale, QDD * scale, _torque()]),
               delimiter=delimiter, header=header, comments="")  # fmt: skip
    return path


def test_the_units_table_has_one_label_per_quantity_and_axis():
    assert axis_unit("stiffness", "rotary") == "N m/rad"
    assert axis_unit("mass", "rotary") == "kg m^2"
    assert axis_unit("viscous", "linear") == "N s/m"
    assert on_axis("N/m", "rotary") == "N m/rad"
    assert on_axis("velocity [m/s]", "rotary") == "velocity [rad/s]"
    assert on_axis("1", "rotary") == "1" and on_axis("s", "rotary") == "s"
    with pytest.raises(ValueError, match="`axis` must be one of 'linear', 'rotary'"):
        axis_unit("force", "angular")


def test_degrees_and_newton_metres_make_a_rotary_axis(tmp_path):
    m = Measurement.from_csv(_joint_csv(tmp_path), "t [s]", position="q [deg]",
                             applied_force="tau [N m]")  # fmt: skip
    assert m.axis == "rotary" and m.unit("stiffness") == "N m/rad"
    np.testing.assert_allclose(m.position, Q, rtol=1e-12, atol=1e-15)
    assert m.window(0.1, 1.0).axis == "rotary"
    assert m.resample(2e-3).axis == "rotary"


def test_an_explicit_axis_labels_unitless_columns_and_must_agree_with_units(tmp_path):
    path = tmp_path / "bare.txt"
    np.savetxt(path, np.column_stack([T, Q, _torque()]))
    m = Measurement.from_csv(path, 0, position=1, applied_force=2, axis="rotary")
    assert m.axis == "rotary"
    assert "taken as rad (no unit given)" in m.source.describe()
    assert "taken as N m (no unit given)" in m.source.describe()
    assert Measurement(T, position=Q).axis == "linear"
    assert Measurement(T, position=Q, axis="rotary").unit("force") == "N m"
    with pytest.raises(ValueError, match="`axis` 'linear' contradicts the units read"):
        Measurement.from_csv(_joint_csv(tmp_path), "t [s]", position="q [deg]", axis="linear")
    with pytest.raises(ValueError, match="`axis` must be one of"):
        Measurement(T, position=Q, axis="angular")


def test_records_on_different_axes_are_refused():
    lin, rot = Measurement(T, position=Q), Measurement(T, position=Q, axis="rotary")
    assert common_axis([rot, rot]) == "rotary"
    with pytest.raises(ValueError, match="one kind of axis"):
        common_axis([lin, rot])


def test_a_joined_record_keeps_the_rotary_axis(tmp_path):
    a = Measurement(T, position=Q, axis="rotary")
    b = Measurement(T, applied_force=_torque())
    assert Measurement.join([a, b]).axis == "rotary"


def test_a_rotary_fit_reports_rotary_units(tmp_path):
    m = Measurement.from_csv(_joint_csv(tmp_path), "t [s]", position="q [deg]",
                             velocity="qd [deg/s]", acceleration="qdd [deg/s^2]",
                             applied_force="tau [N m]")  # fmt: skip
    res = fit_motion(m, 2)
    assert res.success, res.message
    assert res.parameters["mass"] == pytest.approx(INERTIA, rel=1e-6)
    assert res.axis == "rotary"
    assert res.units["mass"] == "kg m^2" and res.units["stiffness_1"] == "N m/rad"
    assert res.units["threshold_1"] == "rad" and res.signal_unit == "N m"
    report = res.report()
    assert "N m/rad" in report and "N/m" not in report.replace("N m/rad", "")
    text = model_to_toml(res.model, axis="rotary")
    assert "# k_j [N m/rad]" in text and "# c1 [N m]" in text and "[N/m]" not in text


def test_the_cli_writes_a_rotary_model_file(tmp_path, capsys):
    path = _joint_csv(tmp_path, delimiter="\t")
    out = tmp_path / "fit"
    code = main(["fit", str(path), "--kind", "motion", "--elements", "2", "--columns",
                 "time=t", "position=q", "velocity=qd", "acceleration=qdd",
                 "applied_force=tau", "-o", str(out)])  # fmt: skip
    assert code == 0, capsys.readouterr().out
    text = (out / "model.toml").read_text()
    assert "stiffness = [" in text and "# k_j [N m/rad]" in text
    assert "mass = " in text and "# [kg m^2]" in text and "[N/m]" not in text
    report = (out / "report.md").read_text()
    assert "N m/rad" in report
