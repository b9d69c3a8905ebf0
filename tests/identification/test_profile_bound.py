"""A parameter whose column vanishes on its bound (`identification._profile_bound`): profiled
inward from the bound, and the parameters it carries widened to the values they take along
that profile (a record's preload saturated in the direction of its motion, and its initial
velocity)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import optimize, stats

from presliding.identification._least_squares import solve_least_squares
from presliding.identification._normal_equations import profile_thresholds
from presliding.identification._profile import profile_solution

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
