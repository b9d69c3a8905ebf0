"""Honest fit status: a fit that explains little, or only touches its bounds, is a poor fit.

Every `FitResult` passes through `judge`. The status becomes ``"poor_fit"``
(never ``"converged"``) when

- the model explains less than half of the variance of the fitted signal
  (1 − ‖r‖²/‖y − ȳ‖² < 0.5), or
- every free parameter sits on a bound (the optimiser found nothing inside
  the admissible region),

and the message names the likely causes: units (a signal read in mm or µN
as if it were m or N), the window (a load ramp, idle or saturated stretches),
or the sign convention (friction must oppose positive motion). A fit whose
solver failed keeps the status ``"failed"``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["MIN_EXPLAINED", "explained_variance", "judge", "sign_hint"]

#: Least share of the variance a fit must explain not to be a poor fit.
MIN_EXPLAINED = 0.5


def explained_variance(measured: np.ndarray, fitted: np.ndarray) -> float:
    """1 − ‖measured − fitted‖² / ‖measured − mean‖² (−inf for a constant signal)."""
    spread = float(np.sum((measured - np.mean(measured)) ** 2))
    if not spread > 0:
        return -np.inf
    return 1.0 - float(np.sum((measured - fitted) ** 2)) / spread


def sign_hint(signal: np.ndarray, direction: np.ndarray, what: str) -> str:
    """A note when `signal` mostly has the opposite sign of the motion's `direction`."""
    varies = np.ptp(signal) > 0 and np.ptp(direction) > 0
    if varies and float(np.corrcoef(signal, direction)[0, 1]) < -0.2:
        return (
            f"the {what} mostly has the sign opposite to the motion: its sign convention "
            "looks flipped (scale it by -1)"
        )
    return ""


def judge(
    status: str,
    message: str,
    measured: np.ndarray,
    fitted: np.ndarray,
    free: tuple[str, ...],
    at_bounds: tuple[str, ...],
    signal_label: str,
    hint: str = "",
) -> tuple[str, str]:
    """The status and message of a fit after the poor-fit test (see the module notes)."""
    if status == "failed":
        return status, message
    share = explained_variance(np.asarray(measured, float), np.asarray(fitted, float))
    all_bound = bool(free) and set(free) <= set(at_bounds)
    if share >= MIN_EXPLAINED and not all_bound:
        return status, message
    reasons = []
    if share < MIN_EXPLAINED:
        pct = "none" if not np.isfinite(share) or share <= 0 else f"{100 * share:.3g} %"
        reasons.append(
            f"the model explains {pct} of the variance of the {signal_label} (at least "
            f"{100 * MIN_EXPLAINED:g} % is expected)"
        )
    if all_bound:
        reasons.append("every fitted parameter sits on a bound")
    causes = [hint] if hint else []
    causes += [
        f"units (the {signal_label} spans {_span(measured)}: a unit in a column header is "
        "converted to SI, else give `units`/`scale` (--units/--scale))",
        "the window (cut load ramps, idle or saturated stretches away with "
        "Measurement.window or --window START:STOP)",
    ]
    if not hint:
        causes.append("the sign (friction must oppose positive motion; flip it with a scale of -1)")
    text = f"poor fit: {'; '.join(reasons)}. Likely causes: {'; '.join(causes)}. Solver: {message}"
    return "poor_fit", text


def _span(values: Any) -> str:
    arr = np.asarray(values, dtype=float)
    if arr.size == 0:
        return "nothing"
    return f"{float(arr.min()):.3g} to {float(arr.max()):.3g}"
