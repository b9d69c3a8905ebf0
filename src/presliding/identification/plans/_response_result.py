"""The public result of a pooled response fit: model, derived values, units, predictor."""

from __future__ import annotations

import re
from dataclasses import replace

import numpy as np

from presliding.identification.fit_result import FitResult
from presliding.identification.records import _pooled_problem as pp

#: What the message and the report say of a fit of free records only.
PER_UNIT_MASS = (
    "no record has an applied force, so mass and forces are determined only up to a common "
    "factor: they are reported per unit mass (mass = 1; forces in N/kg, stiffnesses in "
    "N/(m·kg)); give `mass` or `coulomb_level` to scale them"
)
#: Units of the quantities the pooled fits add (the others: `_units.parameter_units`).
EXTRA_UNITS = {
    "height": "N/m^2",
    "max_threshold": "m",
    "length": "m",
    "preload": "N",
    "largest_swing": "m",
    "reachable_coulomb_level": "N",
    "effective_elements": "1",
    "coulomb_level_ratio": "1",
}


def response_result(
    sol, problem: pp.PooledProblem, spec, pruned, notes, boot, per_unit_mass: bool, signal: str
) -> FitResult:
    """The public result of a pooled response fit."""
    from presliding.identification.plans._predictors import ResponsePredictor

    values = sol.values
    full = np.array([values[x] for x in problem.names])
    o_y, o_v, status, _ = problem.simulate(full)
    ok = bool(np.all(status == 0) and np.all(np.isfinite(o_v)))
    if not ok and sol.status == "converged":
        sol = replace(sol, status="failed", message="the simulation failed at the optimum")
    if per_unit_mass:
        sol = replace(sol, message=f"{sol.message}; {PER_UNIT_MASS}")
    model = spec.model(values)
    derived = {"coulomb_level": spec.coulomb_level(values)} if not spec.has_level_parameter else {}
    c1, k, r = spec.bank(values)
    if spec.density is None:
        derived.update({f"threshold_{j + 1}": float(x) for j, x in enumerate(r)})
        if spec.equal and spec.n:
            derived["breakaway_each"] = float(k[0] * r[0])
    fm = spec.coulomb_level(values) - c1
    mid, shift = fm, 0.0
    if spec.negative is not None:  # c1⁻ and ρ = F_c⁻/F_c⁺; a preload about the mid band
        rho = spec.ratio(values)
        if spec.n:  # without elements c1⁻ is the parameter itself
            derived["coulomb_negative"] = rho * c1
        derived["coulomb_level_ratio"] = rho
        mid, shift = 0.5 * (1.0 + rho) * fm, 0.5 * (1.0 - rho) * fm
    if problem.initial_state == "preload":
        for i in range(problem.n_rec):
            x = problem.nuisance("preload_fraction", i)
            derived[x.replace("preload_fraction", "preload")] = values[x] * mid + shift
    derived.update(pruned.derived(spec))
    measured, fitted = (
        (np.concatenate([r.position for r in problem.records]), o_y[0])
        if signal == "position"
        else (np.concatenate([r.velocity for r in problem.records]), o_v[0])
    )
    spans = tuple(zip(problem.t_off[:-1].tolist(), problem.t_off[1:].tolist(), strict=True))
    units = {**EXTRA_UNITS} if not per_unit_mass else {}
    units.update({x: "1" for x in problem.names if x.startswith("preload_fraction")})
    if per_unit_mass:
        units.update(_per_kg([*problem.names, *derived]))
    result = FitResult.from_solution(
        sol, model, problem.t_all, measured, fitted, kind="output-error response",
        abscissa_label="time [s]", signal_label="position" if signal == "position" else "velocity",
        signal_unit="m" if signal == "position" else "m/s", units=units, derived=derived,
    )  # fmt: skip
    return replace(
        result, records=spans if problem.n_rec > 1 else (), bootstrap=boot, notes=tuple(notes),
        predictor=ResponsePredictor(problem, values),
    )  # fmt: skip


def _per_kg(names: list[str]) -> dict[str, str]:
    """Units of the parameters reported per unit mass."""
    per = {"mass": "1 (fixed)", "coulomb": "N/kg", "coulomb_level": "N/kg",
           "coulomb_negative": "N/kg", "coulomb_level_negative": "N/kg",
           "viscous_negative": "N s/(m kg)",
           "stiffness": "N/(m kg)", "breakaway": "N/kg", "viscous": "N s/(m kg)",
           "offset": "N/kg", "preload": "N/kg", "reachable_coulomb_level": "N/kg",
           "height": "N/(m^2 kg)"}  # fmt: skip
    out = {}
    for x in names:
        base = re.sub(r"_\d+$", "", x)
        if base in per:
            out[x] = per[base]
    return out
