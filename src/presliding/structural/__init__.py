"""Jointed structures end to end: amplitude-dependent modes, ring-downs, joint fits, periodic
responses.

Structural dynamics of structures with frictional joints (bolted joints as Iwan models,
i.e. PI operators with a density): quasi-static modal analysis, exact for the model, free
decays and what a ring-down measures, and the frequency responses under harmonic forcing.

Files
-----
structure.py      `JointedStructure`: M, K, C, the joints' directions W, one PI or Iwan model each
backbone.py       `modal_backbone`, `ModalBackbone`: ω(a), ζ(a), D(a) of a mode, exactly
_single_joint.py  the closed-form virgin curve of a structure with one joint (any density)
periodic.py       `periodic_orbit`, `frequency_response`, `force_response`: exact periodic
                  responses (shooting, pseudo-arclength continuation, Floquet multipliers)
periodic_results.py  `PeriodicOrbit`, `FrequencyResponse`
_pieces.py        the closed form between events of a structure with stop joints (c1 = 0)
_joint_events.py  its events: on a grid of the closed form, grazing checked, refined by Brent
_joint_run.py     its event loop: samples, exact state transition and parameter derivative
_shooting.py      Newton on the period map, continuation (tangent, corrector, corners)
_orbit.py         an orbit's pieces: samples, exact peak amplitudes, exact Fourier coefficients
_slow_flow.py     what a slow free decay shows: the loop's first harmonic, ζ from the energy
motion.py         `simulate_structure`, `simulate_ring_down`, `StructureMotion`: exact motion
ring_down.py      `analyze_ring_down`, `RingDown`: ω(A), ζ(A) of a free decay (analytic
                  signal or peaks), stated errors, comparison with a backbone
_ring_down_estimators.py  band-pass, analytic signal, extremes, windowed fits
fit_joint.py      `fit_joint`: a joint (Segalman, Mindlin, Jenkins) and the mode's viscous
                  damping from ω(a), ζ(a) or D(a), on the engine of every fit
_joint_model.py   the one-mode model it adjusts, and what each kind of data measures

May import: `presliding.identification`, `presliding.network`, `presliding.analysis`,
`presliding.measurement`, `presliding.motion`, `presliding.friction`, `presliding.hysteresis`
and the root's shared modules.
"""

from presliding.structural.backbone import ModalBackbone, modal_backbone
from presliding.structural.fit_joint import fit_joint
from presliding.structural.motion import StructureMotion, simulate_ring_down, simulate_structure
from presliding.structural.periodic import force_response, frequency_response, periodic_orbit
from presliding.structural.periodic_results import FrequencyResponse, PeriodicOrbit
from presliding.structural.ring_down import RingDown, analyze_ring_down
from presliding.structural.structure import JointedStructure

__all__ = [
    "FrequencyResponse",
    "JointedStructure",
    "ModalBackbone",
    "PeriodicOrbit",
    "RingDown",
    "StructureMotion",
    "analyze_ring_down",
    "fit_joint",
    "force_response",
    "frequency_response",
    "modal_backbone",
    "periodic_orbit",
    "simulate_ring_down",
    "simulate_structure",
]
