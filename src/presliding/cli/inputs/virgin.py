"""The virgin loadings a record holds, for ``presliding fit --kind virgin``.

A rig's ramp file seldom holds one ramp only: the contact rests, is loaded,
held and unloaded again. Each run of the position between turning points
(reversals beyond the record's tolerance and a tenth of its travel, so that
retreats of a few encoder counts are none) is read as follows:

- the first run of a record that starts at rest is a virgin loading: F_v(s) =
  ±F at s = |y − y_0|;
- a run from a turning point (y_r, F_r) follows Masing's rule, F = F_r ∓
  2·F_v(|y − y_r|/2), until it has travelled as far as the run before it (twice
  as far after a virgin loading): it becomes a ramp of half the travel and half
  the force change, F_v(s) = ±(F − F_r)/2 at s = |y − y_r|/2;
- F_r is the force where the contact stopped (the first sample of its rest at
  the turning point), and each run ends where it first reaches its end position
  (a driven force goes on changing there while the contact rests).

Whether a record starts at rest: ``--ramps`` and ``--segments ramps`` say so;
otherwise a record with at most one turning point is taken to (a ramp, or a
ramp and its return), and one with more is read as loops, which use no run
before the second turning point (`fit_virgin_curve` with ``loops=True`` when
every record is such).
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["virgin_inputs"]


def _turns(y: np.ndarray) -> np.ndarray:
    from presliding.identification.fit_virgin import RAMP_RETREAT
    from presliding.identification.prediction import reversal_tolerance
    from presliding.identification.problem._pi_regression import reversal_indices

    tol = max(reversal_tolerance(y), RAMP_RETREAT * float(np.ptp(y)))
    return reversal_indices(np.ascontiguousarray(y), tol)


def _end(seg: np.ndarray, tol: float) -> int:
    """Samples of a run up to the first that reaches its end position."""
    at_end = np.flatnonzero(np.abs(seg - seg[-1]) <= tol)
    return int(at_end[0]) + 1 if at_end.size else seg.shape[0]


def _runs(y: np.ndarray, f: np.ndarray, turns: np.ndarray, from_rest: bool) -> list[tuple]:
    """The virgin ramps (y, F) of one record's runs (module notes)."""
    from presliding.identification.prediction import reversal_tolerance

    tol = reversal_tolerance(y)
    marks = [0, *turns.tolist(), y.shape[0] - 1]
    out = []
    for k in range(len(marks) - 1):
        i0, i1 = marks[k], marks[k + 1]
        seg_y, seg_f = y[i0 : i1 + 1], f[i0 : i1 + 1]
        if k == 0:
            if from_rest:
                n = _end(seg_y, tol)
                out.append((seg_y[:n], seg_f[:n]))
            continue
        if k == 1 and not from_rest:
            continue  # the run before it did not start at a turning point: no known span
        first = i0  # where the contact came to rest at the turning point
        while first > marks[k - 1] + 1 and abs(y[first - 1] - y[i0]) <= tol:
            first -= 1
        span = abs(y[i0] - y[marks[k - 1]]) * (2.0 if k == 1 else 1.0)
        travel = np.abs(seg_y - y[i0])
        n = min(_end(seg_y, tol), int(np.argmax(travel > span * (1 + 1e-12))) or seg_y.shape[0])
        if n > 2:
            out.append((0.5 * (seg_y[:n] - y[i0]), 0.5 * (seg_f[:n] - f[first])))
    return out


def virgin_inputs(ys: list[np.ndarray], fs: list[np.ndarray], labels: list[str],
                  from_rest: bool | None) -> tuple[list, list, bool, list[str]]:  # fmt: skip
    """(displacements, forces, loops, notes) for `fit_virgin_curve` from whole records.

    `from_rest` True: every record starts at rest (``--ramps``, ``--segments ramps``);
    False: they are loops (``--segments loops``); None: told by the turning points.
    """
    turns = [_turns(np.asarray(y, dtype=float)) for y in ys]
    counts = [t.shape[0] for t in turns]
    if from_rest is None and all(c == 0 for c in counts):
        return list(ys), list(fs), False, []
    if from_rest is None and all(c >= 2 for c in counts):
        return list(ys), list(fs), True, []
    if from_rest is False and all(c >= 2 for c in counts):
        return list(ys), list(fs), True, []
    out_y: list[Any] = []
    out_f: list[Any] = []
    notes = []
    for y, f, t, label in zip(ys, fs, turns, labels, strict=True):
        rest = from_rest if from_rest is not None else t.shape[0] <= 1
        runs = _runs(np.asarray(y, float), np.asarray(f, float), t, bool(rest))
        out_y += [r[0] for r in runs]
        out_f += [r[1] for r in runs]
        start = "a virgin loading from rest, then " if rest else ""
        notes.append(f"{label}: {t.shape[0]} turning point(s); {len(runs)} run(s) used as "
                     f"virgin ramps ({start}returns by Masing's rule, F_v(s) = ±(F − F_r)/2 "
                     "at s = |y − y_r|/2)")  # fmt: skip
    if not out_y:
        raise ValueError("no run of the records is a virgin loading or a return from a "
                         "turning point; fit loops with two or more reversals, or ramps from "
                         "rest (--ramps).")  # fmt: skip
    return out_y, out_f, False, notes
