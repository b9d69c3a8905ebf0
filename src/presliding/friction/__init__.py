"""Friction models: the PI friction law and the classical baselines (eqs. 7–10).

Files
-----
pi_friction.py        `PIFriction`: c1·sign(ẏ) + Σ k_j (y − x_j) (eq. 8), or a density μ (eq. 10)
baselines.py          `CoulombFriction`, `DahlFriction`, `LuGreFriction` and their states
creep.py              `CreepingFriction`: PI friction in series with a Kelvin–Voigt element
gms.py                `GMSFriction`, `GMSState`: generalized Maxwell-slip (Stribeck curve, lag)
comparison.py         `compare`: several models on one displacement path, as a `Comparison`
preload.py            `preloaded_state`: a memory with a given elastic force (a record's preload)
batch.py              `friction_batch`: B finite-element models on one path as a `PIBatch`
_baseline_kernels.py  compiled time loops of the Dahl and LuGre models, and their single steps
_gms_kernels.py       the GMS element over a step in closed form, and its path loop
_parts.py             a model's elements or its density, typed (`elements`, `density_of`)
_summary.py           what a `PIFriction` shows in a notebook: levels and stiffness
_pi_setup.py          validation and set-up of a `PIFriction` on construction
_sides.py             asymmetric friction: the two sides' levels, the asymmetric play band
_model_checks.py      checks the layers above make of a model (Coulomb element, finite stiffness)

May import: `presliding.hysteresis` and the package root's shared modules.
"""

from presliding.friction.baselines import (
    CoulombFriction,
    DahlFriction,
    DahlState,
    LuGreFriction,
    LuGreState,
)
from presliding.friction.batch import friction_batch
from presliding.friction.comparison import Comparison, compare
from presliding.friction.creep import CreepingFriction
from presliding.friction.gms import GMSFriction, GMSState
from presliding.friction.pi_friction import PIFriction
from presliding.friction.preload import preloaded_state

__all__ = [
    "Comparison",
    "CoulombFriction",
    "CreepingFriction",
    "DahlFriction",
    "DahlState",
    "GMSFriction",
    "GMSState",
    "LuGreFriction",
    "LuGreState",
    "PIFriction",
    "compare",
    "friction_batch",
    "preloaded_state",
]
