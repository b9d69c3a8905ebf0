"""The names lmfit and scipy users look for on a fit result (`FitResult` inherits them).

``chisqr``, ``ndata`` and ``var_names`` are fields of `FitResult`; from them
``nvarys``, ``nfree``, ``redchi``, ``aic``, ``bic`` and ``x`` follow with lmfit's
definitions, and ``to_lmfit`` gives an ``lmfit.Parameters`` to start another fit.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["LmfitNames", "bound_text", "bounds_lines", "interval_text"]

FloatArray = NDArray[np.float64]


class LmfitNames:
    """lmfit's and scipy's names, computed from the fields of a `FitResult`."""

    chisqr: float
    ndata: int
    var_names: tuple[str, ...]
    parameters: dict[str, float]
    bounds: dict[str, tuple[float, float]]
    fixed: tuple[str, ...]
    tied: tuple[str, ...]
    ties: dict[str, tuple[str, float, float]]

    @property
    def nvarys(self) -> int:
        """Number of free (varied) parameters, lmfit's name (`var_names` lists them)."""
        return len(self.var_names)

    @property
    def x(self) -> FloatArray:
        """The free parameter vector, in the order of `var_names` (scipy's ``x``)."""
        return np.array([self.parameters[n] for n in self.var_names], dtype=float)

    @property
    def nfree(self) -> int:
        """Degrees of freedom, ``ndata − nvarys`` (lmfit's name)."""
        return self.ndata - self.nvarys

    @property
    def redchi(self) -> float:
        """Reduced chi-square ``chisqr / (ndata − nvarys)`` (lmfit's name)."""
        return self.chisqr / self.nfree if self.nfree > 0 else float("nan")

    @property
    def aic(self) -> float:
        """Akaike information criterion ``n·ln(χ²/n) + 2·nvarys`` (lmfit's definition)."""
        return self._log_chi() + 2.0 * self.nvarys

    @property
    def bic(self) -> float:
        """Bayesian information criterion ``n·ln(χ²/n) + ln(n)·nvarys`` (lmfit's definition)."""
        return self._log_chi() + float(np.log(max(self.ndata, 1))) * self.nvarys

    def _log_chi(self) -> float:
        n = self.ndata
        if n < 1 or not np.isfinite(self.chisqr):
            return float("nan")
        return n * float(np.log(max(self.chisqr, np.finfo(float).tiny) / n))

    def to_lmfit(self) -> Any:
        """The parameters as an ``lmfit.Parameters`` (value, bounds, vary, linear ties).

        It can be passed back as `initial` to any fit. Needs lmfit (the extra
        ``presliding[lmfit]``): an ImportError names it otherwise.
        """
        from presliding.identification.problem._parameters import to_lmfit

        ties = {n: self.ties[n] for n in self.tied if n in self.ties}
        held = (*self.fixed, *(n for n in self.tied if n not in ties))  # tied to a fixed one
        return to_lmfit(self.parameters, self.bounds, held, ties)


def interval_text(lo: float, hi: float) -> str:
    """An interval with "unbounded" for an end the data do not bound (±inf)."""
    a = "unbounded" if np.isinf(lo) else f"{lo:.6g}"
    b = "unbounded" if np.isinf(hi) else f"{hi:.6g}"
    return f"[{a}, {b}]"


def bound_text(bounds: tuple[float, float] | None, value: float) -> str:
    if bounds is None:
        return f"{value:.6g}"
    return f"{bounds[0]:.6g}" if value == bounds[0] else f"{bounds[1]:.6g}"


def bounds_lines(bounds: dict[str, tuple[float, float]], order: list[str]) -> list[str]:
    """Bounds grouped by range, parameters in their order (at most 8 named per range)."""
    groups: dict[tuple[float, float], list[str]] = {}
    for n in order:
        if n in bounds:
            groups.setdefault(bounds[n], []).append(n)
    lines = []
    for (lo, hi), names in groups.items():
        rng = f"[{lo:.6g}, {hi:.6g}]".replace("[-inf", "(-inf").replace("inf]", "inf)")
        more = f" and {len(names) - 8} more" if len(names) > 8 else ""
        lines.append(f"  {rng}: {', '.join(names[:8])}{more}")
    return ["", "bounds:", *lines] if lines else []
