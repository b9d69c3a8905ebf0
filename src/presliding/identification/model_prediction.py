"""A given model (a model file's friction and mass) predicting a record it was not fitted to.

`predict_record(model, mass, measurement)` simulates the record's motion from
its applied force (eq. 17, the exact event method) and compares it with the
measured position or velocity, as `FitResult.predict` does for a fit that is
still in memory. Two starts:

- ``initial="measured"``: the first samples' position and velocity, the
  friction memory saturated in the direction of motion (steady sliding before
  the record), relaxed when the record starts at rest without a force;
  nothing is estimated from the record;
- ``initial="fit"``: the initial velocity (and, when the position is compared,
  the initial position) fitted to the record itself with the model held: these
  parameters are taken from the predicted record, and the prediction names them.

Reversals are counted alike on the measured and the predicted position, at the
given tolerance or the record's own `reversal_tolerance`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from presliding._validation import (
    as_choice,
    as_nonnegative_scalar,
    as_positive_scalar,
    fmt,
    renamed_keyword,
)
from presliding.friction.pi_friction import PIFriction
from presliding.identification.prediction import (
    Prediction,
    count_reversals,
    counted,
)
from presliding.identification.prediction import reversal_tolerance as own_tolerance
from presliding.motion.simulation import simulate

__all__ = ["predict_record"]


def _rest(y: np.ndarray, v: np.ndarray, tol: float) -> float | None:
    """The final position when the record ends at rest (its last tenth within `tol`)."""
    tail = y[-max(3, y.shape[0] // 10) :]
    del v  # a quantised velocity is never exactly 0: the position decides
    return float(y[-1]) if float(np.ptp(tail)) <= max(tol, 0.0) else None


def predict_record(
    model: PIFriction,
    mass: float,
    measurement: Any,
    *,
    signal: str | None = None,
    initial: str = "measured",
    force_offset: float = 0.0,
    reversal_tolerance: float | None = None,
    **deprecated: Any,
) -> Prediction:
    """Predict a record's motion with a given model and mass (module notes).

    Parameters
    ----------
    model : PIFriction
    mass : float
        m [kg] (kg m² on a rotary axis).
    measurement : Measurement
        Time, the position or velocity (or both), and the applied force
        (free motion when absent).
    signal : {"velocity", "position"}, optional
        The signal compared; default velocity when measured, else position.
    initial : {"measured", "fit"}
        The start: the first samples, or fitted to the record (module notes).
    force_offset : float
        F_0 of a model file's ``[measurement]`` table: u − F_0 acts on the mass.
    reversal_tolerance : float, optional
        Travel [m or rad] by which reversals are counted, measured and predicted
        alike (default: the record's own `reversal_tolerance`, three quanta or
        noise levels). Its old name ``tolerance`` works with a DeprecationWarning.

    Returns
    -------
    Prediction
    """
    tolerance = renamed_keyword(deprecated, "tolerance", "reversal_tolerance",
                                reversal_tolerance, "predict_record")  # fmt: skip
    if deprecated:
        raise TypeError(f"predict_record() got an unexpected keyword argument "
                        f"{next(iter(deprecated))!r}.")  # fmt: skip
    if not isinstance(model, PIFriction):
        raise TypeError(f"`model` must be a PIFriction; got {type(model).__name__}.")
    m = as_positive_scalar("mass", mass)
    initial = as_choice("initial", initial, ("measured", "fit"))
    t = np.asarray(measurement.time, dtype=float)
    if signal is None:
        signal = "velocity" if measurement.velocity is not None else "position"
    signal = as_choice("signal", signal, ("velocity", "position"))
    (measured,) = measurement.require(signal, purpose=f"predicting the {signal}")
    if measurement.position is not None:
        y = np.asarray(measurement.position, dtype=float)
    else:
        y = np.concatenate([[0.0], np.cumsum(0.5 * (measured[1:] + measured[:-1]) * np.diff(t))])
    v = (np.asarray(measurement.velocity, dtype=float) if measurement.velocity is not None
         else np.gradient(y, t))  # fmt: skip
    u = measurement.applied_force
    force = (np.zeros_like(t) if u is None else np.asarray(u, dtype=float)) - float(force_offset)
    tol = own_tolerance(y) if tolerance is None else as_nonnegative_scalar(
        "reversal_tolerance", tolerance)  # fmt: skip

    def run(y0: float, v0: float) -> Any:
        # sliding (or pushed) at the start: the memory saturated its way; at rest: relaxed
        state = "saturated" if v0 != 0.0 or force[0] != 0.0 else "relaxed"
        return simulate(model, m, applied_force=(t, force), initial_position=y0,
                        initial_velocity=v0, initial_state=state, t_start=float(t[0]),
                        t_eval=t)  # fmt: skip

    start = {"initial_position": float(y[0]), "initial_velocity": float(v[0])}
    own: dict[str, float] = {}
    if initial == "fit":
        start, own = _fit_start(run, start, measured, signal)
    res = run(start["initial_position"], start["initial_velocity"])
    predicted = res.position if signal == "position" else res.velocity
    status, message = ("success", "") if res.success else ("failed", res.message)
    if measurement.position is None:
        own.setdefault("initial_position", start["initial_position"])
    return Prediction.build(
        t, measured, predicted, (signal, "time [s]"),
        measured_reversals=count_reversals(y, tol), predicted_reversals=count_reversals(
            res.position, tol), measured_rest=_rest(y, v, tol),
        predicted_rest=_rest(res.position, res.velocity, tol), parameters=own, status=status,
        message=message, **counted(initial, tol, y),
    )  # fmt: skip


def _fit_start(
    run: Any, start: dict[str, float], measured: np.ndarray, signal: str
) -> tuple[dict[str, float], dict[str, float]]:
    """The initial velocity (and position, when compared) that match the record best."""
    from scipy.optimize import least_squares

    names = ["initial_velocity"] + (["initial_position"] if signal == "position" else [])
    scale = max(float(np.ptp(measured)), 1e-300)
    width = {"initial_velocity": max(abs(start["initial_velocity"]), 1e-12),
             "initial_position": scale}  # fmt: skip

    def residual(x: np.ndarray) -> np.ndarray:
        values = {**start, **{n: start[n] + x[i] * width[n] for i, n in enumerate(names)}}
        res = run(values["initial_position"], values["initial_velocity"])
        got = res.position if signal == "position" else res.velocity
        return np.nan_to_num((got - measured) / scale, nan=1e3, posinf=1e3, neginf=-1e3)

    out = least_squares(residual, np.zeros(len(names)), x_scale=1.0, max_nfev=100)
    if not np.all(np.isfinite(out.x)):
        raise ValueError(f"the start could not be fitted to the record; got {fmt(out.x)}.")
    fitted = {n: start[n] + float(out.x[i]) * width[n] for i, n in enumerate(names)}
    return {**start, **fitted}, fitted
