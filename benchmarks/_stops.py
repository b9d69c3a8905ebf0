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


#: the servo rig stand-in (`servo_stop_records`): a rotary axis, 10 000-count encoder
SERVO_COUNTS = 10_000
SERVO_INERTIA = 6e-3
SERVO_TRUTH = {"mass": SERVO_INERTIA, "coulomb_level": 0.05, "coulomb": 0.02,
               "stiffness_1": 30.0, "stiffness_2": 6.0}  # fmt: skip


def servo_model() -> PIFriction:
    c = (SERVO_TRUTH["coulomb_level"] - SERVO_TRUTH["coulomb"]) / 2
    k = [SERVO_TRUTH["stiffness_1"], SERVO_TRUTH["stiffness_2"]]
    return PIFriction(SERVO_TRUTH["coulomb"], k, breakaway=[c, c])


def servo_stop(rng, samples=1000, dt=1e-3):
    """One stop of the servo stand-in: turning at 0.5–1.5 rad/s from steady sliding
    (saturated memory), under a constant torque of 10–40 % of F_c either way until it
    rests; the angle read by a 10 000-count encoder (0.2 counts of noise before the
    rounding), the velocity its difference quotient, as the drive gives it."""
    fric, quantum = servo_model(), 2.0 * np.pi / SERVO_COUNTS
    d = rng.choice([-1.0, 1.0])
    v0 = d * rng.uniform(0.5, 1.5)
    torque = rng.choice([-1.0, 1.0]) * rng.uniform(0.1, 0.4) * SERVO_TRUTH["coulomb_level"]
    y0 = rng.uniform(-np.pi, np.pi)
    state = preloaded_state(fric, fric.max_elastic_force * d, direction=d, position=y0)
    t = np.arange(samples) * dt
    u = np.full(samples, torque)
    res = simulate(fric, SERVO_INERTIA, applied_force=(t, u), initial_position=y0,
                   initial_velocity=v0, initial_state=state, t_eval=t)  # fmt: skip
    assert res.success
    y = quantum * np.round((res.position + 0.2 * quantum * rng.standard_normal(samples)) / quantum)
    meas = Measurement(t, position=y, velocity=np.gradient(y, t), applied_force=u)
    return meas, {"initial_position": y0, "initial_velocity": v0, "preload_fraction": d}, res


def servo_stop_records(seed, n_records=20, **kw):
    rng = np.random.default_rng(seed)
    out = [servo_stop(rng, **kw) for _ in range(n_records)]
    return [o[0] for o in out], [o[1] for o in out], [o[2] for o in out]
