"""Why a fit is poor: the likely causes a ``poor_fit`` message names (`_status`).

Units, window or sign only when they look wrong (a signal whose span is
implausible in SI, a signal standing still over a third of the samples or
dominated by a ramp, a force whose sign opposes the motion's), otherwise model
inadequacy, with the fit's own note (`masing_check`'s verdict where the records
hold loops).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

__all__ = ["poor_fit_text"]

#: Least share of the variance a fit must explain not to be a poor fit.
MIN_EXPLAINED = 0.5


def poor_fit_text(
    share: float,
    all_bound: bool,
    measured: np.ndarray,
    signal_label: str,
    hint: str,
    model_hint: str | Callable[[], str],
    message: str,
) -> str:
    reasons = []
    if share < MIN_EXPLAINED:
        pct = "none" if not np.isfinite(share) or share <= 0 else f"{100 * share:.3g} %"
        reasons.append(
            f"the model explains {pct} of the variance of the {signal_label} (at least "
            f"{100 * MIN_EXPLAINED:g} % is expected)"
        )
    if all_bound:
        reasons.append("every fitted parameter sits on a bound")
    name = "explained" if share < MIN_EXPLAINED else "all_bounds"
    causes = [hint] if hint else []
    if not _plausible_span(measured, signal_label):
        causes.append(
            f"units (the {signal_label} spans {_span(measured)}, implausible in SI: a unit in "
            "a column header is converted to SI, else give `units`/`scale` (--units/--scale))"
        )
    window = _window_hint(measured)
    if window:
        causes.append(
            f"the window ({window}: cut load ramps, idle or saturated stretches away with "
            "Measurement.window or --window START:STOP)"
        )
    if not causes:
        more = model_hint() if callable(model_hint) else model_hint
        causes.append(
            "model inadequacy: units, window and sign look right, so the model cannot "
            "explain these data (a mechanism it lacks, e.g. Coulomb friction alone on a "
            "viscous damper: try more elements, a viscous term or another model)"
            + (f"; {more}" if more else "")
        )
    text = f"poor fit: {'; '.join(reasons)}. Likely causes: {'; '.join(causes)}. Solver: {message}"
    return f"rule {name}: {text}"


#: Spans of a signal that are plausible in SI for a rig, by the words of its label.
_PLAUSIBLE = (
    (("force", "torque"), 1e-5, 1e6),
    (("position", "displacement"), 1e-9, 10.0),
    (("velocity",), 1e-8, 100.0),
)


def _plausible_span(measured: np.ndarray, label: str) -> bool:
    """False when the signal's span is implausible in SI (mm read as m, µN as N, ...)."""
    span = float(np.ptp(measured)) if measured.size else 0.0
    for words, lo, hi in _PLAUSIBLE:
        if any(w in label for w in words):
            return lo <= span <= hi
    return True


def _window_hint(measured: np.ndarray) -> str:
    """What looks wrong with the window: idle or saturated stretches, or a ramp ("" if none)."""
    n = measured.shape[0]
    if n < 8:
        return ""
    still = float(np.mean(np.diff(measured) == 0.0))
    if still > 0.3:
        return f"the signal stands still over {100 * still:.0f} % of the samples"
    t = np.arange(n, dtype=float)
    spread = float(np.sum((measured - measured.mean()) ** 2))
    if spread > 0:
        slope = np.polyfit(t, measured, 1)
        trend = 1.0 - float(np.sum((measured - np.polyval(slope, t)) ** 2)) / spread
        if trend > 0.9:
            return f"a ramp or drift explains {100 * trend:.0f} % of the signal's variance"
    return ""


def _span(values: Any) -> str:
    arr = np.asarray(values, dtype=float)
    if arr.size == 0:
        return "nothing"
    return f"{float(arr.min()):.3g} to {float(arr.max()):.3g}"
