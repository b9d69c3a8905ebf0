"""The public result of a quasi-static fit (`fit_quasi_static`): position against the
applied force, and the floor of F_c (`level_floor`, also the fit's lower bound).

The errors are raised to the floor that runs of equal quantised samples imply
(`_quasi_static_errors`: a record's initial position is fixed by its first samples alone);
the result carries the model (a `CreepingFriction` with ``creep=True``), the preloads as
forces (about the mid band of an asymmetric model), the note of an F_c on its floor, the
plateau ends of an undetermined split as profile points, and the predictor.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from presliding._validation import fmt
from presliding.friction.creep import CreepingFriction
from presliding.friction.pi_friction import PIFriction
from presliding.identification._fit_engine import FitRun
from presliding.identification.records._quasi_static_errors import with_run_floor
from presliding.identification.solve._least_squares import Solution
from presliding.measurement.measurement import common_axis

__all__ = ["level_floor", "quasi_static_result"]

_UNITS = {"height": "N/m^2", "max_threshold": "m", "length": "m", "preload": "N"}


def level_floor(req: Any, records: Any) -> float:
    """The lower bound of F_c: the largest |u| (without an offset) and `min_coulomb_level`;
    of F_c⁺ an asymmetric model's: the largest u."""
    largest = records.u_sides[0] if req.spec.negative else records.u_max
    return max(req.fmin, largest * (1 + 1e-9)) if not req.offset else req.fmin


def quasi_static_result(req: Any, run: FitRun, sol: Solution, boot: Any,
            summary: Any) -> Any:  # fmt: skip
    """The public result: position against the applied force (module notes)."""
    from presliding.identification.fit_result import FitResult
    from presliding.identification.plans._predictors import QuasiStaticPredictor

    records, spec, values = run.problem.records, req.spec, sol.values
    sol = with_run_floor(sol, records)  # errors of parameters fixed by runs of equal samples
    o_y, _, status, _ = records.simulate(np.array([values[x] for x in records.names]))
    if np.any(status != 0) and sol.status == "converged":
        sol = replace(sol, status="failed", message="no quasi-static response at the optimum")
    derived = {"coulomb_level": spec.coulomb_level(values)} if not spec.has_level_parameter else {}
    fm = spec.coulomb_level(values) - max(values["coulomb"], 0.0)
    mid, shift = fm, 0.0
    if spec.negative is not None:  # c1⁻, ρ = F_c⁻/F_c⁺; a preload about the mid band
        rho = spec.ratio(values)
        derived.update(coulomb_negative=rho * max(values["coulomb"], 0.0),
                       coulomb_level_ratio=rho)  # fmt: skip
        mid, shift = 0.5 * (1.0 + rho) * fm, 0.5 * (1.0 - rho) * fm
    if req.initial_state == "preload":
        for i in range(records.n_rec):
            x = records.nuisance("preload_fraction", i)
            derived[x.replace("preload_fraction", "preload")] = values[x] * mid + shift
    units = {x: "1" for x in records.names if x.startswith("preload_fraction")}
    if spec.negative is not None:
        units["coulomb_level_ratio"] = "1"
    contact = spec.model(values)
    model: PIFriction | CreepingFriction = contact
    if req.creep:
        model = CreepingFriction(contact, max(values["creep_compliance"], 0.0),
                                 max(values["creep_time"], 0.0))  # fmt: skip
    result = FitResult.from_solution(
        sol, model, records.u_all, np.concatenate([r.position for r in req.recs]),
        o_y[0], kind="quasi-static", abscissa_label="applied force", signal_label="position",
        signal_unit="m", units={**units, **_UNITS}, derived=derived,
        rotary=common_axis(req.records) == "rotary",
        model_hint=lambda: _masing_note(spec.model(values), req.recs),
    )  # fmt: skip
    floor = level_floor(req, records)
    if floor > 0 and spec.has_level_parameter and values["coulomb_level"] <= floor * (1 + 1e-6):
        note = (f"F_c sits on its lower bound {fmt(floor)} (the largest applied force or "
                "`min_coulomb_level`): the loops do not determine it")  # fmt: skip
        result = replace(result, notes=(note,))
    flat = {x: "profile" for x in spec.k_names  # a plateau's ends: points of the profile
            if result.interval_method.get(x) == "wald"
            and not np.isfinite(result.standard_error[x])}  # fmt: skip
    if flat:
        result = replace(result, interval_method={**result.interval_method, **flat})
    spans = tuple(zip(records.t_off[:-1].tolist(), records.t_off[1:].tolist(), strict=True))
    return replace(result, records=spans if records.n_rec > 1 else (), bootstrap=boot,
                   predictor=QuasiStaticPredictor(records, values), search=summary)  # fmt: skip


def _masing_note(model: Any, recs: list) -> str:
    """masing_check's verdict on the records' loops (position against applied force)."""
    from presliding.identification.masing import masing_verdict

    return masing_verdict(model, [(r.position, r.applied_force) for r in recs])
