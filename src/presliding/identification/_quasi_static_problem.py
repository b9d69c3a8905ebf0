"""The pooled quasi-static problem: positions of every record from its applied force.

Each record i follows y = Γ[u − offset] from a memory with elastic force
preload_fraction_i·F_m at initial_position_i, on the branch opposite to the
record's first motion (`preloaded_state`; the record starts with a reversal at
its preload), or (``"continuing"``) from saturation opposite to its first
motion, which the record continues (any memory whose last branch the first
motion continues gives the same positions up to a shift, so no preload is
fitted then): the exact quasi-static inverse of the friction
model with c1 (`presliding.hysteresis.PIInverse`), run by compiled stop sums,
one record after another (no Python work per sample). The residual layout,
the structured Jacobian and the trust box are those of `PooledProblem`.

A parameter set whose F_c is not above every |u − offset| has no quasi-static
response: its residual is inf, so the solver rejects it.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from presliding.friction.preload import preload_deformation
from presliding.hysteresis.inverse import PIInverse
from presliding.hysteresis.operators import PIOperator, PIState
from presliding.identification._model_spec import TINY, ModelSpec
from presliding.identification._pooled_problem import PooledProblem, Record

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
        """Positions (P, S), zero velocities, status (−2: |u| >= F_c) and zero reversal counts."""
        sets = np.atleast_2d(sets)
        n_par, n_s = sets.shape[0], self.t_all.shape[0]
        o_y = np.zeros((n_par, n_s))
        status = np.zeros((n_par, self.n_rec), dtype=np.int64)
        col = self.index
        for p in range(n_par):
            q = dict(zip(self.names, sets[p], strict=True))
            c1, k, r = self.spec.bank(q)
            if rigid:
                c1, k, r = c1 + k[0] * r[0], k[1:], r[1:]
            keep = k > TINY
            k, r = k[keep], np.minimum(r[keep], 1e300)
            offset = q["offset"] if "offset" in col else 0.0
            if k.shape[0] == 0 or not c1 + float(k @ r) > 0:
                status[p] = -2
                continue
            inverse = PIInverse(PIOperator(r, k), coulomb=c1)
            for i, rec in enumerate(self.records):
                a, b = self.t_off[i], self.t_off[i + 1]
                u = rec.applied_force - offset
                if not np.max(np.abs(u)) < inverse.force_limit:
                    status[p, i] = -2
                    continue
                y0 = q[self.nuisance("initial_position", i)]
                f = np.zeros(k.shape[0])
                d = self.direction[i]
                if self.initial_state == "preload":
                    frac = min(max(q[self.nuisance("preload_fraction", i)], -1.0), 1.0)
                    preload_deformation(k, r, frac, d, True, f)
                elif self.initial_state == "continuing":  # saturated, then moving on
                    f[:] = -d * r
                state = PIState(y0, y0 - f, d)
                o_y[p, a:b] = inverse.apply(u, state)[0]
        return o_y, np.zeros_like(o_y), status, np.zeros_like(status)
