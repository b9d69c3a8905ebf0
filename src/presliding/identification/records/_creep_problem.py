"""The pooled quasi-static problem with creep: PI friction in series with a Kelvin–Voigt element.

Each record's position is that of `QuasiStaticProblem` (the exact inverse of the
PI model, `_quasi_static_kernel`) plus the creep deflection y_c of
τ·ẏ_c + y_c = J·(u − offset) (`presliding.friction.CreepingFriction`), which
starts at rest with the record's first force and is integrated exactly with u
linear between samples (`presliding.friction.creep.creep_deflections`, every
record and parameter set in one compiled call). The shared parameters add
``creep_compliance`` J >= 0 [m/N] and ``creep_time`` τ >= 0 [s]; with J = 0 the
residual is the PI model's, bit for bit.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from presliding.friction.creep import creep_deflections
from presliding.identification.problem._model_spec import ModelSpec
from presliding.identification.records._pooled_record import Record
from presliding.identification.records._quasi_static_problem import QuasiStaticProblem

FloatArray = NDArray[np.float64]
CREEP = ("creep_compliance", "creep_time")


class CreepQuasiStaticProblem(QuasiStaticProblem):
    """Residual of a pooled quasi-static fit with creep (module notes)."""

    def subset(self, records: list[Record], suffix: bool = True) -> CreepQuasiStaticProblem:
        """The same problem on other records."""
        return CreepQuasiStaticProblem(records, self.spec, self.initial_state,
                                       offset="offset" in self.shared, suffix=suffix)  # fmt: skip

    @staticmethod
    def shared_names(spec: ModelSpec, offset: bool, viscous: bool) -> list[str]:
        return [*spec.names, *CREEP] + (["offset"] if offset else [])

    def simulate(self, sets: FloatArray, rigid: bool = False) -> tuple:
        """`QuasiStaticProblem.simulate` plus each record's creep deflection."""
        sets = np.atleast_2d(sets)
        o_y, o_v, status, n_rev = super().simulate(sets, rigid)
        col = self.index
        compliance = np.ascontiguousarray(np.maximum(sets[:, col["creep_compliance"]], 0.0))
        tau = np.ascontiguousarray(np.maximum(sets[:, col["creep_time"]], 0.0))
        offset = sets[:, col["offset"]] if "offset" in col else np.zeros(sets.shape[0])
        start = np.full((sets.shape[0], self.n_rec), np.nan)
        creep_deflections(compliance, tau, np.ascontiguousarray(offset), start, self.u_all,
                          self.t_all, self.t_off, o_y)  # fmt: skip
        return o_y, o_v, status, n_rev
