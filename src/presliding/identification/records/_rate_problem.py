"""The pooled output-error problem of a rate-dependent family (GMS, LuGre, Dahl).

The records, parameter names, residual layout, difference quotients, structured
Jacobian and trust box are those of `PooledProblem` (the shared parameters are
``mass``, the family's (`_family_spec.FamilySpec`), ``viscous`` and ``offset``
when asked; each record its initial position, velocity and, with a preload, its
``preload_fraction``); only the simulation differs: every record and parameter
set in one compiled call of the implicit step (`_rate_kernel`), ``substeps``
steps per sample interval.
"""

from __future__ import annotations

from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from presliding.identification.problem._family_spec import FamilySpec
from presliding.identification.problem._model_spec import TINY
from presliding.identification.records import _rate_kernel as rk
from presliding.identification.records._pooled_problem import PooledProblem
from presliding.identification.records._pooled_record import Record

FloatArray = NDArray[np.float64]


class RateProblem(PooledProblem):
    """Residual of a pooled fit of a rate-dependent family (module notes)."""

    #: the PI model's siblings are not this family's: a failed residual test names no cause
    names_causes = False

    def __init__(self, records: list[Record], spec: FamilySpec,
                 signal_weights: tuple[float, float], initial_state: str, *, offset: bool,
                 suffix: bool, viscous: bool = False, velocity: str = "auto",
                 substeps: int = 4):  # fmt: skip
        self.substeps, self.family = substeps, spec
        # the family's spec stands in for a `ModelSpec`: names, bounds, model, bank
        super().__init__(records, cast(Any, spec), signal_weights, initial_state, offset=offset,
                         suffix=suffix, viscous=viscous, velocity=velocity)  # fmt: skip
        self.u_all = np.ascontiguousarray(np.concatenate([r.applied_force for r in records]))
        self.rate_mode = np.full(self.n_rec, rk.RELAXED if initial_state == "relaxed"
                                 else rk.BRANCH, dtype=np.int64)  # fmt: skip

    def subset(self, records: list[Record], suffix: bool = True) -> RateProblem:
        """The same problem (family, weights, memory, offset, σ, steps) on other records."""
        return RateProblem(records, self.family, (self.w_v, self.w_y), self.initial_state,
                           offset="offset" in self.shared, suffix=suffix,
                           viscous="viscous" in self.shared, velocity=self.velocity,
                           substeps=self.substeps)  # fmt: skip

    def free_jacobian(self, rigid: bool = False, sparse_output: bool | None = None):
        """`PooledProblem.free_jacobian` by forward differences from the residual just
        evaluated (half the simulations of central ones: the implicit step is smooth in the
        parameters between its stick decisions, and its simulations cost the most)."""
        return super().free_jacobian(rigid, True if sparse_output is None else sparse_output)

    def kernel_arrays(self, sets: FloatArray) -> tuple:
        """(par, k, c, mass, offset) of the parameter sets (rows of full vectors)."""
        n_par = sets.shape[0]
        n_z = self.family.n if self.family.family == "gms" else 1
        par = np.zeros((n_par, 6))
        k, c = np.ones((n_par, n_z)), np.ones((n_par, n_z))
        for p in range(n_par):
            q = dict(zip(self.names, sets[p].tolist(), strict=True))
            par[p], kp, cp = self.family.pack(q)
            if kp.shape[0]:
                k[p], c[p] = kp, cp
        col = self.index
        mass = np.maximum(sets[:, col["mass"]], TINY)
        offset = sets[:, col["offset"]] if "offset" in col else np.zeros(n_par)
        return par, k, c, mass, np.ascontiguousarray(offset)

    def simulate(self, sets: FloatArray, rigid: bool = False) -> tuple:
        """Positions, velocities as measured (P, S), status and (no) reversal counts (P, R)."""
        sets = np.atleast_2d(sets)
        par, k, c, mass, offset = self.kernel_arrays(sets)
        n_par, n_s = sets.shape[0], self.t_all.shape[0]
        per = len(self.shared) + np.arange(self.n_rec) * len(self.kinds)
        y0 = np.ascontiguousarray(sets[:, per])
        v0 = np.ascontiguousarray(sets[:, per + 1])
        if self.initial_state == "preload":
            frac = np.clip(sets[:, per + 2], -1.0, 1.0)
        else:
            frac = np.repeat(self.direction[None, :], n_par, axis=0)
        o_y, o_v = np.empty((n_par, n_s)), np.empty((n_par, n_s))
        status = np.zeros((n_par, self.n_rec), dtype=np.int64)
        rk.rate_responses(
            self.family.code, par, k, c, mass, offset, y0, v0, np.ascontiguousarray(frac),
            self.rate_mode, self.direction, self.t_all, self.t_off, self.u_all, self.substeps,
            o_y, o_v, status,
        )  # fmt: skip
        self.as_measured(o_y, o_v)
        return o_y, o_v, status, np.zeros_like(status)
