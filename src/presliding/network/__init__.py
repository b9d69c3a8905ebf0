"""Structures with many friction contacts: multi-DOF motion with exact stiction per contact.

M·q̈ + C·q̇ + K·q + W·λ = f(t), each contact c a 1-D tangential contact g_c = w_cᵀq with
its own `PIFriction` (eq. 8; the paper's closing question: eq. 17 with interacting
stop nonlinearities).

Files
-----
structure.py          `NetworkStructure` (M, C, K, W, models, f) and helpers: a chain, a
                      mass on several contacts, a modal model with contacts
exact.py              `simulate_network`: exact event-driven motion
moreau.py             `simulate_network_moreau`: Moreau–Jean time stepping (many contacts)
results.py            `NetworkResult`, `NetworkEnergy`, `NetworkState`
_piece.py             the closed form of one piece (modes, or a matrix exponential)
_events.py            events on a grid of the closed form, refined by Brent's method
_contact_problem.py   stick/slip at an instant: the box QP over the Delassus matrix
_exact_run.py         the event loop's operations on its state
_moreau_kernel.py     its compiled loop: θ-method, PGS on the Delassus matrix per step
_plots.py             figures of a network result

May import: `presliding.friction`, `presliding.hysteresis` and the root's shared modules.
It does not import `presliding.motion` or `presliding.analysis` (sibling layers).
"""

from presliding.network.exact import simulate_network
from presliding.network.moreau import simulate_network_moreau
from presliding.network.results import NetworkEnergy, NetworkResult, NetworkState
from presliding.network.structure import (
    NetworkStructure,
    chain_structure,
    modal_structure,
    multi_contact_structure,
)

__all__ = [
    "NetworkEnergy",
    "NetworkResult",
    "NetworkState",
    "NetworkStructure",
    "chain_structure",
    "modal_structure",
    "multi_contact_structure",
    "simulate_network",
    "simulate_network_moreau",
]
