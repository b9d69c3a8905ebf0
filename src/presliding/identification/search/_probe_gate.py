"""Whether the search's best needs the probes of other valleys: floor, starts, stationarity.

The probes that move the best optimum to a neighbouring valley (the element split of
`_probes.split_starts`, the steps along eq. 17's scale of `_scale_probe`, the far step of
`_flat_probe`) cost more than the search itself on a fit that needs none of them. They are
needed where the best is not known to be the optimum:

1. it is above the noise floor (`_search.at_floor`: the pooled residual or a record more
   than `FLOOR_FACTOR` times its floor, or a status other than converged), or
2. the starts of the search ended apart, or a probe that is not gated (below) moved the
   best: the cost has several minima there, or
3. the search's solve stopped short: the Gauss–Newton model where it ended,
   m(δ) = ‖r + Jδ‖², predicts a decrease gᵀA⁺g (g = Jᵀr, A = JᵀJ over the free
   parameters not held on a bound, the scaled pseudo-inverse of `_normal_equations`) of
   more than `STATIONARY` times the profile's threshold t²·s² (s² = ‖r‖²/(n − p), t at the
   fit's level), on the objective the search solved (`predicted_decrease`). Such a solve
   stopped on a kink of the piecewise smooth residual (a stop moving across a sample, a
   preload at its saturation): the step the model promises fails, the damping grows and
   the relative step test ends the solve as converged.

The noise-floor rule alone cannot tell those valleys from the optimum: its factor 3 on the
RMS allows a cost 9 times the floor's, and the valleys the probes leave lie 5–45 % above
the optimum. On the search study's pooled stops (`benchmarks/identification_search.py`,
8 records, 40 seeds) the split and scale probes lowered the cost by 6.5–44 % in 8 fits
whose search had ended within the floor rule with one start; where their search ended, the
Gauss–Newton decrease was 150–2 000 thresholds (the 5 kHz stops that ended a quarter low
on the scale, `tests/identification/search/test_scale_probe.py`: 260), and 0–5 thresholds in
the fits where no probe paid (the 20-record benchmark's data sets 0 and 2: 0.003 and 0.15;
its data set 1, which the probes move, 250). The probes that re-engage an element that never
engaged or leave the rigid corner (`_probes.engage_starts`, `corner_starts`) are asked for
by the best itself (such an element) and run before this test.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from presliding.identification.records._pooled_problem import PooledProblem
from presliding.identification.search._search import at_floor
from presliding.identification.solve._least_squares import Solution
from presliding.identification.solve._normal_equations import scaled_pinv
from presliding.identification.solve._structured_lm import structured_normal

__all__ = ["STATIONARY", "needs_probes", "predicted_decrease"]

#: the Gauss–Newton decrease at the best, in units of the profile's threshold t²·s², above
#: which the best is not stationary (module notes)
STATIONARY = 10.0


def predicted_decrease(sol: Solution, values: Mapping[str, float] | None = None) -> float:
    """The decrease of ‖r‖² the Gauss–Newton model predicts from `values` (default: the
    solution's own), in units of t²·s² there (module notes, 3), with the residual and
    Jacobian of `sol` (its profiler, evaluated as the problem compares now); inf where it
    cannot be formed (no profiler, a residual or Jacobian that is not finite)."""
    prof: Any = sol.profiler
    if prof is None or sol.status == "failed" or not prof.free:
        return float("inf")
    at = sol.values if values is None else values
    x = np.clip(np.array([at[n] for n in prof.free], dtype=float), prof.lower, prof.upper)
    r = np.asarray(prof.fun(x), dtype=float)
    if not np.all(np.isfinite(r)):
        return float("inf")
    a, g, _ = structured_normal(prof.jacobian(x), r)
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(g))):
        return float("inf")
    free = ~(((x <= prof.lower) & (g > 0)) | ((x >= prof.upper) & (g < 0)))  # not held
    gf = g[free]
    decrease = float(gf @ scaled_pinv(a[np.ix_(free, free)]) @ gf) if gf.size else 0.0
    threshold = prof.quantile**2 * float(r @ r) / max(r.shape[0] - x.shape[0], 1)
    return decrease / threshold if threshold > 0 else (0.0 if decrease == 0 else float("inf"))


def needs_probes(problem: PooledProblem, sol: Solution, starts_agree: bool,
                 decrease: float) -> bool:  # fmt: skip
    """Whether the probes of other valleys are needed from the search's best `sol` (module
    notes): above the floor, starts that ended apart, or not stationary (`decrease`, the
    `predicted_decrease` of the search's own solve)."""
    if not (starts_agree and at_floor(problem, sol)):
        return True
    return not decrease <= STATIONARY
