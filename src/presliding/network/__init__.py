"""Structures with many friction contacts: multi-DOF motion with exact stiction per contact.

M·q̈ + C·q̇ + K·q + W·λ = f(t), each contact c a 1-D tangential contact g_c = w_cᵀq with
its own `PIFriction` (eq. 8; the paper's closing question: eq. 17 with interacting
stop nonlinearities), and quasi-static networks of springs, Coulomb sliders and stops
reduced to one exact PI operator (Krejčí et al., Phys. Rev. E 90, 032822, 2014).

Files
-----
structure.py          `NetworkStructure` (M, C, K, W, models, f) and helpers: a chain, a
                      mass on several contacts, a modal model with contacts
exact.py              `simulate_network`: exact event-driven motion
moreau.py             `simulate_network_moreau`: Moreau–Jean time stepping (many contacts)
results.py            `NetworkResult`, `NetworkEnergy`, `NetworkState`
_start.py             the start of a run (initial state, t_start, t_end), checked once
_piece.py             the closed form of one piece (modes, or a matrix exponential)
_events.py            certified events: cells of the closed form with derivative bounds
_contact_problem.py   stick/slip at an instant: the box QP over the Delassus matrix
_exact_run.py         the event loop's operations on its state (stick sets with general
                      redundancy, ill-conditioned damped modes)
_exact_kernel.py      the compiled event loop: pieces, events, samples
_kernel_piece.py      compiled: a piece's modes (Cholesky + eigh) and affine event functions
_kernel_damped.py     compiled: damped pieces by complex modes, their dissipation
_kernel_events.py     compiled: certified events on cells, Brent's method
_kernel_contacts.py   compiled: the box QP over the Delassus matrix, the decision at rest
_warm.py              the compiled loop on a cold cache: compiled by a second process
_moreau_kernel.py     its compiled loop: θ-method, PGS on the Delassus matrix per step
_moreau_sparse.py     its sparse loop: Gauss–Seidel on the velocities, no Ŵ⁻¹
_matrices.py          the structure's matrices checked (dense or scipy.sparse), sizes first
_plots.py             figures of a network result
slider_network.py     `SliderNetwork`: springs, Coulomb sliders and stops (quasi-static)
quasi_static.py       `quasi_static_network`: the exact piecewise-linear quasi-static response
_qs_solver.py         the event-driven active-set solution of the sweeping process
compile.py            `compile_network`: a network driven through one input as a `PIFriction`
compile_joints.py     `compile_structure`: a structure with joints loaded along one vector as a
                      linear spring plus a PI operator (force-driven, order-preservation checked)

May import: `presliding.friction`, `presliding.hysteresis` and the root's shared modules.
It does not import `presliding.motion` or `presliding.analysis` (sibling layers).
"""

from presliding.network.compile import compile_network, network_virgin_curve
from presliding.network.compile_joints import CompiledStructure, compile_structure
from presliding.network.exact import simulate_network
from presliding.network.moreau import simulate_network_moreau
from presliding.network.quasi_static import QuasiStaticNetworkResult, quasi_static_network
from presliding.network.results import NetworkEnergy, NetworkResult, NetworkState
from presliding.network.slider_network import GROUND, SliderNetwork
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
