"""Energy of a mass with PI friction: stored, kinetic and dissipated (eq. after 12).

For the free motion of eq. 12 with a mass m the total energy is

    E = ½·(m·v² + ∫_0^R f(y, r)² dμ(r))          (Σ_j k_j f_j² for finite elements)

and it only decreases: along any path the friction force does the work
W = ∫ F dy = ΔE_el + D with the dissipation

    D = c1·∫|dy| + ∫_0^R r·(total slip of the stop r) dμ(r) >= 0,

the Coulomb element losing c1 per unit length and every stop r losing r per
unit slip and unit stiffness (its break-away force c = k·r, eq. 6). For a
continuous density the stops with r <= ρ slide (ρ the front, see
`MemoryState`), so the stop part is ∫ M1(ρ) |dy| and is integrated exactly.

A viscous term σ·ẏ (``PIFriction.viscous``) dissipates σ·∫ẏ² dt on top of D.
It depends on the time course of the motion, not on the path alone, so the
path functions here leave it out; `viscous_dissipation` integrates it along a
sampled motion, and `presliding.simulate` records it exactly as
``MotionResult.energy.viscous``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_nonnegative_scalar,
    as_real_scalar,
    as_signal,
    check_finite_derived,
    check_increasing,
    check_same_length,
)
from presliding.friction._parts import density_of, elements
from presliding.friction._sides import require_symmetric
from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis.general_pi import GeneralPIOperator, MemoryState, run_density
from presliding.hysteresis.operators import PIState, play, start_memory

__all__ = ["dissipated_energy", "elastic_energy", "total_energy", "viscous_dissipation"]

FloatArray = NDArray[np.float64]


def _model(model: PIFriction) -> PIFriction:
    if not isinstance(model, PIFriction):
        raise TypeError(f"`model` must be a PIFriction; got {type(model).__name__}.")
    return model


def elastic_energy(model: PIFriction, state: PIState | MemoryState) -> float:
    """Stored elastic energy ½∫ f² dμ of the friction contact in `state`.

    Parameters
    ----------
    model : PIFriction
    state : PIState or MemoryState
        A state of this model (finite elements: `PIState`; density: `MemoryState`).

    Returns
    -------
    float
        ½ Σ_j k_j (y − x_j)² or ½∫_0^R f(r)² dμ(r) [J]; the Coulomb element
        stores nothing.
    """
    model = _model(model)
    if model.is_discrete:
        if not isinstance(state, PIState):
            raise TypeError(
                f"`state` must be a PIState for a finite-element model; got {type(state).__name__}."
            )
        k, r, _ = elements(model)
        state.check_against(r)
        f = state.deformation
        return float(0.5 * np.sum(k * f * f))
    if not isinstance(state, MemoryState):
        raise TypeError(
            f"`state` must be a MemoryState for a density model; got {type(state).__name__}."
        )
    return GeneralPIOperator(density_of(model)).elastic_energy(state)


def total_energy(
    model: PIFriction, mass: float, velocity: float, state: PIState | MemoryState
) -> float:
    """E = ½·(m·v² + ∫ f² dμ), the energy of a mass with this friction (eq. after 12).

    Parameters
    ----------
    model : PIFriction
    mass : float
        m >= 0 [kg].
    velocity : float
        v [m/s].
    state : PIState or MemoryState
        Memory of the friction contact (finite elements: `PIState`; density:
        `MemoryState`), see `elastic_energy`.

    Returns
    -------
    float
        ½·m·v² plus the stored elastic energy [J]; it never increases along a
        free motion (eq. 12).
    """
    m = as_nonnegative_scalar("mass", mass)
    v = as_real_scalar("velocity", velocity)
    total = 0.5 * m * v * v + elastic_energy(model, state)  # Python floats: overflow gives inf
    check_finite_derived("energy ½·m·v² + ½∫ f² dμ", total, ("mass", "velocity"))
    return total


def dissipated_energy(
    model: PIFriction, displacement: ArrayLike, state: PIState | MemoryState | None = None
) -> FloatArray:
    """Cumulative energy dissipated by the friction contact along a sampled path.

    D[t] is the work of the friction force from the start up to sample t
    minus the change of stored elastic energy: the Coulomb element's
    c1·Σ|Δy| plus the slip losses of the stops. It is computed exactly for a
    path that is monotone between samples.

    Parameters
    ----------
    model : PIFriction
    displacement : array_like, shape (T,)
    state : PIState or MemoryState, optional
        Memory before the first sample; the motion from ``state.last_input`` to
        ``displacement[0]`` is included. Default: relaxed at ``displacement[0]``
        (D[0] = 0).

    Returns
    -------
    ndarray, shape (T,)
        Nondecreasing, >= 0 [J]. The rate-independent part: the viscous term
        of a model with σ > 0 is not included (see `viscous_dissipation`).
    """
    model = _model(model)
    require_symmetric(model, "dissipated_energy")
    y = as_signal("displacement", displacement)
    expected = PIState if model.is_discrete else MemoryState
    if state is not None and not isinstance(state, expected):
        kind = "a finite-element" if model.is_discrete else "a density"
        raise TypeError(
            f"`state` must be a {expected.__name__} or None for {kind} model; "
            f"got {type(state).__name__}."
        )
    y0 = y[0] if state is None else state.last_input
    coulomb = model.coulomb * np.cumsum(np.abs(np.diff(y, prepend=y0)))
    if model.is_discrete:
        _, r, c = elements(model)
        x0, prev, _ = start_memory(y, r, state)  # validates the state
        if model.n_elements == 0:
            return coulomb
        path = np.concatenate([[prev], y])
        x = play(path, r, x0)
        x = x.reshape(path.shape[0], -1)
        slip = np.abs(np.diff(x, axis=0)) @ c
        return coulomb + np.cumsum(slip)
    _, stops, _ = run_density(density_of(model), y, state, dissipation=True)
    return coulomb + stops


def viscous_dissipation(model: PIFriction, time: ArrayLike, velocity: ArrayLike) -> FloatArray:
    """Cumulative energy σ·∫ẏ² dt dissipated by the viscous term along a sampled motion.

    The trapezoidal rule on the samples (second order in the sample spacing;
    exact for a velocity linear between samples). For an exact record of a
    simulated motion use ``MotionResult.energy.viscous``.

    Parameters
    ----------
    model : PIFriction
        Its ``viscous`` coefficient σ [N·s/m] is used (0 gives zeros); with
        ``viscous_negative``, σ⁻ while ẏ < 0.
    time : array_like, shape (T,)
        Strictly increasing sample times [s].
    velocity : array_like, shape (T,)
        ẏ at those times [m/s].

    Returns
    -------
    ndarray, shape (T,)
        Nondecreasing, >= 0, starting at 0 [J].
    """
    model = _model(model)
    t = as_signal("time", time)
    v = as_signal("velocity", velocity)
    check_same_length(time=t, velocity=v)
    check_increasing("time", t)
    if model.viscous_negative is None:
        power = model.viscous * v * v
    else:  # asymmetric: σ⁺ while ẏ > 0, σ⁻ while ẏ < 0
        power = np.where(v < 0, model.viscous_negative, model.viscous) * v * v
    out = np.zeros(t.shape[0])
    np.cumsum(0.5 * (power[1:] + power[:-1]) * np.diff(t), out=out[1:])
    return out
