"""Sine-driven records of the adequacy studies, from a truth the fit may not describe.

The base design (issue 34's review): m = 1.5 kg, c1 = 0.2 N, F_c = 0.8 N and three
elements of equal break-away force (k = 6000, 2000, 700 N/m); six records of 800
samples at 1 kHz, each driven by u = A·sin(2π f t) with A anywhere in
0.5–1.6 F_c, f in 1.5–4 Hz and either sign, from a random preload (±0.8 F_m) at a
random position, moving at 5–20 mm/s in the direction of the memory's branch and of
the force's first half-wave; a 1 µm encoder with 0.2 µm noise, the velocity the difference
quotient of the quantised position (as a servo drive gives it).

`records(seed, misfit)` gives the records of one seed and the truth of the shared
parameters the fit of the symmetric three-element model estimates; a misfit changes
the data-generating model or the recording:

* ``none``: correctly specified;
* ``n0``, ``n1``: the truth above, fitted with 0 or 1 element (too few elements);
* ``asymmetric``: c1⁻ = 1.3·c1 and break-away forces 1.3× as large for −y;
* ``viscous``: a viscous term σ·ẏ with σ = 6 N·s/m;
* ``density``: a continuous uniform density (F_m = 0.6 N, max threshold 2e-4 m) in
  place of the elements (fitted with three);
* ``delay1`` … ``delay5``: the force recorded 1–5 samples late;
* ``noise5``: noise of 5 quanta (correctly specified: the fit should stay right).
"""

from __future__ import annotations

import numpy as np

from presliding import Measurement, PIFriction, Uniform, preloaded_state, simulate

MASS, COULOMB, LEVEL = 1.5, 0.2, 0.8
STIFFNESS = (6000.0, 2000.0, 700.0)
QUANTUM, NOISE = 1e-6, 2e-7
SAMPLES, RATE = 800, 1e3
MISFITS = ("none", "n0", "n1", "asymmetric", "viscous", "density", "delay1", "delay3",
           "delay5", "noise5")  # fmt: skip
#: what the fit is called with (the number of elements of the misfits n0, n1)
OPTIONS = {"signal": "both", "initial_state": "preload"}


def truth() -> dict[str, float]:
    out = {"mass": MASS, "coulomb_level": LEVEL, "coulomb": COULOMB}
    out.update({f"stiffness_{j + 1}": k for j, k in enumerate(STIFFNESS)})
    return out


def model(misfit: str = "none") -> PIFriction:
    n = len(STIFFNESS)
    c = [(LEVEL - COULOMB) / n] * n
    if misfit == "asymmetric":
        return PIFriction(COULOMB, list(STIFFNESS), breakaway=c, coulomb_negative=1.3 * COULOMB,
                          breakaway_negative=[1.3 * x for x in c])  # fmt: skip
    if misfit == "viscous":
        return PIFriction(COULOMB, list(STIFFNESS), breakaway=c, viscous=6.0)
    if misfit == "density":
        r_max = 2e-4
        return PIFriction(COULOMB, density=Uniform(height=2 * (LEVEL - COULOMB) / r_max**2,
                                                   max_threshold=r_max))  # fmt: skip
    return PIFriction(COULOMB, list(STIFFNESS), breakaway=c)


def n_elements(misfit: str) -> int:
    return {"n0": 0, "n1": 1}.get(misfit, len(STIFFNESS))


def record(rng: np.random.Generator, fric: PIFriction, misfit: str = "none",
           samples: int = SAMPLES, rate: float = RATE) -> tuple[Measurement, dict]:  # fmt: skip
    """One sine-driven record of `fric` (module notes), and its own true parameters."""
    t = np.arange(samples) / rate
    amp = rng.uniform(0.5, 1.6) * LEVEL * rng.choice([-1.0, 1.0])
    u = amp * np.sin(2 * np.pi * rng.uniform(1.5, 4.0) * t)
    d = float(np.sign(amp))
    y0 = rng.uniform(-1e-3, 1e-3)
    fraction = rng.uniform(-0.8, 0.8)
    # an asymmetric model's memory is one of its symmetric part (its −y thresholds are wider)
    base = model() if misfit == "asymmetric" else fric
    state = preloaded_state(base, fraction * (LEVEL - COULOMB), direction=d, position=y0)
    v0 = d * rng.uniform(0.005, 0.02)
    res = simulate(fric, MASS, applied_force=(t, u), initial_position=y0, initial_velocity=v0,
                   initial_state=state, t_eval=t)  # fmt: skip
    noise = 5 * QUANTUM if misfit == "noise5" else NOISE
    y = QUANTUM * np.round((res.position + noise * rng.standard_normal(samples)) / QUANTUM)
    if misfit.startswith("delay"):  # the force recorded late: u[t − lag] at t
        lag = int(misfit[5:])
        u = np.concatenate([np.zeros(lag), u[:-lag]])
    own = {"initial_position": y0, "initial_velocity": v0, "preload_fraction": fraction}
    return Measurement(t, position=y, velocity=np.gradient(y, t), applied_force=u), own


def records(seed: int, misfit: str = "none", n_records: int = 6,
            own: bool = False, **kw) -> list:  # fmt: skip
    """The records of one seed (module notes); with `own`, (record, its own truth) pairs."""
    rng = np.random.default_rng(seed)
    fric = model(misfit)
    out = [record(rng, fric, misfit, **kw) for _ in range(n_records)]
    return out if own else [m for m, _ in out]


def full_truth(pairs: list) -> dict[str, float]:
    """The shared truth and every record's own (suffixed), of (record, own) pairs."""
    out = truth()
    for i, (_, own) in enumerate(pairs):
        out.update({f"{k}_{i + 1}": v for k, v in own.items()})
    return out
