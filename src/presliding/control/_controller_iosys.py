"""Controllers as python-control systems (behind `to_iosys`): the arithmetic of the loop kernels.

Both the update and the output call the compiled single steps of
`presliding.control._loop` on a copy of the state, so a python-control loop and
`simulate_loop` compute the same numbers.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from presliding._validation import as_nonnegative_scalar
from presliding.control import _loop
from presliding.control.controllers import PID, DiscreteController

PID_KEYS = ("kp", "ki", "kd")


def _pid_parameters(base: np.ndarray, pid: PID, params: dict) -> np.ndarray:
    given = [k for k in PID_KEYS if k in params]
    if not given:
        return base
    p = base.copy()
    for i, key in enumerate(PID_KEYS):
        if key in params:
            p[i] = as_nonnegative_scalar(key, params[key])
    if pid.anti_windup == "back-calculation" and pid.tracking_time is None:
        p[8] = p[0] / p[1] if p[0] > 0 and p[1] > 0 else pid.dt
    return p


def controller_system(control: Any, ctrl: PID | DiscreteController, name: str, ins, outs) -> Any:
    """A discrete NonlinearIOSystem with inputs (reference, position) and output u."""
    if isinstance(ctrl, PID):
        base = ctrl.parameters()

        def step(x, u, params):
            s = np.array(x, dtype=np.float64)
            p = _pid_parameters(base, ctrl, params)
            out = _loop.pid_output(p, s, float(u[0]), float(u[1]), 0.0)
            return out, s

        states = ["integral", "derivative", "previous", "started"]
    else:
        low, high = ctrl.limits
        a, b = np.ascontiguousarray(ctrl.A), np.ascontiguousarray(ctrl.B)
        c, d = np.ascontiguousarray(ctrl.C), np.ascontiguousarray(ctrl.D)
        w, tmp = np.empty(2), np.empty(ctrl.n_states)

        def step(x, u, params):
            s = np.array(x, dtype=np.float64).reshape(-1)
            out = _loop.ss_output(a, b, c, d, s, low, high, float(u[0]), float(u[1]), 0.0,
                                  w, tmp)  # fmt: skip
            return out, s

        states = [f"x_{j}" for j in range(ctrl.n_states)]

    def update(t, x, u, params):
        return step(x, u, params)[1]

    def output(t, x, u, params):
        return np.array([step(x, u, params)[0]])

    return control.NonlinearIOSystem(
        update, output, inputs=ins, outputs=outs, states=states, dt=ctrl.dt, name=name
    )
