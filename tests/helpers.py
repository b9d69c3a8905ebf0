"""Hypothesis strategies and small helpers shared by the presliding tests.

Import them with ``from tests.helpers import ...``; the fixtures live in
``conftest.py``.
"""

from __future__ import annotations

import itertools
import math
import os
import signal
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field, fields, is_dataclass
from typing import Any

import numpy as np
import pytest
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
        state = preloaded_state(model, elastic_share(model, frac * d), direction=d,
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


def elastic_share(model: PIFriction, fraction: float) -> float:
    """`fraction` of the largest elastic force on its side: F_m, or of an asymmetric model
    F_m⁺ = Σ c_j⁺ (fraction > 0) and F_m⁻ = Σ c_j⁻ (fraction < 0)."""
    if model.is_symmetric:
        return fraction * model.max_elastic_force
    k = np.asarray(model.stiffness)
    side = model.threshold if fraction > 0 or model.threshold_negative is None else (
        model.threshold_negative)  # fmt: skip
    return fraction * float(k @ side)


def random_preload_stops(seed: int, model: PIFriction, n_records: int = 4, samples: int = 500,
                         mass: float = 2.0, truth: bool = False):  # fmt: skip
    """Stops of the search study's design: each record's preload anywhere in ±0.8 F_m of
    either sign (of its side's F_m for an asymmetric model), initial velocities of both signs,
    a decelerating force of random level and length, a 1 µm encoder with 0.2 µm noise,
    velocity from the quantised position. With `truth`, each record comes as (record, initial
    velocity, preload fraction)."""
    from presliding import Measurement, preloaded_state, simulate

    rng = np.random.default_rng(seed)
    t = np.arange(samples) * 1e-3
    out = []
    for _ in range(n_records):
        v0 = rng.choice([-1.0, 1.0]) * rng.uniform(0.02, 0.06)
        d = float(np.sign(v0))
        fraction = rng.uniform(-0.8, 0.8)
        y0 = rng.uniform(-1e-3, 1e-3)
        state = preloaded_state(model, elastic_share(model, fraction), direction=d,
                                position=y0)  # fmt: skip
        u = np.where(t < rng.uniform(0.03, 0.08), -d * rng.uniform(0.1, 0.6), 0.0)
        res = simulate(model, mass, applied_force=(t, u), initial_position=y0,
                       initial_velocity=v0, initial_state=state, t_eval=t)  # fmt: skip
        y = 1e-6 * np.round((res.position + 2e-7 * rng.standard_normal(samples)) / 1e-6)
        meas = Measurement(t, position=y, velocity=np.gradient(y, t), applied_force=u)
        out.append((meas, v0, fraction) if truth else meas)
    return out


def rate_stops(model: Any, seed: int, n_records: int = 3, samples: int = 300, *,
               mass: float = 2.0, substeps: int = 4, noise: float = 0.0,
               dt: float = 1e-3):  # fmt: skip
    """Stops of a rate-dependent model (GMS, LuGre, Dahl), simulated as `fit_response`
    simulates them (`substeps` implicit steps per sample): steady sliding at v0, a force
    against it for a while, then free; the position with Gaussian `noise`, the velocity its
    difference quotient (exact without noise). Returns the records and each one's (y0, v0)."""
    from presliding import Measurement, simulate

    rng = np.random.default_rng(seed)
    t = np.arange(samples) * dt
    out, truth = [], []
    for _ in range(n_records):
        d = float(rng.choice([-1.0, 1.0]))
        v0, y0 = d * rng.uniform(0.02, 0.06), rng.uniform(-1e-3, 1e-3)
        u = np.where(t < rng.uniform(0.03, 0.08), -d * rng.uniform(0.1, 0.6), 0.0)
        res = simulate(model, mass, applied_force=(t, u), initial_position=y0,
                       initial_velocity=v0, initial_state="saturated", t_eval=t,
                       method="implicit", step=dt / substeps)  # fmt: skip
        y = res.position + noise * rng.standard_normal(samples)
        v = np.gradient(y, t) if noise > 0 else res.velocity
        out.append(Measurement(t, position=y, velocity=v, applied_force=u))
        truth.append((y0, v0))
    return out, truth


def sine_records(seed: int, model: PIFriction, n_records: int = 4, samples: int = 500, *,
                 mass: float = 1.5, delay: int = 0, base: PIFriction | None = None):  # fmt: skip
    """Sine-driven records of issue 34's review design (smaller): each from a random preload
    (±0.8 F_m, the memory of `base` or `model`) at a random position, moving at 5–20 mm/s
    in the direction of the force's first half-wave u = A·sin(2πft), A in 0.5–1.6 F_c, f in
    1.5–4 Hz; a 1 µm encoder with 0.2 µm noise, the velocity its difference quotient;
    `delay`: the force recorded that many samples late."""
    from presliding import Measurement, preloaded_state, simulate

    rng = np.random.default_rng(seed)
    memory = base or model
    level = memory.coulomb_level
    t = np.arange(samples) * 1e-3
    out = []
    for _ in range(n_records):
        amp = rng.uniform(0.5, 1.6) * level * rng.choice([-1.0, 1.0])
        u = amp * np.sin(2 * np.pi * rng.uniform(1.5, 4.0) * t)
        d = float(np.sign(amp))
        y0 = rng.uniform(-1e-3, 1e-3)
        state = preloaded_state(memory, rng.uniform(-0.8, 0.8) * memory.max_elastic_force,
                                direction=d, position=y0)  # fmt: skip
        res = simulate(model, mass, applied_force=(t, u), initial_position=y0,
                       initial_velocity=d * rng.uniform(0.005, 0.02), initial_state=state,
                       t_eval=t)  # fmt: skip
        y = 1e-6 * np.round((res.position + 2e-7 * rng.standard_normal(samples)) / 1e-6)
        if delay:
            u = np.concatenate([np.zeros(delay), u[:-delay]])
        out.append(Measurement(t, position=y, velocity=np.gradient(y, t), applied_force=u))
    return out


def pooled_problem_at(records, nuisance, shared: dict[str, float], n_elements: int = 2):
    """The pooled problem of stop records with equal break-away forces (preload start), its
    typical scales set at `shared` and each record's true own values (`nuisance`, as
    `stop_records` returns them); returns the problem and those values."""
    from presliding.identification.problem._model_spec import ModelSpec
    from presliding.identification.records import _pooled_problem as pp
    from presliding.identification.records._pooled_record import as_record

    spec = ModelSpec(n_elements, True, None, 32)
    problem = pp.PooledProblem([as_record(m) for m in records], spec, (1.0, 50.0), "preload",
                               offset=False, suffix=True)  # fmt: skip
    values = dict(shared)
    for i, n in enumerate(nuisance):
        for k in problem.kinds:
            values[problem.nuisance(k, i)] = n[k]
    problem.set_typical(values)
    return problem, values


# ----------------------------------------------------------------- the bad-input review
# Every public entry point meets bad values of every class that applies to each of its
# arguments (the tables are in tests/**/test_bad_inputs.py). The promise checked: a
# ValueError or TypeError in one sentence naming the argument the user passed, within a
# time limit and without a RuntimeWarning. A value that may be legal (huge, tiny) is
# either refused that way or gives a finite result.
_TYPES = (("str", "1.0"), ("None", None), ("list_of_str", ["a", "b"]), ("dict", {"a": 1.0}))
_SCALAR = (*_TYPES, ("bool", True), ("array", [1.0, 2.0]), ("nan", math.nan),
           ("inf", math.inf), ("-inf", -math.inf))  # fmt: skip
_VECTOR = (("str", "1 2"), ("None", None), ("list_of_str", ["a", "b"]), ("dict", {"a": 1.0}),
           ("bool", [True, False]), ("nan", [1.0, math.nan]), ("inf", [1.0, math.inf]),
           ("empty", []), ("2d", [[1.0, 2.0], [3.0, 4.0]]),
           ("ragged", [[1.0], [1.0, 2.0]]))  # fmt: skip
_COUNT = (("str", "3"), ("None", None), ("bool", True), ("float", 2.5), ("nan", math.nan),
          ("dict", {"a": 1}), ("negative", -1))  # fmt: skip
_OBJECTS = (("None", None), ("str", "nope"), ("float", 3.0), ("object", object()),
            ("dict", {"a": 1.0}))  # fmt: skip
_BIG = (("huge", 1e308),)
_SMALL = (("huge", 1e308), ("tiny", 1e-320))


def _kind(bad: Any, legal: Any = ()) -> tuple[tuple[str, Any, bool], ...]:
    """(label, value, False) for each bad value, then (label, value, True) for legal ones."""
    return (*((lab, v, False) for lab, v in bad), *((lab, v, True) for lab, v in legal))


_VEC = tuple((lab, v) for lab, v in _VECTOR if lab != "2d")
#: kind -> ((label, value, may be legal), ...)
KINDS: dict[str, tuple[tuple[str, Any, bool], ...]] = {
    "real": _kind(_SCALAR, _BIG),
    "nonnegative": _kind((*_SCALAR, ("negative", -3.0)), _SMALL),
    "positive": _kind((*_SCALAR, ("negative", -3.0), ("zero", 0.0)), _SMALL),
    "count": _kind((*_COUNT, ("zero", 0)), (("huge", 10**12),)),
    "count0": _kind(_COUNT, (("huge", 10**12),)),
    "signal": _kind((*_VEC, ("2d", [[0.0, 1.0], [1.0, 2.0]])), (("huge", [0.0, 1e308, -1e308]),)),
    "positive_vector": _kind(
        (*_VECTOR, ("negative", [1.0, -3.0]), ("zero", [1.0, 0.0])),
        (("huge", [1e308, 1e308]), ("tiny", [1e-320, 1e-320])),
    ),
    "nonnegative_vector": _kind(
        (*_VECTOR, ("negative", [1.0, -3.0])),
        (("huge", [1e308, 1e308]), ("tiny", [1e-320, 1e-320])),
    ),
    "positive_array": _kind(  # element by element, any shape (empty and 2-d are legal)
        (
            *((lab, v) for lab, v in _VECTOR if lab not in ("empty", "2d")),
            ("negative", [1.0, -3.0]),
            ("zero", [1.0, 0.0]),
        ),
        (
            ("huge", [1e308, 1e308]),
            ("tiny", [1e-320, 1e-320]),
            ("empty", []),
            ("2d", [[1e-6, 2e-6], [3e-6, 4e-6]]),
        ),
    ),
    "real_vector": _kind(_VECTOR, (("huge", [1e308, -1e308]),)),
    "real_array": _kind(
        tuple((lab, v) for lab, v in _VECTOR if lab not in ("empty", "2d")),
        (("huge", [1e308, -1e308]),),
    ),
    "matrix": _kind((*_VEC, ("1d", [1.0, 2.0]), ("3d", [[[1.0]]]))),
    "choice": _kind(
        (("unknown", "nope"), ("None", None), ("int", 3), ("list", ["a"]), ("empty", ""))
    ),
    "name": _kind(  # a free name: any non-empty string
        (("None", None), ("int", 3), ("list", ["a"]), ("empty", "")), (("free", "nope"),)
    ),
    "object": _kind(_OBJECTS),
    "callable": _kind(tuple((lab, v) for lab, v in _OBJECTS if lab != "dict")),
    "mapping": _kind((("str", "nope"), ("list", [1.0, 2.0]), ("float", 3.0))),
}


@dataclass
class Entry:
    """A public entry point: `call(**good)` succeeds; `args` maps each argument to its kind
    (a key of `KINDS`; a trailing "?" allows None, "*" an empty array, "~" infinity, and "!"
    leaves out the values that may be legal, for calls that would run long on them);
    `extra` holds cases of its own: (label, overrides, needle, may be legal); `needles`
    gives an argument other names its errors may use ("a|b")."""

    call: Callable[..., Any]
    good: dict[str, Any]
    args: dict[str, str]
    extra: list[tuple[str, dict[str, Any], str, bool]] = field(default_factory=list)
    needles: dict[str, str] = field(default_factory=dict)


class Make:
    """A value built at test time from the test's temporary folder (files, folders)."""

    def __init__(self, build: Callable[[Any], Any]) -> None:
        self.build = build


def bad_input_cases(entries: dict[str, Entry], known: frozenset[str] = frozenset()) -> list[Any]:
    """pytest parameters (entry, overrides, needle, may be legal), one per bad value; the ids
    in `known` are open gaps, marked as strict expected failures (fixing one fails the test
    until its id leaves the list)."""
    params = []
    for name, entry in entries.items():
        for arg, kind in entry.args.items():
            skip = {"?": "None", "*": "empty", "~": "inf"}
            skip = {label for mark, label in skip.items() if mark in kind}
            needle = entry.needles.get(arg, arg)
            for label, value, legal in KINDS[kind.rstrip("?*~!")]:
                if label in skip or (legal and "!" in kind):
                    continue
                params.append((entry, {arg: value}, needle, legal, f"{name}-{arg}-{label}"))
        for label, overrides, needle, legal in entry.extra:
            params.append((entry, overrides, needle, legal, f"{name}-{label}"))
    gap = pytest.mark.xfail(strict=True, reason="an open gap of the bad-input review")
    return [pytest.param(*p[:4], id=p[4], marks=[gap] if p[4] in known else []) for p in params]


class _Hang(Exception):
    pass


def _alarm(signum: int, frame: Any) -> None:
    raise _Hang


def _finite(value: Any, where: str = "result", depth: int = 0) -> None:
    if depth > 3 or value is None or isinstance(value, (str, bytes, bool)):
        return
    if isinstance(value, (float, np.floating)) or (
        isinstance(value, np.ndarray) and value.dtype.kind == "f"
    ):
        assert np.all(np.isfinite(value)), f"{where} is not finite: {value!r}"[:300]
    elif isinstance(value, (tuple, list)):
        for i, item in enumerate(value[:50]):
            _finite(item, f"{where}[{i}]", depth + 1)
    elif is_dataclass(value) and not isinstance(value, type):
        for f in fields(value):
            # stop_time: inf where a member still moves at the end (documented)
            if f.name not in ("model", "final_state", "controller", "predictor", "stop_time"):
                _finite(getattr(value, f.name), f"{where}.{f.name}", depth + 1)


def check_bad_input(
    entry: Entry, overrides: dict[str, Any], needle: str, legal: bool, tmp_path: Any,
    timeout: float = 20.0,
) -> None:  # fmt: skip
    """Call the entry point with the bad value and check the promise (see above)."""
    kwargs = {**entry.good, **overrides}
    kwargs = {k: v.build(tmp_path) if isinstance(v, Make) else v for k, v in kwargs.items()}
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, timeout)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                result = entry.call(**kwargs)
            except (ValueError, TypeError, FileNotFoundError, IsADirectoryError) as exc:
                message = str(exc)
                if isinstance(exc, OSError):  # a missing file or a folder: Python's own errors
                    assert "file:" in needle, f"{type(exc).__name__}: {message}"
                assert "\n" not in message.strip(), f"more than one line: {message!r}"
                files = [n[5:] for n in needle.split("|") if n.startswith("file:")]
                if files and isinstance(kwargs[files[0]], (str, os.PathLike)):
                    # errors in a file name the file first
                    assert message.startswith(str(kwargs[files[0]])), message
                else:
                    named = any(f"`{n}{e}" in message for n in needle.split("|") for e in "`.[")
                    assert named, f"does not name `{needle}`: {message!r}"
                    assert "got" in message, f"does not give the value received: {message!r}"
                assert message.count(". ") == 0 or "(" in message, f"two sentences: {message!r}"
            except _Hang:
                pytest.fail(f"no answer within {timeout} s")
            except Exception as exc:
                pytest.fail(f"{type(exc).__name__}: {exc}"[:400])
            else:
                assert legal, f"accepted: {overrides!r}"[:300]
                _finite(result)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    noisy = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
    assert not noisy, f"warnings: {noisy}"


def check_good_call(entry: Entry, tmp_path: Any) -> None:
    """The table's starting point works: its good call succeeds without a warning."""
    kwargs = {k: v.build(tmp_path) if isinstance(v, Make) else v for k, v in entry.good.items()}
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        entry.call(**kwargs)


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
