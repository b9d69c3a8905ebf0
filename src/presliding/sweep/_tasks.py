"""The per-chunk work of ``presliding sweep``: one quantity at many grid points.

A `SweepTask` carries the base model, its motion and the quantity; each grid
point is the free motion m·ÿ + c1·Sign(ẏ) + F_el(y) = u (eqs. 12, 17) with the
swept parameters replaced. `evaluate_chunk` is the function the sweep runs on
every chunk, either by the exact event batch (`simulate_batch`) or by the
work-energy balance of eqs. 13-16 (`analysis.turning_points`). The
specification that builds the task is read and validated in `_sweep_spec`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from presliding.friction._parts import elements
from presliding.friction._sides import require_symmetric
from presliding.friction.pi_friction import PIFriction
from presliding.model_io import MotionSettings


@dataclass(frozen=True)
class SweepTask:
    """Everything a worker needs to evaluate chunks of grid points (picklable)."""

    model: PIFriction
    motion: MotionSettings
    quantity: str
    method: str
    single_thread: bool = False

    def __post_init__(self) -> None:
        require_symmetric(self.model, "presliding sweep")


def point_parameters(task: SweepTask, columns: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """c1, m and v0 of each point of a chunk: the axes' values, else the base model's."""
    n = next(iter(columns.values())).shape[0]
    model, motion = task.model, task.motion
    if "coulomb_ratio" in columns:
        c1 = columns["coulomb_ratio"] * model.max_elastic_force
    else:
        c1 = columns.get("coulomb", np.full(n, model.coulomb))
    return {
        "coulomb": np.ascontiguousarray(c1, dtype=np.float64),
        "mass": np.ascontiguousarray(columns.get("mass", np.full(n, motion.mass))),
        "initial_velocity": np.ascontiguousarray(
            columns.get("initial_velocity", np.full(n, motion.initial_velocity))
        ),
    }


def evaluate_chunk(task: SweepTask, /, **columns: np.ndarray) -> np.ndarray:
    """The quantity of each point of a chunk, and whether its motion stopped.

    Module level (picklable by reference), so worker processes and Dask can run
    it: ``functools.partial(evaluate_chunk, task)`` is the sweep's ``fn``.

    Returns
    -------
    ndarray, shape (n, 2)
        Column 0: the quantity (NaN where the motion has not stopped); column 1:
        1.0 where it stopped, 0.0 where not.
    """
    p = point_parameters(task, columns)
    if task.method == "simulate":
        value, stopped = _by_simulation(task, p)
    else:
        value, stopped = _by_analysis(task, p)
    return np.column_stack([np.where(stopped, value, np.nan), stopped.astype(np.float64)])


def _by_simulation(task: SweepTask, p: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The exact event batch (`simulate_batch`) over [0, t_end], sampled at the ends only."""
    from presliding.motion.simulation import simulate_batch

    if task.single_thread:  # one worker per core already: no threads inside a worker
        import numba

        numba.set_num_threads(1)
    model, mo = task.model, task.motion
    n = p["coulomb"].shape[0]
    stiffness, threshold, _ = elements(model)
    k = np.broadcast_to(stiffness, (n, model.n_elements))
    r = np.broadcast_to(threshold, (n, model.n_elements))
    res = simulate_batch(
        coulomb=p["coulomb"],
        stiffness=k,
        threshold=r,
        viscous=model.viscous,
        mass=p["mass"],
        initial_velocity=p["initial_velocity"],
        initial_position=mo.initial_position,
        initial_state=mo.initial_state,
        applied_force=mo.applied_force,
        t_end=mo.t_end,
        t_eval=[0.0, mo.t_end],
    )
    stopped = np.isfinite(res.stop_time) & (res.member_status == "success")
    value = {
        "reversals": res.n_reversals.astype(np.float64),
        "rest_position": res.final_position,
        "stop_time": res.stop_time,
    }[task.quantity]
    return value, stopped


def _by_analysis(task: SweepTask, p: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """`analysis.turning_points` point by point (the work-energy balance, eqs. 13-16)."""
    from presliding.analysis.stops import turning_points

    model, mo = task.model, task.motion
    n = p["coulomb"].shape[0]
    value = np.empty(n)
    stopped = np.zeros(n, dtype=bool)
    for i in range(n):
        c1 = float(p["coulomb"][i])
        if model.is_discrete:
            point = PIFriction(c1, model.stiffness, threshold=model.threshold,
                               viscous=model.viscous)  # fmt: skip
        else:
            point = PIFriction(c1, density=model.density, viscous=model.viscous)
        tp = turning_points(
            point,
            float(p["mass"][i]),
            float(p["initial_velocity"][i]),
            mo.initial_state,
            initial_position=mo.initial_position,
        )
        stopped[i] = tp.status == "stopped"
        if task.quantity == "reversals":
            value[i] = tp.n_reversals
        else:
            value[i] = tp.rest_position if stopped[i] else np.nan
    return value, stopped


__all__ = ["SweepTask", "evaluate_chunk", "point_parameters"]
