"""The pooled output-error problem: records packed for one compiled call, residual, Jacobian.

Parameters are named. Shared across records: ``mass``, the friction model's
parameters (`ModelSpec`), ``viscous`` σ [N·s/m] (and σ⁻ ``viscous_negative`` of
an asymmetric model) and the force ``offset`` when asked.
Per record i (suffix ``_i`` from 1, none for a single `Measurement`):
``initial_position``, ``initial_velocity`` and, with a preload,
``preload_fraction`` (the initial elastic force over F_m).

The residual of record i is w_v·(v_sim − v) and/or w_y·(y_sim − y); records
are stacked in order, each record's velocity block before its position block.

A record's velocity may be compared through the difference quotient of the
simulated position (`_pooled_record`).

Jacobian: finite differences exploiting the structure. A free parameter that
moves only per-record parameters touches only those records' rows, so the
columns of different records are perturbed together (one group per kind of
per-record parameter, plus one per shared parameter), central differences
(one-sided at a bound), all groups simulated in one call of
`_pooled_kernel.pooled_responses`. With R records of three nuisance parameters
and p shared ones, a Jacobian costs 2·(p + 3) record sets instead of 2·(p + 3R).
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding.identification.intervals._covariance import Link
from presliding.identification.problem._model_spec import TINY, ModelSpec
from presliding.identification.records import _pooled_jacobian as pj
from presliding.identification.records import _pooled_kernel as pk
from presliding.identification.records._pooled_banks import (
    banks_one_by_one,
    element_banks,
    negative_sides,
    sided_arrays,
)
from presliding.identification.records._pooled_record import Record, difference_matrix
from presliding.identification.solve._least_squares import _Map
from presliding.motion._forcing import as_forcing

FloatArray = NDArray[np.float64]
MAX_EVENTS = 10_000_000
NUISANCE = ("initial_position", "initial_velocity", "preload_fraction")
MODES = {"relaxed": pk.RELAXED, "saturated": pk.BRANCH, "preload": pk.BRANCH,
         "continuing": pk.BRANCH}  # fmt: skip


class PooledProblem:
    """Residual and structured Jacobian of a pooled output-error fit (module notes)."""

    #: the residual tests may try this model's siblings (more elements, an asymmetry, a
    #: viscous term) to name a failed test's likely cause (`_residual_blocks.candidates`)
    names_causes: bool = True

    def __init__(
        self,
        records: list[Record],
        spec: ModelSpec,
        signal_weights: tuple[float, float],
        initial_state: str,
        *,
        offset: bool,
        suffix: bool,
        viscous: bool = False,
        velocity: str = "auto",
    ):
        self.records, self.spec = records, spec
        self.velocity = velocity  # how held-out records' velocities are read (`as_record`)
        self.exact_velocity = False  # True: the exact velocity compared (`exact_velocity_compared`)
        self._last: tuple | None = None  # the last residual evaluated (`residual`)
        self._links: list[Link] | None = None  # (`links`)
        self._columns: dict[tuple, tuple] = {}  # a parameter map's columns (`free_jacobian`)
        self.w_v, self.w_y = signal_weights
        self.initial_state = initial_state
        self.n_rec = len(records)
        lengths = [r.time.shape[0] for r in records]
        self.t_off = np.concatenate([[0], np.cumsum(lengths)]).astype(np.int64)
        self.t_all = np.ascontiguousarray(np.concatenate([r.time for r in records]))
        pieces = []
        for r in records:
            t0 = float(r.time[0])
            pieces.append(as_forcing((r.time, r.applied_force), "zoh", t0).pieces(t0, r.time[-1]))
        self.u_off = np.concatenate([[0], np.cumsum([p[0].shape[0] for p in pieces])]).astype(
            np.int64
        )
        self.ut_all = np.ascontiguousarray(np.concatenate([p[0] for p in pieces]))
        self.uv_all = np.ascontiguousarray(np.concatenate([p[1] for p in pieces]))
        self.mode = np.full(self.n_rec, MODES[initial_state], dtype=np.int64)
        self.direction = np.array([r.direction for r in records])
        self.shared = self.shared_names(spec, offset, viscous)
        kinds = self.nuisance_kinds(initial_state)
        self.kinds = kinds
        self.record_of: dict[str, int | None] = dict.fromkeys(self.shared)
        self.names = list(self.shared)
        for i in range(self.n_rec):
            for kind in kinds:
                name = f"{kind}_{i + 1}" if suffix else kind
                self.names.append(name)
                self.record_of[name] = i
        self.index = {x: j for j, x in enumerate(self.names)}
        self.rows = self._row_blocks()
        self.n_res = int(self.rows[-1][1].stop) if self.rows else 0
        self._layout()
        self._plan_quotients()
        self.data = self._residual_of(
            np.concatenate([r.position for r in records])[None],
            np.concatenate([r.velocity for r in records])[None],
            measured=True,
        )[0]

    def subset(self, records: list[Record], suffix: bool = True) -> PooledProblem:
        """The same problem (model, weights, memory, offset, σ) on other records."""
        return PooledProblem(records, self.spec, (self.w_v, self.w_y), self.initial_state,
                             offset="offset" in self.shared, suffix=suffix,
                             viscous="viscous" in self.shared,
                             velocity=self.velocity)  # fmt: skip

    # ------------------------------------------------------------ layout
    @staticmethod
    def shared_names(spec: ModelSpec, offset: bool, viscous: bool) -> list[str]:
        """The parameters every record shares."""
        sigma = ["viscous", "viscous_negative"][: 2 if spec.negative else 1] if viscous else []
        return ["mass", *spec.names] + sigma + (["offset"] if offset else [])

    @staticmethod
    def nuisance_kinds(initial_state: str) -> list[str]:
        """The kinds of parameters each record has of its own."""
        kinds = ["initial_position", "initial_velocity"]
        return kinds + (["preload_fraction"] if initial_state == "preload" else [])

    @property
    def equal(self) -> bool:
        """Equal break-away forces (elements)."""
        return self.spec.equal and self.spec.density is None

    @property
    def k_names(self) -> list[str]:
        return self.spec.k_names

    @property
    def c_names(self) -> list[str]:
        return self.spec.c_names

    def nuisance(self, kind: str, i: int) -> str:
        """The name of record i's parameter of `kind`."""
        return self.names[len(self.shared) + i * len(self.kinds) + self.kinds.index(kind)]

    def _row_blocks(self) -> list[tuple[int, slice]]:
        """(record, rows) of every residual block, velocity before position."""
        out, start = [], 0
        for i in range(self.n_rec):
            n = int(self.t_off[i + 1] - self.t_off[i])
            for w in (self.w_v, self.w_y):
                if w:
                    out.append((i, slice(start, start + n)))
                    start += n
        return out

    @property
    def links(self) -> list[Link]:
        """The velocity blocks that are the difference quotient of their record's position
        block (both compared), for the covariance (`_covariance.Link`)."""
        if not (self.w_v and self.w_y) or self.exact_velocity:
            return []
        if self._links is None:  # made once: they depend on the records' times alone
            self._links = []
            for i, rec in enumerate(self.records):
                if rec.difference:
                    (_, vel), (_, pos) = [b for b in self.rows if b[0] == i]
                    self._links.append(Link(vel, pos, difference_matrix(rec.time, rec.difference),
                                            self.w_v / self.w_y))  # fmt: skip
        return list(self._links)

    def record_rows(self, i: int) -> NDArray[np.intp]:
        """Residual rows of record i."""
        return self._record_rows[i]

    def _layout(self) -> None:
        """Sample index, signal weights and record rows of every residual row."""
        idx, wv, wy = [], [], []
        for i in range(self.n_rec):
            samples = np.arange(self.t_off[i], self.t_off[i + 1])
            for w, is_v in ((self.w_v, True), (self.w_y, False)):
                if w:
                    idx.append(samples)
                    wv.append(np.full(samples.shape[0], w if is_v else 0.0))
                    wy.append(np.full(samples.shape[0], 0.0 if is_v else w))
        self._idx = np.concatenate(idx)
        self._wv, self._wy = np.concatenate(wv), np.concatenate(wy)
        rows: dict[int, list] = {i: [] for i in range(self.n_rec)}
        for i, block in self.rows:
            rows[i].append(np.arange(block.start, block.stop))
        self._record_rows = {i: np.concatenate(r) for i, r in rows.items()}

    def _residual_of(self, o_y: FloatArray, o_v: FloatArray, measured: bool = False) -> FloatArray:
        """Weighted stacked signals (measured) or signals minus data, per parameter set."""
        out = np.empty((o_y.shape[0], self._idx.shape[0]))
        data = np.zeros(self._idx.shape[0]) if measured else self.data
        pk.assemble(o_y, o_v, self._idx, self._wv, self._wy, data, out)
        return out

    # ------------------------------------------------------------ simulation
    def unpack(self, sets: FloatArray, rigid: bool = False) -> tuple:
        """Kernel arrays for parameter sets (rows of full parameter vectors), both sides."""
        n_par = sets.shape[0]
        col = self.index
        rho = None
        if self.spec.density is None and self.spec.n > 0:  # elements: all sets at once
            c1_all, k_arr, r_arr = element_banks(self.spec, self.index, sets)
            rho = negative_sides(self.spec, self.index, sets, c1_all, k_arr, r_arr)
            if rigid:  # element 1 rigid-plastic (k_1 → ∞): its c_1 joins c1
                c1_all = c1_all + k_arr[:, 0] * r_arr[:, 0]
                k_arr, r_arr = k_arr[:, 1:], r_arr[:, 1:]
            k_arr, r_arr = np.ascontiguousarray(k_arr), np.ascontiguousarray(r_arr)
        else:
            c1_all, k_arr, r_arr = banks_one_by_one(self.spec, self.names, sets, rigid)
        c1n, rn = sided_arrays(self.spec, self.index, sets, c1_all, r_arr, rho)
        mass = np.maximum(sets[:, col["mass"]], TINY)
        offset = sets[:, col["offset"]] if "offset" in col else np.zeros(n_par)
        sigma = np.maximum(sets[:, col["viscous"]], 0.0) if "viscous" in col else np.zeros(n_par)
        sigman = np.maximum(sets[:, col["viscous_negative"]], 0.0) if "viscous_negative" in col \
            else sigma  # fmt: skip
        per = len(self.shared) + np.arange(self.n_rec) * len(self.kinds)
        y0 = np.ascontiguousarray(sets[:, per])
        v0 = np.ascontiguousarray(sets[:, per + 1])
        if self.initial_state == "preload":
            frac = np.clip(sets[:, per + 2], -1.0, 1.0)
        else:  # saturated: steady sliding in the direction of the first motion, F_el = d·F_m
            frac = np.repeat(self.direction[None, :], n_par, axis=0)
        return (mass, c1_all, c1n, sigma, sigman, k_arr, r_arr, rn, offset, y0, v0,
                np.ascontiguousarray(frac))  # fmt: skip

    def simulate(self, sets: FloatArray, rigid: bool = False) -> tuple:
        """Positions, velocities as measured (P, S; `as_measured`), status and reversal
        counts (P, R)."""
        arrays = self.unpack(np.atleast_2d(sets), rigid)
        n_par, n_s = arrays[0].shape[0], self.t_all.shape[0]
        o_y, o_v = np.empty((n_par, n_s)), np.empty((n_par, n_s))
        status = np.zeros((n_par, self.n_rec), dtype=np.int64)
        n_rev = np.zeros((n_par, self.n_rec), dtype=np.int64)
        pk.pooled_responses(
            *arrays, self.mode, self.direction, self.t_all, self.t_off, self.ut_all,
            self.uv_all, self.u_off, MAX_EVENTS, o_y, o_v, status, n_rev,
        )  # fmt: skip
        self.as_measured(o_y, o_v)
        return o_y, o_v, status, n_rev

    @contextmanager
    def exact_velocity_compared(self) -> Iterator[None]:
        """Within: the exact simulated velocity is compared for every record (the search of
        `_response_plan`), as if each velocity were measured."""
        self.exact_velocity, self._last = True, None
        try:
            yield
        finally:
            self.exact_velocity, self._last = False, None

    def as_measured(self, o_y: FloatArray, o_v: FloatArray) -> None:
        """Velocities (P, S), in place, as each record measures them: the difference quotient
        of the simulated positions where the record's velocity is one (module notes)."""
        if self.exact_velocity:
            return
        if self._quotient is not None:  # every such record in one compiled pass
            pk.quotients(o_y, o_v, *self._quotient)
        for i in self._short:  # too short for its quotient: numpy says why
            rec = self.records[i]
            a, b = self.t_off[i], self.t_off[i + 1]
            o_v[:, a:b] = np.gradient(o_y[:, a:b], rec.time, axis=1,
                                      edge_order=2 if rec.difference == 2 else 1)  # fmt: skip

    def _plan_quotients(self) -> None:
        """The compiled form of each record's difference quotient (`pk.quotient_plan`)."""
        n = self.t_all.shape[0]
        plan = (np.full(n, -1, dtype=np.int64), *(np.zeros(n, dtype=np.int64) for _ in range(3)),
                *(np.zeros(n) for _ in range(3)))  # fmt: skip
        self._short: list[int] = []
        used = False
        for i, rec in enumerate(self.records):
            if not rec.difference:
                continue
            order = 2 if rec.difference == 2 else 1
            if rec.time.shape[0] < order + 1:
                self._short.append(i)
                continue
            pk.quotient_plan(rec.time, int(self.t_off[i]), order, plan)
            used = True
        self._quotient = plan if used else None

    def residuals(self, sets: FloatArray, rigid: bool = False) -> FloatArray:
        """Residual of every parameter set (P, n_res); inf rows where a simulation failed."""
        o_y, o_v, status, _ = self.simulate(sets, rigid)
        out = self._residual_of(o_y, o_v)
        bad = np.any(status != 0, axis=1) | ~np.all(np.isfinite(out), axis=1)
        out[bad] = np.inf
        return out

    def residual(self, rigid: bool = False):
        """fun(p) -> r for the least-squares solver (p: all parameters, in order).

        The last evaluation is kept: a forward-difference Jacobian at the same
        point starts from it.
        """

        def fun(p: FloatArray) -> FloatArray:
            r = self.residuals(p[None], rigid)[0]
            self._last = (rigid, p.copy(), r)
            return r

        return fun

    # ------------------------------------------------------------ Jacobian
    def free_jacobian(self, rigid: bool = False, sparse_output: bool | None = None):
        """jac(pm, x, lo, hi) -> Jacobian over the free parameters (module notes).

        Dense, or a CSC matrix (``sparse_output``; default: for large problems,
        which the solver hands to `_structured_lm`).
        """
        if sparse_output is None:
            sparse_output = self.n_res > 5000
        # small problems: central differences; large ones: forward differences from
        # the residual the solver has just evaluated (half the simulations)
        central = not sparse_output
        cache: dict[int, tuple] = {}

        def jac(pm: _Map, x: FloatArray, lo: FloatArray, hi: FloatArray) -> Any:
            if id(pm) not in cache:  # each map's columns laid out once for the problem
                key = (pm.free, pm.matrix.tobytes(), sparse_output)
                if key not in self._columns:
                    rows = [self.rows_of_column(pm, j) for j in range(len(pm.free))]
                    groups = self.column_groups(pm)
                    layout = pj.ForwardLayout(groups, rows, self.n_res) if sparse_output else None
                    self._columns[key] = (groups, rows, layout)
                cache[id(pm)] = (pm, *self._columns[key])
            _, groups, col_rows, layout = cache[id(pm)]
            up, down = pj.difference_steps(x, lo, hi, self.typical(pm), central)
            base = None if central else self._last_residual(rigid, pm.full(x))
            if base is not None and layout is not None:  # the usual case: one gather
                return pj.forward_jacobian(self, pm, x, up, down, groups, layout, rigid, base)
            values = pj.difference_columns(self, pm, x, up, down, groups, col_rows, rigid, base)
            return pj.assemble(values, col_rows, self.n_res, x.shape[0], sparse_output)

        return jac

    def _last_residual(self, rigid: bool, full: FloatArray) -> FloatArray | None:
        """The residual the solver has just evaluated at `full` (None: another point)."""
        last = getattr(self, "_last", None)
        if last is not None and last[0] == rigid and np.array_equal(last[1], full):
            return last[2]
        return None

    def step_limit(self, p: FloatArray) -> FloatArray:
        """Largest change of each parameter in one solver step (a trust box).

        Shared parameters: half their value (or their typical size); initial
        positions and velocities: a tenth of the records' spans; preloads: 0.25.
        """
        shared, floor, out = self._step_parts
        out = out.copy()
        out[shared] = 0.5 * np.maximum(np.abs(p[shared]), floor)
        return out

    def typical(self, pm: _Map) -> FloatArray:
        """A magnitude of each free parameter, below which the difference step stays."""
        return np.array([self._typ.get(n, 1e-12) for n in pm.free])

    def set_typical(self, start: dict[str, float]) -> None:
        """Magnitudes of the parameters: from the start values and the signal spans."""
        v_span = max(max(float(np.ptp(r.velocity)) for r in self.records), TINY)
        p_span = max(max(float(np.ptp(r.position)) for r in self.records), TINY)
        floor = {"initial_position": 1e-3 * p_span, "initial_velocity": 1e-3 * v_span,
                 "preload_fraction": 1e-3}  # fmt: skip
        self._limits = {"initial_position": 0.1 * p_span, "initial_velocity": 0.1 * v_span,
                        "preload_fraction": 0.25}  # fmt: skip
        self._typ = {}
        for x in self.names:
            kind = next((k for k in NUISANCE if x.startswith(k)), None)
            self._typ[x] = floor[kind] if kind else 1e-6 * max(abs(start.get(x, 0.0)), TINY)
        kinds = [next((k for k in NUISANCE if x.startswith(k)), None) for x in self.names]
        shared = np.array([k is None for k in kinds], dtype=bool)
        self._step_parts = (shared, 1e6 * np.array([self._typ[x] for x in self.names])[shared],
                            np.array([self._limits[k] if k else 0.0 for k in kinds]))  # fmt: skip

    def records_of_column(self, pm: _Map, j: int) -> set[int] | None:
        """Records a free parameter touches (None: all)."""
        out: set[int] = set()
        for i in np.flatnonzero(pm.matrix[:, j]):
            rec = self.record_of[self.names[i]]
            if rec is None:
                return None
            out.add(rec)
        return out

    def rows_of_column(self, pm: _Map, j: int) -> NDArray[np.intp]:
        recs = self.records_of_column(pm, j)
        if recs is None:
            return np.arange(self.n_res)
        if len(recs) == 1:
            return self._record_rows[next(iter(recs))]
        return np.concatenate([self._record_rows[i] for i in sorted(recs)])

    def column_groups(self, pm: _Map) -> list[list[int]]:
        """Free columns perturbed together: those touching disjoint sets of records."""
        groups: list[tuple[list[int], set[int] | None]] = []
        for j in range(len(pm.free)):
            recs = self.records_of_column(pm, j)
            for cols, used in groups:
                if recs is not None and used is not None and not (recs & used):
                    cols.append(j)
                    used |= recs
                    break
            else:
                groups.append(([j], None if recs is None else set(recs)))
        return [cols for cols, _ in groups]
