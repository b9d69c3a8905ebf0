"""What a slowly decaying free vibration of the mode shows, from its backbone (slow flow).

At a turning point of amplitude a the stored energy is E(a) = ½k_∞a² + ½M2(a) + ½a²T(a)
(the loop's tip is on the backbone; the stops that slid hold ½k_j r_j²), so E'(a) =
a·P'(a), and the energy balance over a cycle, E'(a)·Δa = −D(a), gives the decay rate
σ = −ȧ/a = ω·D/(2π·a·E'(a)): a ring-down measures ζ_d = D/(2π·a²·P'(a)) (P' the
backbone's tangent), where the quasi-static definition has D/(2π·a·P(a)) (its secant).
Its frequency is the first harmonic of the Masing loop (the describing function):
ω₁² = k_∞ + Σ_j k_j·h(r_j/a), h(x) = (θ − ½ sin 2θ)/π with cos θ = 1 − 2x (x < 1),
h = 1 for x >= 1; for a loop given by its virgin curve P_v, ω₁² = (2/πa)·∫₀^π
[P(a) − 2P_v(a(1 − cos θ)/2)]·cos θ dθ (Gauss–Legendre on θ).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: Gauss–Legendre nodes on θ for a loop given by its virgin curve.
NODES = 400


@lru_cache(maxsize=8)
def _gauss(nodes: int) -> tuple[FloatArray, FloatArray]:
    """Gauss–Legendre nodes and weights on [0, π] (computed once per size)."""
    z, w = np.polynomial.legendre.leggauss(nodes)
    return 0.5 * np.pi * (z + 1.0), 0.5 * np.pi * w


def stop_harmonic(x: FloatArray) -> FloatArray:
    """h(r/a): the in-phase first-harmonic stiffness of a stop per unit of its stiffness."""
    x = np.minimum(x, 1.0)
    theta = np.arccos(1.0 - 2.0 * x)
    return np.asarray((theta - 0.5 * np.sin(2.0 * theta)) / np.pi)


def harmonic_stiffness_elements(k_lin: float, k: FloatArray, r: FloatArray,
                                a: FloatArray) -> FloatArray:  # fmt: skip
    """ω₁² (unit modal mass) of k_∞·u plus the stops (k_j, r_j), at amplitudes a."""
    if k.shape[0] == 0:
        return np.full(a.shape, k_lin)
    return np.asarray(k_lin + stop_harmonic(r[None, :] / a[:, None]) @ k)


def harmonic_stiffness_density(tail: Callable[[FloatArray], FloatArray], support: float,
                               a: FloatArray, nodes: int = 96) -> FloatArray:  # fmt: skip
    """Σ_j k_j·h(r_j/a) for a density μ given by its tail T(r) = μ((r, R]): by parts,
    (8/π)·∫₀^u T(a·x)·√(x(1 − x)) dx with u = min(1, R/a) (h' = (8/π)√(x(1 − x))),
    on x = u(1 − cos t)/2 by Gauss–Legendre in t (every amplitude at once)."""
    t, w = _gauss(nodes)
    u = np.minimum(1.0, support / a)[:, None]
    x = 0.5 * u * (1.0 - np.cos(t))[None, :]
    jac = 0.5 * u * np.sin(t)[None, :]
    r = np.minimum(a[:, None] * x, support * (1.0 - 1e-15))
    values = np.asarray(tail(r.ravel()), dtype=np.float64).reshape(r.shape)
    integrand = values * np.sqrt(np.maximum(x * (1.0 - x), 0.0)) * jac
    return np.asarray(8.0 / np.pi * (integrand @ w))


def harmonic_stiffness_curve(virgin: Callable[[FloatArray], FloatArray],
                             a: FloatArray) -> FloatArray:  # fmt: skip
    """ω₁² of the Masing loop of the virgin curve P_v at amplitudes a (quadrature)."""
    theta, w = _gauss(NODES)
    out = np.empty(a.shape[0])
    for i, ai in enumerate(a):
        s = 0.5 * ai * (1.0 - np.cos(theta))
        top = virgin(np.array([ai]))[0]
        branch = top - 2.0 * virgin(s)
        out[i] = 2.0 / (np.pi * ai) * float(w @ (branch * np.cos(theta)))
    return out
