"""How each fit predicts another record (behind `FitResult.predict`).

A held-out record has its own nuisance parameters (initial position, velocity,
preload), which no other record determines. With ``initial="fit"`` (default)
they are estimated from the record itself with every shared parameter held at
its fitted value: the physics is predicted, the record's unknown start is not
held against it. ``initial="measured"`` takes them from the first samples
(preload: saturated, as a record in steady sliding).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from presliding._validation import as_choice
from presliding.identification.prediction import (
    Prediction,
    count_reversals,
    counted,
    reversal_tolerance,
)
from presliding.identification.records import _pooled_problem as pp
from presliding.identification.solve._least_squares import solve_least_squares

INITIAL = ("fit", "measured")


def _rest(y: np.ndarray, v: np.ndarray | None, tol: float) -> float | None:
    """The final position when the record ends at rest (its last tenth within `tol`)."""
    tail = y[-max(3, y.shape[0] // 10) :]
    if v is not None and v[-1] != 0.0:
        return None
    return float(y[-1]) if float(np.ptp(tail)) <= max(tol, 0.0) else None


class ResponsePredictor:
    """Prediction of a record's motion by a pooled response fit.

    `fractions`: further preloads its own start is solved from with ``initial="fit"`` (the
    best kept; the rate families': a preload saturated in the motion's direction holds its
    local solve on its bound); none by default.
    """

    def __init__(self, problem: pp.PooledProblem, values: dict[str, float],
                 fractions: tuple[float, ...] = ()):  # fmt: skip
        self.problem = problem
        self.shared = {x: values[x] for x in problem.shared}
        self.fractions = fractions

    def predict(
        self, result: Any, measurement: Any, initial: str = "fit", tolerance: float | None = None
    ) -> Prediction:
        from presliding.identification.plans._response_setup import check_records, initial_bounds

        initial = as_choice("initial", initial, INITIAL)
        p = self.problem
        signal = "both" if p.w_v and p.w_y else ("velocity" if p.w_v else "position")
        (rec,) = check_records(measurement, signal, ("velocity", "position", "both"), p.velocity)
        sub = p.subset([rec], suffix=False)
        start = dict(self.shared)
        start.update(initial_position=float(rec.position[0]),
                     initial_velocity=float(rec.velocity[0]))  # fmt: skip
        if p.initial_state == "preload":
            start["preload_fraction"] = float(sub.direction[0]) if rec.velocity[0] else 0.0
        start = {x: start[x] for x in sub.names}
        status, message = "success", ""
        if initial == "fit":
            fixed = dict(self.shared)
            if not p.w_y:
                fixed["initial_position"] = float(rec.position[0])
            sub.set_typical(start)
            begins = [start] + [{**start, "preload_fraction": f} for f in self.fractions
                                if p.initial_state == "preload"]  # fmt: skip
            solves = [solve_least_squares(
                sub.residual(), b, fixed=fixed, bounds=initial_bounds(sub, p.initial_state),
                free_jacobian=sub.free_jacobian(), tolerance=1e-8, max_evaluations=200,
            ) for b in begins]  # fmt: skip
            out = min(solves, key=lambda o: np.inf if o.status == "failed" else float(
                o.residual @ o.residual))  # fmt: skip
            if out.status == "failed":
                status, message = "failed", f"initial conditions not found: {out.message}"
            else:
                start = out.values
        full = np.array([start[x] for x in sub.names])
        o_y, o_v, st, _ = sub.simulate(full)
        if np.any(st != 0):
            status, message = "failed", "the simulation failed"
        y_sim, v_sim = o_y[0], o_v[0]
        tol = reversal_tolerance(rec.position) if tolerance is None else tolerance
        measured_sig, predicted_sig = (
            (rec.position, y_sim) if signal == "position" else (rec.velocity, v_sim)
        )
        own = {x: float(start[x]) for x in sub.names if x not in self.shared}
        measured_v = measurement.velocity if measurement.velocity is not None else None
        return Prediction.build(
            rec.time, measured_sig, predicted_sig,
            ("position" if signal == "position" else "velocity", "time [s]"),
            measured_reversals=count_reversals(rec.position, tol),
            predicted_reversals=count_reversals(y_sim, tol),
            measured_rest=_rest(rec.position, measured_v, tol),
            predicted_rest=_rest(y_sim, v_sim, tol),
            parameters=own, status=status, message=message,
            **counted(initial, tol, rec.position),
        )  # fmt: skip


class QuasiStaticPredictor:
    """Prediction of a record's positions by a pooled quasi-static fit."""

    def __init__(self, problem: Any, values: dict[str, float]):
        self.problem = problem
        self.shared = {x: values[x] for x in problem.shared}

    def predict(
        self, result: Any, measurement: Any, initial: str = "fit", tolerance: float | None = None
    ) -> Prediction:
        from presliding.identification.plans._response_setup import check_quasi_static_records

        initial = as_choice("initial", initial, INITIAL)
        p = self.problem
        (rec,) = check_quasi_static_records(measurement)
        sub = p.subset([rec], suffix=False)
        start = {**self.shared, "initial_position": float(rec.position[0])}
        if p.initial_state == "preload":
            start["preload_fraction"] = 0.0
        start = {x: start[x] for x in sub.names}
        status, message = "success", ""
        if initial == "fit":
            from presliding.identification.plans._response_setup import record_starts

            start = record_starts(sub, start)
        o_y, _, st, _ = sub.simulate(np.array([start[x] for x in sub.names]))
        if np.any(st != 0):
            status, message = "failed", "no quasi-static response (|u| >= F_c)"
        tol = reversal_tolerance(rec.position) if tolerance is None else tolerance
        own = {x: float(start[x]) for x in sub.names if x not in self.shared}
        return Prediction.build(
            rec.applied_force, rec.position, o_y[0], ("position", "applied force"),
            measured_reversals=count_reversals(rec.position, tol),
            predicted_reversals=count_reversals(o_y[0], tol), parameters=own, status=status,
            message=message, **counted(initial, tol, rec.position),
        )  # fmt: skip
