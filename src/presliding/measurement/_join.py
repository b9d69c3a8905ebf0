"""`Measurement.join`: records of different signals (one file per signal) on one time base.

Rules, in order:

1. Every record is a `Measurement`; no signal may appear in two records.
2. The result spans the overlap of the records, [max of the first times, min
   of the last times]; samples outside it are dropped (the count per record is
   noted in the result's `source`). The overlap must hold at least 2 samples.
3. Same clock: when every record has, within the overlap, as many samples as
   the first record and each time agrees with the first record's to within
   0.1 % of its median step (time stamps written with different precision),
   the signals are joined on the first record's times, unchanged.
4. Otherwise the records are on different clocks. With ``interpolate=False``
   (the default) this is an error naming the records and the first sample
   that differs: nothing is interpolated silently. With ``interpolate=True``
   every other record's signals are linearly interpolated onto the first
   record's times within the overlap.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from presliding._validation import fmt
from presliding.measurement._source import Source

__all__ = ["join_records"]

_SAME_CLOCK = 1e-3  # relative to the first record's median step


def join_records(records: Sequence[Any], interpolate: bool, cls: type) -> Any:
    """The joined `Measurement` (see the module notes); `cls` is `Measurement`."""
    if isinstance(records, (str, bytes)) or not isinstance(records, Sequence):
        raise TypeError(f"`records` must be a sequence of Measurement; got {fmt(records)}.")
    if not isinstance(interpolate, bool):
        raise TypeError(f"`interpolate` must be True or False; got {fmt(interpolate)}.")
    if not records:
        raise ValueError("`records` must hold at least one Measurement; got none.")
    for i, rec in enumerate(records):
        if not isinstance(rec, cls):
            raise TypeError(f"`records[{i}]` must be a Measurement; got {type(rec).__name__}.")
    owner: dict[str, int] = {}
    for i, rec in enumerate(records):
        for name in rec.signals():
            if name in owner:
                raise ValueError(
                    f"`records` must hold each signal once; `{name}` is in records "
                    f"{owner[name]} and {i}."
                )
            owner[name] = i
    lo = max(float(r.time[0]) for r in records)
    hi = min(float(r.time[-1]) for r in records)
    first = records[0]
    tol = _SAME_CLOCK * first.sampling_step
    keep = [(r.time >= lo - tol) & (r.time <= hi + tol) for r in records]
    base = first.time[keep[0]]
    if base.shape[0] < 2:
        spans = "; ".join(
            f"record {i}: {fmt(float(r.time[0]))} to {fmt(float(r.time[-1]))} s"
            for i, r in enumerate(records)
        )
        raise ValueError(
            f"`records` must overlap in time by at least 2 samples; got {base.shape[0]} ({spans})."
        )
    signals: dict[str, np.ndarray] = {}
    notes = []
    for i, (rec, sel) in enumerate(zip(records, keep, strict=True)):
        times = rec.time[sel]
        same = times.shape == base.shape and bool(np.all(np.abs(times - base) <= tol))
        if not same and not interpolate:
            raise ValueError(_mismatch(i, times, base, tol))
        for name, values in rec.signals().items():
            if same:
                signals[name] = values[sel]
            else:
                signals[name] = np.interp(base, rec.time, values)
        dropped = int(rec.n_samples - np.count_nonzero(sel))
        if not same:
            notes.append(f"record {i}: interpolated onto the times of record 0")
        if dropped:
            notes.append(f"record {i}: {dropped} samples outside the overlap dropped")
    parts = tuple(r.source if r.source is not None else Source(None, "arrays") for r in records)
    source = Source(None, "join", parts=parts, notes=tuple(notes))
    axis = "rotary" if any(getattr(r, "axis", None) == "rotary" for r in records) else None
    return cls(base, **signals, source=source, axis=axis)


def _mismatch(i: int, times: np.ndarray, base: np.ndarray, tol: float) -> str:
    if times.shape != base.shape:
        detail = f"{times.shape[0]} samples in the overlap against {base.shape[0]} of record 0"
    else:
        j = int(np.argmax(np.abs(times - base) > tol))
        detail = f"t = {fmt(float(times[j]))} against {fmt(float(base[j]))} s at sample {j}"
    return (
        f"`records` 0 and {i} are sampled at different times ({detail}); pass "
        "interpolate=True to interpolate onto the times of record 0, or resample them first."
    )
