"""An independent, slow reference: parallel elastic-perfectly-plastic springs.

Written from the physics of the Maxwell-slip picture (paper, Section 2), not
from the library's update formula. Spring j (stiffness k_j, break-away force
c_j = k_j r_j, eq. 6) carries the elastic deformation f_j. Every displacement
increment Δy stretches all springs by Δy; a spring whose deformation would
exceed its threshold slips, so its deformation stays at ±r_j (eq. 3, eq. 5).
The friction force is c1·sign(ẏ) plus Σ k_j f_j (eq. 8).

Everything is done one increment and one spring at a time in plain Python
floats, so nothing here shares code with the compiled kernels.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np


@dataclass
class SpringRun:
    """Result of driving the spring bank along a path."""

    elastic: np.ndarray  # Σ k_j f_j at each sample, shape (T,)
    deformation: np.ndarray  # f_j at each sample, shape (T, N)
    direction: np.ndarray  # sign of the last nonzero increment at each sample, shape (T,)

    def play_positions(self, y: Sequence[float]) -> np.ndarray:
        """Positions x_j = y − f_j of the slider ends (the play outputs), shape (T, N)."""
        return np.asarray(y, dtype=float)[:, None] - self.deformation


def drive_springs(
    y: Sequence[float],
    stiffness: Sequence[float],
    threshold: Sequence[float],
    *,
    deformation: Sequence[float] | None = None,
    previous_input: float | None = None,
    direction: float = 0.0,
) -> SpringRun:
    """Drive a bank of elastic-perfectly-plastic springs along the samples ``y``.

    Parameters
    ----------
    y : sequence of float
        Displacement samples; the displacement moves monotonically between them.
    stiffness, threshold : sequences of float
        k_j and r_j of the springs.
    deformation : sequence of float, optional
        Deformations f_j before the first sample (default: all zero, the
        relaxed spring bank).
    previous_input : float, optional
        Displacement at which ``deformation`` holds (default ``y[0]``).
    direction : float
        Sign of the last motion before the first sample (0: none yet).
    """
    ys = [float(v) for v in y]
    ks = [float(v) for v in stiffness]
    rs = [float(v) for v in threshold]
    f = [0.0] * len(ks) if deformation is None else [float(v) for v in deformation]
    prev = ys[0] if previous_input is None else float(previous_input)
    d = float(direction)
    n_time, n_el = len(ys), len(ks)
    elastic = np.empty(n_time)
    deform = np.empty((n_time, n_el))
    dirs = np.empty(n_time)
    for t, yt in enumerate(ys):
        step = yt - prev
        if step > 0:
            d = 1.0
        elif step < 0:
            d = -1.0
        prev = yt
        total = 0.0
        for j in range(n_el):
            stretched = f[j] + step  # every spring follows the common displacement ...
            if stretched > rs[j]:  # ... until its force reaches +c_j: it slips
                stretched = rs[j]
            elif stretched < -rs[j]:  # ... or -c_j
                stretched = -rs[j]
            f[j] = stretched
            deform[t, j] = stretched
            total += ks[j] * stretched
        elastic[t] = total
        dirs[t] = d
    return SpringRun(elastic, deform, dirs)


def virgin_force(u: float, stiffness: Sequence[float], threshold: Sequence[float]) -> float:
    """Initial loading curve of the spring bank: Σ k_j·sign(u)·min(|u|, r_j)."""
    s = 1.0 if u > 0 else (-1.0 if u < 0 else 0.0)
    return s * sum(k * min(abs(u), r) for k, r in zip(stiffness, threshold, strict=True))
