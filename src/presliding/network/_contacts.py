"""The contacts' constant data, gathered once at the start of a run (both paths)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


@dataclass
class Contacts:
    """The contacts' constant data: Coulomb c1, viscous σ_v, elements (flattened)."""

    c1: FloatArray
    sigma: FloatArray
    k: FloatArray  # element stiffnesses, all contacts one after the other
    r: FloatArray  # thresholds
    owner: NDArray[np.int64]  # the contact of each element
    start: NDArray[np.int64]  # offsets: the elements of contact c are start[c]:start[c+1]

    @classmethod
    def of(cls, models: Any) -> Contacts:
        ks = [np.asarray(m.stiffness, dtype=float) for m in models]
        rs = [np.asarray(m.threshold, dtype=float) for m in models]
        sizes = np.array([k.shape[0] for k in ks], dtype=np.int64)
        return cls(
            c1=np.array([m.coulomb for m in models]),
            sigma=np.array([m.viscous for m in models]),
            k=np.concatenate(ks) if ks else np.empty(0),
            r=np.concatenate(rs) if rs else np.empty(0),
            owner=np.repeat(np.arange(len(models), dtype=np.int64), sizes),
            start=np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64),
        )

    def per_contact(self, values: FloatArray) -> FloatArray:
        """Σ of element values over each contact's elements (last axis)."""
        n_e = values.shape[-1]
        if n_e == 0:
            return np.zeros((*values.shape[:-1], self.c1.shape[0]))
        lo = self.start[:-1]
        empty = lo == self.start[1:]
        padded = np.concatenate([values, np.zeros((*values.shape[:-1], 1))], axis=-1)
        out = np.add.reduceat(padded, lo, axis=-1)  # a contact's elements lo[c]:lo[c+1]
        out[..., empty] = 0.0
        return out
