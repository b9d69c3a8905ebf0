"""When the probes of other valleys run (`_probe_gate`): the floor, the starts, stationarity."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from presliding import PIFriction, fit_response
from presliding.identification._fit_engine import cost
from presliding.identification.plans import _response_plan as rp
from presliding.identification.search._nuisance_search import search_nuisance
from presliding.identification.search._probe_gate import (
    STATIONARY,
    needs_probes,
    predicted_decrease,
)
from presliding.identification.search._scale_probe import scaled, scaled_names
from presliding.identification.solve._least_squares import solve_least_squares
from tests.helpers import random_preload_stops
from tests.identification.search.test_scale_probe import OPTIONS, SHARED, _run

MODEL = PIFriction(0.3, [4000.0, 2000.0, 1000.0, 500.0], breakaway=[0.175] * 4)


def test_the_predicted_decrease_of_a_linear_model_is_the_cost_above_its_optimum():
    """For a model linear in its parameters the Gauss–Newton model is the cost itself:
    gᵀA⁻¹g at any point is the cost there less the optimum's, here in units of t²·s² at
    that point; at the optimum it is 0 (to round-off)."""
    rng = np.random.default_rng(3)
    x = np.linspace(0.0, 1.0, 50)
    design = np.column_stack([np.ones_like(x), x, x**2])
    y = design @ [1.0, -0.5, 0.3] + rng.normal(0.0, 0.05, x.shape)
    sol = solve_least_squares(lambda p: design @ p - y, {"a": 0.0, "b": 0.0, "c": 0.0},
                              jacobian=lambda p: design, tolerance=1e-12)  # fmt: skip
    best = np.array([sol.values[n] for n in "abc"])
    away = {"a": best[0] + 0.03, "b": best[1] - 0.1, "c": best[2] + 0.05}
    r_away = design @ np.array(list(away.values())) - y
    rise = float(r_away @ r_away) - cost(sol)
    t = stats.t.ppf(0.975, x.size - 3)
    assert predicted_decrease(sol, away) == pytest.approx(
        rise / (t**2 * float(r_away @ r_away) / (x.size - 3)), rel=1e-9
    )
    assert predicted_decrease(sol) < 1e-12


def test_a_fit_at_the_floor_runs_no_probe_of_other_valleys(monkeypatch):
    """Stops fitted from the truth: the search ends at the noise floor, one start, a
    stationary optimum. No split, scale or far-step probe runs (each would cost more
    than the search did)."""
    called = []
    for name in ("scale_probe", "flat_probe", "split_starts"):
        original = getattr(rp, name)

        def spy(*a, _name=name, _original=original, **k):
            called.append(_name)
            return _original(*a, **k)

        monkeypatch.setattr(rp, name, spy)
    records = random_preload_stops(2, MODEL, 3, 400, truth=True)
    truth = dict(SHARED)
    for i, (_, v0, fraction) in enumerate(records, start=1):
        truth.update({f"initial_velocity_{i}": v0, f"preload_fraction_{i}": fraction})
    fit = fit_response([r[0] for r in records], **OPTIONS, initial=truth)
    assert fit.search.residual_over_floor < 3.0 and fit.n_starts == 1
    assert called == []


def test_a_fit_in_a_scale_valley_still_gets_the_scale_probe():
    """Five stops, mass and forces 28 % low with every record's block searched for them
    (the valley of `test_scale_probe`): a local solve stays in that valley, under the
    noise-floor rule, but it stopped on a kink (the Gauss–Newton model promises far more
    than the profile's threshold), so the probes run; from the true valley they do not."""
    run = _run(random_preload_stops(5, MODEL, 5, 600), **OPTIONS)
    p = run.problem
    names = scaled_names(p.records, p.fixed, p.tied)
    begin, _, _ = search_nuisance(p.records, {**p.initial, **scaled(SHARED, names, 0.72)},
                                  p.fixed, p.bounds)  # fmt: skip
    low = run.solve(begin)
    assert low.values["mass"] < 1.7  # in the valley
    assert predicted_decrease(low) > STATIONARY
    assert needs_probes(p.records, low, True, predicted_decrease(low))
    true, _, _ = search_nuisance(p.records, {**p.initial, **SHARED}, p.fixed, p.bounds)
    at_truth = run.solve(true)
    assert cost(at_truth) < cost(low)
    assert not needs_probes(p.records, at_truth, True, predicted_decrease(at_truth))
