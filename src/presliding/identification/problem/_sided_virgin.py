"""The two branches of an asymmetric virgin curve as one least-squares problem.

Loading from rest in +y follows F_v⁺(s) = c1 + Σ_j k_j·min(s, r_j), in −y
F_v⁻(s) = c1⁻ + Σ_j k_j·min(s, r_j⁻) (`presliding.friction._sides`: the elements share
their stiffnesses, each side has its thresholds and Coulomb element). With the samples
(s, F_v) of ramps of either sign and their side, the residual of the parameters
``coulomb``, ``coulomb_negative``, ``stiffness_j``, ``threshold_j``, ``threshold_negative_j``
is linear in all but the thresholds, and its Jacobian is exact (∂min(s, r)/∂r is 1 or 0).
The symmetric curve is the case c1⁻ = c1, r_j⁻ = r_j: a symmetric fit's values lifted so
(`lifted`) are the nested start.

Loops cannot tell the sides apart: after a reversal every branch follows the mean curve
2·F̄_v(|y − y_r|/2) of c̄1 = (c1 + c1⁻)/2 and r̄_j = (r_j + r_j⁻)/2 whatever its direction
(Masing's rule for the shifted play, `_sides`), so only ramps from rest identify the sides.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._validation import as_bounds
from presliding.friction.pi_friction import PIFriction
from presliding.identification.problem._fit_problem import FitProblem
from presliding.identification.problem._pi_regression import element_names

FloatArray = NDArray[np.float64]

__all__ = ["SidedVirgin", "sided_names"]


def sided_names(n: int) -> tuple[list[str], list[str], list[str]]:
    """Names of the stiffnesses, the thresholds in +y and those in −y."""
    k_names, r_names = element_names(n)
    return k_names, r_names, [f"threshold_negative_{j + 1}" for j in range(n)]


class SidedVirgin:
    """The two branches' samples and their residual (module notes)."""

    def __init__(self, s: FloatArray, force: FloatArray, side: FloatArray, n: int):
        self.s, self.force, self.n = s, force, n
        self.up = side > 0
        self.k_names, self.r_names, self.rn_names = sided_names(n)
        self.names = ("coulomb", "coulomb_negative", *self.k_names, *self.r_names,
                      *self.rn_names)  # fmt: skip

    def _parts(self, q: FloatArray) -> tuple[float, float, FloatArray, FloatArray]:
        n = self.n
        r = np.where(self.up[:, None], q[2 + n : 2 + 2 * n][None, :], q[2 + 2 * n :][None, :])
        return q[0], q[1], q[2 : 2 + n], r

    def fitted(self, q: FloatArray) -> FloatArray:
        """F_v of every sample, on its side's branch."""
        c1, c1n, k, r = self._parts(np.asarray(q, dtype=float))
        elastic = np.minimum(self.s[:, None], r) @ k if self.n else 0.0
        return np.where(self.up, c1, c1n) + elastic

    def residual(self, q: FloatArray) -> FloatArray:
        return self.fitted(q) - self.force

    def jacobian(self, q: FloatArray) -> FloatArray:
        _, _, k, r = self._parts(np.asarray(q, dtype=float))
        n, up = self.n, self.up
        out = np.zeros((self.s.shape[0], 2 + 3 * n))
        out[:, 0], out[:, 1] = up, ~up
        out[:, 2 : 2 + n] = np.minimum(self.s[:, None], r)
        slope = (self.s[:, None] > r) * k[None, :]
        out[:, 2 + n : 2 + 2 * n] = np.where(up[:, None], slope, 0.0)
        out[:, 2 + 2 * n :] = np.where(up[:, None], 0.0, slope)
        return out

    def lifted(self, values: Mapping[str, float], ratio: float = 1.0) -> dict[str, float]:
        """A symmetric fit's values with the negative side `ratio` times the positive one
        (1: the symmetric curve exactly, the nested start)."""
        out = {x: float(values[x]) for x in ("coulomb", *self.k_names, *self.r_names)}
        out["coulomb_negative"] = ratio * out["coulomb"]
        out.update({m: ratio * out[p] for p, m in zip(self.r_names, self.rn_names, strict=True)})
        return {x: out[x] for x in self.names}

    def side_ratio(self) -> float:
        """The level of the − branch over the + branch's where both reach (medians of the
        samples beyond the smaller branch's half travel), within [1/3, 3]."""
        reach = 0.5 * min(float(np.max(self.s[self.up])), float(np.max(self.s[~self.up])))
        far = self.s >= reach
        up = float(np.median(self.force[far & self.up]))
        down = float(np.median(self.force[far & ~self.up]))
        return float(np.clip(down / up, 1 / 3, 3.0)) if up > 0 and down > 0 else 1.0

    def problem(self, start: Mapping[str, float], smallest: float, fixed: Mapping[str, float],
                tied: Mapping[str, Any], bounds: Any, initial: Mapping[str, float] | None
                ) -> FitProblem:  # fmt: skip
        """The `FitProblem` from `start` (the user's `initial` over it), thresholds >= `smallest`,
        the user's bounds within the natural ones."""
        box = {x: (0.0, np.inf) for x in ("coulomb", "coulomb_negative", *self.k_names)}
        box.update({x: (smallest, np.inf) for x in (*self.r_names, *self.rn_names)})
        for key, (lo, hi) in as_bounds("bounds", bounds, self.names).items():
            old = box[key]
            box[key] = (max(old[0], lo), min(old[1], hi))
        begin = dict(start)
        for key, val in dict(initial or {}).items():
            if key not in begin:
                raise ValueError(f"`initial` must name parameters of the fit; got {key!r}.")
            begin[key] = float(val)
        return FitProblem(self.names, begin, box, dict(fixed), dict(tied),
                          residual_function=self.residual,
                          jacobian_function=self.jacobian)  # fmt: skip

    def model(self, values: Mapping[str, float]) -> PIFriction | None:
        """The asymmetric PIFriction of the values (None where they do not form one)."""
        k = np.array([values[x] for x in self.k_names])
        keep = k > 0  # an element of zero stiffness is left out (as `pi_model` does)
        r = np.array([values[x] for x in self.r_names])[keep]
        rn = np.array([values[x] for x in self.rn_names])[keep]
        c1, c1n = max(values["coulomb"], 0.0), max(values["coulomb_negative"], 0.0)
        try:
            return PIFriction(c1, k[keep], threshold=r, coulomb_negative=c1n,
                              threshold_negative=rn)  # fmt: skip
        except (TypeError, ValueError):
            return None
