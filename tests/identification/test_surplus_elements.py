"""A pooled fit with more elements than the data need: the surplus elements coalesce.

The example stops (`presliding example-data`) are made by one element. With the default
four, the search ended in a valley where two elements held break-away force at thresholds
of 1.5 m and 360 m that the records never reach (F_c 0.69 N where 0.37 N is reached, the
residual twice the noise's) and the fit was called ``model_inadequate``; the model with
four elements of the truth's threshold is the truth itself.
"""

from __future__ import annotations

from dataclasses import replace

import pytest

from presliding import fit_response
from presliding.cli.example_data import _FOLDER, TRUTH
from presliding.identification.plans import _response_plan as rp
from presliding.measurement.measurement import Measurement


@pytest.fixture(scope="module")
def stops():
    return [Measurement.from_csv(_FOLDER / f"stop_{i}.csv", 0, position=1, applied_force=2,
                                 units={"position": "mm"}) for i in (1, 2, 3)]  # fmt: skip


def test_surplus_elements_of_the_example_stops_coalesce_at_the_truth(stops):
    fit = fit_response(stops, 4, signal="position")
    assert fit.status in ("converged", "not_identifiable"), fit.message
    assert fit.adequacy.passed
    truth = TRUTH["stops"]
    level = truth["coulomb"] + sum(truth["breakaway"])  # F_c = c1 + Σ c_j
    for name, value in (("mass", truth["mass"]), ("coulomb", truth["coulomb"]),
                        ("coulomb_level", level)):  # fmt: skip
        low, high = fit.confidence_interval[name]
        assert low <= value <= high, (name, low, high)
    # every element at the truth's threshold, 0.35 N / 4000 N/m
    r = [(level - fit.parameters["coulomb"]) / 4 / fit.parameters[f"stiffness_{j}"]
         for j in range(1, 5)]  # fmt: skip
    assert r == pytest.approx([truth["breakaway"][0] / truth["stiffness"][0]] * 4, rel=0.01)


def test_a_lower_start_whose_solve_stopped_short_makes_a_local_minimum(stops, monkeypatch):
    """The coalesced start's solve stopped on its cap below the valley: the valley is kept
    (an optimum) and its failing residual tests are the search's, not the model's."""
    original, calls, merged = rp.solve_probes, [], []
    original_merged = rp._merged

    def recording(*args):
        merged.append(original_merged(*args))
        return merged[-1]

    def capped(problem, solve, starts, best, *a, **k):
        found, probes = original(problem, solve, starts, best, *a, **k)
        if merged and starts is merged[-1]:  # the coalesced starts: stopped short
            calls.append(found is not best)
            if found is not best:
                found = replace(found, status="max_evaluations")
        return found, probes

    monkeypatch.setattr(rp, "_merged", recording)
    monkeypatch.setattr(rp, "solve_probes", capped)
    fit = fit_response(stops, 4, signal="position")
    assert calls[0]  # the coalesced start went below the valley
    assert fit.status == "local_minimum", fit.message
    assert "rule search" in fit.message and fit.parameters["coulomb_level"] > 0.68
