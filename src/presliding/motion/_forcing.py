"""The applied force u(t) of eq. 17: a constant, a callable u(t), or samples.

Samples ``(time, value)`` are held piecewise constant between sample times
(``hold="zoh"``, as a digital controller applies them) or interpolated linearly
(``hold="linear"``). Before the first sample time the force is undefined (an
error); after the last one the last value is held.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_choice,
    as_real_scalar,
    as_signal,
    check_same_length,
    check_size,
    fmt,
)

FloatArray = NDArray[np.float64]

HOLDS = ("zoh", "linear")


@dataclass(frozen=True, eq=False)
class Forcing:
    """A validated applied force. ``kind`` is "constant", "sampled" or "callable"."""

    kind: str
    hold: str
    times: FloatArray
    values: FloatArray
    func: Callable[[Any], Any] | None = None  # u(t): on an array, or on one time

    @property
    def piecewise_constant(self) -> bool:
        """True when u is constant between known breakpoints (the exact method applies)."""
        return self.kind == "constant" or (self.kind == "sampled" and self.hold == "zoh")

    def pieces(self, t_start: float, t_end: float) -> tuple[FloatArray, FloatArray]:
        """Start times and values of the constant pieces of u on [t_start, t_end].

        The first start time is t_start; consecutive equal values are merged, so
        a single piece means u is constant from t_start on.
        """
        if self.kind == "constant":
            return np.array([t_start]), self.values.copy()
        i0 = int(np.searchsorted(self.times, t_start, side="right")) - 1
        i1 = int(np.searchsorted(self.times, t_end, side="left"))
        t = self.times[i0:i1].copy()
        t[0] = t_start
        val = self.values[i0:i1]
        same = val[1:] == val[:-1]
        if same.any():
            keep = np.concatenate(([True], ~same))
            return np.ascontiguousarray(t[keep]), np.ascontiguousarray(val[keep])
        return t, np.ascontiguousarray(val)

    def event_pieces(self, t_start: float, t_end: float) -> tuple[FloatArray, FloatArray]:
        """`pieces` for the event kernels: a change of u exactly at t_end is a last piece.

        u is continuous from the right, so a sample at a change of u has the new
        value; a run that ends on a change of u gives its last sample the value
        after the change, as a longer run does, and a continuation from there
        resumes the very piece that the longer run starts at that time.
        """
        u_t, u_val = self.pieces(t_start, t_end)
        if self.kind != "sampled":
            return u_t, u_val
        j = int(np.searchsorted(self.times, t_end, side="left"))
        if j < self.times.shape[0] and self.times[j] == t_end and t_end > u_t[-1]:
            after = float(self.values[j])
            if after != u_val[-1]:
                return np.append(u_t, t_end), np.append(u_val, after)
        return u_t, u_val

    def loop_form(
        self, t0: float, t_end: float, n_steps: int
    ) -> tuple[int, FloatArray, FloatArray, FloatArray]:
        """(kind, times, values, midpoint values) for the implicit loops.

        A constant or sampled u is evaluated inside the loop at the midpoints of
        the n_steps equal steps (no array of step times); a callable is called
        once on every midpoint (its array is checked against the size limit
        first).
        """
        empty = np.empty(0)
        if self.kind == "constant":
            return 0, empty, self.values, empty
        if self.kind == "sampled":
            kind = 1 if self.hold == "zoh" else 2
            i0 = max(int(np.searchsorted(self.times, t0, side="right")) - 1, 0)
            return kind, self.times[i0:], self.values[i0:], empty
        check_size("step", (t_end - t0) / n_steps, n_steps, what="values of u (one per step)")
        h = (t_end - t0) / n_steps
        mid = t0 + (np.arange(n_steps) + 0.5) * h
        return 3, empty, empty, self(mid)

    def __call__(self, t: ArrayLike) -> FloatArray:
        """u at the times t (an array)."""
        t = np.asarray(t, dtype=np.float64)
        if self.kind == "constant":
            return np.full(t.shape, self.values[0])
        if self.kind == "sampled":
            if self.hold == "linear":
                return np.interp(t, self.times, self.values)
            idx = np.searchsorted(self.times, t, side="right") - 1
            return self.values[np.maximum(idx, 0)]
        assert self.func is not None  # kind "callable"
        return _call_user(self.func, t)


def _call_user(func: Callable[[Any], Any], t: FloatArray) -> FloatArray:
    """Evaluate a user u(t) on an array, vectorising a scalar function if needed."""
    import warnings

    try:  # numpy < 2.5 only warns when a scalar function converts a size-1 array
        with warnings.catch_warnings():
            warnings.simplefilter("error", DeprecationWarning)
            out = _real_values(func(t), t.shape)
    except (TypeError, ValueError, DeprecationWarning):
        out = None
    if out is None:
        out = np.empty(t.shape)
        flat = out.reshape(-1)
        for i, ti in enumerate(t.ravel()):
            value = func(float(ti))
            one = _real_values(value, ())
            if one is None:
                raise TypeError(
                    "`applied_force` must return one real number per time; got "
                    f"{fmt(value)} at t = {fmt(float(ti))}."
                )
            flat[i] = one
    bad = ~np.isfinite(out)
    if bad.any():
        i = int(np.argmax(bad.ravel()))
        raise ValueError(
            f"`applied_force` must return finite values; got {fmt(out.ravel()[i])} "
            f"at t = {fmt(float(t.ravel()[i]))}."
        )
    return np.ascontiguousarray(out)


def _real_values(value: Any, shape: tuple[int, ...]) -> FloatArray | None:
    """`value` as float64 of the given shape, or None if it is not real numbers of that shape."""
    if isinstance(value, (str, bytes)):
        return None
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError):  # ragged sequences
        return None
    if arr.dtype.kind not in "iuf" or arr.shape != shape:
        return None
    return np.asarray(arr, dtype=np.float64)


def as_forcing(applied_force: Any, hold: str, t_start: float) -> Forcing:
    """Validate `applied_force` (constant, callable or (time, value) pair) and `hold`."""
    hold = as_choice("hold", hold, HOLDS)
    if callable(applied_force):
        f = Forcing("callable", hold, np.empty(0), np.empty(0), applied_force)
        f(np.array([t_start]))  # fails early with a clear message
        return f
    if isinstance(applied_force, (tuple, list)) and len(applied_force) == 2:
        time = as_signal("applied_force[0]", applied_force[0])
        value = as_signal("applied_force[1]", applied_force[1])
        check_same_length(**{"applied_force[0]": time, "applied_force[1]": value})
        steps = np.diff(time)
        if (steps <= 0).any():
            i = int(np.argmax(steps <= 0)) + 1
            raise ValueError(
                "`applied_force[0]` (time) must be strictly increasing; "
                f"got {fmt(time[i])} after {fmt(time[i - 1])} at index {i}."
            )
        if time[0] > t_start:
            raise ValueError(
                f"`applied_force[0]` (time) must start at or before `t_start` = {fmt(t_start)}; "
                f"got {fmt(time[0])}."
            )
        return Forcing("sampled", hold, time, value)
    if np.ndim(applied_force) != 0 or isinstance(applied_force, (str, bytes)):
        raise TypeError(
            "`applied_force` must be a number, a callable u(t) or a pair (time, value) of "
            f"equal-length arrays; got {fmt(applied_force)}."
        )
    u = as_real_scalar("applied_force", applied_force)
    return Forcing("constant", hold, np.empty(0), np.array([u]))
