"""The one-mode model a joint fit adjusts: a joint, a linear spring and viscous damping.

Per unit modal mass, in the coordinate of the data's amplitude a: P(a) = k₀·a + F_v(a),
F_v the joint's virgin curve (a PI operator: Segalman's four-parameter Iwan density,
Mindlin's contact, or one Jenkins element), and the fixture's viscous damping c. What
the data measure, by `definition`:

* 'ring_down'   (a free decay, `analyze_ring_down`): ω₁(a), the loop's first harmonic,
  and ζ = D/(2π·a²·P'(a)) + c/(2ω₁) (`_slow_flow`);
* 'steady_state' (stepped sines at resonance, the first harmonic's energy balance):
  ω₁(a) and ζ = D/(2π·a²·ω₁²) + c/(2ω₁);
* 'quasi_static' (quasi-static modal analysis): ω = √(P/a), ζ = D/(2π·a·P) + c/(2ω);

and D(a) itself, the joint's dissipation per cycle.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from presliding.analysis import amplitude_response
from presliding.friction import PIFriction
from presliding.hysteresis import MindlinContact, SegalmanIwan
from presliding.structural._slow_flow import harmonic_stiffness_density, stop_harmonic

FloatArray = NDArray[np.float64]

DEFINITIONS = ("ring_down", "steady_state", "quasi_static")


def _segalman(p: Mapping[str, float]) -> PIFriction:
    joint = SegalmanIwan(p["stiffness"], p["slip_force"], p["exponent"], p["mass_ratio"])
    return PIFriction(0.0, density=joint)


def _mindlin(p: Mapping[str, float]) -> PIFriction:
    return PIFriction(0.0, density=MindlinContact(p["slip_force"], p["slip_displacement"]))


def _jenkins(p: Mapping[str, float]) -> PIFriction:
    return PIFriction(0.0, [p["stiffness"]], breakaway=[p["slip_force"]])


@dataclass(frozen=True)
class JointKind:
    """A joint model's parameters, their bounds and units, and how to build it."""

    names: tuple[str, ...]
    bounds: Mapping[str, tuple[float, float]]
    units: Mapping[str, str]
    build: Callable[[Mapping[str, float]], PIFriction]


STIFF, FORCE = "N/(m kg)", "N/kg"
JOINTS = {
    "segalman": JointKind(
        ("stiffness", "slip_force", "exponent", "mass_ratio"),
        {"stiffness": (0.0, np.inf), "slip_force": (0.0, np.inf), "exponent": (-0.999, 1.0),
         "mass_ratio": (0.0, np.inf)},
        {"stiffness": STIFF, "slip_force": FORCE, "exponent": "", "mass_ratio": ""},
        _segalman,
    ),
    "mindlin": JointKind(
        ("slip_force", "slip_displacement"),
        {"slip_force": (0.0, np.inf), "slip_displacement": (0.0, np.inf)},
        {"slip_force": FORCE, "slip_displacement": "m"},
        _mindlin,
    ),
    "jenkins": JointKind(
        ("stiffness", "slip_force"),
        {"stiffness": (0.0, np.inf), "slip_force": (0.0, np.inf)},
        {"stiffness": STIFF, "slip_force": FORCE},
        _jenkins,
    ),
}  # fmt: skip
#: The parameters every joint fit adds: the rest of the mode's stiffness and its damping.
MODE = {"linear_stiffness": (0.0, np.inf), "viscous": (0.0, np.inf)}
MODE_UNITS = {"linear_stiffness": STIFF, "viscous": "N s/(m kg)"}


def segalman_elements(joint: SegalmanIwan, cells: int) -> PIFriction:
    """Segalman's joint as stops for the exact event solver: the power law R·r^χ in equal
    cells (each cell's stiffness at its midpoint) and the point mass S as its own stop
    at φ_max (a plain midpoint discretisation would move it half a cell inwards)."""
    edges = np.linspace(0.0, joint.max_threshold, cells + 1)
    chi = joint.exponent
    k = joint.height * (edges[1:] ** (chi + 1) - edges[:-1] ** (chi + 1)) / (chi + 1)
    r = 0.5 * (edges[1:] + edges[:-1])
    if joint.point_mass > 0:
        k, r = np.r_[k, joint.point_mass], np.r_[r, joint.max_threshold]
    return PIFriction(0.0, k, threshold=r)


def _tail(joint: PIFriction, a: FloatArray) -> FloatArray:
    density = joint.density
    assert density is not None
    return np.where(a < density.max_threshold, np.asarray(density.tail(a), dtype=float), 0.0)


def _harmonic(joint: PIFriction, a: FloatArray) -> FloatArray:
    """The joint's first-harmonic in-phase stiffness at amplitudes a."""
    if joint.is_discrete:
        k, r = np.asarray(joint.stiffness), np.asarray(joint.threshold)
        return np.asarray(stop_harmonic(r[None, :] / a[:, None]) @ k)
    density = joint.density
    assert density is not None
    return harmonic_stiffness_density(density.tail, density.max_threshold, a)


def predict(kind: JointKind, values: Mapping[str, float], a: FloatArray,
            definition: str) -> tuple[FloatArray, FloatArray, FloatArray]:  # fmt: skip
    """(ω, ζ, D) of the model at amplitudes a (module notes)."""
    joint = kind.build(values)
    k0, c = values["linear_stiffness"], values["viscous"]
    ar = amplitude_response(joint, a)
    d = ar.dissipation
    if definition == "quasi_static":
        p = k0 * a + ar.force
        w = np.sqrt(p / a)
        return w, d / (2.0 * math.pi * p * a) + c / (2.0 * w), d
    w = np.sqrt(k0 + _harmonic(joint, a))
    if definition == "steady_state":
        return w, d / (2.0 * math.pi * a * a * w * w) + c / (2.0 * w), d
    tangent = np.maximum(k0 + _tail(joint, a), 1e-12 * (k0 + joint.initial_stiffness))
    return w, d / (2.0 * math.pi * a * a * tangent) + c / (2.0 * w), d
