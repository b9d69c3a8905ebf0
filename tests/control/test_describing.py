"""The describing function: closed form and density integral against python-control's
numerical route over the stateful friction force, and its properties."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from presliding import Exponential, PiecewiseConstant, PIFriction, Uniform
from presliding.control import describing_function
from presliding.friction.baselines import CoulombFriction
from tests.helpers import PROPERTY, friction_models

MODEL = PIFriction(coulomb=0.2, stiffness=[400.0, 60.0], breakaway=[0.3, 0.4])
BANK = PIFriction(coulomb=0.0, stiffness=[400.0, 60.0, 9.0], breakaway=[0.3, 0.4, 0.2])
UNIFORM = PIFriction(0.1, density=Uniform(height=3.5e7, max_threshold=2e-4))
EXPONENTIAL = PIFriction(0.05, density=Exponential(height=7e7, length=1e-4))


def _numerical(model, amplitude, n):
    """python-control's numerical describing function of the stateful force call."""
    control = pytest.importorskip("control")
    from presliding.control import FrictionNonlinearity

    return complex(
        control.describing_function(
            FrictionNonlinearity(model), [amplitude], num_points=n, try_method=False
        )[0]
    )


@pytest.mark.parametrize("amplitude", [4e-4, 3e-3, 0.05])
def test_bank_agrees_with_the_numerical_route(amplitude):
    """Without c1 the force is continuous along the cycle: the rule is second order and
    4000 points agree to 1e-6 (below every threshold: to rounding, a linear spring)."""
    exact = describing_function(BANK, amplitude)
    num = _numerical(BANK, amplitude, 4000)
    assert abs(num - exact) <= 1e-6 * abs(exact)


@pytest.mark.parametrize(
    ("model", "amplitude", "n"),
    [
        (MODEL, 1e-4, 4000),
        (MODEL, 5e-3, 4000),
        (MODEL, 0.5, 4000),
        (UNIFORM, 1e-4, 2000),
        (UNIFORM, 2e-3, 4000),
        (EXPONENTIAL, 5e-4, 2000),
    ],
)
def test_with_coulomb_element_agrees_with_the_numerical_route(model, amplitude, n):
    """With c1 the force jumps at the turning points, which python-control's grid samples
    (θ = π/2, 3π/2 for n divisible by 4): its error is then 4c1/(nA) on the real part
    exactly, first order, and one Richardson step (n, 2n) leaves the second-order rest."""
    exact = describing_function(model, amplitude)
    coarse, fine = _numerical(model, amplitude, n), _numerical(model, amplitude, 2 * n)
    first_order = 4.0 * model.coulomb / (2 * n * amplitude)
    assert fine.real - exact.real == pytest.approx(first_order, rel=2e-2)
    assert abs((2.0 * fine - coarse) - exact) <= 1e-6 * abs(exact)


def test_python_control_uses_the_exact_form_and_plots():
    control = pytest.importorskip("control")
    from presliding.control import FrictionNonlinearity

    F = FrictionNonlinearity(MODEL)
    assert isinstance(F, control.DescribingFunctionNonlinearity)
    amps = np.geomspace(1e-4, 1.0, 7)
    # python-control evaluates one amplitude at a time: the same closed form to rounding
    np.testing.assert_allclose(control.describing_function(F, amps),
                               describing_function(MODEL, amps), rtol=1e-14, atol=0)  # fmt: skip
    # python-control's plot draws −1/N(A) from the exact form
    s = control.tf("s")
    loop = control.feedback(1 / s**2, 400.0 + 50.0 * s)
    resp = control.describing_function_response(loop, F, amps)
    np.testing.assert_allclose(resp.N_vals, -1 / describing_function(MODEL, amps), rtol=1e-14)
    assert control.describing_function_plot(resp) is not None


def test_calling_the_nonlinearity_walks_the_force():
    pytest.importorskip("control")
    from presliding.control import FrictionNonlinearity

    y = np.array([0.0, 1e-3, 3e-3, -2e-3, 4e-4])
    F = FrictionNonlinearity(MODEL)
    got = [F(v) for v in y]
    np.testing.assert_array_equal(got, MODEL.force(y, MODEL.relaxed_state(0.0))[0])
    F.reset()
    assert F(0.0) == 0.0 and "PIFriction" in repr(F)


def test_small_and_large_amplitudes():
    a = np.array([1e-9, 1e-7])
    # below every threshold: a spring Σk, the Coulomb element in quadrature
    expected = MODEL.initial_stiffness + 4j * 0.2 / (np.pi * a)
    np.testing.assert_allclose(describing_function(MODEL, a), expected, rtol=1e-15)
    # far beyond: the whole level F_c acts as Coulomb friction, 4F_c/(πA) in quadrature
    big = 1e6
    n = describing_function(MODEL, big)
    assert n.imag == pytest.approx(4 * MODEL.coulomb_level / (np.pi * big), rel=1e-6)
    assert 0 < n.real < 1e-10
    assert describing_function(CoulombFriction(0.7), 2.0) == pytest.approx(4j * 0.7 / (2 * np.pi))


@PROPERTY
@given(friction_models(), st.floats(-5.0, 1.0))
def test_properties(model, log_a):
    """0 <= Re N <= Σk (a stiffness that softens), Im N >= 4c1/(πA) (energy is dissipated,
    never created), and Im N·π·A² is the Masing loop area 8∫φ − 4Aφ(A) + 4c1·A."""
    a = 10.0**log_a
    n = describing_function(model, a)
    assert -1e-12 <= n.real <= model.initial_stiffness * (1 + 1e-12) + 1e-12
    assert n.imag >= 4 * model.coulomb / (np.pi * a) * (1 - 1e-12) - 1e-12
    u = np.linspace(0.0, a, 20001)
    phi = model.virgin_curve(u, elastic_only=True)
    area = 8 * np.trapezoid(phi, u) - 4 * a * phi[-1] + 4 * model.coulomb * a
    scale = (model.max_elastic_force + model.coulomb) * a  # the largest loop area / 4
    assert n.imag * np.pi * a * a == pytest.approx(area, rel=1e-6, abs=1e-6 * scale)


@pytest.mark.parametrize(
    "density",
    [
        Uniform(height=3.5e7, max_threshold=2e-4),
        Exponential(height=7e7, length=1e-4),
        Exponential(height=7e7, length=1e-4, max_threshold=3e-4),
        PiecewiseConstant([0.0, 1e-4, 3e-4, 4e-4], [2e7, 5e6, 1e7]),
    ],
    ids=["uniform", "exponential", "truncated", "piecewise"],
)
def test_density_is_the_limit_of_its_discretisations(density):
    """N(A) of μ against the closed form of midpoint discretisations (second order)."""
    model = PIFriction(0.1, density=density)
    big_r = density.max_threshold if np.isfinite(density.max_threshold) else 40 * 1e-4
    amps = np.array([3e-5, 1.5e-4, 5e-4, 2e-2])
    exact = describing_function(model, amps)
    errors = []
    for cells in (2000, 4000):
        fine = PIFriction(0.1, density=density.discretize(cells, big_r))
        errors.append(np.max(np.abs(describing_function(fine, amps) - exact) / np.abs(exact)))
    assert errors[1] < 5e-5 and errors[1] < errors[0] / 3.5  # second order


def test_uniform_density_against_a_direct_integral():
    """Re N of a uniform μ as ∫ n(A; r)·height dr by scipy's adaptive quadrature."""
    from scipy.integrate import quad

    h, big_r, a = 3.5e7, 2e-4, 1.3e-4
    model = PIFriction(0.0, density=Uniform(height=h, max_threshold=big_r))

    def n_re(r):
        psi = 2 * np.arcsin(np.sqrt(r / a))
        return (psi - np.sin(psi) * np.cos(psi)) / np.pi

    sliding = quad(n_re, 0.0, a, epsabs=0, epsrel=1e-13)[0]
    expected = h * (sliding + (big_r - a))
    assert describing_function(model, a).real == pytest.approx(expected, rel=1e-12)


def test_errors():
    with pytest.raises(ValueError, match=r"^`amplitude` must be positive; got 0\.0\.$"):
        describing_function(MODEL, 0.0)
    with pytest.raises(ValueError, match=r"^`amplitude` must be positive; got -1\.0\.$"):
        describing_function(MODEL, [1.0, -1.0])
    with pytest.raises(ValueError, match=r"^`amplitude` must be finite"):
        describing_function(MODEL, np.inf)
    with pytest.raises(TypeError, match=r"^`model` must be a PIFriction or CoulombFriction"):
        describing_function("model", 1.0)
    assert describing_function(MODEL, [[1e-3, 2e-3]]).shape == (1, 2)
    assert describing_function(MODEL, []).shape == (0,)  # element by element, as a ufunc
    # the largest amplitudes give N -> 0 without overflow; a subnormal one overflows 4c1/(πA)
    level = MODEL.coulomb + float(np.sum(MODEL.breakaway))  # F_c (eq. 9): all elements slide
    big = describing_function(MODEL, 1e308)
    assert big.imag == pytest.approx(4.0 * level / np.pi / 1e308, rel=1e-6, abs=0.0)
    with pytest.raises(ValueError, match=r"^`amplitude` must give a finite quadrature part"):
        describing_function(MODEL, [1e-3, 1e-320])
