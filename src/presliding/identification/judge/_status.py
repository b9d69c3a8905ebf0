"""One status judge for every fit: the rules, in the order they are applied.

Every `FitResult` (``fit_presliding``, ``fit_motion``, ``fit_virgin_curve``,
``fit_response``, ``fit_quasi_static``) passes through `judge`, and the command
line maps its status to an exit code with `exit_code`. The message starts with
the rule that fired (``"rule <name>: ..."``). ``success`` is True only for
``"converged"``.

==================== ========================================================== ====
status               rule that gives it (the first that fires wins)             exit
==================== ========================================================== ====
``failed``           ``solver``: the optimiser or the model failed (kept as     1
                     given).
``poor_fit``         ``explained``: the model explains less than half of the    1
                     variance (1 − ‖r‖²/‖y − ȳ‖² < 0.5); ``all_bounds``: every
                     free parameter sits on a bound.
``max_evaluations``  ``budget``: the evaluation limit stopped the optimiser.    1
``local_minimum``    ``search``: a better optimum exists, or the residual stays 1
                     far above the noise floor (set by the search).
``not_identifiable`` ``singular``: a direction of parameter space the data do   1
                     not determine; ``correlation``: |ρ| ≥ 0.999 between two
                     free parameters, both with an interval wider than 10 % of
                     the value (a ridge the noise moves along); ``error``: a
                     standard error that is not finite; ``interval``: an
                     interval end the data do not bound, or one spanning more
                     than two orders of magnitude; ``profile``: a flat profile
                     (set by a check); ``optima``: another local optimum the
                     search reached is within the profile's likelihood-ratio
                     threshold of the best and outside an interval (the
                     interval widened to hold both, `_alternatives`).
``at_bound``         ``bound``: a model parameter sits on its bound (c1 = 0,    1
                     k_j = 0, ...), where the linearised interval does not
                     hold; a record's start, an offset and a viscous
                     coefficient of 0 are natural values, not bounds.
``converged``        none of the above.                                         0
==================== ========================================================== ====

A poor fit's message names the likely causes: units, window or sign only when
they look wrong (a signal whose span is implausible in SI, a signal standing
still over a third of the samples or dominated by a ramp, a force whose sign
opposes the motion's), otherwise model inadequacy, with the fit's own note
(`model_hint`: `presliding.identification.masing_check`'s verdict where the
records hold loops).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

__all__ = [
    "EXIT_CODES",
    "MAX_CORRELATION",
    "MAX_DECADES",
    "MIN_EXPLAINED",
    "STATUSES",
    "exit_code",
    "explained_variance",
    "judge",
    "sign_hint",
]

#: Every status a fit can end with; only "converged" is a success.
STATUSES = (
    "converged",
    "local_minimum",
    "not_identifiable",
    "poor_fit",
    "at_bound",
    "max_evaluations",
    "failed",
)
#: Exit code of ``presliding fit`` for each status (every ``--kind`` alike).
EXIT_CODES = {s: (0 if s == "converged" else 1) for s in STATUSES}
#: Least share of the variance a fit must explain not to be a poor fit.
MIN_EXPLAINED = 0.5
#: |ρ| at or above which two parameters are not separately determined.
MAX_CORRELATION = 0.999
#: A correlated pair is undetermined only where an interval exceeds this share of its value.
LOOSE = 0.1
#: Interval spanning more decades than this (hi/value or value/lo): not determined.
MAX_DECADES = 2.0
#: Parameters whose bound is a natural value (a record's start, an offset, no viscous friction).
NATURAL = ("initial_velocity", "initial_position", "preload_fraction", "offset", "viscous")
_SOLVER_KEPT = ("failed", "max_evaluations", "local_minimum")


def exit_code(status: str) -> int:
    """The command line's exit code for a fit's `status` (0 only for "converged")."""
    return EXIT_CODES.get(status, 1)


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


def _names(names: Sequence[str]) -> str:
    shown = list(dict.fromkeys(names))
    return ", ".join(shown[:6]) + (f" and {len(shown) - 6} more" if len(shown) > 6 else "")


def _rule(name: str, text: str, message: str) -> str:
    message = re.sub(r"^rule \w+: ", "", message)
    return f"rule {name}: " + "; ".join(x for x in (text, message) if x)


def undetermined(
    values: Mapping[str, float],
    standard_error: Mapping[str, float],
    intervals: Mapping[str, tuple[float, float]],
    covariance: Any,
    free: Sequence[str],
    at_bounds: Sequence[str],
    bounds: Mapping[str, tuple[float, float]],
) -> tuple[str, str]:
    """The first not-identifiable rule that fires, as (rule, text); ("", "") for none."""
    names = list(values)
    inner = [x for x in free if x not in at_bounds and x in values]
    bad = [x for x in inner if not np.isfinite(standard_error.get(x, 0.0))]
    if bad:
        return "error", f"the data do not determine {_names(bad)} (standard error not finite)"
    if covariance is not None and len(inner) > 1:
        cov = np.asarray(covariance, dtype=float)
        idx = [names.index(x) for x in inner]
        sub = cov[np.ix_(idx, idx)]
        d = np.sqrt(np.abs(np.diag(sub)))
        with np.errstate(divide="ignore", invalid="ignore"):
            rho = sub / np.outer(d, d)
        loose = [_loose(values[x], intervals.get(x), bounds.get(x)) for x in inner]
        pairs = [
            f"{inner[i]} ~ {inner[j]} (ρ = {rho[i, j]:+.4f})"
            for i in range(len(inner))
            for j in range(i + 1, len(inner))
            if np.isfinite(rho[i, j])
            and abs(rho[i, j]) >= MAX_CORRELATION
            and loose[i]
            and loose[j]
        ]
        if pairs:
            return "correlation", (
                f"the data do not separate {_names(pairs)}: |ρ| >= {MAX_CORRELATION:g}, "
                "only a combination of them is determined"
            )
    wide = []
    for x in inner:
        lo, hi = intervals.get(x, (-np.inf, np.inf))
        blo, bhi = bounds.get(x, (-np.inf, np.inf))
        v = values[x]
        if (np.isinf(lo) and np.isinf(blo)) or (np.isinf(hi) and np.isinf(bhi)):
            wide.append(f"{x} (unbounded)")
        elif blo >= 0 and v > 0 and (
            hi > v * 10**MAX_DECADES or (lo > 0 and v > lo * 10**MAX_DECADES)
        ):  # fmt: skip
            wide.append(f"{x} ([{lo:.3g}, {hi:.3g}])")
    if wide:
        return "interval", (
            f"the data do not determine {_names(wide)}: the interval is not bounded or spans "
            f"more than {MAX_DECADES:g} orders of magnitude"
        )
    return "", ""


def _loose(
    value: float, interval: tuple[float, float] | None, bound: tuple[float, float] | None
) -> bool:
    """An interval wider than `LOOSE` of the value (of the range, for a parameter bounded on
    both sides, such as a preload fraction in [−1, 1]): a ridge that matters."""
    if interval is None:
        return True
    lo, hi = interval
    half = max(value - lo, hi - value)
    if bound is not None and np.all(np.isfinite(bound)):
        return not half <= LOOSE * float(bound[1] - bound[0])
    return not half <= LOOSE * abs(value)


def _held(
    values: Mapping[str, float],
    free: Sequence[str],
    at_bounds: Sequence[str],
    bounds: Mapping[str, tuple[float, float]],
) -> str:
    """A poor fit's cause: model parameters held on (or within 1e-5 of) a finite bound."""
    held = []
    for x in free:
        if x.startswith(NATURAL) or x not in values:
            continue
        v = values[x]
        for end in bounds.get(x, (-np.inf, np.inf)):
            if end == 0 or not np.isfinite(end):  # 0: the natural "none" of a nonnegative one
                continue
            if x in at_bounds or abs(v - end) <= 1e-5 * abs(end):
                held.append(f"{x} = {v:.6g} on its bound {end:.6g}")
                break
    if not held:
        return ""
    return (
        f"the bounds ({', '.join(held)}: the data ask for a value beyond it; check "
        "`bounds`, `min_coulomb_level` and the fixed values)"
    )


def model_bounds(
    values: Mapping[str, float],
    free: Sequence[str],
    at_bounds: Sequence[str],
    bounds: Mapping[str, tuple[float, float]],
) -> list[str]:
    """Free model parameters on a bound (a record's start or an offset excluded), as text."""
    out = []
    for x in free:
        if x.startswith(NATURAL) or x not in values:
            continue
        lo, hi = bounds.get(x, (-np.inf, np.inf))
        if x in at_bounds or values[x] == lo or values[x] == hi:
            out.append(f"{x} = {values[x]:.6g}")
    return out


def judge(
    status: str,
    message: str,
    measured: np.ndarray,
    fitted: np.ndarray,
    free: tuple[str, ...],
    at_bounds: tuple[str, ...],
    signal_label: str,
    hint: str = "",
    *,
    values: Mapping[str, float] | None = None,
    standard_error: Mapping[str, float] | None = None,
    intervals: Mapping[str, tuple[float, float]] | None = None,
    covariance: Any = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    model_hint: str | Callable[[], str] = "",
) -> tuple[str, str]:
    """The status and message of a fit under the rules of the module table.

    `status` and `message` are the solver's (and the search's); the keyword
    arguments give what the identifiability and bound rules read (without
    `values` only the poor-fit rules apply). `hint` is a cause found by the
    caller (a flipped sign); `model_hint` the model-inadequacy note used when
    units, window and sign look right.
    """
    if status == "failed":
        return status, message if message.startswith("rule ") else _rule("solver", "", message)
    measured = np.asarray(measured, dtype=float)
    fitted = np.asarray(fitted, dtype=float)
    share = explained_variance(measured, fitted)
    all_bound = bool(free) and set(free) <= set(at_bounds)
    if share < MIN_EXPLAINED or all_bound:
        held = _held(values or {}, free, at_bounds, bounds or {})
        if held:
            hint = "; ".join(x for x in (hint, held) if x)
        return "poor_fit", _poor_fit_text(
            share, all_bound, measured, signal_label, hint, model_hint, message
        )
    if status in _SOLVER_KEPT:
        rule = {"max_evaluations": "budget", "local_minimum": "search"}[status]
        return status, message if message.startswith("rule ") else _rule(rule, "", message)
    if values is None:
        return status, message
    bounds = bounds or {}
    if status == "not_identifiable" and not message.startswith("rule "):
        return status, _rule("singular" if "singular" in message else "profile", "", message)
    rule, text = undetermined(
        values, standard_error or {}, intervals or {}, covariance, free, at_bounds, bounds
    )
    if rule:
        return "not_identifiable", _rule(rule, text, message)
    if status == "not_identifiable":
        return status, message
    on = model_bounds(values, free, at_bounds, bounds)
    if status == "at_bound" or on:
        if status == "at_bound":
            return status, message if message.startswith("rule ") else _rule("bound", "", message)
        text = (
            f"the solution sits on a bound ({', '.join(on)}), where the linearised intervals "
            "do not hold"
        )
        return "at_bound", _rule("bound", text, message)
    return status, message


def _poor_fit_text(
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
