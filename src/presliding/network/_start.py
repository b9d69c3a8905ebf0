"""The start of a network run: initial state, start time and end time, checked once.

Shared by the exact path (`simulate_network`) and Moreau–Jean
(`simulate_network_moreau`): a "relaxed" start (no element deformed) or a
`NetworkState` continuing a run, positions and velocities overriding the state's.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._validation import (
    as_real_scalar,
    as_state_vector,
    check_size,
    check_time_span,
    fmt,
)
from presliding.network.results import NetworkState

FloatArray = NDArray[np.float64]

#: The most samples a run returns (`t_eval`, `samples`), as `simulate` and its files allow.
MAX_SAMPLES = 10_000_000


def check_samples(t_eval: Any, width: int) -> int:
    """The number of samples of `t_eval`, checked (at most `MAX_SAMPLES`, and their rows of
    `width` numbers within memory) before it is copied or converted."""
    shape = t_eval.shape if isinstance(t_eval, np.ndarray) else None
    if shape is None:
        try:
            count = len(t_eval)
        except TypeError:
            count = 1
    else:
        count = int(np.prod(shape)) if len(shape) != 1 else int(shape[0])
    if count > MAX_SAMPLES:
        raise ValueError(f"`t_eval` must have at most {MAX_SAMPLES:,} samples; got {count:,}.")
    check_size("t_eval", f"{count} samples", 2.0 * count * (width + 1), what="sampled values")
    return count


@dataclass
class Start:
    """Where a run starts: t0, q, q̇, g, element deformations e, modes s, last directions."""

    t0: float
    t_end: float
    q: FloatArray
    v: FloatArray
    g: FloatArray
    e: FloatArray
    s: FloatArray
    last: FloatArray


def run_start(w: FloatArray, n_elements: int, initial_position: Any, initial_velocity: Any,
              initial_state: Any, t_start: Any, t_end: Any) -> Start:  # fmt: skip
    """The checked start of a run on the contact matrix `w` (n × n_c) with `n_elements`."""
    n, n_c = w.shape
    if isinstance(initial_state, NetworkState):
        st = initial_state
        if st.deformation.shape != (n_elements,) or st.position.shape != (n,):
            raise ValueError(
                "`initial_state` must belong to this structure (same coordinates and elements);"
                f" got {st.position.shape[0]} coordinates and {st.deformation.shape[0]} elements."
            )
        t0 = st.time if t_start is None else as_real_scalar("t_start", t_start)
        q = st.position.copy() if initial_position is None else as_state_vector(
            "initial_position", initial_position, n)  # fmt: skip
        v = st.velocity.copy() if initial_velocity is None else as_state_vector(
            "initial_velocity", initial_velocity, n)  # fmt: skip
        g, s = st.contact_displacement.copy(), st.mode.copy()
        if not np.array_equal(q, st.position):
            g = q @ w
        if not np.array_equal(v, st.velocity):
            s = np.sign(v @ w)
        e, last = st.deformation.copy(), st.last_direction.copy()
    elif isinstance(initial_state, str) and initial_state == "relaxed":
        t0 = 0.0 if t_start is None else as_real_scalar("t_start", t_start)
        q = np.zeros(n) if initial_position is None else as_state_vector(
            "initial_position", initial_position, n)  # fmt: skip
        v = np.zeros(n) if initial_velocity is None else as_state_vector(
            "initial_velocity", initial_velocity, n)  # fmt: skip
        g, e, s, last = q @ w, np.zeros(n_elements), np.sign(v @ w), np.zeros(n_c)
    else:
        raise ValueError(f"`initial_state` must be 'relaxed' or a NetworkState; got "
                         f"{fmt(initial_state)}.")  # fmt: skip
    t_end = as_real_scalar("t_end", t_end)
    if not t_end > t0:
        raise ValueError(f"`t_end` must be after the start time {t0!r}; got {fmt(t_end)}.")
    check_time_span("t_end", t_end, t_end - t0)
    return Start(float(t0), float(t_end), q, v, np.asarray(g, dtype=float), e,
                 np.asarray(s, dtype=float), np.asarray(last, dtype=float))  # fmt: skip
