"""Checks after an output-error fit (`_response_checks`): coalesced elements."""

from __future__ import annotations

import numpy as np
import pytest

from presliding.identification.checks._response_checks import coalesced_split, split_coalesced
from presliding.identification.solve._solution import Solution

K = ["stiffness_1", "stiffness_2", "stiffness_3"]
ROWS = 400
SIGMA = 0.01  # noise of each residual row: s² = cost/dof ≈ σ²


def _solution(values, residual, status="converged", se=None):
    free = tuple(values)
    se = se or dict.fromkeys(free, 1.0)
    ci = {x: (values[x] - 1.96 * se[x], values[x] + 1.96 * se[x]) for x in free}
    cov = np.diag([se[x] ** 2 for x in free])
    return Solution(dict(values), dict(se), ci, 0.95, (), (), residual, status,
                    "converged (`ftol` termination condition is satisfied)", 1,
                    covariance=cov, free=free)  # fmt: skip


NOISE = SIGMA * np.random.default_rng(1).standard_normal(ROWS)
#: the best fit: the pair stiffness_2/stiffness_3 coalesced at 1500 (a sum of 3000), its
#: linearised errors those of a kink (±21, as on the 300-sample stops)
BEST = {"mass": 2.0, "stiffness_1": 4000.0, "stiffness_2": 1500.02, "stiffness_3": 1499.99}
GARBAGE = {"mass": 0.01, "stiffness_1": 60.0, "stiffness_2": 21.0, "stiffness_3": 21.0}


def _cost_solve(curvature):
    """A stand-in solve: the refit with the pair held at a split d = (k_a − k_b)/2 leaves
    the noise plus a rise of curvature·d² (nothing else moves); a free refit comes back to
    the coalesced point."""
    calls = []

    def solve(begin, extra=None, **kw):
        calls.append(dict(extra or {}))
        if not extra:
            return _solution(BEST, NOISE.copy(), se=GARBAGE)
        d = 0.5 * abs(extra["stiffness_2"] - extra["stiffness_3"])
        r = NOISE.copy()
        r[0] += np.sqrt(max(float(NOISE @ NOISE) + curvature * d * d - float(r[1:] @ r[1:]),
                            0.0)) - NOISE[0]  # fmt: skip
        return _solution({**BEST, **extra}, r, status="max_evaluations")

    return solve, calls


def test_a_coalesced_pair_is_not_converged_and_its_intervals_span_the_split():
    """300-sample stops: the pair came back to 1486/1486 from the split start, its errors
    ±21 N/m from the kink, the truth 2000/1000 (z = 24, a wrong "converged" before)."""
    t2s2 = 1.96**2 * float(NOISE @ NOISE) / (ROWS - 4)
    curvature = t2s2 / 400.0**2  # the cost rises by t²·s² at a split of ±400
    solve, calls = _cost_solve(curvature)
    sol = coalesced_split(split_coalesced(_solution(BEST, NOISE.copy(), se=GARBAGE), solve, K),
                          solve, K)  # fmt: skip
    assert sol.status == "not_identifiable"
    assert "split of stiffness_2 and stiffness_3" in sol.message
    assert np.isinf(sol.standard_error["stiffness_2"])
    assert np.isinf(sol.standard_error["stiffness_3"])
    assert sol.standard_error["stiffness_1"] == 60.0  # the others keep theirs
    half = 0.5 * (BEST["stiffness_2"] + BEST["stiffness_3"])
    lo2, hi2 = sol.confidence_interval["stiffness_2"]
    lo3, hi3 = sol.confidence_interval["stiffness_3"]
    assert lo2 <= half and 400.0 < hi2 - half <= 0.4 * half + 1e-9  # the first step above
    assert lo3 <= 1100.0 and hi3 >= half
    assert lo3 == pytest.approx(half - (hi2 - half))  # mirror images
    # every split held: the sum fixed and the pair's values moved apart
    held = [c for c in calls if c]
    assert all(c["stiffness_2"] + c["stiffness_3"] == pytest.approx(2 * half) for c in held)
    assert np.isinf(np.diag(sol.covariance)[2]) and np.isinf(np.diag(sol.covariance)[3])


def test_a_flat_split_spans_every_split_down_to_an_element_of_stiffness_zero():
    solve, _ = _cost_solve(0.0)
    sol = coalesced_split(_solution(BEST, NOISE.copy(), se=GARBAGE), solve, K)
    half = 0.5 * (BEST["stiffness_2"] + BEST["stiffness_3"])
    assert sol.status == "not_identifiable"
    assert sol.confidence_interval["stiffness_3"][0] == pytest.approx(0.0, abs=1e-9)
    assert sol.confidence_interval["stiffness_2"][1] == pytest.approx(2 * half)


def test_a_pair_that_only_comes_close_is_left_to_its_covariance():
    """Two elements 5 % apart have different thresholds: their columns differ and the
    covariance describes the split (the judge's correlation rule reads it)."""
    values = {**BEST, "stiffness_2": 1540.0, "stiffness_3": 1466.0}
    sol = _solution(values, NOISE.copy())

    def solve(begin, extra=None, **kw):  # the split refit comes back, no better
        return _solution(values, NOISE.copy())

    out = coalesced_split(split_coalesced(sol, solve, K), solve, K)
    assert out.status == "converged" and out.standard_error == sol.standard_error


def test_a_fit_in_the_coulomb_corner_is_restarted_with_softer_elements():
    """5 kHz stops: c1 = 1.088 above the parameter F_c = 0.224 (the elements carry nothing,
    no gradient leads back), the stiffnesses those of a start 16 times too stiff; 2 × the
    noise floor. The restarts from the model's F_c with the elements 10 and 100 times
    softer reach the floor."""
    from presliding.identification.checks._response_checks import escape_coulomb

    k4 = ["stiffness_1", "stiffness_2", "stiffness_3", "stiffness_4"]
    corner = {"mass": 2.04, "coulomb_level": 0.224, "coulomb": 1.088, "stiffness_1": 76917.0,
              "stiffness_2": 72899.0, "stiffness_3": 52286.0, "stiffness_4": 21076.0}  # fmt: skip
    starts = []

    def solve(begin, **kw):
        starts.append(dict(begin))
        soft = begin["stiffness_1"] < 1e4  # the second restart (× 0.01) reaches the floor
        return _solution(begin, NOISE * (1.0 if soft else 1.4))

    sol = escape_coulomb(_solution(corner, NOISE * 1.45), solve, k4)
    assert len(starts) == 2
    for share, start in zip((0.1, 0.01), starts, strict=True):
        assert start["coulomb_level"] == 1.088  # the model's F_c (eq. 9), not the parameter
        assert start["coulomb"] == pytest.approx(0.6 * 1.088)
        assert start["stiffness_4"] == pytest.approx(share * 21076.0)
        assert start["stiffness_1"] <= 2 * start["stiffness_2"]  # off the rigid corner too
    assert sol.values["stiffness_1"] < 1e4 and float(sol.residual @ sol.residual) == (
        pytest.approx(float(NOISE @ NOISE))
    )
    # elements that carry force: nothing to restart
    starts.clear()
    kept = _solution({**corner, "coulomb": 0.2}, NOISE.copy())
    assert escape_coulomb(kept, solve, k4) is kept and not starts
