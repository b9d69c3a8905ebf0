"""Honest fit status: poor fits, parameters on bounds, units and labels in reports."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.figure import Figure

import presliding as ps
from presliding.identification.judge._status import judge
from presliding.identification.solve._least_squares import STATUSES, name_list
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
    # units (a few N), window and sign look right: the message names model inadequacy
    # and masing_check's verdict on the loops, not units, window or sign
    assert "variance" in res.message and "model inadequacy" in res.message
    assert "masing_check" in res.message
    assert "units (" not in res.message and "the window (" not in res.message
    # the same noise read in µN as N: the units are named
    tiny = ps.fit_presliding(y, 1e-7 * noise, 2)
    assert tiny.status == "poor_fit" and "units (" in tiny.message
    assert "model inadequacy" not in tiny.message


def test_a_flipped_sign_is_named_first():
    y, f = _loops()
    res = ps.fit_presliding(y, -f, 2)
    assert res.status == "poor_fit"
    assert "sign convention looks flipped" in res.message.split("Likely causes:")[1][:120]


def test_a_parameter_on_its_bound_is_reported_exactly_there():
    y, f = _loops()
    res = ps.fit_presliding(y, f, 2)
    # c1 on its bound 0 is "at_bound" here as in fit_response (one judge for every fit)
    assert res.status == "at_bound" and not res.success
    assert res.message.startswith("rule bound:") and "coulomb = 0" in res.message
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
    assert judge("failed", "boom", measured, 0 * measured, ("a",), (), "x") == (
        "failed",
        "rule solver: boom",
    )
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


# ---------------------------------------------------------------- the judge's rules one by one
_Y = np.sin(np.linspace(0.0, 6.0, 50))
_FREE = ("coulomb", "stiffness_1")
_OK = {"coulomb": 1.0, "stiffness_1": 100.0}
_BOUNDS = {"coulomb": (0.0, np.inf), "stiffness_1": (0.0, np.inf)}


def _judge(status="converged", values=_OK, se=None, ci=None, cov=None, at=(), free=_FREE):
    se = se or {"coulomb": 0.1, "stiffness_1": 5.0}
    ci = ci or {"coulomb": (0.8, 1.2), "stiffness_1": (90.0, 110.0)}
    return judge(
        status, "solver text", _Y, _Y + 0.01, free, at, "force", values=values,
        standard_error=se, intervals=ci, covariance=cov, bounds=_BOUNDS,
    )  # fmt: skip


def test_a_clean_fit_is_converged_and_the_only_exit_code_zero():
    from presliding.identification.judge._status import EXIT_CODES, exit_code

    assert _judge() == ("converged", "solver text")
    assert set(EXIT_CODES) == set(STATUSES)
    assert [s for s in STATUSES if exit_code(s) == 0] == ["converged"]
    assert "local_minimum" in STATUSES


def test_rule_correlation_names_the_pair():
    cov = np.array([[1.0, 0.9995], [0.9995, 1.0]])
    wide = {"coulomb": (0.5, 1.5), "stiffness_1": (60.0, 140.0)}
    status, message = _judge(cov=cov, ci=wide)
    assert status == "not_identifiable" and message.startswith("rule correlation:")
    assert "coulomb ~ stiffness_1" in message
    assert _judge(cov=np.array([[1.0, 0.99], [0.99, 1.0]]), ci=wide)[0] == "converged"
    # a ridge along which both are still tightly determined (noise-free data) is not flagged
    assert _judge(cov=cov)[0] == "converged"


def test_rule_error_names_the_parameter_with_an_infinite_standard_error():
    status, message = _judge(se={"coulomb": 0.1, "stiffness_1": np.inf})
    assert status == "not_identifiable" and message.startswith("rule error:")
    assert "stiffness_1" in message and "coulomb" not in message.split(";")[0]


def test_rule_interval_unbounded_or_spanning_decades():
    status, message = _judge(ci={"coulomb": (0.8, 1.2), "stiffness_1": (90.0, np.inf)})
    assert status == "not_identifiable" and message.startswith("rule interval:")
    assert "stiffness_1 (unbounded)" in message
    status, message = _judge(ci={"coulomb": (0.8, 1.2), "stiffness_1": (0.0, 6.2e208)})
    assert status == "not_identifiable" and "stiffness_1" in message
    # an interval reaching the bound 0 within two decades is determined
    assert _judge(ci={"coulomb": (0.0, 2.0), "stiffness_1": (90.0, 110.0)})[0] == "converged"


def test_rule_bound_flags_model_parameters_but_not_natural_zeros():
    values = {"coulomb": 0.0, "stiffness_1": 100.0}
    status, message = _judge(values=values, at=("coulomb",))
    assert status == "at_bound" and message.startswith("rule bound:") and "coulomb = 0" in message
    values = {"viscous": 0.0, "stiffness_1": 100.0}
    free = ("viscous", "stiffness_1")
    out = judge(
        "converged", "ok", _Y, _Y, free, ("viscous",), "force", values=values,
        standard_error={"viscous": 0.1, "stiffness_1": 1.0},
        intervals={"viscous": (0.0, 0.2), "stiffness_1": (98.0, 102.0)},
        bounds={"viscous": (0.0, np.inf)},
    )  # fmt: skip
    assert out[0] == "converged"


def test_solver_statuses_are_kept_and_named_and_a_poor_fit_wins():
    assert _judge("max_evaluations")[1].startswith("rule budget:")
    assert _judge("local_minimum")[0] == "local_minimum"
    assert _judge("local_minimum")[1].startswith("rule search:")
    status, message = judge("max_evaluations", "x", _Y, 0 * _Y, _FREE, (), "force")
    assert status == "poor_fit" and message.startswith("rule explained:")


def test_a_poor_fit_that_looks_right_names_model_inadequacy_not_units():
    status, message = judge(
        "converged", "ok", _Y, 0 * _Y, _FREE, (), "force",
        model_hint="model inadequacy: the loops break Masing's rules",
    )  # fmt: skip
    assert status == "poor_fit" and "model inadequacy" in message
    assert "the loops break Masing's rules" in message
    assert "units (" not in message and "the window (" not in message
    # a signal standing still over most samples: the window is named, not the model
    idle = np.concatenate([_Y, np.full(200, _Y[-1])])
    status, message = judge("converged", "ok", idle, 0 * idle, _FREE, (), "force")
    assert "the window (the signal stands still" in message and "inadequacy" not in message


def test_two_elements_fitted_to_data_from_one_are_not_identifiable():
    """The second element is not in the data: its interval is unbounded or spans decades,
    and the fit says so naming it, never "converged"."""
    y = piecewise_linear([0.0, 0.8, -0.8, 0.4, -0.2, 0.6, -0.6], 1e-3) * 1e-3
    model = ps.PIFriction(0.2, [500e3], [1.0])
    f = model.force(y)[0] + np.random.default_rng(0).normal(0.0, 0.01, y.shape)
    res = ps.fit_presliding(y, f, 2)
    assert res.status == "not_identifiable" and not res.success
    assert res.message.startswith("rule ") and "_2" in res.message.split(";")[0]
    from presliding.identification.judge._status import exit_code

    assert exit_code(res.status) == 1


def _failed(records, cause=None):
    from presliding.identification.judge._adequacy import Adequacy, Cause, Finding

    found = tuple(Finding("level", i, "position", 3.0, 1.5, 0, "") for i in records)
    named = None if cause is None else Cause(cause, 20.0, 0.5, 1.0, f"a {cause}")
    return Adequacy(found, tuple(3.0 for _ in records), len(records), named)


@pytest.mark.parametrize(
    ("adequacy", "agree", "some_fit", "expected"),
    [
        (_failed([0, 1, 2]), True, False, "model_inadequate"),  # every record, starts agree
        (_failed([1]), True, True, "local_minimum"),  # others pass: their own valley likely
        (_failed([0, 1, 2]), False, False, "local_minimum"),  # the starts ended apart
        (_failed([1], "delay"), True, True, "model_inadequate"),  # a mechanism is named
        (_failed([0, 1], "asymmetry"), False, True, "model_inadequate"),
    ],
)
def test_rule_adequacy_tells_the_model_from_a_valley(adequacy, agree, some_fit, expected):
    """A model whose tests fail is inadequate where a mechanism is named or every record
    fails with starts that agree; with no mechanism named, other records of the same shared
    model passing (or starts that ended apart) make a better optimum likely."""
    from presliding.identification.judge._status import adequacy_verdict

    status, message = adequacy_verdict("converged", "", adequacy, agree, some_fit=some_fit)
    assert status == expected
    assert message.startswith("rule " + ("search" if expected == "local_minimum" else "adequacy"))
