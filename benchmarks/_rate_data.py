"""Synthetic records of the rate-dependent models for the studies (generated with the library).

`rate_stops`: stops of a GMS model (or LuGre, Dahl) as a servo drive records them —
steady sliding at v0 with a preload of the branch family the pooled fits use
(`presliding.friction.preload`; for GMS the elements' forces times the Stribeck factor
at v0, the saturated ones slipping), a force against the motion for a while, then free
to rest; 1 kHz, a 1 µm encoder with 0.2 µm noise, the velocity the position's
difference quotient; simulated with `substeps` implicit steps per sample.
`creeping_loops`: a PI contact in series with a Kelvin–Voigt element under decaying
sines below break-away, from a relaxed start (0.1 µrad encoder, 30 nrad noise).
"""

from __future__ import annotations

import numpy as np

from presliding import (
    CreepingFriction,
    GMSFriction,
    GMSState,
    Measurement,
    PIFriction,
    preloaded_state,
    quasi_static_response,
    simulate,
)

MASS = 2.0


def gms_truth() -> GMSFriction:
    """c1 = 0.3 N, two elements of 0.35 N (F_C = 1 N), F_S = 1.4 N at 15 mm/s, lag 4 ms."""
    pi = PIFriction(0.3, [3000.0, 600.0], breakaway=[0.35, 0.35])
    return GMSFriction.from_pi(pi, static_level=1.4, stribeck_velocity=0.015, lag_time=0.004)


def creep_truth() -> CreepingFriction:
    """c1 = 0.1, three elements of 0.3 (F_c = 1 N·m), J = 3e-5 rad/(N·m), τ = 0.15 s."""
    return CreepingFriction(PIFriction(0.1, [2e4, 5e3, 1e3], breakaway=[0.3, 0.3, 0.3]),
                            3e-5, 0.15)  # fmt: skip


def gms_preload(model: GMSFriction, fraction: float, direction: float, position: float,
                velocity: float) -> GMSState:  # fmt: skip
    """The GMS state of the pooled fits' preload (module notes)."""
    pi = model.pi_friction
    state = preloaded_state(pi, fraction * pi.max_elastic_force, direction=direction,
                            position=position)  # fmt: skip
    deformation = position - state.play
    shat = float(model.stribeck(velocity)) / model.coulomb_level
    slipping = np.where(deformation * direction >= pi.threshold, direction, 0.0)
    return GMSState(position, 0.0, pi.stiffness * deformation * shat, slipping, velocity,
                    direction)  # fmt: skip


def rate_stops(model: GMSFriction, seed: int, n_records: int = 6, samples: int = 500,
               substeps: int = 16, quantum: float = 1e-6, noise: float = 2e-7
               ) -> list[Measurement]:  # fmt: skip
    rng = np.random.default_rng(seed)
    dt = 1e-3
    t = np.arange(samples) * dt
    out = []
    for _ in range(n_records):
        d = float(rng.choice([-1.0, 1.0]))
        v0, y0 = d * rng.uniform(0.02, 0.06), rng.uniform(-1e-3, 1e-3)
        state = gms_preload(model, d * rng.uniform(0.2, 1.0), d, y0, v0)
        u = np.where(t < rng.uniform(0.03, 0.08), -d * rng.uniform(0.1, 0.6), 0.0)
        res = simulate(model, MASS, applied_force=(t, u), initial_position=y0,
                       initial_velocity=v0, initial_state=state, t_eval=t, method="implicit",
                       step=dt / substeps)  # fmt: skip
        y = quantum * np.round((res.position + noise * rng.standard_normal(samples)) / quantum)
        out.append(Measurement(t, position=y, velocity=np.gradient(y, t), applied_force=u))
    return out


def creeping_loops(seed: int, n_records: int = 5, samples: int = 400, quantum: float = 1e-7,
                   noise: float = 3e-8) -> list[Measurement]:  # fmt: skip
    model = creep_truth()
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n_records):
        duration = rng.uniform(1.5, 3.0)
        t = np.linspace(0.0, duration, samples)
        amplitude = rng.uniform(0.5, 0.9) * model.coulomb_level
        u = amplitude * np.sin(2 * np.pi * rng.uniform(0.5, 1.5) * t + rng.uniform(0, 2 * np.pi))
        u *= np.exp(-t / duration)
        res = quasi_static_response(model, u, time=t)
        y = quantum * np.round((res.position + noise * rng.standard_normal(samples)) / quantum)
        out.append(Measurement(t, position=y, applied_force=u))
    return out
