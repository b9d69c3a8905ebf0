"""Hypothesis strategies and small helpers shared by the presliding tests.

Import them with ``from tests.helpers import ...``; the fixtures live in
``conftest.py``.
"""

from __future__ import annotations

import itertools

import numpy as np
from hypothesis import settings
from hypothesis import strategies as st

from presliding import PIFriction

# ----------------------------------------------------------------- the paper's Figure 3
#: c = [1, 1, 1], k2,3 = [10, 4] and k1 in {500, 50, 5} (Section 2, Figure 3).
FIGURE3_FIRST_STIFFNESS = (500.0, 50.0, 5.0)
FIGURE3_BREAKAWAY = (1.0, 1.0, 1.0)


def figure3_model(k1: float, coulomb: float = 0.0) -> PIFriction:
    return PIFriction(coulomb=coulomb, stiffness=[k1, 10.0, 4.0], breakaway=FIGURE3_BREAKAWAY)


# ----------------------------------------------------------------- hypothesis
PROPERTY = settings(max_examples=60, deadline=None)


def _log_uniform(lo_exp: float, hi_exp: float) -> st.SearchStrategy[float]:
    return st.floats(lo_exp, hi_exp, allow_nan=False).map(lambda e: float(10.0**e))


@st.composite
def banks(
    draw: st.DrawFn, min_size: int = 1, max_size: int = 6, threshold_decades: tuple = (-2.0, 0.0)
) -> tuple[np.ndarray, np.ndarray]:
    """(stiffness k_j, threshold r_j) of a random bank of elasto-plastic elements."""
    n = draw(st.integers(min_size, max_size))
    k = draw(st.lists(_log_uniform(-1.0, 3.0), min_size=n, max_size=n))
    r = draw(st.lists(_log_uniform(*threshold_decades), min_size=n, max_size=n))
    return np.array(k), np.array(r)


@st.composite
def friction_models(draw: st.DrawFn, max_size: int = 6) -> PIFriction:
    """A random PIFriction: c1 >= 0 (often 0) and 0..max_size elements."""
    k, r = draw(banks(min_size=0, max_size=max_size))
    if k.size == 0:
        coulomb = draw(st.floats(0.01, 5.0))
    else:
        coulomb = draw(st.one_of(st.just(0.0), st.floats(0.0, 5.0)))
    return PIFriction(coulomb, k, threshold=r)


@st.composite
def paths(
    draw: st.DrawFn, scale: float = 1.0, min_size: int = 1, max_size: int = 60, offset: float = 0.0
) -> np.ndarray:
    """Random displacement samples (the path moves linearly between them), |y − offset| <= 5·scale.

    Each sample is a jump to a new level (moves of several thresholds), a small
    move from the previous sample (inside the play zones) or a repeat (no motion).
    """
    n = draw(st.integers(min_size, max_size))
    kinds = draw(st.lists(st.sampled_from(["jump", "nudge", "stay"]), min_size=n, max_size=n))
    samples = []
    level = 0.0
    for i, kind in enumerate(kinds):
        if kind == "jump" or i == 0:
            level = draw(st.floats(-2.0 * scale, 2.0 * scale))
        elif kind == "nudge":
            level = level + draw(st.floats(-0.05 * scale, 0.05 * scale))
        samples.append(level)
    return offset + np.clip(samples, -5.0 * scale, 5.0 * scale)


@st.composite
def turning_points(draw: st.DrawFn, scale: float = 1.0, max_size: int = 10) -> list[float]:
    """Alternating turning points y_0, y_1, ... (each move reverses the previous one)."""
    n = draw(st.integers(2, max_size))
    lengths = draw(st.lists(st.floats(0.01 * scale, 2.0 * scale), min_size=n - 1, max_size=n - 1))
    sign = draw(st.sampled_from([-1.0, 1.0]))
    points = [draw(st.floats(-scale, scale))]
    for length in lengths:
        points.append(points[-1] + sign * length)
        sign = -sign
    return points


def sample_between(points: list[float], step: float) -> np.ndarray:
    """Samples along straight moves between the points, every point a sample."""
    pieces = [np.array(points[:1], dtype=float)]
    for a, b in itertools.pairwise(points):
        n = max(1, int(np.ceil(abs(b - a) / step)))
        pieces.append(a + (b - a) * np.arange(1, n + 1) / n)
        pieces[-1][-1] = b
    return np.concatenate(pieces)


def one_error_line(capsys, *needles):
    """The command printed exactly one error line, no traceback, containing each needle."""
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    for needle in needles:
        assert needle in lines[0], lines[0]
    return lines[0]


# ----------------------------------------------------------------- pooled identification
def stop_records(seed: int, n_records: int, model: PIFriction, mass: float = 2.0, *,
                 samples: int = 600, dt: float = 1e-3, quantum: float = 0.0, noise: float = 0.0,
                 free: bool = False, preload: bool = True):  # fmt: skip
    """Synthetic stops (exact event method): a slide decelerated by a force, then free.

    Each record starts at y0 with v0 and a preload on the branch of its motion
    (`preloaded_state`); the position is rounded to `quantum` (if > 0) after
    Gaussian `noise`, the velocity is its difference quotient. Returns the
    measurements and the true per-record values.
    """
    from presliding import Measurement, preloaded_state, simulate

    rng = np.random.default_rng(seed)
    t = np.arange(samples) * dt
    out, truth = [], []
    for _ in range(n_records):
        d = float(rng.choice([-1.0, 1.0]))
        v0 = d * rng.uniform(0.02, 0.06)
        frac = rng.uniform(0.2, 1.0) if preload else 1.0
        y0 = rng.uniform(-1e-3, 1e-3)
        state = preloaded_state(model, frac * model.max_elastic_force * d, direction=d,
                                position=y0)  # fmt: skip
        u = np.zeros(samples) if free else np.where(t < rng.uniform(0.03, 0.08), -0.3 * d, 0.0)
        res = simulate(model, mass, applied_force=(t, u), initial_position=y0,
                       initial_velocity=v0, initial_state=state, t_eval=t)  # fmt: skip
        y = res.position + noise * rng.standard_normal(samples)
        if quantum > 0:
            y = quantum * np.round(y / quantum)
        v = np.gradient(y, t) if (quantum > 0 or noise > 0) else res.velocity
        out.append(Measurement(t, position=y, velocity=v, applied_force=None if free else u))
        truth.append({"initial_position": y0, "initial_velocity": v0, "preload_fraction": frac * d,
                      "n_reversals": res.n_reversals})  # fmt: skip
    return out, truth


def rounding_break_away(c1: float) -> tuple[float, float]:
    """(u, F_el) with |u − F_el| > c1 while u − c1·s − F_el rounds to <= 0 (s = sign(u − F_el))."""
    for fel in np.linspace(0.17, 0.93, 4001):
        for steps in range(1, 6):
            g = -c1
            for _ in range(steps):
                g = np.nextafter(g, -1.0)
            u = float(fel + g)
            gg = u - fel
            s = np.sign(gg)
            if abs(gg) > c1 and s * ((u - c1 * s) - fel) <= 0.0:
                return u, float(fel)
    raise AssertionError("no such pair found")
