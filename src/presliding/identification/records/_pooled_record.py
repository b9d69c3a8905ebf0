"""A measured record as the pooled fit reads it, and how its velocity is compared.

`as_record` checks and completes one `Measurement`: the position (or the
integral of the velocity), the velocity (or the difference quotient of the
position), the applied force and the direction of the motion before the first
sample.

A record's velocity that is the difference quotient of its position (computed
here when only the position is given, or detected: equal to
``numpy.gradient(position, time)`` to rounding) is compared with the same
difference quotient of the simulated position, not with the exact simulated
velocity (`Record.difference`, `difference_order`). The quotient is one-sided at
a record's ends and a central difference elsewhere; it differs from the exact
velocity by O(a·Δt) (a the acceleration) at the ends and wherever the
acceleration jumps (a stop, a change of u), which would bias the initial
velocity and the forces otherwise.
The choice is `VELOCITY`: ``"auto"`` (detect), ``"difference"``, ``"measured"``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding.identification.records import _response_tools as rt
from presliding.measurement.measurement import Measurement

__all__ = ["VELOCITY", "Record", "as_record", "difference_matrix", "difference_order"]

FloatArray = NDArray[np.float64]
VELOCITY = ("auto", "difference", "measured")


@dataclass(frozen=True)
class Record:
    """One measured record, checked and completed for the fit."""

    time: FloatArray
    position: FloatArray  # measured, or the integral of the velocity
    velocity: FloatArray  # measured, or the difference quotient of the position
    applied_force: FloatArray  # zeros for a free record
    forced: bool
    direction: float  # of the motion before the first sample
    #: edge order of the difference quotient ``numpy.gradient(position, time)`` the velocity
    #: is (the model's velocity is then taken the same way); 0: a measured velocity
    difference: int = 0
    #: whether the position was measured (False: the integral of a measured velocity)
    measured_position: bool = True


def difference_order(t: FloatArray, y: FloatArray, v: FloatArray) -> int:
    """The edge order (1 or 2) of ``numpy.gradient(y, t, edge_order=...)`` that `v` equals to
    rounding (a few ulps of the largest speed per sample), or 0 when it is neither."""
    scale = float(np.max(np.abs(v))) if v.size else 0.0
    for order in (1, 2):
        if t.shape[0] <= order or not scale > 0:
            continue
        g = np.gradient(y, t, edge_order=order)
        if float(np.max(np.abs(v - g))) <= 1e-9 * scale:
            return order
    return 0


def difference_matrix(t: FloatArray, order: int) -> Any:
    """The sparse matrix D with D·y = ``numpy.gradient(y, t, edge_order=order)``.

    Every row of D has its entries within two columns of the diagonal, so the
    gradients of five combs (ones at the indices ≡ k mod 5) give all of them.
    """
    from scipy import sparse

    n = t.shape[0]
    i = np.arange(n)
    rows, cols, vals = [], [], []
    for k in range(5):
        g = np.gradient((i % 5 == k).astype(float), t, edge_order=2 if order == 2 else 1)
        j = i - 2 + (k - (i - 2)) % 5  # the one column ≡ k (mod 5) within two of i
        ok = (j >= 0) & (j < n) & (g != 0)
        rows.append(i[ok])
        cols.append(j[ok])
        vals.append(g[ok])
    return sparse.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)
    )


def as_record(m: Measurement, velocity: str = "auto") -> Record:
    """The record of a measurement (velocity or position must be present).

    `velocity` (`VELOCITY`): ``"auto"`` compares the model's difference quotient where the
    record's velocity is one of its position (computed here, or detected); ``"difference"``
    does so whenever the position is given (edge order 1 unless 2 is detected);
    ``"measured"`` always compares the model's exact velocity.
    """
    t = m.time
    order = 0
    if m.velocity is None:
        v = np.gradient(m.require("position")[0], t)
        order = 1 if velocity != "measured" and t.shape[0] > 1 else 0
    else:
        v = m.velocity
        if m.position is not None and velocity != "measured":
            order = difference_order(t, m.position, v)
            if velocity == "difference" and order == 0 and t.shape[0] > 1:
                order = 1
    y = m.position if m.position is not None else rt.integral(t, v)
    u = m.applied_force if m.applied_force is not None else np.zeros_like(t)
    measured = m.position is not None
    direction = rt.initial_direction(v, u, y if measured else None)
    return Record(t, y, v, u, bool(np.any(u)), direction, order, measured)
