"""A parameter whose column vanishes on its bound (`identification._profile_bound`): profiled
inward from the bound, and the parameters it carries widened to the values they take along
that profile (a record's preload saturated in the direction of its motion, and its initial
velocity)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import optimize, stats

from presliding import PIFriction, fit_response
from presliding.identification.intervals._profile import profile_solution
from presliding.identification.solve._least_squares import solve_least_squares
from presliding.identification.solve._normal_equations import NEAR_FLAT, profile_thresholds
from tests.helpers import random_preload_stops

T = np.linspace(0.0, 1.0, 80)
SHAPE = np.exp(-T)  # close to a line: the offset and slope absorb most of it


def _model(p):
    """y = a + b·t + (1 − f)²·exp(−t): the column of f vanishes at f = 1 (as a preload's)."""
    return p[0] + p[1] * T + (1.0 - p[2]) ** 2 * SHAPE


def _data():
    # a little of −exp(−t) in the data: the best f has (1 − f)² < 0, so f sits on its bound 1
    rng = np.random.default_rng(3)
    return 0.5 - 0.2 * T - 0.05 * SHAPE + rng.normal(0.0, 0.02, T.shape)


def _closed_form(y, f):
    """The cost with f held and a, b re-optimised (linear least squares), and a, b."""
    design = np.column_stack([np.ones_like(T), T])
    target = y - (1.0 - f) ** 2 * SHAPE
    beta = np.linalg.lstsq(design, target, rcond=None)[0]
    r = design @ beta - target
    return float(r @ r), beta


def test_a_flat_column_on_its_bound_is_profiled_inward_and_widens_its_partners():
    y = _data()
    sol = solve_least_squares(
        lambda p: _model(p) - y, {"offset": 0.0, "slope": 0.0, "fraction": 0.5},
        bounds={"fraction": (-1.0, 1.0)}, tolerance=1e-12,
    )  # fmt: skip
    assert sol.values["fraction"] == 1.0
    assert sol.confidence_interval["fraction"] == (-1.0, 1.0)  # the Wald interval sees nothing
    out = profile_solution(sol)
    n = T.shape[0]
    c0 = float(sol.residual @ sol.residual)
    crit = stats.t.ppf(0.975, n - 3) ** 2 * c0 / (n - 3)  # t²·s² (independent residuals)

    exact = optimize.brentq(lambda f: _closed_form(y, f)[0] - c0 - crit, -1.0, 1.0 - 1e-9)
    lo, hi = out.confidence_interval["fraction"]
    assert out.interval_method["fraction"] == "profile"
    assert hi == 1.0
    # the walk's level is its partners' largest threshold, t²·s² up to how the fit's
    # covariance cuts the flat column (0.5 % here): the end to 1e-3 of the range
    assert abs(lo - exact) <= 1e-3 * 2.0

    # the partners: the hull of their Wald interval and their values along that profile
    along = np.array([_closed_form(y, f)[1] for f in np.linspace(exact, 1.0, 201)])
    t = stats.t.ppf(0.975, n - 3)
    for i, name in enumerate(("offset", "slope")):
        wald = sol.confidence_interval[name]
        want = (min(wald[0], along[:, i].min()), max(wald[1], along[:, i].max()))
        got = out.confidence_interval[name]
        assert got[0] < wald[0] or got[1] > wald[1]  # the profile reaches beyond Wald
        assert out.interval_method[name] == "partner"
        half = t * sol.standard_error[name]
        assert abs(got[0] - want[0]) <= 0.05 * half  # the end above, carried
        assert abs(got[1] - want[1]) <= 0.05 * half
        assert out.standard_error[name] == pytest.approx((got[1] - got[0]) / (2 * t))
    # the second optima read the profile's level for all three, not a ratio of cut variances
    limits = profile_thresholds(out)
    assert limits["fraction"] == pytest.approx(crit, rel=1e-9)  # t²·s²: all three carried
    assert limits["offset"] == limits["slope"] == limits["fraction"]


def test_an_initial_velocity_whose_preload_is_saturated_gets_an_interval_from_its_profile(
    monkeypatch,
):
    """Three stops; the first one's preload (0.69 in the motion's direction) fits on its bound
    1 (or a hair inside it), where its column vanishes. Read there, the initial velocity's
    Wald error is 1.9e-5 m/s and the truth 19 of them away; the preload's profile inward from
    the bound holds the truth, and the velocity's interval follows it (z about 4 on the
    raised error)."""
    from presliding.identification import fit_result

    model = PIFriction(0.3, [4000.0, 2000.0, 1000.0, 500.0], breakaway=[0.175] * 4)
    drawn = random_preload_stops(5020, model, 5, 1000, truth=True)
    (meas, v0, fraction), others = drawn[2], [drawn[0], drawn[4]]
    records = [meas] + [o[0] for o in others]
    seen = []
    original = fit_result.profile_solution

    def keep(sol, *args, **kwargs):
        seen.append(sol)
        return original(sol, *args, **kwargs)

    monkeypatch.setattr(fit_result, "profile_solution", keep)
    fit = fit_response(records, signal="both", initial_state="preload")
    wald = min(seen, key=lambda s: float(s.residual @ s.residual))
    # on its bound, or a hair inside it where the solver stopped (from a start 1e-4 away it
    # ended at 0.99915): within NEAR_FLAT of the range, profiled from the bound alike
    assert fit.parameters["preload_fraction_1"] == pytest.approx(1.0, abs=NEAR_FLAT * 2.0)
    # the case: the Wald interval read on the bound misses the initial velocity by far
    name = "initial_velocity_1"
    lo, hi = wald.confidence_interval[name]
    assert not lo <= v0 <= hi
    assert abs(wald.values[name] - v0) > 10.0 * wald.standard_error[name]

    lo_f, hi_f = fit.confidence_interval["preload_fraction_1"]
    assert fit.interval_method["preload_fraction_1"] == "profile"
    assert hi_f == 1.0 and lo_f <= fraction < hi_f
    assert fit.interval_method[name] == "partner"
    lo_v, hi_v = fit.confidence_interval[name]
    assert lo_v < lo and hi_v >= hi  # widened towards the side the preload's move allows
    assert abs(fit.parameters[name] - v0) < 5.0 * fit.standard_error[name]
    t = (hi - wald.values[name]) / wald.standard_error[name]  # the fit's quantile
    assert fit.standard_error[name] == pytest.approx((hi_v - lo_v) / (2.0 * t), rel=1e-9)
    line = next(x for x in fit.report().splitlines() if x.startswith(name))
    assert "saturated parameter's profile" in line


def test_a_flat_column_a_hair_inside_its_bound_is_profiled_from_the_bound():
    """A solver stops a saturated preload at 1 − 3e-5 as well as on 1 (light stage, seed 3 of
    the design study: its record's velocity 6.8 standard errors from the truth): the column
    is as flat there, the walk starts on the bound and the partners widen the same."""
    from dataclasses import replace

    y = _data()
    sol = solve_least_squares(
        lambda p: _model(p) - y, {"offset": 0.0, "slope": 0.0, "fraction": 0.5},
        bounds={"fraction": (-1.0, 1.0)}, tolerance=1e-12,
    )  # fmt: skip
    on = profile_solution(sol)
    inside = profile_solution(replace(sol, values={**sol.values, "fraction": 1.0 - 3e-5}))
    assert inside.interval_method["fraction"] == "profile"
    assert inside.confidence_interval["fraction"][1] == 1.0
    for name in ("offset", "slope", "fraction"):
        assert inside.confidence_interval[name] == pytest.approx(on.confidence_interval[name],
                                                                 rel=1e-6, abs=1e-9)  # fmt: skip
    assert inside.interval_method["offset"] == inside.interval_method["slope"] == "partner"
