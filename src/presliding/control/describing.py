"""The describing function of PI friction (eqs. 8, 10), exact for elements and densities.

python-control's convention: for the input y = A·sin θ on a steady cycle,

    N(A) = (1/(π·A)) ∫_0^{2π} F(A sin θ)·(sin θ + j·cos θ) dθ.

A steady symmetric cycle of amplitude A runs on Masing branches of the virgin
curve φ (the descending one is φ(A) − 2φ((A − y)/2)), so every stop of threshold
r contributes on its own. A stop of unit stiffness that slides (r < A) gives,
with ψ = 2·arcsin(sqrt(r/A)) (the angle over which it sticks after a reversal),

    n(A; r) = (ψ − sin ψ·cos ψ + j·sin²ψ) / π,

and one that never slides (r >= A) gives 1. Hence, for finite elements,

    N(A) = Σ_j k_j·n(A; r_j) + j·4·c1/(π·A)            (closed form),

the Coulomb element's square wave c1·sign(ẏ) contributing 4c1/(πA) in
quadrature (phase lead: friction dissipates). For a density μ (eq. 10) the same
sum is a Stieltjes integral; integrated by parts,

    Re N = (2/π) ∫_0^π T(A·sin²(ψ/2))·sin²ψ dψ,     T(r) = μ((r, R]),
    Im N = 4·(A·M1(A) − M2(A))/(π·A²) + 4·c1/(π·A),

where M1, M2 are the moments of μ (`Density.M1`, `Density.M2`): the imaginary
part is exact and the real part a one-dimensional integral, computed by
Gauss–Legendre rules between the kinks of T (and on geometric pieces towards
r = 0), to rounding for the densities provided. Im N·π·A² is the energy
dissipated per cycle (Masing's rule), Re N the equivalent stiffness (Σk_j for
small A without c1, eq. 7).

A viscous term σ·ẏ is not a function of the amplitude alone (its describing
function is j·σ·ω): it is left out of N(A) and belongs to the linear part of the
loop, where `predict_limit_cycles` puts it (P/(1 + P·(C + σ·s))).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import as_real_array, check_finite_derived
from presliding.friction._sides import require_symmetric
from presliding.friction.baselines import CoulombFriction
from presliding.friction.pi_friction import PIFriction

__all__ = ["describing_function"]

FloatArray = NDArray[np.float64]
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(32)


def friction_model(model: Any) -> PIFriction:
    """A PIFriction (a CoulombFriction becomes its PI form)."""
    if isinstance(model, CoulombFriction):
        return model.as_pi_friction
    if not isinstance(model, PIFriction):
        raise TypeError(
            f"`model` must be a PIFriction or CoulombFriction; got {type(model).__name__}."
        )
    require_symmetric(model, "describing_function (and the friction nonlinearity)")
    return model


def _amplitudes(amplitude: ArrayLike) -> FloatArray:
    """A > 0, finite, of any shape (N(A) is evaluated element by element, as a ufunc)."""
    a = as_real_array("amplitude", amplitude)
    bad = ~(a > 0)
    if bad.any():
        first = float(a[bad].flat[0]) if a.ndim else float(a)
        raise ValueError(f"`amplitude` must be positive; got {first!r}.")
    return a


def _psi_terms(rho: FloatArray) -> tuple[FloatArray, FloatArray]:
    """(ψ − sin ψ cos ψ, sin²ψ) for ψ = 2·arcsin(sqrt(ρ)), 0 <= ρ <= 1, without cancellation."""
    psi = 2.0 * np.arcsin(np.sqrt(rho))
    sin2 = 4.0 * rho * (1.0 - rho)
    sc = 2.0 * np.sqrt(rho * (1.0 - rho)) * (1.0 - 2.0 * rho)
    small = psi < 2e-2
    p2 = psi * psi
    series = psi * p2 * (2.0 / 3.0 - p2 * (2.0 / 15.0 - p2 * (4.0 / 315.0 - p2 * 2.0 / 2835.0)))
    return np.where(small, series, psi - sc), sin2


def elements_df(stiffness: FloatArray, threshold: FloatArray, a: FloatArray) -> Any:
    """Σ_j k_j·n(A; r_j) for amplitudes `a` (any shape): the closed form."""
    flat = a.reshape(-1, 1)
    rho = np.minimum(threshold[None, :] / flat, 1.0)
    lin, sin2 = _psi_terms(rho)
    re = (lin / np.pi) @ stiffness
    im = (sin2 / np.pi) @ stiffness
    return (re + 1j * im).reshape(a.shape)


def _density_kinks(density: Any) -> FloatArray:
    pts = [float(density.max_threshold)]
    for attr in ("breaks", "grid"):
        if hasattr(density, attr):
            pts.extend(np.asarray(getattr(density, attr), dtype=float).tolist())
    kinks = np.asarray(pts)
    return kinks[np.isfinite(kinks) & (kinks > 0)]


def density_df(density: Any, a: FloatArray) -> Any:
    """The elastic N(A) of a density μ: exact imaginary part, Gauss–Legendre real part."""
    flat = a.reshape(-1)
    kinks = _density_kinks(density)
    out = np.empty(flat.shape[0], dtype=complex)
    for i, amp in enumerate(flat):
        r_top = min(amp, float(density.max_threshold))
        rs = np.concatenate(([0.0], amp * np.logspace(-12, -1, 12), kinks, [r_top]))
        rs = np.unique(rs[(rs >= 0.0) & (rs <= r_top)])
        edges = 2.0 * np.arcsin(np.sqrt(np.minimum(rs / amp, 1.0)))
        lo, hi = edges[:-1, None], edges[1:, None]
        psi = 0.5 * (hi - lo) * _NODES[None, :] + 0.5 * (hi + lo)
        wts = 0.5 * (hi - lo) * _WEIGHTS[None, :]
        r = amp * np.sin(0.5 * psi) ** 2
        tail = np.asarray(density.tail(r.ravel())).reshape(r.shape)
        re = 2.0 / np.pi * float(np.sum(wts * tail * np.sin(psi) ** 2))
        im = 4.0 * (amp * density.M1(amp) - density.M2(amp)) / (np.pi * amp * amp)
        out[i] = re + 1j * im
    return out.reshape(a.shape)


def describing_function(model: PIFriction | CoulombFriction, amplitude: ArrayLike) -> Any:
    """N(A) of the friction force for y = A·sin θ on a steady cycle (python-control's convention).

    Parameters
    ----------
    model : PIFriction or CoulombFriction
        Finite elements (closed form) or a density (one-dimensional integral).
    amplitude : float or array_like
        A > 0 [m].

    Returns
    -------
    complex or ndarray of complex
        N(A) [N/m], the shape of `amplitude`. Re N is the equivalent stiffness,
        Im N = (energy dissipated per cycle)/(π·A²) >= 0.

    Examples
    --------
    >>> model = PIFriction(coulomb=0.5, stiffness=[100.0], breakaway=[1.0])
    >>> describing_function(model, 0.005)          # elastic element, Coulomb in quadrature
    (100+127.32395447351627j)
    >>> abs(describing_function(model, 1e3) - 4 * 1.5 / (3.141592653589793e3) * 1j) < 1e-6
    True
    """
    model = friction_model(model)
    a = _amplitudes(amplitude)
    with np.errstate(over="ignore", divide="ignore", invalid="ignore", under="ignore"):
        if model.is_discrete:
            el = elements_df(np.asarray(model.stiffness), np.asarray(model.threshold), a)
        else:
            el = density_df(model.density, a)
        im = np.imag(el) + (4.0 / np.pi) * model.coulomb / a  # π·A overflows for A ~ 1e308
    # a subnormal A (1e-320) makes 4·c1/(π·A) overflow: an error, not inf
    check_finite_derived("quadrature part Im N(A) (energy per cycle/(π·A²))", im, "amplitude")
    check_finite_derived("equivalent stiffness Re N(A)", np.real(el), "amplitude")
    out = np.real(el) + 1j * im
    return complex(out) if np.ndim(out) == 0 else out
