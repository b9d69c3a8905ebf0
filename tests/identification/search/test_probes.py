"""Probes of the neighbouring valleys after a search (`_probes`)."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import PIFriction, fit_response
from presliding.identification.search._probes import (
    CORNER,
    corner_starts,
    engage_starts,
    merge_starts,
    split_starts,
)
from tests.helpers import stop_records

K = ["stiffness_1", "stiffness_2", "stiffness_3", "stiffness_4"]
MODEL = PIFriction(0.3, [4000.0, 2000.0, 1000.0, 500.0], breakaway=[0.175] * 4)
SHARED = {"mass": 2.0, "coulomb_level": 1.0, "coulomb": 0.3, "stiffness_1": 4000.0,
          "stiffness_2": 2000.0, "stiffness_3": 1000.0, "stiffness_4": 500.0}  # fmt: skip


def test_an_element_that_never_engaged_is_re_engaged_at_the_saturation_force():
    values = {"coulomb_level": 1.5, "coulomb": 0.3, "stiffness_1": 5000.0,
              "stiffness_2": 1000.0, "stiffness_3": 400.0, "stiffness_4": 10.0}  # fmt: skip
    lowered, kept = engage_starts(values, K)
    assert lowered["stiffness_4"] == kept["stiffness_4"] == 1000.0  # median of the others
    # the force the three engaged elements carried at saturation stays: c1 + 3·(F_c − c1)/4
    assert lowered["coulomb_level"] == pytest.approx(0.3 + 0.75 * 1.2)
    assert kept["coulomb_level"] == 1.5
    assert engage_starts({**values, "stiffness_4": 60.0}, K) == []  # 1.2 % of the largest


def _elements(values, k_names):
    """Each element's (threshold, break-away force) of equal break-away forces."""
    c = (values["coulomb_level"] - values["coulomb"]) / len(k_names)
    return sorted((c / values[x], c) for x in k_names)


def test_the_coalesced_starts_are_models_a_model_with_more_elements_contains():
    """The valley of the example stops: two elements that slide, two that hold break-away
    force at thresholds beyond the records' swing (1.5 m and 360 m)."""
    values = {"coulomb_level": 0.6917, "coulomb": 0.3195, "stiffness_1": 2690.0,
              "stiffness_2": 1528.0, "stiffness_3": 0.0614, "stiffness_4": 2.6e-4}  # fmt: skip
    one, lowered, pairs = merge_starts(values, K, live=[0, 1], reachable=0.3722)
    total = sum(values[x] for x in K)
    for start in (one, lowered):  # one threshold, the stiffness at small amplitude kept
        assert all(start[x] == pytest.approx(total / 4) for x in K)
    assert one["coulomb_level"] == values["coulomb_level"] and lowered["coulomb_level"] == 0.3722
    # the two that slide, each split into two copies: their thresholds and forces kept
    was = _elements(values, K)[:2]
    now = _elements(pairs, K)
    np.testing.assert_allclose([r for r, _ in now], np.repeat([r for r, _ in was], 2))
    assert sum(c for _, c in now) == pytest.approx(sum(c for _, c in was))
    assert len(merge_starts(values, K, live=[0, 1, 2], reachable=0.3722)) == 2  # 3 ∤ 4
    assert merge_starts(values, K[:1], live=[0], reachable=0.3722) == []


def test_the_rigid_corner_and_the_split_moves():
    values = {"coulomb_level": 1.0, "coulomb": 0.1, "stiffness_1": 4e7, "stiffness_2": 2000.0}
    (start,) = corner_starts(values, K[:2])
    assert start["stiffness_1"] == 4000.0 and start["stiffness_2"] == 2000.0
    assert corner_starts({**values, "stiffness_1": 3e4}, K[:2]) == []
    splits = split_starts({**values, "stiffness_1": 4000.0}, K[:2])
    assert [(s["stiffness_1"], s["stiffness_2"]) for s in splits] == [(3800.0, 2200.0),
                                                                      (4200.0, 1800.0)]  # fmt: skip
    for s in splits:  # the total stiffness is kept
        assert s["stiffness_1"] + s["stiffness_2"] == pytest.approx(6000.0)


def test_a_fit_in_the_valley_of_an_element_that_never_engaged_finds_the_true_one():
    """Quantised stops started in the valley where k_4 → 0 and F_c ≈ 1.3 (cost 36 % above
    the true valley): a single solve stays there; the search's probes leave it."""
    records, nuisance = stop_records(10, 3, MODEL, samples=400, quantum=1e-6, noise=2e-7)
    start = {**SHARED, "stiffness_1": 5000.0, "stiffness_4": 5.0, "coulomb_level": 1.5}
    for i, n in enumerate(nuisance):
        start.update({f"{k}_{i + 1}": n[k] for k in
                      ("initial_position", "initial_velocity", "preload_fraction")})  # fmt: skip
    options = {"signal": "both", "initial_state": "preload", "initial": start}
    local = fit_response(records, **options, multistart=False)
    assert local.parameters["stiffness_4"] < 1.0  # the other valley exists
    fit = fit_response(records, **options)
    assert fit.parameters["stiffness_4"] > 100.0
    assert fit.parameters["coulomb_level"] == pytest.approx(1.0, rel=0.05)
    cost = float(np.sum((fit.fitted - fit.measured) ** 2))
    assert cost < 0.99 * float(np.sum((local.fitted - local.measured) ** 2))


def _solution(values, cost, status):
    from presliding.identification.solve._solution import Solution

    return Solution(dict(values), {}, {}, 0.95, (), (), np.array([np.sqrt(cost)]), status, "", 1)


def test_a_capped_probe_below_the_best_is_solved_on_never_kept_on_its_cap():
    """A light stage's fine encoder: the main solve stops on its step test a little above
    the optimum that a probe reaches capped in the same basin; the best is then solved on
    (a status ``max_evaluations`` on a fit at the noise floor otherwise)."""
    from presliding.identification.search._probes import solve_probes

    best = _solution({"mass": 1.0}, 1.0, "converged")
    calls = []

    def solve(begin, max_evaluations=None):
        calls.append(max_evaluations)
        if max_evaluations is not None:  # the probe's short solve: capped below the best
            return _solution({"mass": 1.001}, 0.9999, "max_evaluations")
        return _solution({"mass": 1.0015}, 0.9998, "converged")

    problem = type("Problem", (), {"shared": ("mass",)})()
    found, probes = solve_probes(problem, solve, [{"mass": 1.0}], best, budget=40)
    assert calls == [40, None]
    assert found.status == "converged" and found.values["mass"] == 1.0015
    assert [p.status for p in probes] == ["converged"]


def test_beside_the_rigid_corner_the_engage_starts_leave_the_corner():
    """From a corner at k_1 ~ 1e15 every other element looks dead (below 1 % of k_1). Started
    with k_1 kept, the re-engaged starts let c1 fall to 0 beside the near-rigid element,
    whose response rings at MHz after each stop (~6e5 reversals per record and evaluation:
    a 300-sample pooled fit spent 130 s there); the corner element starts at `CORNER` times
    the next one instead (the median of the others then counts it there)."""
    values = {"coulomb_level": 1.0, "coulomb": 0.3, "stiffness_1": 9e15,
              "stiffness_2": 5164.9, "stiffness_3": 1620.0, "stiffness_4": 688.4}  # fmt: skip
    starts = engage_starts(values, K)
    assert len(starts) == 6  # each of the three elements, F_c lowered and kept
    cap = CORNER * 5164.9
    for start in starts:
        assert start["stiffness_1"] == cap
        assert max(start[x] for x in K[1:]) <= cap
    assert starts[1]["stiffness_2"] == np.median([cap, 1620.0, 688.4])  # element 2 re-engaged
    assert engage_starts({**values, "stiffness_1": 4000.0}, K) == []  # no corner, none dead
