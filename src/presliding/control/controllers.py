"""Discrete controllers of a sampled-data loop: `PID` and `DiscreteController`.

Both act at the sample instants t_k = t_0 + k·dt on the measured position y_k
and the reference r_k; their output u_k is held over [t_k, t_k + dt) (zero-order
hold) and applied to the mass (eq. 17). The PID, with e_k = r_k − y_k,

    u_k = sat( kp·e_k + I_k + D_k + u_ff,k ),
    D_k = (T_f·D_{k−1} + kd·(s_k − s_{k−1})) / (T_f + dt),     s = −y (or e),
    I_{k+1} = I_k + ki·dt·e_k   (+ anti-windup),

is the backward-Euler discretisation of C(s) = kp + ki/s + kd·s/(T_f·s + 1)
(`PID.continuous`), with the derivative on the measurement by default (no kick
at a step of the reference) and no derivative kick at k = 0 (s_{−1} = s_0).
The anti-windup of a saturated output is either conditional integration
("clamping": no integration while the output is saturated and the error drives
it further in) or back-calculation (I_{k+1} += dt/T_t·(u_k − v_k), v_k the
unsaturated output).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._validation import (
    as_choice,
    as_nonnegative_scalar,
    as_positive_scalar,
    as_real_array,
    as_real_scalar,
    fmt,
)

__all__ = ["PID", "DiscreteController"]

FloatArray = NDArray[np.float64]
ANTI_WINDUP = ("clamping", "back-calculation", "none")
DERIVATIVE_ON = ("measurement", "error")


def _limits(limit: Any) -> tuple[float, float]:
    """(low, high) of a saturation: None, a positive bound L (±L) or a pair (low, high)."""
    if limit is None:
        return -math.inf, math.inf
    if np.ndim(limit) == 0:
        bound = as_positive_scalar("limit", limit)
        return -bound, bound
    pair = as_real_array("limit", limit)
    if pair.shape != (2,):
        raise ValueError(
            f"`limit` must be None, a positive number or a pair (low, high); got shape "
            f"{pair.shape}."
        )
    if not pair[0] < pair[1]:
        raise ValueError(
            f"`limit` (low, high) must have low < high; got {fmt(pair[0])} and {fmt(pair[1])}."
        )
    return float(pair[0]), float(pair[1])


@dataclass(frozen=True)
class PID:
    """A discrete PID position controller with sample time, saturation and anti-windup.

    Parameters
    ----------
    kp, ki, kd : float
        Gains >= 0 [N/m, N/(m·s), N·s/m] of C(s) = kp + ki/s + kd·s/(T_f·s + 1).
    dt : float, keyword only
        Sample time [s] (> 0); the output is held over each period.
    filter_time : float, keyword only
        T_f >= 0 [s], the time constant of the derivative's first-order filter.
    limit : float or (float, float), optional, keyword only
        Saturation of the output: ±limit, or (low, high) [N]. None: none.
    anti_windup : "clamping", "back-calculation" or "none", keyword only
        What the integral does while the output saturates (see the module notes).
    tracking_time : float, optional, keyword only
        T_t > 0 [s] of back-calculation; default kp/ki (the integral time), or dt.
    derivative_on : "measurement" or "error", keyword only
        Differentiate −y (no kick at reference steps, the default) or e = r − y.

    Examples
    --------
    >>> pid = PID(400.0, 4000.0, 10.0, dt=1e-3, limit=5.0)
    >>> pid.continuous()          # doctest: +SKIP
    """

    kp: float
    ki: float = 0.0
    kd: float = 0.0
    dt: float = field(default=1e-3, kw_only=True)
    filter_time: float = field(default=0.0, kw_only=True)
    limit: Any = field(default=None, kw_only=True)
    anti_windup: str = field(default="clamping", kw_only=True)
    tracking_time: float | None = field(default=None, kw_only=True)
    derivative_on: str = field(default="measurement", kw_only=True)

    def __post_init__(self) -> None:
        for name in ("kp", "ki", "kd"):
            object.__setattr__(self, name, as_nonnegative_scalar(name, getattr(self, name)))
        if self.kp == 0.0 and self.ki == 0.0 and self.kd == 0.0:
            raise ValueError("`kp`, `ki` and `kd` must not all be zero; got 0.0, 0.0 and 0.0.")
        object.__setattr__(self, "dt", as_positive_scalar("dt", self.dt))
        object.__setattr__(
            self, "filter_time", as_nonnegative_scalar("filter_time", self.filter_time)
        )
        as_choice("anti_windup", self.anti_windup, ANTI_WINDUP)
        as_choice("derivative_on", self.derivative_on, DERIVATIVE_ON)
        low, high = _limits(self.limit)
        object.__setattr__(self, "limit", None if self.limit is None else (low, high))
        if self.tracking_time is not None:
            tt = as_positive_scalar("tracking_time", self.tracking_time)
            object.__setattr__(self, "tracking_time", tt)

    @property
    def limits(self) -> tuple[float, float]:
        """(low, high) of the output; ±inf without saturation."""
        return _limits(self.limit)

    @property
    def effective_tracking_time(self) -> float:
        """T_t of back-calculation: as given, else kp/ki, else dt."""
        if self.tracking_time is not None:
            return self.tracking_time
        return self.kp / self.ki if self.kp > 0 and self.ki > 0 else self.dt

    def with_gains(self, kp: float, ki: float, kd: float) -> PID:
        """The same controller with other gains."""
        return PID(kp, ki, kd, dt=self.dt, filter_time=self.filter_time, limit=self.limit,
                   anti_windup=self.anti_windup, tracking_time=self.tracking_time,
                   derivative_on=self.derivative_on)  # fmt: skip

    def parameters(self) -> FloatArray:
        """The compiled form [kp, ki, kd, dt, T_f, low, high, anti-windup, T_t, on-error]."""
        low, high = self.limits
        return np.array([
            self.kp, self.ki, self.kd, self.dt, self.filter_time, low, high,
            float(ANTI_WINDUP.index(self.anti_windup)), self.effective_tracking_time,
            float(self.derivative_on == "error"),
        ])  # fmt: skip

    def continuous(self) -> Any:
        """C(s) = kp + ki/s + kd·s/(T_f·s + 1) as a python-control transfer function."""
        from presliding.control._optional import python_control as _control

        ct = _control()
        s = ct.tf("s")
        c = ct.tf([self.kp], [1.0])
        if self.ki:
            c = c + self.ki / s
        if self.kd:
            c = c + self.kd * s / (self.filter_time * s + 1.0)
        return ct.minreal(c, verbose=False) if self.ki else c


@dataclass(frozen=True, eq=False)
class DiscreteController:
    """A discrete state-space controller x_{k+1} = A x_k + B w_k, u_k = sat(C x_k + D w_k).

    Parameters
    ----------
    A, B, C, D : array_like
        Matrices of shapes (n, n), (n, p), (1, n) and (1, p); p = 1: w_k = e_k =
        r_k − y_k; p = 2: w_k = (r_k, y_k). n may be 0 (a static gain D).
    dt : float, keyword only
        Sample time [s] (> 0).
    limit : float or (float, float), optional, keyword only
        Saturation of the output (no anti-windup: the state is not corrected).
    """

    A: FloatArray
    B: FloatArray
    C: FloatArray
    D: FloatArray
    dt: float = field(default=1e-3, kw_only=True)
    limit: Any = field(default=None, kw_only=True)

    def __post_init__(self) -> None:
        mats = {}
        for name in ("A", "B", "C", "D"):
            arr = as_real_array(name, getattr(self, name))
            if arr.ndim != 2:
                arr = np.atleast_2d(arr) if arr.ndim < 2 else arr
            if arr.ndim != 2:
                raise ValueError(f"`{name}` must be a matrix; got shape {arr.shape}.")
            mats[name] = np.ascontiguousarray(arr)
        a = mats["A"] if mats["A"].size else np.zeros((0, 0))  # [] or [[]]: no states
        if a.shape[0] != a.shape[1]:
            raise ValueError(f"`A` must be a square matrix (n, n); got shape {a.shape}.")
        n = a.shape[0]
        p = mats["D"].shape[1]

        # B (n, p) and C (1, n) may be given flat; with n = 0 they must be empty
        b, c = mats["B"], mats["C"]
        if n == 0:
            b = np.zeros((0, p)) if b.size == 0 else b
            c = np.zeros((1, 0)) if c.size == 0 else c
        else:
            b = b.reshape(n, -1) if b.size % n == 0 else b
            c = c.reshape(1, n) if c.size == n else c
        want = {"A": (n, n), "B": (n, p), "C": (1, n), "D": (1, p)}
        for name, arr in (("A", a), ("B", b), ("C", c), ("D", mats["D"])):
            if arr.shape != want[name]:
                raise ValueError(
                    f"`{name}` must have shape {want[name]} (n = {n} states, p = {p} inputs); "
                    f"got shape {arr.shape}."
                )
        if p not in (1, 2):
            raise ValueError(
                f"`D` must have 1 column (input e = r − y) or 2 (inputs r, y); got {p}."
            )
        for name, arr in (("A", a), ("B", b), ("C", c), ("D", mats["D"])):
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        object.__setattr__(self, "dt", as_positive_scalar("dt", self.dt))
        low, high = _limits(self.limit)
        object.__setattr__(self, "limit", None if self.limit is None else (low, high))

    @property
    def limits(self) -> tuple[float, float]:
        """(low, high) of the output [N]; ±inf without saturation."""
        return _limits(self.limit)

    @property
    def n_states(self) -> int:
        """n, the controller's states (0: a static gain D)."""
        return int(self.A.shape[0])

    @property
    def n_inputs(self) -> int:
        """p: 1 when the controller reads the error e_k, 2 when it reads (r_k, y_k)."""
        return int(self.D.shape[1])

    @classmethod
    def from_lti(cls, system: Any, *, limit: Any = None) -> DiscreteController:
        """From a discrete python-control system (StateSpace or TransferFunction, SISO or
        with inputs (reference, position)); its ``dt`` must be a number of seconds."""
        from presliding.control._optional import python_control as _control

        ct = _control()
        if not isinstance(system, ct.LTI):
            raise TypeError(f"`system` must be a python-control LTI system; got "
                            f"{type(system).__name__}.")  # fmt: skip
        dt = system.dt
        if dt is None or dt is True or dt == 0 or isinstance(dt, bool):
            raise ValueError(
                "`system` must be discrete-time with its sample time in seconds (dt > 0); "
                f"got dt = {dt!r}."
            )
        ss = ct.ss(system)
        return cls(ss.A, ss.B, ss.C, ss.D, dt=as_real_scalar("dt", dt), limit=limit)
