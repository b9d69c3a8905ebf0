"""The model families `compare_fits` fits side by side: a registry others extend.

`FAMILIES` maps a family's name to its fitter; `register_family` adds one. A fitter is a
callable ``fitter(records, **options) -> FitResult``:

* ``records`` is a list of at least one `Measurement`, the records every family fits;
* ``options`` are the keyword options `compare_fits` was given for every family, updated
  with the family's own (``candidates={"pi": {"n_elements": 3}}``); a fitter raises
  TypeError for an option it does not take, so that nothing given is ignored;
* it returns a `FitResult` of the same residual as every other family (the same records,
  compared signal and weights, e.g. by `fit_response`'s pooled engine), so that its
  ``chisqr``, ``ndata`` and ``nvarys`` give comparable RSS, AIC and BIC, with its own
  ``status`` and ``message`` (the one status table of every fit); and its
  ``predict(measurement, initial=...)`` returns a `Prediction` of a held-out record
  (``initial="measured"``: from its first samples, nothing fitted to it).

A new family registers from its own module, at import (``register_family("gms", fit_gms)``
in a module that `presliding.identification` imports), without editing this one; its name
is letters, digits and ``-``, and the command line's ``presliding fit --compare`` takes it
too (``--elements`` goes to every family whose fitter has an ``n_elements`` argument).

A family whose fit carries another family's fit of the same records and options (as
``result.asymmetry.symmetric``: ``"pi-asymmetric"`` fits ``"pi"`` first) names it in
`CARRIES`; `compare_fits` then takes that fit from it instead of fitting the records twice.

The families shipped: ``"pi"`` (`fit_response`: the PI model of eq. 17, ``n_elements`` 4 by
default, a count or ``"auto"``), ``"pi-asymmetric"`` (the same with ``asymmetric=True``: the
two directions' levels; its fit carries the asymmetry test) and ``"coulomb"`` (Coulomb
friction alone, ``n_elements=0``; with ``viscous=True`` Coulomb and viscous); and, registered
by `rate_families`, ``"gms"`` (generalized Maxwell-slip: the PI elements with a Stribeck curve
and frictional lag, ``n_elements`` 4 by default), ``"lugre"`` and ``"dahl"`` (with a mass),
each `fit_response(family=...)`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from presliding._validation import fmt

if TYPE_CHECKING:  # pragma: no cover
    from presliding.identification.fit_result import FitResult
    from presliding.measurement.measurement import Measurement

__all__ = ["CARRIES", "FAMILIES", "register_family"]

Fitter = Callable[..., "FitResult"]


def _pi(records: list[Measurement], n_elements: int | str = 4, **options: Any) -> FitResult:
    from presliding.identification.fit_response import fit_response

    return fit_response(records, n_elements, **options)


def _pi_asymmetric(records: list[Measurement], n_elements: int | str = 4,
                   **options: Any) -> FitResult:  # fmt: skip
    from presliding.identification.fit_response import fit_response

    return fit_response(records, n_elements, asymmetric=True, **options)


def _coulomb(records: list[Measurement], **options: Any) -> FitResult:
    from presliding.identification.fit_response import fit_response

    return fit_response(records, 0, **options)


#: The model families by name (module notes: what a fitter takes and returns).
FAMILIES: dict[str, Fitter] = {"pi": _pi, "pi-asymmetric": _pi_asymmetric, "coulomb": _coulomb}
#: family → the family whose fit its fit carries as ``asymmetry.symmetric`` (module notes)
CARRIES: dict[str, str] = {"pi-asymmetric": "pi"}


def register_family(name: str, fitter: Fitter, *, replace: bool = False) -> None:
    """Add a model family to `FAMILIES` (module notes: the fitter's contract).

    Parameters
    ----------
    name : str
        The family's name in `compare_fits` and ``presliding fit --compare``
        (letters, digits and ``-``).
    fitter : callable
        ``fitter(records, **options) -> FitResult``.
    replace : bool, keyword only
        Replace a family of that name (otherwise a name taken is refused).
    """
    if not isinstance(name, str) or not name or not all(c.isalnum() or c == "-" for c in name):
        raise ValueError(f"`name` must be letters, digits and '-'; got {fmt(name)}.")
    if not callable(fitter):
        raise TypeError(f"`fitter` must be callable; got {type(fitter).__name__}.")
    if name in FAMILIES and not replace:
        raise ValueError(f"`name` {name!r} is a family already; pass replace=True to replace it.")
    FAMILIES[name] = fitter
