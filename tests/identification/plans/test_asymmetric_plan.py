"""fit_response(asymmetric=True): the symmetric fit first, the asymmetric one from it, the test."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import PIFriction, fit_response
from presliding.identification.plans._asymmetric_plan import lifted, split_negative
from presliding.identification.problem._model_spec import ModelSpec
from presliding.identification.records import _pooled_kernel as pk
from presliding.identification.records import _pooled_problem as pp
from presliding.identification.records._pooled_record import as_record
from tests.helpers import stop_records

C1, K, C = 0.3, [4000.0, 1000.0], [0.35, 0.35]
RATIO = 0.8
SYMMETRIC = PIFriction(C1, K, breakaway=C)
ASYMMETRIC = PIFriction(C1, K, breakaway=C, coulomb_negative=RATIO * C1,
                        breakaway_negative=[RATIO * c for c in C])  # fmt: skip


def _problem(records, asymmetric: bool) -> pp.PooledProblem:
    spec = ModelSpec(2, True, None, 32, asymmetric)
    return pp.PooledProblem([as_record(m) for m in records], spec, (1.0, 0.0), "preload",
                            offset=not asymmetric, suffix=True)  # fmt: skip


def _values(problem: pp.PooledProblem, truth: list[dict], shared: dict) -> np.ndarray:
    values = dict(shared)
    for i, t in enumerate(truth):
        for kind in problem.kinds:
            values[problem.nuisance(kind, i)] = t[kind]
    return np.array([values[x] for x in problem.names])


def test_the_asymmetric_kernel_moves_as_the_mean_model_under_a_shifted_force():
    """The sided pooled kernel: F_c⁻ = ρ·F_c⁺ (every level the same share) moves exactly as
    the symmetric model of the mean levels under u − (F_c⁺ − F_c⁻)/2, from the same preloads
    (the play band shifted by (r⁺ − r⁻)/2): the equivalence the parameterisation rests on."""
    records, truth = stop_records(3, 3, ASYMMETRIC)
    sided, offset = _problem(records, True), _problem(records, False)
    mean = 0.5 * (1 + RATIO)
    shared = {"mass": 2.0, "coulomb": C1, "coulomb_level": C1 + sum(C), "stiffness_1": K[0],
              "stiffness_2": K[1]}  # fmt: skip
    y_a, v_a, status, _ = sided.simulate(_values(sided, truth, {
        **shared, "coulomb_level_negative": RATIO * shared["coulomb_level"]}))  # fmt: skip
    y_b, v_b, _, _ = offset.simulate(_values(offset, truth, {
        **shared, "coulomb": mean * C1, "coulomb_level": mean * shared["coulomb_level"],
        "offset": 0.5 * (1 - RATIO) * shared["coulomb_level"]}))  # fmt: skip
    assert np.all(status == 0) and np.ptp(v_a) > 1e-2
    np.testing.assert_allclose(v_a, v_b, rtol=0, atol=1e-12)
    np.testing.assert_allclose(y_a, y_b, rtol=0, atol=1e-14)


def test_equal_sides_are_the_symmetric_kernel_bit_for_bit():
    """F_c⁻ = F_c⁺ passes the sided kernel the symmetric arrays: the same residual to the last
    bit (the nested start is the symmetric optimum exactly)."""
    records, truth = stop_records(4, 2, SYMMETRIC)
    sided = _problem(records, True)
    spec = ModelSpec(2, True, None, 32)
    plain = pp.PooledProblem(sided.records, spec, (1.0, 0.0), "preload", offset=False,
                             suffix=True)  # fmt: skip
    shared = {"mass": 1.9, "coulomb": 0.31, "coulomb_level": 1.02, "stiffness_1": 3900.0,
              "stiffness_2": 1100.0}  # fmt: skip
    x = _values(plain, truth, shared)
    y = _values(sided, truth, {**shared, "coulomb_level_negative": 1.02})
    np.testing.assert_array_equal(sided.residuals(y), plain.residuals(x))
    assert sided.spec.ratio(dict(zip(sided.names, y, strict=True))) == 1.0


def test_the_kernel_refuses_arrays_of_different_shapes():
    arrays = [np.ones(2) for _ in range(5)]
    k = np.ones((2, 3))
    with pytest.raises(ValueError, match="share their sets and elements"):
        pk.pooled_responses(np.ones(2), *arrays[:4], k, k, np.ones((2, 2)), np.ones(2))


def test_asymmetric_stops_give_both_levels_and_a_supported_asymmetry():
    records, _ = stop_records(11, 4, ASYMMETRIC, quantum=1e-6, noise=2e-7)
    fit = fit_response(records, 2, initial_state="preload", asymmetric=True)
    p = fit.parameters
    assert p["coulomb_level"] == pytest.approx(1.0, rel=0.02)
    assert p["coulomb_level_negative"] == pytest.approx(RATIO, rel=0.02)
    assert fit.derived["coulomb_level_ratio"] == pytest.approx(RATIO, abs=0.01)
    assert fit.model.coulomb_levels == pytest.approx((p["coulomb_level"],
                                                      p["coulomb_level_negative"]))  # fmt: skip
    test = fit.asymmetry
    assert test.verdict == "supported" and test.p_value < 1e-6 and test.delta_bic < 0
    assert test.symmetric.status != "failed" and "coulomb_level_negative" not in (
        test.symmetric.parameters)  # fmt: skip
    assert test.rss[1] <= test.rss[0]  # nested: the asymmetric fit starts at the symmetric one
    assert test.degrees_of_freedom[0] == 1
    assert fit.n_evaluations > test.symmetric.n_evaluations
    assert "asymmetry: supported" in fit.report() and fit.to_dict()["asymmetry"]["p_value"] > 0


def test_symmetric_stops_do_not_support_an_asymmetry():
    records, _ = stop_records(12, 4, SYMMETRIC, quantum=1e-6, noise=2e-7)
    fit = fit_response(records, 2, initial_state="preload", asymmetric=True)
    assert fit.asymmetry.verdict == "not supported", fit.asymmetry.message
    assert fit.asymmetry.p_value > 0.05
    assert "prefer asymmetric=False" in fit.asymmetry.message


def test_the_asymmetry_is_an_offset_to_the_records():
    """asymmetric=True and offset=True fit the same model: the same optimum (module notes of
    `_model_spec`), F_c⁺ − F_c⁻ = 2·offset."""
    records, _ = stop_records(13, 2, ASYMMETRIC, quantum=1e-6, noise=2e-7)
    sided = fit_response(records, 2, asymmetric=True)
    offset = fit_response(records, 2, offset=True)
    assert sided.chisqr == pytest.approx(offset.chisqr, rel=1e-5)
    diff = sided.parameters["coulomb_level"] - sided.parameters["coulomb_level_negative"]
    assert diff == pytest.approx(2 * offset.parameters["offset"], rel=1e-3)


def test_viscous_sides_and_the_coulomb_model():
    records, _ = stop_records(14, 3, ASYMMETRIC, quantum=1e-6, noise=2e-7)
    fit = fit_response(records, 0, asymmetric=True, viscous=True)
    assert {"coulomb_negative", "viscous_negative"} <= set(fit.parameters)
    assert fit.asymmetry.degrees_of_freedom[0] == 2
    assert fit.model.coulomb_negative == pytest.approx(fit.parameters["coulomb_negative"])


@pytest.mark.parametrize(("options", "error", "match"), [
    ({"offset": True}, ValueError, "`offset` must be False with `asymmetric`=True"),
    ({"density": "uniform"}, ValueError, "`asymmetric` friction needs elements"),
    ({"asymmetric": "yes"}, TypeError, "`asymmetric` must be True or False"),
])  # fmt: skip
def test_bad_asymmetric_requests_are_refused_before_any_fit(options, error, match):
    records, _ = stop_records(15, 2, SYMMETRIC)
    with pytest.raises(error, match=match):
        fit_response(records, 2, **{"asymmetric": True, **options})


def test_negative_sides_go_to_the_asymmetric_fit_only():
    request = {
        "initial": {"viscous_negative": 0.7, "mass": 2.0},
        "fixed": {"coulomb_negative": 0.2},
        "bounds": None,
        "tied": {"coulomb_level_negative": "coulomb_level", "coulomb": ("mass", 0.1)},
    }
    out = split_negative(request)
    assert out["initial"] == {"mass": 2.0} and out["fixed"] is None
    assert out["tied"] == {"coulomb": ("mass", 0.1)}


def test_lifted_keeps_the_mean_levels():
    spec = ModelSpec(2, True, None, 32, True)
    names = ["mass", *spec.names]
    values = {"mass": 2.0, "coulomb": 0.3, "coulomb_level": 1.0, "stiffness_1": 1.0,
              "stiffness_2": 2.0}  # fmt: skip
    same = lifted(spec, values, names)
    assert same["coulomb_level_negative"] == 1.0 and same["coulomb"] == 0.3
    sided = lifted(spec, values, names, 0.8)
    assert sided["coulomb_level_negative"] / sided["coulomb_level"] == pytest.approx(0.8)
    assert 0.5 * (sided["coulomb_level"] + sided["coulomb_level_negative"]) == pytest.approx(1.0)
    assert 0.5 * (1 + 0.8) * sided["coulomb"] == pytest.approx(0.3)
