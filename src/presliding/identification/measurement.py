"""Measured signals for identification: loading, checking, resampling, differentiating.

A `Measurement` holds sampled signals on one time base. Section 4 of the paper
identifies the friction model from the driving force u(t), the displacement
y(t) and at least its first derivative (eq. 17); encoders measure y quantised,
so velocity and acceleration are estimated here with a zero-phase low-pass
filter followed by central differences (`Measurement.differentiate`; the
filters `lowpass` and `estimate_derivatives` live in `_filters` and are
re-exported here).

Units follow the library convention (s, m, m/s, m/s², N) or any consistent
set; `from_csv` and `from_mat` take a per-signal `scale` to convert on reading
(for example ``{"position": 1e-3}`` for millimetres, or a negative factor to
flip a sign convention).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._validation import (
    as_choice,
    as_positive_scalar,
    as_real_scalar,
    as_signal,
    check_same_length,
    fmt,
)
from presliding.identification._filters import estimate_derivatives, lowpass

__all__ = ["Measurement", "estimate_derivatives", "lowpass"]

FloatArray = NDArray[np.float64]

SIGNALS = ("position", "velocity", "acceleration", "applied_force", "friction_force")
_FORCES = ("applied_force", "friction_force")
# Relative spread of the sampling step accepted as uniform (clock jitter of
# single-precision time stamps is far below this).
_UNIFORM_TOL = 1e-3


@dataclass(frozen=True, eq=False)
class Measurement:
    """Signals sampled on one time base (units: s, m, m/s, m/s², N).

    Parameters
    ----------
    time : array_like, shape (T,)
        Sample times t [s], strictly increasing, at least 2 samples.
    position : array_like, shape (T,), optional
        Displacement y [m] of the friction contact (eq. 17).
    velocity : array_like, shape (T,), optional
        ẏ [m/s].
    acceleration : array_like, shape (T,), optional
        ÿ [m/s²].
    applied_force : array_like, shape (T,), optional
        Driving force u [N] (the right-hand side of eq. 17).
    friction_force : array_like, shape (T,), optional
        Measured friction force F [N], positive when it opposes positive motion.

    All given signals must be finite and have the same length as `time`; at
    least one signal must be given. Arrays are stored read-only.
    """

    time: FloatArray
    position: FloatArray | None = None
    velocity: FloatArray | None = None
    acceleration: FloatArray | None = None
    applied_force: FloatArray | None = None
    friction_force: FloatArray | None = None

    def __post_init__(self) -> None:
        t = as_signal("time", self.time, min_length=2)
        steps = np.diff(t)
        if not np.all(steps > 0):
            i = int(np.argmax(~(steps > 0))) + 1
            raise ValueError(
                f"`time` must be strictly increasing; got {fmt(t[i])} after {fmt(t[i - 1])} "
                f"at index {i}."
            )
        t.setflags(write=False)
        object.__setattr__(self, "time", t)
        given = {}
        for name in SIGNALS:
            value = getattr(self, name)
            if value is None:
                continue
            arr = as_signal(name, value)
            check_same_length(time=t, **{name: arr})
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
            given[name] = arr
        if not given:
            raise ValueError(
                "a Measurement must hold at least one signal besides `time`; got none of "
                + ", ".join(f"`{s}`" for s in SIGNALS)
                + "."
            )

    # ------------------------------------------------------------------ properties
    @property
    def n_samples(self) -> int:
        """Number of samples T."""
        return int(self.time.shape[0])

    @property
    def duration(self) -> float:
        """t[-1] − t[0] [s]."""
        return float(self.time[-1] - self.time[0])

    @property
    def sampling_step(self) -> float:
        """Median sampling step [s]."""
        return float(np.median(np.diff(self.time)))

    @property
    def is_uniform(self) -> bool:
        """True when every step is within 0.1 % of the median step."""
        steps = np.diff(self.time)
        return bool(np.all(np.abs(steps - self.sampling_step) <= _UNIFORM_TOL * self.sampling_step))

    def signals(self) -> dict[str, FloatArray]:
        """The signals that are present, by name (time not included)."""
        return {n: getattr(self, n) for n in SIGNALS if getattr(self, n) is not None}

    def require(self, *names: str, purpose: str = "this") -> None:
        """Raise a clear error unless every named signal is present.

        Parameters
        ----------
        *names : str
            Signal names, each one of ``SIGNALS`` ('position', 'velocity',
            'acceleration', 'applied_force', 'friction_force').
        purpose : str
            What the signals are needed for, quoted in the error message.

        Raises
        ------
        ValueError
            If a name is not a signal name, or a named signal is absent.
        """
        for n in names:
            as_choice("names", n, SIGNALS)
        missing = [n for n in names if getattr(self, n) is None]
        if missing:
            raise ValueError(
                f"`measurement` must hold {', '.join(f'`{n}`' for n in missing)} for {purpose}; "
                f"it holds {', '.join(f'`{n}`' for n in self.signals())}."
            )

    # ------------------------------------------------------------------ transformations
    def window(self, start: float | None = None, end: float | None = None) -> Measurement:
        """The samples with start <= t <= end (either bound may be None).

        Parameters
        ----------
        start, end : float, optional
            Finite bounds [s] of the window, inclusive; None leaves that side
            open. The window must hold at least 2 samples.

        Returns
        -------
        Measurement
            The same signals restricted to the window.
        """
        lo = -np.inf if start is None else as_real_scalar("start", start)
        hi = np.inf if end is None else as_real_scalar("end", end)
        if hi < lo:
            raise ValueError(f"`end` must be at least `start` {fmt(lo)}; got {fmt(hi)}.")
        keep = (self.time >= lo) & (self.time <= hi)
        if np.count_nonzero(keep) < 2:
            raise ValueError(
                f"`start` and `end` must enclose at least 2 samples; got "
                f"{int(np.count_nonzero(keep))} in [{fmt(lo)}, {fmt(hi)}] (time runs from "
                f"{fmt(self.time[0])} "
                f"to {fmt(self.time[-1])})."
            )
        return self._map(lambda a: a[keep], self.time[keep])

    def resample(self, step: float) -> Measurement:
        """Linear interpolation of every signal onto a uniform grid t0, t0 + step, ... <= t_end.

        Use it before `differentiate` when the sampling has gaps or jitter, or to
        decimate (choose ``step`` a multiple of the original step, after a low-pass
        with `lowpass` when the signals carry content above the new Nyquist rate).

        Parameters
        ----------
        step : float
            Uniform sampling step [s] (> 0, at most the duration).

        Returns
        -------
        Measurement
            Every signal interpolated onto the new grid.
        """
        h = as_positive_scalar("step", step)
        n = int(np.floor(self.duration / h * (1 + 1e-12))) + 1
        if n < 2:
            raise ValueError(
                f"`step` must be at most the duration {fmt(self.duration)} s; got {fmt(h)}."
            )
        grid = self.time[0] + h * np.arange(n)
        return self._map(lambda a: np.interp(grid, self.time, a), grid)

    def differentiate(
        self,
        cutoff: float,
        *,
        method: str = "butter",
        order: int = 4,
        filter_forces: bool = False,
    ) -> Measurement:
        """Estimate velocity and acceleration from the (quantised) position.

        See `estimate_derivatives` for the filter. The position is kept as
        measured (the play operators of eq. 17 take it raw); velocity and
        acceleration are replaced. With ``filter_forces=True`` the forces pass
        through the same zero-phase low-pass, so that every linear term of
        eq. 17 sees the same filter (the usual "parallel filtering").

        Parameters
        ----------
        cutoff : float
            Low-pass cut-off frequency [Hz] (> 0, below the Nyquist rate).
        method : {'butter', 'savgol'}
            Zero-phase filter, see `estimate_derivatives`.
        order : int
            Butterworth order, or the Savitzky–Golay polynomial order.
        filter_forces : bool
            Also low-pass the forces with the same filter.

        Returns
        -------
        Measurement
            Position and (unless `filter_forces`) forces as before; velocity and
            acceleration estimated.
        """
        self.require("position", purpose="differentiation")
        self._require_uniform("differentiate")
        v, a = estimate_derivatives(self.time, self.position, cutoff, method=method, order=order)
        out = replace(self, velocity=v, acceleration=a)
        if filter_forces:
            filtered = {
                n: lowpass(self.time, getattr(self, n), cutoff, method=method, order=order)
                for n in _FORCES
                if getattr(self, n) is not None
            }
            out = replace(out, **filtered)
        return out

    def _require_uniform(self, what: str) -> None:
        if not self.is_uniform:
            steps = np.diff(self.time)
            raise ValueError(
                f"`{what}` needs uniform sampling; steps range from {fmt(float(steps.min()))} "
                f"to {fmt(float(steps.max()))} s. Call `resample(step)` first."
            )

    def _map(self, fn: Any, time: FloatArray) -> Measurement:
        return Measurement(time, **{n: fn(a) for n, a in self.signals().items()})

    # ------------------------------------------------------------------ readers
    @classmethod
    def from_csv(
        cls,
        path: str | os.PathLike[str],
        time: str | int,
        *,
        delimiter: str | None = None,
        scale: Mapping[str, float] | None = None,
        **columns: str | int,
    ) -> Measurement:
        """Read a delimited text file with one header line.

        Parameters
        ----------
        path : path-like
        time : str or int
            Column holding the time (header name or 0-based index).
        delimiter : str, optional
            Column separator; default: a tab if the header has one, else a comma
            if it has one, else whitespace.
        scale : mapping, optional
            Factor per signal name ("time", "position", ...) applied on reading.
        **columns : str or int
            Columns of the signals, by signal name, e.g. ``position="Position [mm]"``.

        Examples
        --------
        The tribometer file of the shared data (mm and µN; friction sign flipped)::

            Measurement.from_csv(path, "Time [s]", position="Position [mm]",
                                 friction_force="Friction [uN]",
                                 scale={"position": 1e-3, "friction_force": -1e-6})
        """
        _check_signal_names(columns)
        with open(path, encoding="utf-8") as fh:
            header = fh.readline().rstrip("\r\n")
        if delimiter is None:
            delimiter = "\t" if "\t" in header else ("," if "," in header else None)
        names = [h.strip() for h in (header.split(delimiter) if delimiter else header.split())]
        wanted = {"time": time, **columns}
        index = {sig: _column_index(sig, col, names) for sig, col in wanted.items()}
        data = np.loadtxt(
            path, delimiter=delimiter, skiprows=1, usecols=sorted(set(index.values())), ndmin=2
        )
        col_of = {c: i for i, c in enumerate(sorted(set(index.values())))}
        raw = {sig: data[:, col_of[c]] for sig, c in index.items()}
        return cls._build(raw, scale, lambda s: s)

    @classmethod
    def from_mat(
        cls,
        path: str | os.PathLike[str],
        time: str = "t",
        *,
        scale: Mapping[str, float | str] | None = None,
        **variables: str,
    ) -> Measurement:
        """Read a MATLAB file (versions 4 and 5, through scipy.io.loadmat).

        Parameters
        ----------
        path : path-like
        time : str
            Variable holding the time.
        scale : mapping, optional
            Factor per signal name; a string names a scalar variable of the file
            (e.g. ``{"applied_force": "gtau"}`` for force = gtau · voltage).
        **variables : str
            Variables of the signals, by signal name, e.g. ``position="qm"``.

        Examples
        --------
        The EMPS benchmark file::

            Measurement.from_mat(path, position="qm", applied_force="vir",
                                 scale={"applied_force": "gtau"})
        """
        from scipy.io import loadmat

        _check_signal_names(variables)
        contents = loadmat(path)
        available = sorted(k for k in contents if not k.startswith("__"))

        def get(name: str) -> np.ndarray:
            if name not in contents:
                raise ValueError(
                    f"variable {name!r} is not in {os.fspath(path)!r}; it holds {available}."
                )
            return np.asarray(contents[name]).squeeze()

        raw = {sig: get(var) for sig, var in {"time": time, **variables}.items()}
        return cls._build(raw, scale, get)

    @classmethod
    def _build(
        cls, raw: dict[str, Any], scale: Mapping[str, Any] | None, lookup: Any
    ) -> Measurement:
        scale = dict(scale or {})
        _check_signal_names(scale, allow_time=True)
        out = {}
        for sig, arr in raw.items():
            factor = scale.get(sig, 1.0)
            if isinstance(factor, str):
                factor = lookup(factor)
            if np.ndim(factor) != 0:
                raise ValueError(
                    f"`scale` for {sig!r} must be a scalar; got shape {np.shape(factor)}."
                )
            out[sig] = np.asarray(arr, dtype=np.float64) * float(factor)
        return cls(**out)


def _check_signal_names(names: Mapping[str, Any], allow_time: bool = False) -> None:
    allowed = (("time",) if allow_time else ()) + SIGNALS
    for name in names:
        if name not in allowed:
            raise ValueError(f"signal names must be among {', '.join(allowed)}; got {name!r}.")


def _column_index(signal: str, column: str | int, names: list[str]) -> int:
    if isinstance(column, (int, np.integer)) and not isinstance(column, bool):
        if not 0 <= column < len(names):
            raise ValueError(f"column of `{signal}` must be in 0..{len(names) - 1}; got {column}.")
        return int(column)
    if column not in names:
        raise ValueError(f"column of `{signal}` must be one of {names}; got {column!r}.")
    return names.index(column)
