"""The pooled quasi-static problem: positions of every record from its applied force.

Each record i follows y = Γ[u − offset] from a memory with elastic force
preload_fraction_i·F_m at initial_position_i, on the branch opposite to the
record's first motion (`preloaded_state`; the record starts with a reversal at
its preload), or (``"continuing"``) from saturation opposite to its first
motion, which the record continues (any memory whose last branch the first
motion continues gives the same positions up to a shift, so no preload is
fitted then): the exact quasi-static inverse of the friction
model with c1 (as `presliding.hysteresis.PIInverse`), every record and parameter
set in one compiled call (`_quasi_static_kernel`). The residual layout,
the structured Jacobian and the trust box are those of `PooledProblem`.

A parameter set whose F_c is not above every |u − offset| has no quasi-static
response: its residual is inf, so the solver rejects it (an asymmetric model: F_c⁺
above every u, F_c⁻ above every −u).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from presliding.identification.problem._model_spec import TINY, ModelSpec
from presliding.identification.records import _quasi_static_kernel as qk
from presliding.identification.records._pooled_problem import PooledProblem
from presliding.identification.records._pooled_record import Record

FloatArray = NDArray[np.float64]


def first_direction(u: FloatArray, y: FloatArray) -> float:
    """Direction of a record's first motion: where the position first leaves its start
    by more than its noise and quantum (`reversal_tolerance`), else the force's."""
    from presliding.identification.prediction import reversal_tolerance

    for sig, tol in ((y, reversal_tolerance(y)), (u, 1e-3 * float(np.ptp(u)))):
        big = np.flatnonzero(np.abs(sig - sig[0]) > tol)
        if big.size:
            return float(np.sign(sig[big[0]] - sig[0]))
    return 1.0


class QuasiStaticProblem(PooledProblem):
    """Residual of a pooled quasi-static fit (module notes); position only."""

    def __init__(self, records: list[Record], spec: ModelSpec, initial_state: str, *,
                 offset: bool, suffix: bool):  # fmt: skip
        super().__init__(records, spec, (0.0, 1.0), initial_state, offset=offset, suffix=suffix)
        # the memory's branch runs opposite to the record's first motion: the record
        # starts with a reversal at its preload (a memory whose branch the first motion
        # continued would depend on the preload and the position only through the
        # position of its turning point, and the two could not be told apart)
        self.direction = -np.array([first_direction(r.applied_force, r.position) for r in records])
        self.u_max = max(float(np.max(np.abs(r.applied_force))) for r in records)
        #: the largest applied force in +y and in −y (the floors of F_c⁺ and F_c⁻)
        self.u_sides = (max(float(np.max(r.applied_force)) for r in records),
                        max(float(np.max(-r.applied_force)) for r in records))  # fmt: skip
        self.u_all = np.ascontiguousarray(np.concatenate([r.applied_force for r in records]))
        modes = {"preload": qk.PRELOAD, "continuing": qk.CONTINUING, "relaxed": qk.RELAXED}
        self.qs_mode = np.full(self.n_rec, modes[initial_state], dtype=np.int64)

    def subset(self, records: list[Record], suffix: bool = True) -> QuasiStaticProblem:
        """The same problem on other records."""
        return QuasiStaticProblem(records, self.spec, self.initial_state,
                                  offset="offset" in self.shared, suffix=suffix)  # fmt: skip

    @staticmethod
    def shared_names(spec: ModelSpec, offset: bool, viscous: bool) -> list[str]:
        return [*spec.names] + (["offset"] if offset else [])

    @staticmethod
    def nuisance_kinds(initial_state: str) -> list[str]:
        return ["initial_position"] + (["preload_fraction"] if initial_state == "preload" else [])

    def simulate(self, sets: FloatArray, rigid: bool = False) -> tuple:
        """Positions (P, S), zero velocities, status (−2: |u| >= F_c) and zero reversal counts.

        All parameter sets and records in one compiled call (`_quasi_static_kernel`).
        """
        sets = np.atleast_2d(sets)
        n_par, n_s = sets.shape[0], self.t_all.shape[0]
        banks, ratios = [], np.ones(n_par)
        for p in range(n_par):
            q = dict(zip(self.names, sets[p], strict=True))
            c1, k, r = self.spec.bank(q)
            ratios[p] = self.spec.ratio(q)  # F_c⁻/F_c⁺ (1: one side)
            if rigid:
                c1, k, r = c1 + k[0] * r[0], k[1:], r[1:]
            keep = k > TINY
            banks.append((c1, k[keep], np.minimum(r[keep], 1e300)))
        n_el = max(1, max(b[1].shape[0] for b in banks))
        k_arr, r_arr = np.zeros((n_par, n_el)), np.ones((n_par, n_el))
        for p, (_, k, r) in enumerate(banks):
            k_arr[p, : k.shape[0]], r_arr[p, : r.shape[0]] = k, r
        c1_all = np.array([b[0] for b in banks])
        c1n, rn = c1_all, r_arr  # one side: the same arrays
        if self.spec.negative is not None:
            c1n, rn = ratios * c1_all, np.ascontiguousarray(ratios[:, None] * r_arr)
        col = self.index
        offset = sets[:, col["offset"]] if "offset" in col else np.zeros(n_par)
        per = len(self.shared) + np.arange(self.n_rec) * len(self.kinds)
        y0 = np.ascontiguousarray(sets[:, per])
        if self.initial_state == "preload":
            frac = np.ascontiguousarray(np.clip(sets[:, per + 1], -1.0, 1.0))
        else:
            frac = np.zeros((n_par, self.n_rec))
        o_y = np.zeros((n_par, n_s))
        status = np.zeros((n_par, self.n_rec), dtype=np.int64)
        qk.quasi_static_positions(c1_all, c1n, k_arr, r_arr, rn, offset, y0, frac, self.qs_mode,
                                  self.direction, self.u_all, self.t_off, o_y, status)  # fmt: skip
        empty = np.array([b[1].shape[0] == 0 or not b[0] + float(b[1] @ b[2]) > 0 for b in banks])
        status[empty] = qk.NO_RESPONSE
        return o_y, np.zeros_like(o_y), status, np.zeros_like(status)
