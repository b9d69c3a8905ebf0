"""Structures with many friction contacts: multi-DOF motion with exact stiction per contact.

M·q̈ + C·q̇ + K·q + W·λ = f(t), each contact c a 1-D tangential contact g_c = w_cᵀq with
its own `PIFriction` (eq. 8; the paper's closing question: eq. 17 with interacting
stop nonlinearities), and quasi-static networks of springs, Coulomb sliders and stops
reduced to one exact PI operator (Krejčí et al., Phys. Rev. E 90, 032822, 2014).

Files
-----
structure.py          `NetworkStructure` (M, C, K, W, models, f) and helpers: a chain, a
                      mass on several contacts, a modal model with contacts
results.py            `NetworkResult`, `NetworkEnergy`, `NetworkState`
_start.py             the start of a run (initial state, t_start, t_end), checked once
_contacts.py          the contacts' constant data (Coulomb, viscous, elements), both paths
_matrices.py          the structure's matrices checked (dense or scipy.sparse), sizes first
_plots.py             figures of a network result
_moved.py             the old module paths (``presliding.network.exact``, ...) kept as aliases

Rooms
-----
events/               exact event-driven motion (`simulate_network`): closed-form pieces,
                      certified events, the contact decision, the compiled event loop
stepping/             Moreau–Jean time stepping (`simulate_network_moreau`), dense and sparse
sliders/              quasi-static networks of springs, Coulomb sliders and stops
                      (`SliderNetwork`, `quasi_static_network`)
reduction/            a network or a structure with joints driven through one input as one PI
                      operator (`compile_network`, `compile_structure`)

Data flows one way: the shared ground above imports no room; `events` and `stepping` run a
`NetworkStructure` and do not import each other; `reduction` builds on `sliders`.

May import: `presliding.friction`, `presliding.hysteresis` and the root's shared modules.
It does not import `presliding.motion` or `presliding.analysis` (sibling layers).
"""

from presliding.network import _moved  # noqa: F401  (registers the old module paths)
from presliding.network.events.exact import simulate_network
from presliding.network.reduction.compile import compile_network, network_virgin_curve
from presliding.network.reduction.compile_joints import CompiledStructure, compile_structure
from presliding.network.results import NetworkEnergy, NetworkResult, NetworkState
from presliding.network.sliders.quasi_static import QuasiStaticNetworkResult, quasi_static_network
from presliding.network.sliders.slider_network import GROUND, SliderNetwork
from presliding.network.stepping.moreau import simulate_network_moreau
from presliding.network.structure import (
    NetworkStructure,
    chain_structure,
    modal_structure,
    multi_contact_structure,
)

__all__ = [
    "GROUND",
    "CompiledStructure",
    "NetworkEnergy",
    "NetworkResult",
    "NetworkState",
    "NetworkStructure",
    "QuasiStaticNetworkResult",
    "SliderNetwork",
    "chain_structure",
    "compile_network",
    "compile_structure",
    "modal_structure",
    "multi_contact_structure",
    "network_virgin_curve",
    "quasi_static_network",
    "simulate_network",
    "simulate_network_moreau",
]
