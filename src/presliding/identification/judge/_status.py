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
``local_minimum``    ``search``: a better optimum of this model exists or is    1
                     likely: the residual stays far above the noise floor while
                     the starts ended apart, or while some records fit at
                     their floor, and the residuals name no mechanism the model
                     lacks nor fail on every record (set by the search).
``model_inadequate`` ``adequacy``: the residuals are not what the noise model   1
                     says (`_adequacy`: a record's level above its floor, a
                     residual that is not white, or one that correlates with
                     the input or the motion), and no better optimum of this
                     model is likely: the model does not describe the data.
                     The message names the test, the record and the lag, and
                     the likely cause when a diagnostic points to it (an
                     asymmetry, a velocity dependence, a delay, too few
                     elements). Its intervals are not calibrated.
``not_identifiable`` ``singular``: a direction of parameter space the data do   1
                     not determine; ``correlation``: |ρ| ≥ 0.999 between two
                     free parameters, both with an interval wider than 10 % of
                     the value (a ridge the noise moves along); ``error``: a
                     standard error that is not finite; ``interval``: an
                     interval end the data do not bound, or one spanning more
                     than two orders of magnitude; ``profile``: a flat profile
                     (set by a check), or a linearised interval wider than
                     half the value on each side whose profile
                     stopped unresolved (its inner optimisations disagree:
                     the cost has other valleys within reach); ``optima``:
                     another
                     local optimum the
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

from presliding.identification.judge._poor_fit import MIN_EXPLAINED, poor_fit_text

__all__ = [
    "EXIT_CODES",
    "MAX_CORRELATION",
    "MAX_DECADES",
    "MIN_EXPLAINED",
    "OPTIMUM",
    "STATUSES",
    "adequacy_verdict",
    "exit_code",
    "explained_variance",
    "judge",
    "loose_wald",
    "sign_hint",
]

#: Every status a fit can end with; only "converged" is a success.
STATUSES = (
    "converged",
    "local_minimum",
    "model_inadequate",
    "not_identifiable",
    "poor_fit",
    "at_bound",
    "max_evaluations",
    "failed",
)
#: Exit code of ``presliding fit`` for each status (every ``--kind`` alike).
EXIT_CODES = {s: (0 if s == "converged" else 1) for s in STATUSES}
#: |ρ| at or above which two parameters are not separately determined.
MAX_CORRELATION = 0.999
#: A correlated pair is undetermined only where an interval exceeds this share of its value.
LOOSE = 0.1
#: Interval spanning more decades than this (hi/value or value/lo): not determined.
MAX_DECADES = 2.0
#: A linearised interval wider than this share of the value (each side) of a parameter whose
#: profile stopped unresolved is not one the data support: within a factor 2 of 0, a
#: positive parameter's quadratic approximation does not hold, and the profile that would
#: replace it found other valleys
WIDE_WALD = 0.5
#: Parameters whose bound is a natural value (a record's start, an offset, no viscous friction).
NATURAL = ("initial_velocity", "initial_position", "preload_fraction", "offset", "viscous")
_SOLVER_KEPT = ("failed", "max_evaluations", "local_minimum", "model_inadequate")
_KEPT_RULES = {"max_evaluations": "budget", "local_minimum": "search",
               "model_inadequate": "adequacy"}  # fmt: skip
#: statuses of an optimum (the rules after the search's may still change them)
OPTIMUM = ("converged", "not_identifiable", "at_bound")


def exit_code(status: str) -> int:
    """The command line's exit code for a fit's `status` (0 only for "converged")."""
    return EXIT_CODES.get(status, 1)


def adequacy_verdict(status: str, message: str, adequacy: Any, starts_agree: bool = True,
                     some_fit: bool = False) -> tuple[str, str]:  # fmt: skip
    """Rule ``adequacy`` (module table): an optimum whose residuals fail the tests of
    `_adequacy` is ``model_inadequate``; where a record sits above its floor and no
    mechanism is named, while the starts ended apart or other records of the same shared
    model pass (`some_fit`), a better optimum is likely instead (``local_minimum``)."""
    if status not in OPTIMUM or adequacy is None or adequacy.passed:
        return status, message
    old = "" if status == "converged" else message
    off_floor = any(f.test == "level" for f in adequacy.findings)
    if off_floor and adequacy.cause is None and (some_fit or not starts_agree):
        why = ("other records pass the tests with the same shared model and no mechanism it "
               "lacks explains the rest" if some_fit else "the starts ended apart and the "
               "residual stays above the noise floor")  # fmt: skip
        text = f"local minimum: {why}, so a better optimum of this model is likely; "
        return "local_minimum", _rule("search", text + adequacy.text(), old)
    text = f"model inadequate: {adequacy.text()}"
    return "model_inadequate", _rule("adequacy", text, old)


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
    methods: Mapping[str, str] | None = None,
) -> tuple[str, str]:
    """The first not-identifiable rule that fires, as (rule, text); ("", "") for none.
    `methods` are the intervals' methods (`interval_method`) of the parameters whose profile
    stopped unresolved (`Solution.unresolved`): a model parameter's linearised interval wider
    than `WIDE_WALD` of its value among them is not one the data support (rule
    ``profile``)."""
    methods = methods or {}
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
    unheld = [
        f"{x} (±{100 * (intervals[x][1] - intervals[x][0]) / 2 / abs(values[x]):.0f} %)"
        for x in loose_wald(values, intervals, methods, inner)
    ]
    if unheld:
        return "profile", (
            f"the linearised intervals of {_names(unheld)} are too wide to hold (their "
            "profiles were not resolved: the cost has other valleys within reach)"
        )
    return "", ""


def loose_wald(values: Mapping[str, float], intervals: Mapping[str, tuple[float, float]],
               methods: Mapping[str, str], free: Sequence[str]) -> list[str]:  # fmt: skip
    """The model parameters among `free` whose interval is linearised (``"wald"``) and wider
    than `WIDE_WALD` of the value on each side: one the profile would replace, and did not."""
    return [
        x for x in free
        if methods.get(x) == "wald" and not x.startswith(NATURAL) and x in intervals
        and values.get(x, 0.0) != 0
        and (intervals[x][1] - intervals[x][0]) / 2 > WIDE_WALD * abs(values[x])
    ]  # fmt: skip


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
    for x in free:  # a threshold's bounds are the data's resolution and reach: natural ones
        if x.startswith(NATURAL) or x.startswith("threshold") or x not in values:
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
    interval_method: Mapping[str, str] | None = None,
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
        return "poor_fit", poor_fit_text(
            share, all_bound, measured, signal_label, hint, model_hint, message
        )
    if status in _SOLVER_KEPT:
        rule = _KEPT_RULES[status]
        return status, message if message.startswith("rule ") else _rule(rule, "", message)
    if values is None:
        return status, message
    bounds = bounds or {}
    if status == "not_identifiable" and not message.startswith("rule "):
        return status, _rule("singular" if "singular" in message else "profile", "", message)
    rule, text = undetermined(
        values,
        standard_error or {},
        intervals or {},
        covariance,
        free,
        at_bounds,
        bounds,
        interval_method,
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
