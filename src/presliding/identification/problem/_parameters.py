"""Parameters the way users know them: `initial`, `bounds`, `fixed`, `tied`, lmfit's Parameters.

Every ``fit_*`` passes its parameter arguments through `resolve_parameters`,
one checker with one wording:

- an ``lmfit.Parameters`` given as `initial` becomes start values (``value``),
  bounds (``min``, ``max``), fixed values (``vary=False``) and ties (``expr``
  limited to linear ties ``a*name + b``, ``name*a``, ``name + b``, ``name``);
- contradictory arguments are refused with one sentence naming both: an
  explicit argument (``mass=1``) and ``fixed={"mass": 2}``, a start value and a
  fixed value that differ, a fixed value or a start outside the bounds given,
  a parameter both fixed and tied.

lmfit stays optional: it is imported only by `to_lmfit`, which raises an
ImportError naming the extra ``presliding[lmfit]`` when it is missing.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import Any

import numpy as np

from presliding._interop import require
from presliding._validation import as_real_scalar, fmt

__all__ = [
    "check_flag",
    "check_levels",
    "from_lmfit",
    "is_lmfit_parameters",
    "kept_parameters",
    "resolve_parameters",
    "to_lmfit",
]

Tie = str | tuple[str, float] | tuple[str, float, float]

_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_NAME = r"[A-Za-z_]\w*"
_TIES = (  # (pattern, (factor group, name group, offset group))
    re.compile(rf"^(?P<a>{_NUM})\s*\*\s*(?P<n>{_NAME})\s*(?P<b>[-+]\s*{_NUM})?$"),
    re.compile(rf"^(?P<n>{_NAME})\s*\*\s*(?P<a>{_NUM})\s*(?P<b>[-+]\s*{_NUM})?$"),
    re.compile(rf"^(?P<n>{_NAME})\s*(?P<b>[-+]\s*{_NUM})?$"),
)


def is_lmfit_parameters(value: Any) -> bool:
    """True for an ``lmfit.Parameters`` (checked by type name: lmfit need not be imported)."""
    return type(value).__name__ == "Parameters" and type(value).__module__.startswith("lmfit")


def _linear_tie(name: str, expr: str) -> tuple[str, float, float]:
    text = expr.strip()
    for pattern in _TIES:
        m = pattern.match(text)
        if m:
            a = float(m.group("a")) if "a" in pattern.groupindex and m.group("a") else 1.0
            b = float(m.group("b").replace(" ", "")) if m.group("b") else 0.0
            return m.group("n"), a, b
    raise ValueError(f"`initial[{name!r}].expr` must be a linear tie a*name + b; got {expr!r}.")


def from_lmfit(params: Any) -> tuple[dict, dict, dict, dict]:
    """(initial, bounds, fixed, tied) of an ``lmfit.Parameters``."""
    initial: dict[str, float] = {}
    bounds: dict[str, tuple[float, float]] = {}
    fixed: dict[str, float] = {}
    tied: dict[str, Tie] = {}
    for name, p in params.items():
        if getattr(p, "expr", None):
            tied[name] = _linear_tie(name, p.expr)
            continue
        value = as_real_scalar(f"initial[{name!r}].value", p.value, finite=False)
        if np.isnan(value) or (not p.vary and not np.isfinite(value)):
            raise ValueError(  # NaN gave a "converged" fit with NaN parameters
                f"`initial[{name!r}].value` must be a finite number (or ±inf for no start of a "
                f"varied parameter); got {fmt(value)}."
            )
        lo, hi = float(p.min), float(p.max)
        if np.isnan(lo) or np.isnan(hi):
            raise ValueError(
                f"`initial[{name!r}]` must have bounds that are numbers or ±inf; got min "
                f"{fmt(lo)}, max {fmt(hi)}."
            )
        if np.isfinite(lo) or np.isfinite(hi):
            bounds[name] = (lo, hi)
        if not p.vary:
            fixed[name] = value
        elif np.isfinite(value):
            initial[name] = value
    return initial, bounds, fixed, tied


def to_lmfit(values: Mapping[str, float], bounds: Mapping, fixed: tuple, tied: Mapping) -> Any:
    """An ``lmfit.Parameters`` holding `values` (fixed ones with vary=False, ties as expr)."""
    lmfit = require("lmfit", "an lmfit.Parameters")
    params = lmfit.Parameters()
    for name, value in values.items():
        lo, hi = bounds.get(name, (-np.inf, np.inf))
        params.add(name, value=value, min=lo, max=hi, vary=name not in fixed and name not in tied)
    for name, (target, a, b) in tied.items():
        params[name].expr = f"{a!r}*{target} + {b!r}"
    return params


def _contradiction(first: str, a: Any, second: str, b: Any) -> ValueError:
    return ValueError(
        f"`{first}` ({fmt(a)}) and `{second}` ({fmt(b)}) contradict each other: give one of them."
    )


def resolve_parameters(
    initial: Any = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    fixed: Mapping[str, Any] | None = None,
    tied: Mapping[str, Any] | None = None,
    explicit: Mapping[str, Any] | None = None,
) -> tuple[dict, dict, dict, dict]:
    """`initial`, `bounds`, `fixed` and `tied` as new dicts, checked against each other.

    `initial` may be a mapping or an ``lmfit.Parameters`` (module notes);
    `explicit` maps a fit's own arguments that fix a parameter (``{"mass":
    mass}``; None: not given) to check them against `fixed`. Names are checked
    against the fit's parameters later, by the solver.
    """
    init: dict[str, Any] = {}
    bnd: Any = dict(bounds or {}) if isinstance(bounds, Mapping) or bounds is None else bounds
    fix: dict[str, Any] = (
        dict(fixed or {}) if isinstance(fixed, Mapping) or fixed is None else fixed
    )
    tie: dict[str, Any] = dict(tied or {}) if isinstance(tied, Mapping) or tied is None else tied
    if is_lmfit_parameters(initial):
        i2, b2, f2, t2 = from_lmfit(initial)
        for label, mine, theirs in (("bounds", bnd, b2), ("fixed", fix, f2), ("tied", tie, t2)):
            for n, v in theirs.items():
                if n in mine and mine[n] != v:
                    raise _contradiction(f"{label}[{n!r}]", mine[n], f"initial[{n!r}]", v)
                mine[n] = v
        init = i2
    elif initial is not None:
        if not isinstance(initial, Mapping):
            raise TypeError(
                "`initial` must be a mapping of parameter names to start values or an "
                f"lmfit.Parameters; got {type(initial).__name__}."
            )
        init = {n: as_real_scalar(f"initial[{n!r}]", v) for n, v in initial.items()}
    if not isinstance(fix, dict) or not isinstance(tie, dict) or not isinstance(bnd, dict):
        return init, bnd, fix, tie  # the solver's checker names the wrong type
    for n, v in (explicit or {}).items():
        if v is not None and n in fix and float(fix[n]) != float(v):
            raise _contradiction(n, v, f"fixed[{n!r}]", fix[n])
    for n in set(fix) & set(tie):
        raise _contradiction(f"fixed[{n!r}]", fix[n], f"tied[{n!r}]", tie[n])
    for n, v in init.items():
        if n in fix and float(fix[n]) != v:
            raise _contradiction(f"initial[{n!r}]", v, f"fixed[{n!r}]", fix[n])
        if n in tie:
            raise _contradiction(f"initial[{n!r}]", v, f"tied[{n!r}]", tie[n])
    for n, pair in bnd.items():
        if not isinstance(pair, (tuple, list)) or len(pair) != 2:
            continue  # as_bounds names the malformed pair
        lo, hi = (float(x) for x in pair)
        for label, src in (("fixed", fix), ("initial", init)):
            if n in src and not lo <= float(src[n]) <= hi:
                raise _contradiction(f"{label}[{n!r}]", src[n], f"bounds[{n!r}]", (lo, hi))
    return init, bnd, fix, tie


def check_flag(name: str, value: Any) -> bool:
    """`value` is a bool (numpy's included): a string such as "no" is refused, not truthy."""
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"`{name}` must be True or False; got {type(value).__name__} {fmt(value)}.")
    return bool(value)


def check_sides(asymmetric: Any, offset: Any) -> bool:
    """`asymmetric` a bool, and not with an `offset`: the difference of the two directions'
    levels is a constant force (`_model_spec`); returns `asymmetric`."""
    sided = check_flag("asymmetric", asymmetric)
    if sided and offset:
        raise ValueError(
            "`offset` must be False with `asymmetric`=True: a constant force is the difference "
            "of the two directions' levels, (F_c⁺ − F_c⁻)/2 (the fit carries it in "
            "coulomb_level_negative); got offset=True."
        )
    return sided


def check_levels(coulomb_level: Any, min_coulomb_level: Any, fixed: Mapping[str, Any]) -> None:
    """`min_coulomb_level` must not exceed a Coulomb level given by `coulomb_level` or `fixed`."""
    if min_coulomb_level is None:
        return
    for label, level in (("coulomb_level", coulomb_level),
                         ("fixed['coulomb_level']", fixed.get("coulomb_level"))):  # fmt: skip
        if level is not None and float(level) < float(min_coulomb_level):
            raise _contradiction(label, level, "min_coulomb_level", min_coulomb_level)


_ELEMENT = re.compile(r"^(stiffness|breakaway)_(\d+)$")


def kept_parameters(given: Mapping[str, Any], n_elements: int) -> dict[str, dict]:
    """The user's `fixed`, `tied` and `bounds` for a refit with `n_elements` (prune=True).

    Entries of elements the refit no longer has (index above `n_elements`) are
    left out; every other entry is kept as given.
    """

    def kept(name: str) -> bool:
        m = _ELEMENT.match(name)
        return m is None or int(m.group(2)) <= n_elements

    out = {}
    for label in ("fixed", "tied", "bounds"):
        out[label] = {n: v for n, v in given.get(label, {}).items() if kept(n)}
    out["tied"] = {n: v for n, v in out["tied"].items() if kept(v if isinstance(v, str) else v[0])}
    return out
