"""The rate-dependent families as fitters for a registry of model families (GMS, LuGre, Dahl).

A fitter is ``fitter(records, **options) -> FitResult``: `records` a Measurement or a
list of them, `options` any keyword option of `fit_response` (an option the family has
no use for is refused: `fit_response` raises for it), the result the family's pooled
fit by the same engine — the same residual as the PI model's fit of the same records
and options, so its ``chisqr``, ``ndata``, ``nvarys``, AIC and BIC compare with it —
with ``predict(measurement, initial=...)`` for a held-out record. `RATE_FAMILIES` maps
their names to them; importing this module registers them in `compare_fits`' registry
(`families.register_family`), so ``compare_fits(records, ("pi", "gms"))`` and
``presliding fit --compare pi,gms`` fit them beside the PI model.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from presliding.identification.families import register_family
from presliding.identification.fit_response import fit_response
from presliding.identification.fit_result import FitResult

__all__ = ["RATE_FAMILIES", "fit_dahl", "fit_gms", "fit_lugre"]


def fit_gms(records: Any, n_elements: int = 4, **options: Any) -> FitResult:
    """`fit_response(records, n_elements, family="gms", **options)`: generalized Maxwell-slip."""
    return fit_response(records, n_elements, family="gms", **options)


def fit_lugre(records: Any, **options: Any) -> FitResult:
    """`fit_response(records, family="lugre", **options)`: LuGre with a mass."""
    return fit_response(records, family="lugre", **options)


def fit_dahl(records: Any, **options: Any) -> FitResult:
    """`fit_response(records, family="dahl", **options)`: Dahl (α = 1) with a mass."""
    return fit_response(records, family="dahl", **options)


#: The rate-dependent families by name (module notes).
RATE_FAMILIES: dict[str, Callable[..., FitResult]] = {
    "gms": fit_gms,
    "lugre": fit_lugre,
    "dahl": fit_dahl,
}

for _name, _fitter in RATE_FAMILIES.items():  # replace: a reload registers them again
    register_family(_name, _fitter, replace=True)
