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

May import: `presliding.identification`, `presliding.network`, `presliding.analysis`,
`presliding.measurement`, `presliding.motion`, `presliding.friction`, `presliding.hysteresis`
and the root's shared modules.
"""

from presliding.structural.backbone import ModalBackbone, modal_backbone
from presliding.structural.structure import JointedStructure

__all__ = ["JointedStructure", "ModalBackbone", "modal_backbone"]
