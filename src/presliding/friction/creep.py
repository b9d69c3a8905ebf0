"""Creep: PI friction in series with a Kelvin–Voigt element (torque-driven presliding).

A joint held at a constant torque below break-away can keep moving for a while —
the robot joint of issue 35 creeps 5 mdeg in 0.5 s — which no rate-independent
model follows, and its loops then break Masing's rule. `CreepingFriction` puts a
Kelvin–Voigt element (a spring of compliance J in parallel with a dashpot) in
series with the PI contact: the force u passes through both, so

    y = Γ[u] + y_c,        τ·ẏ_c + y_c = J·u,

with Γ the quasi-static response of the PI model (`presliding.quasi_static_response`)
and τ the creep time. Under a constant force the creep deflection tends to J·u with
time constant τ: a bounded creep, as the physics of a visco-elastic part has it (a
Maxwell element in series would drift without bound under any force below
break-away, which is not physical). At rest after unloading it recovers. With
J = 0 the model is the PI model exactly; with τ = 0 the element is a series spring.

Between samples the force is taken linear in time (a slow drive), and the creep
deflection is integrated exactly (`creep_deflections`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from presliding._validation import as_nonnegative_scalar
from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis._jit import njit

__all__ = ["CreepingFriction", "creep_deflections"]


@dataclass(frozen=True, eq=False)
class CreepingFriction:
    """A PI contact in series with a Kelvin–Voigt element (module notes).

    Parameters
    ----------
    friction : PIFriction
        The contact (finite elements, equal sides), as for `quasi_static_response`.
    compliance : float
        J >= 0 [m/N], the creep compliance: the creep deflection J·u that a constant
        force u reaches (0: no creep, the PI model).
    creep_time : float
        τ >= 0 [s], the time constant of the creep (0: a series spring).

    Examples
    --------
    >>> model = CreepingFriction(PIFriction(0.1, [2e4], [0.3]), 2e-6, 0.1)
    >>> model.coulomb_level, model.has_creep
    (0.4, True)
    """

    friction: PIFriction
    compliance: float
    creep_time: float

    def __post_init__(self) -> None:
        if not isinstance(self.friction, PIFriction):
            raise TypeError(f"`friction` must be a PIFriction; got {type(self.friction).__name__}.")
        object.__setattr__(self, "compliance", as_nonnegative_scalar("compliance", self.compliance))
        object.__setattr__(self, "creep_time", as_nonnegative_scalar("creep_time", self.creep_time))

    @property
    def coulomb_level(self) -> float:
        """F_c of the contact (eq. 9): beyond it there is no quasi-static position."""
        return self.friction.coulomb_level

    @property
    def has_creep(self) -> bool:
        """False when J = 0: the model is `friction` exactly."""
        return self.compliance > 0.0

    def __repr__(self) -> str:
        return (f"CreepingFriction({self.friction!r}, compliance={self.compliance!r}, "
                f"creep_time={self.creep_time!r})")  # fmt: skip


@njit(cache=True, error_model="numpy")
def creep_deflections(compliance, creep_time, offset, start, u_all, t_all, t_off,
                      out):  # fmt: skip  # pragma: no cover - compiled
    """out[p, s] += y_c of every record (t_off) for every parameter set p.

    Record i starts at the deflection ``start[p, i]`` (NaN: at equilibrium with its
    first force, J·(u_0 − offset)); u − offset is linear between samples and
    τ·ẏ_c + y_c = J·(u − offset) is solved exactly on each interval: with r = h/τ,
    y_c ← e^(−r)·y_c + J·(q·u_a + (1 − q/r)·Δu), q = 1 − e^(−r).
    """
    for p in range(compliance.shape[0]):
        jp = compliance[p]
        tau = creep_time[p]
        if jp == 0.0:  # no creep: the PI model exactly
            continue
        for i in range(t_off.shape[0] - 1):
            a, b = t_off[i], t_off[i + 1]
            yc = start[p, i]
            if yc != yc:
                yc = jp * (u_all[a] - offset[p])
            out[p, a] += yc
            for m in range(a + 1, b):
                ua = u_all[m - 1] - offset[p]
                du = u_all[m] - u_all[m - 1]
                h = t_all[m] - t_all[m - 1]
                if tau > 0.0:
                    r = h / tau
                    q = -math.expm1(-r)
                    yc = math.exp(-r) * yc + jp * (q * ua + (1.0 - q / r) * du)
                else:
                    yc = jp * (ua + du)
                out[p, m] += yc
