"""Baseline friction models (Coulomb, Dahl 1968, LuGre 1995) against closed forms."""

import itertools

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from presliding import PIFriction
from presliding.friction.baselines import (
    CoulombFriction,
    DahlFriction,
    DahlState,
    LuGreFriction,
    LuGreState,
)
from presliding.friction.comparison import compare
from presliding.hysteresis.operators import PIState
from presliding.signals import piecewise_linear

SETTINGS = settings(max_examples=40, deadline=None)
paths = st.lists(st.floats(-1.0, 1.0), min_size=1, max_size=50).map(np.array)
LUGRE = LuGreFriction(
    coulomb=1.0, static=1.5, stiffness=1e5, damping=300.0, viscous=0.4, stribeck_velocity=0.01
)


# ---------------------------------------------------------------------- Coulomb
def test_coulomb_is_sign_of_last_increment():
    model = CoulombFriction(2.5)
    y = np.array([0.0, 0.0, 1.0, 1.0, 0.5, 0.5, 0.7])
    force, state = model.force(y)
    np.testing.assert_array_equal(force, [0.0, 0.0, 2.5, 2.5, -2.5, -2.5, 2.5])
    assert state.direction == 1.0 and state.last_input == 0.7
    assert model.as_pi_friction == PIFriction(coulomb=2.5)


@SETTINGS
@given(paths, st.integers(1, 49))
def test_coulomb_chunked_equals_whole(y, cut):
    model = CoulombFriction(1.0)
    whole, _ = model.force(y)
    cut = min(cut, y.shape[0])
    a, mid = model.force(y[:cut])
    rest = y[cut:]
    b = model.force(rest, mid)[0] if rest.size else np.empty(0)
    np.testing.assert_array_equal(np.r_[a, b], whole)
    assert np.all(np.isin(whole, [-1.0, 0.0, 1.0]))


def test_coulomb_validation():
    with pytest.raises(ValueError, match=r"`coulomb` must be positive; got 0.0"):
        CoulombFriction(0.0)
    with pytest.raises(TypeError, match="`state` must be a PIState"):
        CoulombFriction(1.0).force([0.0, 1.0], DahlState(0.0, 0.0))


# ---------------------------------------------------------------------- Dahl
def test_dahl_virgin_curve_closed_form_alpha_one():
    fc, s0 = 2.0, 150.0
    y = np.linspace(0.0, 0.1, 7)  # coarse steps: exact regardless of step
    force, _ = DahlFriction(fc, s0).force(y)
    np.testing.assert_allclose(force, fc * (1 - np.exp(-s0 * y / fc)), rtol=1e-14, atol=1e-15)
    neg, _ = DahlFriction(fc, s0).force(-y)
    np.testing.assert_allclose(neg, -force, rtol=0, atol=1e-15)


def test_dahl_reversal_branch_closed_form_and_stiffness():
    """From saturation F = F_c the descending branch is −F_c(1 − 2·exp(−σ0 z/F_c))."""
    fc, s0 = 1.0, 100.0
    model = DahlFriction(fc, s0)
    z = np.linspace(0.0, 0.08, 9)
    force, _ = model.force(0.5 - z, DahlState(0.5, fc))
    np.testing.assert_allclose(force, -fc * (1 - 2 * np.exp(-s0 * z / fc)), rtol=0, atol=1e-14)
    for alpha in (0.5, 1.0, 2.0):  # stiffness σ0·2^α after reversal from full sliding
        h = 1e-9
        f, _ = DahlFriction(fc, s0, alpha).force([0.5 - h], DahlState(0.5, fc))
        assert (fc - f[0]) / h == pytest.approx(s0 * 2**alpha, rel=1e-6)
        f0, _ = DahlFriction(fc, s0, alpha).force([0.0, h])
        assert f0[1] / h == pytest.approx(s0, rel=1e-6)  # rest stiffness σ0


@pytest.mark.parametrize("alpha", [0.5, 1.5, 3.0])
def test_dahl_general_exponent_matches_ode(alpha):
    fc, s0 = 1.0, 50.0
    turning = [0.0, 0.05, -0.02, 0.03]
    segs = [np.linspace(a, b, 6) for a, b in itertools.pairwise(turning)]
    y = np.concatenate([segs[0]] + [seg[1:] for seg in segs[1:]])
    force, _ = DahlFriction(fc, s0, alpha).force(y)
    expected, f = [0.0], 0.0
    for seg in segs:
        s = np.sign(seg[-1] - seg[0])

        def rhs(_, F, s=s):
            return [s0 * max(1 - s * F[0] / fc, 0.0) ** alpha]  # dF/dy = σ0·u^α

        sol = solve_ivp(rhs, (seg[0], seg[-1]), [f], t_eval=seg[1:], rtol=1e-12, atol=1e-14)
        expected.extend(sol.y[0])
        f = sol.y[0, -1]
    np.testing.assert_allclose(force, expected, rtol=1e-8, atol=1e-9)
    coarse, _ = DahlFriction(fc, s0, alpha).force(np.array(turning))  # step independence
    np.testing.assert_allclose(coarse, force[::5], rtol=0, atol=1e-14)


def test_dahl_exponent_below_one_reaches_coulomb_in_finite_travel():
    fc, s0, alpha = 1.0, 10.0, 0.5
    travel = fc / (s0 * (1 - alpha))  # u^(1−α) = 1 − (1−α)σ0 z/F_c hits 0
    force, _ = DahlFriction(fc, s0, alpha).force([0.0, 0.999 * travel, travel, 2 * travel])
    assert force[1] < fc and force[2] == fc and force[3] == fc


@SETTINGS
@given(paths, st.integers(1, 49), st.sampled_from([0.5, 1.0, 2.0]))
def test_dahl_bounded_and_chunked_equals_whole(y, cut, alpha):
    model = DahlFriction(1.0, 30.0, alpha)
    whole, end = model.force(y)
    assert np.all(np.abs(whole) <= 1.0)
    cut = min(cut, y.shape[0])
    a, mid = model.force(y[:cut])
    rest = y[cut:]
    b, end2 = model.force(rest, mid) if rest.size else (np.empty(0), mid)
    np.testing.assert_array_equal(np.r_[a, b], whole)
    assert end2 == end


def test_dahl_validation():
    with pytest.raises(ValueError, match=r"`stiffness` must be positive; got -1.0"):
        DahlFriction(1.0, -1.0)
    with pytest.raises(ValueError, match="`exponent` must be positive"):
        DahlFriction(1.0, 1.0, 0.0)
    with pytest.raises(ValueError, match=r"\|force\| <= coulomb 1.0; got 2.0"):
        DahlFriction(1.0, 1.0).force([0.0], DahlState(0.0, 2.0))
    with pytest.raises(TypeError, match="`state` must be a DahlState"):
        DahlFriction(1.0, 1.0).force([0.0], PIState(0.0, np.empty(0)))
    with pytest.raises(ValueError, match="`displacement` must be finite"):
        DahlFriction(1.0, 1.0).force([0.0, np.nan])


# ---------------------------------------------------------------------- LuGre
@pytest.mark.parametrize("v", [-0.05, -0.004, 0.001, 0.01, 0.3])
def test_lugre_steady_state_is_stribeck_curve(v):
    t = np.linspace(0.0, 2.0, 41)
    force, state = LUGRE.force(v * t, t)
    g = 1.0 + 0.5 * np.exp(-((v / 0.01) ** 2))
    expected = g * np.sign(v) + 0.4 * v
    assert force[-1] == pytest.approx(expected, rel=1e-12)
    assert LUGRE.steady_state_force(v) == pytest.approx(expected, rel=1e-15)
    assert state.bristle == pytest.approx(g * np.sign(v) / 1e5, rel=1e-12)


def test_lugre_exact_between_samples_and_matches_ode():
    model = LuGreFriction(1.0, 1.3, 2e3, 5.0, 0.2, 0.02)
    t = np.linspace(0.0, 0.4, 401)
    y = piecewise_linear([0.0, 0.004, -0.002, 0.003], 1e-5)[:401]
    y = np.interp(t, np.linspace(0, 0.4, y.size), y)
    force, _ = model.force(y, t)
    coarse, _ = model.force(y[::4], t[::4])
    fine = model.force(np.interp(np.linspace(0, 0.4, 1601), t, y), np.linspace(0, 0.4, 1601))[0]
    np.testing.assert_allclose(fine[::4][1:], force[1:], rtol=0, atol=1e-12)
    v = np.diff(y[::4]) / np.diff(t[::4])

    def rhs(tt, z):
        vi = v[min(int(tt / 0.004), v.size - 1)]
        g = 1.0 + 0.3 * np.exp(-((vi / 0.02) ** 2))
        return [vi - 2e3 * abs(vi) * z[0] / g]

    z = [0.0]
    zs = [0.0]
    for i in range(v.size):
        z = solve_ivp(rhs, (t[4 * i], t[4 * (i + 1)]), z, rtol=1e-12, atol=1e-16).y[:, -1]
        zs.append(z[0])
    g = 1.0 + 0.3 * np.exp(-((v / 0.02) ** 2))
    zs = np.array(zs)
    expected = 2e3 * zs[1:] + 5.0 * (v - 2e3 * np.abs(v) * zs[1:] / g) + 0.2 * v
    np.testing.assert_allclose(coarse[1:], expected, rtol=1e-8, atol=1e-10)


def test_lugre_presliding_stiffness_from_rest_and_at_reversal():
    model = LuGreFriction(1.0, 1.5, 1e4, 0.0, 0.0, 0.01)
    t = np.array([0.0, 1.0])
    y = np.array([0.0, 1e-12])  # slow and small: v = 1e-12 m/s
    force, _ = model.force(y, t)
    assert force[1] / 1e-12 == pytest.approx(1e4, rel=1e-6)
    # steady sliding at v1 = 0.1, then a slow reversal: dz/dy = 1 + g(v1)/g(v2)
    slide = LuGreState(0.0, 0.0, model.stribeck(0.1) / 1e4, 0.1)
    f_rev, _ = model.force([-1e-12], [1.0], slide)
    stiff = (model.stribeck(0.1) - f_rev[0]) / 1e-12
    assert stiff == pytest.approx(1e4 * (1 + model.stribeck(0.1) / model.stribeck(1e-12)), rel=1e-6)


@SETTINGS
@given(paths, st.integers(1, 49))
def test_lugre_chunked_equals_whole(y, cut):
    t = np.arange(y.shape[0]) * 1e-3
    whole, end = LUGRE.force(y, t)
    cut = min(cut, y.shape[0])
    a, mid = LUGRE.force(y[:cut], t[:cut])
    b, end2 = LUGRE.force(y[cut:], t[cut:], mid) if cut < y.shape[0] else (np.empty(0), mid)
    np.testing.assert_array_equal(np.r_[a, b], whole)
    assert end2 == end
    assert abs(end.bristle) <= 1.5 / 1e5


def test_lugre_validation():
    with pytest.raises(ValueError, match=r"`static` must be >= `coulomb` 1.0; got 0.5"):
        LuGreFriction(1.0, 0.5, 1.0, 0.0, 0.0, 1.0)
    with pytest.raises(ValueError, match="`damping` must be nonnegative"):
        LuGreFriction(1.0, 1.0, 1.0, -1.0, 0.0, 1.0)
    with pytest.raises(ValueError, match=r"`time` must be strictly increasing; got 1.0 after 1.0"):
        LUGRE.force([0.0, 1.0, 2.0], [0.0, 1.0, 1.0])
    with pytest.raises(ValueError, match=r"`time` must start after the state's time 1.0"):
        LUGRE.force([0.0], [1.0], LuGreState(0.0, 1.0))
    with pytest.raises(ValueError, match="must have the same length"):
        LUGRE.force([0.0, 1.0], [0.0])
    with pytest.raises(ValueError, match=r"`state.bristle` must satisfy \|z\|"):
        LUGRE.force([0.0], [1.0], LuGreState(0.0, 0.0, 1.0))


# ---------------------------------------------------------------------- compare
def test_compare_runs_every_model_on_one_path():
    y = piecewise_linear([0.0, 0.02, -0.02, 0.02], 1e-4)
    t = np.linspace(0.0, 1.0, y.size)
    models = {
        "PI": PIFriction(0.2, [100.0, 20.0], [0.4, 0.4]),
        "Coulomb": CoulombFriction(1.0),
        "Dahl": DahlFriction(1.0, 100.0),
        "LuGre": LUGRE,
    }
    res = compare(models, y, time=t)
    assert res.success and list(res.forces) == list(models)
    np.testing.assert_array_equal(res.forces["Dahl"], models["Dahl"].force(y)[0])
    # Coulomb: F_c times the distance travelled (0.1), less what the trapezoidal rule
    # misses where the force jumps: half a step at the start, a whole one at each reversal
    assert res.work["Coulomb"] == pytest.approx(1.0 * (0.1 - 2.5 * 1e-4), rel=1e-9)
    assert res.rms_difference["PI"] == 0.0 and res.rms_difference["Coulomb"] > 0.0
    assert "∫F dy" in res.report() and "LuGre" in res.report()
    ax = res.plot()
    assert [ln.get_label() for ln in ax.get_lines()[:4]] == list(models)
    np.testing.assert_array_equal(ax.get_lines()[2].get_ydata(), res.forces["Dahl"])
    plt.close(ax.figure)
    with pytest.raises(ValueError, match=r"^`time` must be given for the LuGre model 'LuGreFric"):
        compare([LUGRE], y)
    with pytest.raises(TypeError, match=r"^`models` must be a PIFriction, .* got float at index 0"):
        compare([1.0], y)
    with pytest.raises(ValueError, match="`models` must have distinct labels"):
        compare([CoulombFriction(1.0), CoulombFriction(2.0)], y)


def test_compare_checks_time_before_running():
    y = piecewise_linear([0.0, 0.02, -0.02], 1e-3)
    models = [PIFriction(0.2, [100.0], [0.4]), DahlFriction(1.0, 1.0)]
    with pytest.raises(ValueError, match=r"^`displacement` and `time` must have the same length; "):
        compare(models, y, time=[1.0, 2.0])
    t = np.linspace(0.0, 1.0, y.size)
    t[3] = t[2]
    with pytest.raises(
        ValueError, match=r"^`time` must be strictly increasing; got .* at index 3\.$"
    ):
        compare(models, y, time=t)
    with pytest.raises(ValueError, match=r"^`time` must be finite; got nan at index 0\.$"):
        compare(models, y, time=np.full(y.size, np.nan))
    fig, ax = plt.subplots()
    assert compare(models, y, time=np.linspace(0.0, 1.0, y.size)).plot(ax=ax) is ax
    assert len(ax.get_lines()) >= 2
    plt.close(fig)


@pytest.mark.parametrize("method", ["stribeck", "steady_state_force"])
def test_lugre_curves_validate_velocity(method):
    fn = getattr(LUGRE, method)
    with pytest.raises(ValueError, match=r"^`velocity` must be finite; got nan\.$"):
        fn(np.nan)
    with pytest.raises(ValueError, match=r"^`velocity` must be finite; got inf at index 1\.$"):
        fn([0.1, np.inf])
    for bad in ("a", True, None):
        with pytest.raises(TypeError, match=r"^`velocity` must be a real number or array"):
            fn(bad)
    v = np.array([-0.02, 0.0, 0.01])
    g = 1.0 + 0.5 * np.exp(-((v / 0.01) ** 2))
    expected = g if method == "stribeck" else g * np.sign(v) + 0.4 * v
    np.testing.assert_allclose(fn(v), expected, rtol=1e-15)
    assert np.shape(fn(0.01)) == ()
