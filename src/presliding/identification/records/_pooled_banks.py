"""The banks (c1, k_j, r_j) of many parameter sets of a pooled fit, as kernel arrays;
an asymmetric model's negative side (c1⁻, r_j⁻: ρ times the positive one, `ModelSpec`)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from presliding.identification.problem._model_spec import TINY, ModelSpec

FloatArray = NDArray[np.float64]


def element_banks(spec: ModelSpec, index: dict[str, int],
                  sets: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:  # fmt: skip
    """c1, k_j and r_j of every parameter set of an element model (as `ModelSpec.bank`)."""
    c1 = np.maximum(sets[:, index["coulomb"]], 0.0)
    k = np.maximum(sets[:, [index[x] for x in spec.k_names]], TINY)
    if spec.equal:
        each = np.maximum((sets[:, index["coulomb_level"]] - c1) / spec.n, TINY)
        c = np.repeat(each[:, None], spec.n, axis=1)
    else:
        c = np.maximum(sets[:, [index[x] for x in spec.c_names]], TINY)
    with np.errstate(over="ignore"):
        r = np.minimum(c / k, 1e300)
    return c1, k, r


def banks_one_by_one(spec: ModelSpec, names: Sequence[str], sets: FloatArray,
                     rigid: bool) -> tuple[FloatArray, FloatArray, FloatArray]:  # fmt: skip
    """c1, k_j and r_j of every parameter set (densities, no elements), padded to one width."""
    n_par = sets.shape[0]
    banks = []
    for p in range(n_par):
        c1, k, r = spec.bank(dict(zip(names, sets[p], strict=True)))
        if rigid:  # element 1 rigid-plastic (k_1 → ∞): its c_1 joins c1
            c1, k, r = c1 + k[0] * r[0], k[1:], r[1:]
        banks.append((c1, k, r))
    n_el = max(b[1].shape[0] for b in banks)
    k_arr = np.zeros((n_par, n_el))
    r_arr = np.ones((n_par, n_el))
    for p, (_, k, r) in enumerate(banks):
        k_arr[p, : k.shape[0]], r_arr[p, : r.shape[0]] = k, r
        r_arr[p, k.shape[0] :] = np.max(r) if r.shape[0] else 1.0
    return np.array([b[0] for b in banks]), k_arr, r_arr


def negative_sides(spec: ModelSpec, index: dict[str, int], sets: FloatArray, c1: FloatArray,
                   k: FloatArray, r: FloatArray) -> FloatArray | None:  # fmt: skip
    """ρ = F_c⁻/F_c⁺ of every parameter set of an asymmetric element model (`ModelSpec.ratio`),
    from its unrigid bank; None for one side. Without elements: c1⁻ itself."""
    if spec.negative is None:
        return None
    below = sets[:, index[spec.negative]]
    if spec.n == 0:
        return np.maximum(below, 0.0)
    if spec.equal:
        fc = sets[:, index["coulomb_level"]]
    else:  # as `ModelSpec.coulomb_level` rounds it (ρ = 1 exactly for equal sides)
        fc = np.array([c1[p] + float(k[p] @ r[p]) for p in range(sets.shape[0])])
    return np.maximum(below, TINY) / np.maximum(fc, TINY)


def sided_arrays(spec: ModelSpec, index: dict[str, int], sets: FloatArray, c1: FloatArray,
                 r: FloatArray, rho: FloatArray | None) -> tuple[FloatArray, ...]:  # fmt: skip
    """(c1⁻, r⁻) for the kernel: ρ·c1 and ρ·r (`negative_sides`' ρ of an element model),
    c1⁻ itself without elements, or c1 and r themselves for one side."""
    if rho is not None:
        return rho * c1, np.ascontiguousarray(rho[:, None] * r)
    alone = negative_sides(spec, index, sets, c1, r, r)  # no elements: c1⁻ (None: one side)
    return (c1 if alone is None else alone), r
