"""The generalized Maxwell-slip model along a path: the PI model as its limit, the lag in closed
form, the Stribeck curve at steady sliding, energy never created."""

import itertools

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from presliding import GMSFriction, GMSState, PIFriction
from tests.helpers import PROPERTY, banks, paths

RATE = {"static_level": 1.3, "stribeck_velocity": 2e-3, "lag_time": 4e-3}


@st.composite
def gms_models(draw: st.DrawFn, rate: bool = True) -> GMSFriction:
    """A random GMS model: a PI bank, c1 >= 0, and (with `rate`) a Stribeck drop and a lag."""
    k, r = draw(banks(min_size=1, max_size=5))
    c1 = draw(st.floats(0.0, 2.0))
    pi = PIFriction(c1, k, threshold=r)
    if not rate:
        return GMSFriction.from_pi(pi)
    ratio = draw(st.floats(1.0, 2.5))
    return GMSFriction.from_pi(
        pi, static_level=ratio * pi.coulomb_level,
        stribeck_velocity=draw(st.floats(1e-3, 1.0)),
        stribeck_exponent=draw(st.floats(0.5, 3.0)),
        lag_time=draw(st.one_of(st.just(0.0), st.floats(1e-4, 1.0))),
    )  # fmt: skip


def times_of(y: np.ndarray, draw: st.DrawFn) -> np.ndarray:
    steps = draw(st.lists(st.floats(1e-3, 0.5), min_size=y.shape[0], max_size=y.shape[0]))
    return np.cumsum(steps)


@PROPERTY
@given(gms_models(rate=False), paths(scale=0.05, min_size=2), st.data())
def test_without_stribeck_drop_and_lag_the_force_is_the_pi_models(model, y, data):
    """F_S = F_C and τ = 0: every element is the play element of eq. 8 (to rounding), for
    any timing of the path."""
    t = times_of(y, data.draw)
    force, state = model.force(y, t)
    pi_force, pi_state = model.pi_friction.force(y)
    scale = model.coulomb_level
    np.testing.assert_allclose(force, pi_force, rtol=0, atol=1e-12 * scale)
    k = model.stiffness
    np.testing.assert_allclose(state.forces, k * (pi_state.last_input - pi_state.play),
                               rtol=0, atol=1e-12 * scale)  # fmt: skip
    assert model.is_rate_independent


@PROPERTY
@given(gms_models(), paths(scale=0.05, min_size=2), st.data())
def test_chunked_runs_continue_the_whole_run(model, y, data):
    t = times_of(y, data.draw)
    cut = data.draw(st.integers(1, y.shape[0] - 1))
    whole, end = model.force(y, t)
    first, mid = model.force(y[:cut], t[:cut])
    rest, end2 = model.force(y[cut:], t[cut:], mid)
    np.testing.assert_array_equal(np.r_[first, rest], whole)
    np.testing.assert_array_equal(end.forces, end2.forces)


@PROPERTY
@given(gms_models(), paths(scale=0.05, min_size=2), st.data())
def test_energy_is_never_created(model, y, data):
    """The dissipation (work done on the elements minus their stored energy) never falls
    along any path, whatever the Stribeck drop and the lag; the work is checked against a
    fine quadrature of the force along the same path."""
    t = times_of(y, data.draw)
    dissipated = model._run(y, t, None)[2]
    scale = model.coulomb_level * float(np.ptp(y) + 1e-3)
    assert np.all(np.diff(dissipated) >= -1e-12 * scale)
    # independent: W = ∫F dy on a refined path (linear in time, as the model takes it)
    fine = 64
    tf = np.concatenate([np.linspace(a, b, fine, endpoint=False) for a, b in
                         itertools.pairwise(t)] + [t[-1:]])  # fmt: skip
    yf = np.interp(tf, t, y)
    ff, end = model.force(yf, tf)
    steps = np.diff(yf)
    moved = np.r_[0.0, np.sign(steps)]
    last = np.maximum.accumulate(np.where(moved != 0, np.arange(moved.size), 0))
    direction = np.where(moved[last] != 0, moved[last], 0.0)  # of the last nonzero increment
    speed = np.r_[0.0, np.abs(steps) / np.diff(tf)]
    coulomb = model.coulomb * model.stribeck(speed) / model.coulomb_level * direction
    elements = ff - coulomb
    work = float(np.sum(0.5 * (elements[1:] + elements[:-1]) * steps))  # trapezoids
    assert work - model.elastic_energy(end) >= -1e-3 * scale


def test_the_lag_relaxes_exponentially_towards_the_stribeck_curve():
    """An element slipping at v1 then at a faster v2: its force falls from c·ŝ(v1) to c·ŝ(v2)
    as exp(−t/(τ·ŝ(v2))) (the lag's closed form), while the Coulomb element follows ŝ at once."""
    model = GMSFriction(0.5, [1e5], [1.0], static_level=3.0, stribeck_velocity=0.01,
                        lag_time=0.02)  # fmt: skip
    v1, v2 = 0.005, 0.02
    start = model.saturated_state(0.0, 0.0, 1.0, v1)
    t = np.linspace(0.0, 0.1, 41)[1:]
    force, _ = model.force(v2 * t, t, start)
    shat = model.stribeck([v1, v2]) / model.coulomb_level
    a1, a2 = shat
    expected = 0.5 * a2 + a2 + (a1 - a2) * np.exp(-t / (model.lag_time * a2))
    np.testing.assert_allclose(force, expected, rtol=1e-12)


def test_steady_sliding_reaches_the_stribeck_curve_plus_viscous():
    model = GMSFriction(0.2, [2e4, 5e3], [0.3, 0.5], static_level=1.5, stribeck_velocity=0.01,
                        lag_time=0.01, viscous=2.0)  # fmt: skip
    for v in (-0.03, 0.002, 0.01, 0.2):
        t = np.linspace(0.0, 2.0, 2001)
        force, _ = model.force(v * t, t)
        np.testing.assert_allclose(force[-1], model.steady_force(v), rtol=1e-10)
    assert float(model.steady_force(0.0)) == 0.0
    np.testing.assert_allclose(model.stribeck(0.0), 1.5)


def test_a_slipping_element_is_never_stretched_faster_than_its_spring():
    """The lag pulls a slipping element's force up to the slower speed's higher slip force,
    but never faster than k·v: at a very slow speed after fast sliding it sticks."""
    model = GMSFriction(0.0, [10.0], [1.0], static_level=2.0, stribeck_velocity=1.0,
                        lag_time=1e-3)  # fmt: skip
    start = model.saturated_state(0.0, 0.0, 1.0, 100.0)  # fast: at F_C
    t = np.linspace(0.0, 1.0, 11)[1:]
    force, _ = model.force(1e-3 * t, t, start)  # v = 1 mm/s ≪ v_s: the target is 2 c
    np.testing.assert_allclose(force, 1.0 + 10.0 * 1e-3 * t, rtol=1e-12)  # the spring's rate


def test_construction_is_checked():
    with pytest.raises(ValueError, match=r"`static_level` must be >= the Coulomb level"):
        GMSFriction(0.1, [1e3], [0.2], static_level=0.2, stribeck_velocity=1.0)
    with pytest.raises(ValueError, match=r"`stribeck_velocity` must be given"):
        GMSFriction(0.1, [1e3], [0.2], static_level=0.5)
    with pytest.raises(ValueError, match=r"`lag_time` must be nonnegative"):
        GMSFriction(0.1, [1e3], [0.2], lag_time=-1.0)
    with pytest.raises(ValueError, match=r"`breakaway` must have the same length"):
        GMSFriction(0.1, [1e3, 2e3], [0.2])
    with pytest.raises(ValueError, match=r"`coulomb` must be positive when `stiffness` is empty"):
        GMSFriction(0.0, [], [])
    model = GMSFriction(0.1, [1e3], [0.2], **RATE)
    with pytest.raises(ValueError, match=r"`state.forces` must satisfy"):
        model.force([0.0, 1e-4], [0.0, 1.0], GMSState(0.0, -1.0, [1.0], [0.0]))
    with pytest.raises(ValueError, match=r"`slipping` must hold only"):
        GMSState(0.0, 0.0, [0.1], [0.5])
    with pytest.raises(TypeError, match=r"`state` must be a GMSState"):
        model.force([0.0, 1e-4], [0.0, 1.0], "relaxed")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"`time` must be strictly increasing"):
        model.force([0.0, 1e-4], [1.0, 1.0])


def test_repr_and_pi_round_trip():
    pi = PIFriction(0.2, [1e4, 2e3], [0.3, 0.3], viscous=1.5)
    model = GMSFriction.from_pi(pi, **RATE)
    assert model.pi_friction == pi
    assert not model.is_rate_independent
    assert "lag_time=0.004" in repr(model) and "static_level=1.3" in repr(model)
    assert repr(GMSFriction.from_pi(pi)).endswith("viscous=1.5)")
