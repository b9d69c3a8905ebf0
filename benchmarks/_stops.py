"""Synthetic stop records for the identification benchmarks (generated with the library).

Each record: a mass sliding at v0 on a contact whose memory carries a preload
(the branch family of `preloaded_state`), decelerated by a constant applied
force opposing the motion for a while, then free until it rests. Position is
measured by an encoder (quantised to `quantum`, with a little additive noise),
velocity is the central difference quotient of that position, as on a real
servo drive. Sampled at 1 kHz.
"""

from __future__ import annotations

import numpy as np

from presliding import Measurement, PIFriction, preloaded_state, simulate

MASS = 2.0
#: the paper's structure: F_c, c1 and four elements of equal break-away force
TRUTH = {"mass": MASS, "coulomb_level": 1.0, "coulomb": 0.3, "stiffness_1": 4000.0,
         "stiffness_2": 2000.0, "stiffness_3": 1000.0, "stiffness_4": 500.0}  # fmt: skip
SHARED = tuple(TRUTH)


def model() -> PIFriction:
    k = [TRUTH[f"stiffness_{j}"] for j in range(1, 5)]
    c = (TRUTH["coulomb_level"] - TRUTH["coulomb"]) / 4
    return PIFriction(TRUTH["coulomb"], k, breakaway=[c] * 4)


def stop_record(rng, samples=1000, dt=1e-3, quantum=1e-6, noise=2e-7, forced=True, free_only=False):
    """One record: (Measurement, its true nuisance values, the simulated motion)."""
    fric = model()
    d = rng.choice([-1.0, 1.0])
    v0 = d * rng.uniform(0.02, 0.06)
    fraction = rng.uniform(0.2, 1.0)
    y0 = rng.uniform(-1e-3, 1e-3)
    state = preloaded_state(fric, fraction * fric.max_elastic_force * d, direction=d, position=y0)
    t = np.arange(samples) * dt
    if free_only or not forced:
        u = np.zeros(samples)
    else:
        t_off = rng.uniform(0.03, 0.08)
        u = np.where(t < t_off, -d * rng.uniform(0.1, 0.6), 0.0)
    res = simulate(fric, MASS, applied_force=(t, u), initial_position=y0, initial_velocity=v0,
                   initial_state=state, t_eval=t)  # fmt: skip
    assert res.success
    y = quantum * np.round((res.position + noise * rng.standard_normal(samples)) / quantum)
    v = np.gradient(y, t)
    meas = Measurement(t, position=y, velocity=v, applied_force=None if free_only else u)
    nuisance = {"initial_position": y0, "initial_velocity": v0, "preload_fraction": fraction * d}
    return meas, nuisance, res


def stop_records(seed, n_records, **kw):
    rng = np.random.default_rng(seed)
    out = [stop_record(rng, **kw) for _ in range(n_records)]
    return [o[0] for o in out], [o[1] for o in out], [o[2] for o in out]
