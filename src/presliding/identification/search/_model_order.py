"""Model order from the data: ``n_elements="auto"`` of the pooled fits.

The fit runs for N = 0, 1, ..., `MAX_ELEMENTS` elements (equal break-away
forces or not, as asked), each with ``prune=True``: an element whose play is
wider than every record's swing (its threshold exceeds every excursion: the
data cannot reach it) is dropped and the fit repeated without it, so no kept
element is one the data cannot see. Each order is scored by the Bayesian
information criterion of the pooled residual,

    BIC = n·ln(‖r‖²/n) + p·ln(n)        (n residuals, p free parameters),

and the smallest wins; an order whose fit failed is not a candidate. The table
(N, ‖r‖², BIC, what happened) is on the result (``result.search.order_table``)
and in its report.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

#: largest number of elements tried by ``n_elements="auto"``
MAX_ELEMENTS = 4
#: BIC differences below this are ties, won by the smaller order
TIE = 1e-3


def bic(result: Any) -> tuple[float, float]:
    """(‖r‖², BIC) of a fit from its residual and its free parameters."""
    r = np.asarray(result.measured, float) - np.asarray(result.fitted, float)
    n = max(r.shape[0], 1)
    rss = float(r @ r)
    free = len(result.parameters) - len(result.fixed) - len(result.tied)
    if not rss > 0 or not np.isfinite(rss):
        return rss, -np.inf if rss == 0 else np.inf
    return rss, float(n * np.log(rss / n) + free * np.log(n))


def choose_order(fit: Callable[..., Any], options: dict[str, Any],
                 max_elements: int = MAX_ELEMENTS, minimum: int = 0) -> Any:  # fmt: skip
    """The fit of the order of smallest BIC, with the table of every order (module notes)."""
    rows: list[tuple] = []
    candidates: list[tuple] = []
    result: Any = None
    for n in range(minimum, max_elements + 1):
        result = fit(**{**options, "n_elements": n, "prune": n > 0})
        kept = _elements(result)
        for _ in range(max_elements):  # a refit can leave another element unreached
            reach = int(result.derived.get("effective_elements", kept))
            if not 0 <= reach < kept:
                break
            result = fit(**{**options, "n_elements": reach, "prune": reach > 0})
            kept = _elements(result)
        rss, score = bic(result)
        if result.status == "failed":
            score = np.inf
        rows.append((n, rss, score, result.status if kept == n else
                     f"pruned to {kept}; {result.status}"))  # fmt: skip
        if score < np.inf:
            candidates.append((score, n, result))
    pick = (0.0, minimum, result)
    if candidates:  # the smallest order within TIE of the least BIC (equal fits: fewer elements)
        low = min(c[0] for c in candidates)
        pick = min((c for c in candidates if c[0] <= low + TIE), key=lambda c: c[1])
    best = pick[2]
    table = tuple((int(n), float(c), float(s), note) for n, c, s, note in rows)
    chosen = _elements(best)
    summary = best.search
    if summary is not None:
        summary = replace(summary, order_table=table, chosen_order=int(pick[1]))
    note = (f"n_elements='auto': {chosen} element(s) by BIC over N = {minimum}..{max_elements}, "
            "elements the data cannot reach dropped")  # fmt: skip
    return replace(best, search=summary, notes=(*best.notes, note))


def _elements(result: Any) -> int:
    """The number of elements of a fitted model."""
    model = result.model
    if model is None or not getattr(model, "is_discrete", True):
        return -1
    return int(np.asarray(model.stiffness).shape[0])
