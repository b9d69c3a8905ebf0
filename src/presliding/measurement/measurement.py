"""Measured signals for identification: loading, checking, resampling, differentiating.

A `Measurement` holds sampled signals on one time base. Section 4 of the paper
identifies the friction model from the driving force u(t), the displacement
y(t) and at least its first derivative (eq. 17); encoders measure y quantised,
so velocity and acceleration are estimated here with a zero-phase low-pass
filter followed by central differences (`Measurement.differentiate`; the
filters `lowpass` and `estimate_derivatives` live in `_filters` and are
re-exported here).

Units. Signals are held in SI (s, m, m/s, m/s², N; rad, rad/s, rad/s², N m
for rotary axes). The readers convert on reading: a unit at the end of a
column header (``Position [mm]``, ``x (um)``, ``torque [mN m]``, ``t [ms]``)
is parsed with pint and converted to SI; ``units=`` gives or overrides a unit
per signal; ``scale=`` applies a further factor (a negative one flips a sign
convention). What was read and how it was converted is kept in the
measurement's `source` (`Source.describe`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._axes import as_axis, axis_unit
from presliding._validation import (
    as_choice,
    as_positive_scalar,
    as_real_scalar,
    as_signal,
    check_same_length,
    check_size,
    fmt,
)
from presliding.measurement._filters import estimate_derivatives, lowpass
from presliding.measurement._measurement_readers import MeasurementReaders
from presliding.measurement._source import Source
from presliding.measurement._summary import NotebookView
from presliding.measurement._units import is_quantity, quantity_to_si

__all__ = ["Measurement", "common_axis", "estimate_derivatives", "lowpass"]

FloatArray = NDArray[np.float64]

SIGNALS = ("position", "velocity", "acceleration", "applied_force", "friction_force")
_FORCES = ("applied_force", "friction_force")
# Relative spread of the sampling step accepted as uniform (clock jitter of
# single-precision time stamps is far below this).
_UNIFORM_TOL = 1e-3


@dataclass(frozen=True, eq=False)
class Measurement(MeasurementReaders, NotebookView):
    """Signals sampled on one time base (units: s, m, m/s, m/s², N; rad and N m on a rotary axis).

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

    source : Source, optional
        Where the signals came from (set by the readers; kept by `window`,
        `resample` and `differentiate`).
    axis : {'linear', 'rotary'}, optional
        The kind of axis: linear (m, N, kg) or rotary (rad, N m, kg m²; the
        position an angle, the forces torques). Default: from the units read
        (``deg`` or ``rad`` positions, ``N m`` torques make it rotary), else
        linear. Given explicitly, it must agree with the units read. Fits,
        reports, figures and model files label their quantities in its units.

    All given signals must be finite and have the same length as `time`; at
    least one signal must be given. Arrays are stored read-only.
    """

    time: FloatArray
    position: FloatArray | None = None
    velocity: FloatArray | None = None
    acceleration: FloatArray | None = None
    applied_force: FloatArray | None = None
    friction_force: FloatArray | None = None
    source: Source | None = None
    axis: str | None = None

    def __post_init__(self) -> None:
        rotary_quantity = self._convert_quantities()
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
        if self.source is not None and not isinstance(self.source, Source):
            raise TypeError(f"`source` must be a Source or None; got {type(self.source).__name__}.")
        if not given:
            listed = ", ".join(f"`{s}`" for s in SIGNALS)
            raise ValueError(f"a Measurement must hold at least one signal besides `time`; got "
                             f"none of {listed}.")  # fmt: skip
        self._settle_axis(rotary_quantity)

    def _convert_quantities(self) -> bool | None:
        """pint Quantities to SI magnitudes (dimension checked); whether they are rotary
        (None without Quantities; an error when they mix a rotary and a linear axis)."""
        kinds: dict[bool, str] = {}
        for name in ("time", *SIGNALS):
            value = getattr(self, name)
            if is_quantity(value):
                magnitude, si = quantity_to_si(name, value)
                object.__setattr__(self, name, magnitude)
                if name != "time":
                    kinds.setdefault(si in ("rad", "rad/s", "rad/s^2", "N m"), f"`{name}` in {si}")
        if len(kinds) > 1:
            raise ValueError(
                f"the Quantities mix a rotary and a linear axis: {kinds[True]} (rotary) beside "
                f"{kinds[False]} (linear); give angles with torques, or lengths with forces."
            )
        return next(iter(kinds)) if kinds else None

    def _settle_axis(self, rotary_quantity: bool | None = None) -> None:
        conflict = "" if self.source is None else self.source.axis_conflict()
        if conflict:
            raise ValueError(f"{conflict}.")
        read = None if self.source is None else self.source.axis_read
        if read is None and rotary_quantity is not None:
            read = "rotary" if rotary_quantity else "linear"
        axis = (read or "linear") if self.axis is None else as_axis(self.axis)
        if read is not None and axis != read:
            conversions = self.source.all_conversions() if self.source is not None else ()
            given = [f"{c.signal} in {c.unit}" for c in conversions
                     if c.unit is not None and c.signal != "time"]  # fmt: skip
            units = ", ".join(given) or "pint units"
            raise ValueError(
                f"`axis` {axis!r} contradicts the units read ({units}: a {read} axis); "
                "leave `axis` out or correct the units."
            )
        object.__setattr__(self, "axis", axis)
        if self.source is not None and axis == "rotary":
            object.__setattr__(self, "source", self.source.on_axis(axis))

    def unit(self, quantity: str) -> str:
        """The SI unit of `quantity` (``"position"``, ``"force"``, ``"mass"``, ...) on this axis.

        ``Measurement(..., axis="rotary").unit("stiffness")`` is ``"N m/rad"``.
        """
        return axis_unit(quantity, self.axis or "linear")

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

    def require(self, *names: str, purpose: str = "this") -> tuple[FloatArray, ...]:
        """The named signals, in order; a clear error unless every one is present.

        Parameters
        ----------
        *names : str
            Signal names, each one of ``SIGNALS`` ('position', 'velocity',
            'acceleration', 'applied_force', 'friction_force').
        purpose : str
            What the signals are needed for, quoted in the error message.

        Returns
        -------
        tuple of ndarray
            The signals, in the order named.

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
                f"got one holding {', '.join(f'`{n}`' for n in self.signals())}."
            )
        return tuple(getattr(self, n) for n in names)

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
        out = self._map(lambda a: a[keep], self.time[keep])
        if self.source is None:
            return out
        return replace(out, source=self.source.with_window(start, end))

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
        with np.errstate(over="ignore"):
            count = np.floor(self.duration / h * (1 + 1e-12)) + 1.0
        n_signals = 1 + sum(getattr(self, f) is not None for f in SIGNALS)
        n = check_size("step", h, count, what="samples", item_bytes=8 * n_signals)
        if n < 2:
            raise ValueError(
                f"`step` must be at most the duration {fmt(self.duration)} s; got {fmt(h)}."
            )
        grid = self.time[0] + h * np.arange(n)
        out = self._map(lambda a: np.interp(grid, self.time, a), grid)
        note = f"resampled onto a uniform step of {h:.6g} s (linear interpolation)"
        return out if self.source is None else replace(out, source=self.source.with_note(note))

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
        (position,) = self.require("position", purpose="differentiation")
        self._require_uniform("differentiate")
        v, a = estimate_derivatives(self.time, position, cutoff, method=method, order=order)
        out = replace(self, velocity=v, acceleration=a)
        if filter_forces:
            filtered: dict[str, Any] = {
                n: lowpass(self.time, getattr(self, n), cutoff, method=method, order=order)
                for n in _FORCES
                if getattr(self, n) is not None
            }
            out = replace(out, **filtered)
        if self.source is not None:
            note = (
                f"velocity and acceleration estimated: zero-phase {method} low-pass at "
                f"{cutoff:.6g} Hz, central differences"
                + ("; forces filtered alike" if filter_forces else "")
            )
            out = replace(out, source=self.source.with_note(note))
        return out

    def segments(
        self,
        kind: str = "stops",
        *,
        lead_in: float | None = None,
        rest_speed: float | None = None,
        tolerance: float | None = None,
        min_samples: int = 10,
    ) -> Any:
        """Cut the record into stops, loops or ramps: the pieces and a table of what was cut.

        Parameters
        ----------
        kind : {'stops', 'loops', 'ramps'}
            ``"stops"``: each arrival at rest, from where the applied force drops
            to its final level (else from the speed's peak), less a lead-in, to
            after the rest; ``"loops"``: one closed cycle of the position each
            (turning point to the second turning point after it); ``"ramps"``:
            one monotone run each (turning point to turning point).
        lead_in : float, optional
            Stops only: time [s] kept before the drop (>= 0; default: a fifth of
            the deceleration).
        rest_speed : float, optional
            Stops only: the speed [m/s or rad/s] below which the record is at
            rest (default: 2 % of its 99th-percentile speed, smoothed).
        tolerance : float, optional
            Loops and ramps only: the retreat [m or rad] that makes a turning
            point (default: three quanta of a quantised position, else 1 % of
            its span); a piece must also travel beyond it.
        min_samples : int
            Shorter pieces are left out (an integer >= 2). An option of another
            kind is a ValueError, not ignored; so is a record with nothing to cut.

        Returns
        -------
        Segments
            The pieces (each a `Measurement` whose source notes the cut), their
            ``table()``, ``report()``, ``parameters`` (every value used: passed
            back, they cut the same pieces) and ``plot()``; indexable.

        Examples
        --------
        ``fit_response(list(m.segments("stops")), 2)`` fits every stop of a file
        as a pooled record.
        """
        from presliding.measurement.segments import segment

        return segment(self, kind, lead_in=lead_in, rest_speed=rest_speed, tolerance=tolerance,
                       min_samples=min_samples)  # fmt: skip

    def _require_uniform(self, what: str) -> None:
        if not self.is_uniform:
            steps = np.diff(self.time)
            raise ValueError(
                f"`{what}` needs uniform sampling; steps range from {fmt(float(np.min(steps)))} "
                f"to {fmt(float(np.max(steps)))} s. Call `resample(step)` first."
            )

    def _map(self, fn: Any, time: FloatArray) -> Measurement:
        return Measurement(
            time, **{n: fn(a) for n, a in self.signals().items()}, source=self.source,
            axis=self.axis,
        )  # fmt: skip


def common_axis(records: Any) -> str:
    """The axis shared by a `Measurement` or a sequence of them (an error if they differ)."""
    items = [records] if isinstance(records, Measurement) else list(records)
    axes = {getattr(r, "axis", None) or "linear" for r in items}
    if len(axes) > 1:
        raise ValueError(
            "`records` must all be on one kind of axis; got linear and rotary records "
            "(check the units read, or give `axis` when reading)."
        )
    return axes.pop() if axes else "linear"
