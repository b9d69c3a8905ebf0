"""The rate-dependent friction models the pooled response fit identifies, as named parameters.

`fit_response(family=...)` fits, besides the PI model of `_model_spec`:

* ``"gms"``, the generalized Maxwell-slip model (`GMSFriction`): the PI model's
  parameters (``coulomb_level``, ``coulomb``, ``stiffness_j``, or ``coulomb``,
  ``stiffness_j``, ``breakaway_j``) and ``stribeck_drop`` F_S − F_C >= 0 [N],
  ``stribeck_velocity`` v_s [m/s], ``lag_time`` τ >= 0 [s] (the Stribeck exponent is
  held at 2). With ``stribeck_drop = 0`` and ``lag_time = 0`` it is the PI model.
* ``"lugre"`` (`LuGreFriction`): ``coulomb`` F_c, ``stribeck_drop`` F_s − F_c,
  ``stiffness`` σ0, ``damping`` σ1, ``stribeck_velocity`` v_s (σ2 is the fit's
  ``viscous``).
* ``"dahl"`` (`DahlFriction`, α = 1): ``coulomb`` F_c and ``stiffness`` σ0.

The drop F_S − F_C is fitted instead of F_S so that its bound (0: no Stribeck
fall) is fixed; the static level is a derived value. `pack` gives the parameter
vector of the compiled step (`presliding.motion._rate_step`).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from presliding.friction.baselines import DahlFriction, LuGreFriction
from presliding.friction.gms import GMSFriction
from presliding.identification.problem._model_spec import TINY, ModelSpec
from presliding.motion import _rate_step

FloatArray = NDArray[np.float64]
FAMILIES = ("gms", "lugre", "dahl")
#: the Stribeck exponent δ of the fitted GMS model (Gaussian, as LuGre's)
EXPONENT = 2.0
#: parameters that may be 0 (all others of a family are positive)
NONNEGATIVE = ("coulomb", "stribeck_drop", "lag_time", "damping")
_RATE = ("stribeck_drop", "stribeck_velocity", "lag_time")


class FamilySpec:
    """Named parameters of a GMS, LuGre or Dahl model and their kernel vector (module notes)."""

    def __init__(self, family: str, pi: ModelSpec):
        self.family, self.pi = family, pi
        self.negative = None  # one level for both directions (asymmetric=True is the PI fit's)
        self.code = {"gms": _rate_step.GMS, "lugre": _rate_step.LUGRE,
                     "dahl": _rate_step.DAHL}[family]  # fmt: skip
        self.density, self.cells = None, pi.cells
        if family == "gms":
            self.n, self.equal = pi.n, pi.equal
            self.k_names, self.c_names = pi.k_names, pi.c_names
            self.names = [*pi.names, *_RATE]
        else:
            self.n, self.equal, self.k_names, self.c_names = 0, False, [], []
            self.names = (["coulomb", "stribeck_drop", "stiffness", "damping", "stribeck_velocity"]
                          if family == "lugre" else ["coulomb", "stiffness"])  # fmt: skip
        self.h_names: list[str] = []

    @property
    def has_level_parameter(self) -> bool:
        """True when F_C is a parameter (GMS with equal break-away forces)."""
        return self.family == "gms" and self.pi.has_level_parameter

    def positive(self, name: str) -> bool:
        """Whether a parameter must be positive (not those of `NONNEGATIVE`)."""
        if self.family == "gms" and name in self.pi.names:
            return self.pi.positive(name)
        return name in self.names and name not in NONNEGATIVE

    def bounds(self) -> dict[str, tuple[float, float]]:
        return dict.fromkeys(self.names, (0.0, np.inf))

    # ------------------------------------------------------------ values → model
    def bank(self, q: Mapping[str, float]) -> tuple[float, FloatArray, FloatArray]:
        """c1, k_j, r_j of a GMS model's elements; (F_c, none, none) for LuGre and Dahl."""
        if self.family == "gms":
            return self.pi.bank(q)
        return max(q["coulomb"], TINY), np.empty(0), np.empty(0)

    def coulomb_level(self, q: Mapping[str, float]) -> float:
        """F_C: the friction of fast steady sliding."""
        return self.pi.coulomb_level(q) if self.family == "gms" else float(q["coulomb"])

    def pack(self, q: Mapping[str, float]) -> tuple[FloatArray, FloatArray, FloatArray]:
        """The compiled step's parameter vector and the GMS elements (k, c)."""
        par = np.zeros(_rate_step.N_PARAMETERS)
        sigma = max(q.get("viscous", 0.0), 0.0)
        empty = np.empty(0)
        drop = max(q.get("stribeck_drop", 0.0), 0.0)
        vs = max(q.get("stribeck_velocity", 1.0), TINY)
        if self.family == "gms":
            c1, k, r = self.pi.bank(q)
            fc = self.pi.coulomb_level(q)
            ratio = (fc + drop) / fc if fc > 0 else 1.0
            par[:] = (c1, ratio, vs, EXPONENT, max(q["lag_time"], 0.0), sigma)
            return par, k, k * r
        fc = max(q["coulomb"], TINY)
        s0 = max(q["stiffness"], TINY)
        if self.family == "lugre":
            par[:] = (fc, fc + drop, s0, max(q["damping"], 0.0), sigma, vs)
        else:
            par[:4] = (fc, s0, 1.0, sigma)
        return par, empty, empty

    def model(self, q: Mapping[str, float]) -> GMSFriction | LuGreFriction | DahlFriction:
        """The identified model (σ from ``viscous``)."""
        sigma = max(q.get("viscous", 0.0), 0.0)
        if self.family == "gms":
            c1, k, r = self.pi.bank(q)
            fc = self.pi.coulomb_level(q)
            return GMSFriction(c1, k, k * r, static_level=fc + max(q["stribeck_drop"], 0.0),
                               stribeck_velocity=max(q["stribeck_velocity"], TINY),
                               stribeck_exponent=EXPONENT, lag_time=max(q["lag_time"], 0.0),
                               viscous=sigma)  # fmt: skip
        fc = max(q["coulomb"], TINY)
        if self.family == "lugre":
            return LuGreFriction(fc, fc + max(q["stribeck_drop"], 0.0), max(q["stiffness"], TINY),
                                 max(q["damping"], 0.0), sigma,
                                 max(q["stribeck_velocity"], TINY))  # fmt: skip
        return DahlFriction(fc, max(q["stiffness"], TINY), viscous=sigma)

    def derived(self, q: Mapping[str, float]) -> dict[str, float]:
        """The static level F_S and, for GMS, F_C where it is not a parameter."""
        out: dict[str, float] = {}
        if self.family == "gms":
            if not self.pi.has_level_parameter:
                out["coulomb_level"] = self.pi.coulomb_level(q)
            out["static_level"] = self.pi.coulomb_level(q) + q["stribeck_drop"]
        elif self.family == "lugre":
            out["static"] = q["coulomb"] + q["stribeck_drop"]
        return out
