"""The free/fixed/tied split of named parameters: full = T·free + const.

Parameters may be held *fixed* at a value or *tied* to another one
(p = factor·q + offset); only the remaining *free* parameters are varied.
`parameter_map` resolves the ties (chains included, cycles refused) into the
matrix T and the constant, `free_bounds` carries each parameter's bounds over
to the free parameter it moves alone, and `tie_triples` writes each tie as
(target, factor, offset) for the result.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from presliding._validation import fmt

FloatArray = NDArray[np.float64]
Tie = str | tuple[str, float] | tuple[str, float, float]

__all__ = ["ParameterMap", "free_bounds", "parameter_map", "tie_triples"]


@dataclass(frozen=True)
class ParameterMap:
    """full = T @ free + const, for the free/fixed/tied split of named parameters."""

    names: tuple[str, ...]
    free: tuple[str, ...]
    matrix: FloatArray
    const: FloatArray

    def full(self, free: FloatArray) -> FloatArray:
        return self.matrix @ free + self.const


def _check_names(names: tuple[str, ...], fixed: Mapping, tied: Mapping) -> None:
    for label, spec in (("fixed", fixed), ("tied", tied)):
        for n in spec:
            if n not in names:
                raise ValueError(
                    f"`{label}` must name parameters of the fit ({fmt(list(names))}); got {n!r}."
                )
    both = set(fixed) & set(tied)
    if both:
        raise ValueError(f"a parameter cannot be both fixed and tied; got {sorted(both)}.")


def _triple(spec: Tie) -> tuple[str, float, float]:
    target, factor, shift = (spec, 1.0, 0.0) if isinstance(spec, str) else (*spec, 0.0)[:3]
    return target, factor, shift


def parameter_map(
    names: tuple[str, ...],
    fixed: Mapping[str, float],
    tied: Mapping[str, Tie],
) -> ParameterMap:
    """The map of `names` with `fixed` values and `tied` parameters (checked)."""
    _check_names(names, fixed, tied)
    free = tuple(n for n in names if n not in fixed and n not in tied)
    col = {n: i for i, n in enumerate(free)}
    matrix = np.zeros((len(names), len(free)))
    const = np.zeros(len(names))

    def resolve(n: str, seen: tuple[str, ...]) -> tuple[FloatArray, float]:
        if n in seen:
            raise ValueError(f"`tied` must not form a cycle; got {' -> '.join((*seen, n))}.")
        if n in fixed:
            return np.zeros(len(free)), float(fixed[n])
        if n not in tied:
            row: FloatArray = np.zeros(len(free))
            row[col[n]] = 1.0
            return row, 0.0
        target, factor, shift = _triple(tied[n])
        if target not in names:
            raise ValueError(f"`tied` target of {n!r} must be a parameter; got {target!r}.")
        row, c = resolve(target, (*seen, n))
        return float(factor) * row, float(factor) * c + float(shift)

    for i, n in enumerate(names):
        matrix[i], const[i] = resolve(n, ())
    return ParameterMap(names, free, matrix, const)


def free_bounds(
    pm: ParameterMap, lower: FloatArray, upper: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Bounds on the free parameters implied by the bounds of every parameter."""
    lo = np.full(len(pm.free), -np.inf)
    hi = np.full(len(pm.free), np.inf)
    for i in range(len(pm.names)):
        row = pm.matrix[i]
        nz = np.flatnonzero(row)
        if nz.size != 1:
            continue
        j, f = int(nz[0]), row[nz[0]]
        a, b = (lower[i] - pm.const[i]) / f, (upper[i] - pm.const[i]) / f
        lo[j], hi[j] = max(lo[j], min(a, b)), min(hi[j], max(a, b))
    return lo, hi


def tie_triples(tied: Mapping[str, Tie]) -> dict[str, tuple[str, float, float]]:
    """Each tie as (target, factor, offset): p = factor·target + offset."""
    out = {}
    for n, spec in tied.items():
        target, factor, shift = _triple(spec)
        out[n] = (str(target), float(factor), float(shift))
    return out
