"""The probe along eq. 17's scale (`_scale_probe`): mass and every force scaled together."""

from __future__ import annotations

import inspect
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

from presliding import Measurement, PIFriction, fit_response, preloaded_state, simulate
from presliding.identification._fit_engine import FitRun, cost
from presliding.identification.plans._response_plan import response_problem
from presliding.identification.plans._response_request import check_response
from presliding.identification.search import _scale_probe as sp
from presliding.identification.search._nuisance_search import search_nuisance
from presliding.identification.search._scale_probe import scale_probe, scaled, scaled_names
from presliding.identification.solve._least_squares import Solution
from tests.helpers import random_preload_stops

MODEL = PIFriction(0.3, [4000.0, 2000.0, 1000.0, 500.0], breakaway=[0.175] * 4)
SHARED = {"mass": 2.0, "coulomb_level": 1.0, "coulomb": 0.3, "stiffness_1": 4000.0,
          "stiffness_2": 2000.0, "stiffness_3": 1000.0, "stiffness_4": 500.0}  # fmt: skip
OPTIONS = {"signal": "both", "initial_state": "preload"}


def _stops(seed: int, n: int, samples: int = 600) -> list[Measurement]:
    """Stops of the search study's design (`tests.helpers.random_preload_stops`)."""
    return random_preload_stops(seed, MODEL, n, samples)


def _run(records, **options) -> FitRun:
    """The pooled problem `fit_response` builds for these arguments, as a run."""
    given = {k: p.default for k, p in inspect.signature(fit_response).parameters.items()
             if p.default is not inspect.Parameter.empty}  # fmt: skip
    request = {**given, "records": records, "progress": None, **options}
    problem, fit_options = response_problem(check_response(request))
    return FitRun(problem, fit_options)


def test_the_scale_moves_the_mass_and_every_force_unless_one_is_pinned():
    run = _run(_stops(1, 2, samples=200), **OPTIONS, viscous=True)
    names = scaled_names(run.problem.records, run.problem.fixed, run.problem.tied)
    assert set(names) == {*SHARED, "viscous"}  # not the records' own values
    values = {**SHARED, "viscous": 0.5, "initial_position_1": 1e-4}
    up = scaled(values, names, 1.25)
    assert up["mass"] == 2.5 and up["stiffness_4"] == 625.0 and up["viscous"] == 0.625
    assert up["initial_position_1"] == 1e-4
    # the thresholds r_j = c_j / k_j of eq. 17 stay: c = (F_c − c1)/N scales with k_j
    assert (up["coulomb_level"] - up["coulomb"]) / up["stiffness_2"] == pytest.approx(
        (values["coulomb_level"] - values["coulomb"]) / values["stiffness_2"]
    )
    for pinned in ({"mass": 2.0}, {"coulomb": 0.3}):  # a fixed value pins the scale
        p = _run(_stops(1, 2, samples=200), **OPTIONS, fixed=pinned).problem
        assert scaled_names(p.records, p.fixed, p.tied) == []


def test_a_fit_in_the_scaled_down_valley_is_moved_to_the_true_scale():
    """Five quantised stops with random preloads. Mass and forces 28 % low, every record's
    block searched for those values (how the search meets that valley): a local solve
    stays there, mass near 1.5 at a cost well above the true valley's; the probe along
    the scale, the blocks searched again at each step, reaches the true scale."""
    run = _run(_stops(5, 5), **OPTIONS)
    p = run.problem
    names = scaled_names(p.records, p.fixed, p.tied)
    low = {**p.initial, **scaled(SHARED, names, 0.72)}
    begin, _, _ = search_nuisance(p.records, low, p.fixed, p.bounds)
    local = run.solve(begin)
    assert local.values["mass"] < 1.7  # the valley exists: a solve does not leave it
    best, steps, spent = scale_probe(p.records, run.solve, local, names, p.fixed, p.bounds, 40)
    assert spent > 0 and steps
    assert best.values["mass"] == pytest.approx(2.0, rel=0.03)
    assert best.values["coulomb_level"] == pytest.approx(1.0, rel=0.05)
    assert cost(best) < 0.9 * cost(local)


def _outcome(mass: float, c: float) -> Solution:
    return Solution({"mass": mass}, {}, {}, 0.95, (), (), np.array([np.sqrt(c)]), "converged",
                    "", 1)  # fmt: skip


@pytest.mark.parametrize(("ends", "tried"), [
    (1.90, [1.25, 0.8]),  # slid back from 1.6 towards the best at 2.0: the foot, the probe ends
    (1.62, [1.25, 0.8, 0.8, 0.894, 1.118]),  # stayed near its start: on, then halved
])  # fmt: skip
def test_a_step_whose_solve_slid_back_towards_the_best_ends_the_probe(monkeypatch, ends, tried):
    """The probe's course (`_step` scripted): the first step up fails, the step down from
    mass 2.0 (start 1.6) lowers the cost. A solve that slid back along the scale from its
    start 1.6 to 1.90 (more than half the step, in log) found the foot between the start and
    the old best: no further step. One that stayed on the stair next to its start (1.62)
    is followed by a step on in the same direction and, when that fails, by the halvings."""
    calls = []

    def step(problem, solve, best, names, factor, fixed, bounds, budget, tied=None):
        calls.append(round(factor, 3))
        if len(calls) == 2:  # the step down lowers the cost
            return _outcome(ends, 1.0), 0
        return _outcome(best.values["mass"] * factor, 5.0), 0

    monkeypatch.setattr(sp, "_step", step)
    best, _, _ = sp.scale_probe(None, None, _outcome(2.0, 2.0), ["mass"], {}, {}, 40)
    assert best.values["mass"] == ends and sp.cost(best) == 1.0
    assert calls[: len(tried)] == tried and len(calls) == (2 if ends == 1.90 else 7)


def test_a_step_holds_the_records_parameters_left_on_a_bound_and_releases_them(monkeypatch):
    """The step's course (`search_nuisance` and the solver scripted). The search leaves
    record 1's preload on its bound −1 (saturated memory, invisible in the record): a solve
    with it free ends where it began, above the best (the solver's column scaling sends the
    flat preload thousands of trust boxes away; every trial step fails). The step's solve
    holds it, descends below the best, and one solve of everything releases it."""
    problem = SimpleNamespace(
        names=["mass", "initial_position_1", "preload_fraction_1", "preload_fraction_2"],
        record_of={"mass": None, "initial_position_1": 0, "preload_fraction_1": 0,
                   "preload_fraction_2": 1},
        shared=["mass"],
    )  # fmt: skip
    bounds = {"preload_fraction_1": (-1.0, 1.0), "preload_fraction_2": (-1.0, 1.0)}
    searched = {"mass": 1.6, "initial_position_1": 1e-4, "preload_fraction_1": -1.0,
                "preload_fraction_2": 1.0}  # fmt: skip
    monkeypatch.setattr(sp, "search_nuisance", lambda p, v, f, b: (dict(searched), 3.0, 7))
    calls = []

    def solve(values, extra=None, max_evaluations=None):
        calls.append(dict(extra or {}))
        if extra is None and values["mass"] == 1.6:  # free from the search: stalled there
            return replace(_outcome(1.6, 3.0), values=dict(values))
        return replace(_outcome(1.9, 1.0), values={**values, "mass": 1.9})

    # preload_fraction_2 is fixed by the user: not held by the step (it is not free)
    t, spent = sp._step(problem, solve, _outcome(2.0, 2.0), ["mass"], 0.8,
                        {"preload_fraction_2": 1.0}, bounds, 40)  # fmt: skip
    assert calls[0] == {"preload_fraction_1": -1.0}  # only the free one on its bound
    assert calls[-1] == {}  # released: everything free in the step's last solve
    assert cost(t) == pytest.approx(1.0) and t.values["mass"] == 1.9 and spent >= 7
    # tied record parameters are not held either (the solver cannot hold a tied one)
    assert sp.on_bound(problem, searched, {"preload_fraction_1": "preload_fraction_2"},
                       bounds) == {"preload_fraction_2": 1.0}  # fmt: skip


def _stops_5khz(seed: int, n: int) -> tuple[list[Measurement], dict[str, float]]:
    """Stops of the design study's 5 kHz design (`benchmarks/study_designs.py`, ``khz5``):
    0.5 s records of `MODEL` at 2 kg, each record's preload anywhere in ±0.8 F_m of either
    sign, a 1 µm encoder with 0.2 µm noise; the records and the true values."""
    rng = np.random.default_rng(9000 + seed)
    t = np.arange(2500) / 5e3
    records, truth = [], dict(SHARED)
    for i in range(1, n + 1):
        d = rng.choice([-1.0, 1.0])
        v0 = d * 0.5 * rng.uniform(0.04, 0.12)
        fraction = rng.uniform(-0.8, 0.8)
        y0 = rng.uniform(-1.5, 1.5) * 7e-4
        state = preloaded_state(MODEL, fraction * MODEL.max_elastic_force, direction=d,
                                position=y0)  # fmt: skip
        u = np.where(t < rng.uniform(0.03, 0.08), -d * rng.uniform(0.1, 0.6), 0.0)
        res = simulate(MODEL, 2.0, applied_force=(t, u), initial_position=y0,
                       initial_velocity=v0, initial_state=state, t_eval=t)  # fmt: skip
        y = 1e-6 * np.round((res.position + 2e-7 * rng.standard_normal(t.size)) / 1e-6)
        records.append(Measurement(t, position=y, velocity=np.gradient(y, t), applied_force=u))
        truth.update({f"initial_position_{i}": y0, f"initial_velocity_{i}": v0,
                      f"preload_fraction_{i}": fraction})  # fmt: skip
    return records, truth


@pytest.mark.slow
def test_the_5khz_stops_that_ended_converged_a_quarter_low_reach_the_true_scale():
    """The design study's 5 kHz stops, seed 2 (8 records × 2500 samples, ~10 s): the search
    ends in a valley with mass 1.53 and F_c 0.74, 1 % of the cost above the true valley's
    (hundreds of times the profile's threshold, and under the noise-floor rule). The probe's
    step up from there ended `converged` where it began (a saturated preload on its bound,
    free in the step's solve); held, the steps reach the true scale and its cost."""
    records, truth = _stops_5khz(2, 8)
    fit = fit_response(records, **OPTIONS, n_elements=4)
    ref = fit_response(records, **OPTIONS, n_elements=4, initial=truth, multistart=False)
    assert fit.parameters["mass"] == pytest.approx(2.0, rel=0.02)
    assert fit.parameters["coulomb_level"] == pytest.approx(1.0, rel=0.02)
    assert fit.parameters["coulomb"] == pytest.approx(0.3, rel=0.03)

    def sq(f):
        return float(np.sum((f.fitted - f.measured) ** 2))

    assert sq(fit) <= sq(ref) * (1.0 + 1e-4)  # the true valley's cost, not 1 % above it
