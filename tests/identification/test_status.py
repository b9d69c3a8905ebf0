"""Honest fit status: poor fits, parameters on bounds, units and labels in reports."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.figure import Figure

import presliding as ps
from presliding.identification._least_squares import STATUSES, name_list
from presliding.identification._status import judge
from presliding.signals import piecewise_linear

MODEL = ps.PIFriction(0.0, [500.0, 50.0], [1.0, 1.0])  # no Coulomb element


def _loops():
    y = piecewise_linear([0.0, 0.8, -0.8, 0.4, -0.2, 0.6, -0.6], 1e-3)
    return y, MODEL.force(y)[0]


def test_poor_fit_is_the_documented_status_and_never_a_success():
    assert "poor_fit" in STATUSES
    assert "poor_fit" in ps.FitResult.__doc__


def test_a_fit_that_explains_little_is_a_poor_fit_naming_the_causes():
    y, _ = _loops()
    noise = np.random.default_rng(0).normal(size=y.shape)  # nothing a friction model explains
    res = ps.fit_presliding(y, noise, 2)
    assert res.status == "poor_fit" and not res.success
    for cause in ("variance", "units", "window", "sign"):
        assert cause in res.message


def test_a_flipped_sign_is_named_first():
    y, f = _loops()
    res = ps.fit_presliding(y, -f, 2)
    assert res.status == "poor_fit"
    assert "sign convention looks flipped" in res.message.split("Likely causes:")[1][:120]


def test_a_parameter_on_its_bound_is_reported_exactly_there():
    y, f = _loops()
    res = ps.fit_presliding(y, f, 2)
    assert res.success
    assert res.parameters["coulomb"] == 0.0 and "coulomb" in res.at_bounds
    line = next(ln for ln in res.report().splitlines() if ln.startswith("coulomb "))
    assert " 0 N " in line and line.endswith("(at its bound 0)")
    # the interval of a nonnegative parameter on its bound starts at the bound, not below it
    assert res.confidence_interval["coulomb"][0] == 0.0
    assert res.bounds["coulomb"] == (0.0, np.inf) and "  [0, inf): coulomb" in res.report()
    assert "stiffness_1" in res.report() and " N/m " in res.report()


def test_every_parameter_on_a_bound_is_a_poor_fit():
    measured = np.sin(np.linspace(0.0, 6.0, 50))
    status, message = judge("converged", "ok", measured, measured, ("a", "b"), ("a", "b"), "x")
    assert status == "poor_fit" and "every fitted parameter sits on a bound" in message
    assert judge("failed", "boom", measured, 0 * measured, ("a",), (), "x") == ("failed", "boom")
    assert judge("converged", "ok", measured, measured, ("a", "b"), ("a",), "x")[0] == "converged"


def test_name_lists_follow_parameter_order_and_are_bounded():
    order = tuple(f"stiffness_{j}" for j in range(1, 13))
    assert name_list(["stiffness_10", "stiffness_2", "stiffness_1"], order) == (
        "stiffness_1, stiffness_2, stiffness_10"
    )
    text = name_list(order[::-1], order)
    assert text.startswith("stiffness_1, stiffness_2,") and text.endswith("and 6 more")


def test_motion_fit_labels_carry_one_unit():
    t = np.linspace(0.0, 2.0, 2001)
    u = 1.5 * np.sin(2 * np.pi * t)
    sim = ps.simulate(ps.PIFriction(0.5), 2.0, applied_force=(t, u), t_eval=t)
    m = ps.Measurement(t, position=sim.position, velocity=sim.velocity,
                       acceleration=sim.acceleration, applied_force=u)  # fmt: skip
    res = ps.fit_motion(m, min_speed=1e-9)
    ax = res.plot(ax=Figure().add_subplot())
    assert ax.get_ylabel() == "applied force [N]"
    assert res.units == {"mass": "kg", "coulomb": "N", "coulomb_level": "N",
                         "max_elastic_force": "N", "initial_stiffness": "N/m"}  # fmt: skip
    assert "residual RMS:" in res.report() and " N (applied force)" in res.report()


@pytest.mark.parametrize("rotary", [False, True])
def test_rotary_measurements_give_rotary_units(tmp_path, rotary):
    t = np.linspace(0.0, 2.0, 2001)
    u = 1.5 * np.sin(2 * np.pi * t)
    sim = ps.simulate(ps.PIFriction(0.5), 2.0, applied_force=(t, u), t_eval=t)
    units = ("rad", "rad/s", "rad/s^2", "N m") if rotary else ("m", "m/s", "m/s^2", "N")
    path = tmp_path / "d.csv"
    head = ",".join(f"{n} [{u_}]" for n, u_ in zip("yvau", units, strict=True))
    np.savetxt(path, np.column_stack([t, sim.position, sim.velocity, sim.acceleration, u]),
               delimiter=",", header="t [s]," + head, comments="")  # fmt: skip
    m = ps.Measurement.from_csv(path, 0, position=1, velocity=2, acceleration=3, applied_force=4)
    res = ps.fit_motion(m, min_speed=1e-9)
    assert res.units["mass"] == ("kg m^2" if rotary else "kg")
    assert res.signal_unit == ("N m" if rotary else "N")
