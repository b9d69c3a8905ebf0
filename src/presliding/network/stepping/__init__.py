"""Moreau–Jean time stepping: many contacts, a fixed step, the contact law solved exactly.

Files
-----
moreau.py             `simulate_network_moreau`: Moreau–Jean time stepping (many contacts)
_moreau_kernel.py     its compiled loop: θ-method, PGS on the Delassus matrix per step
_moreau_sparse.py     its sparse loop: Gauss–Seidel on the velocities, no Ŵ⁻¹

May import: network's shared ground (`structure`, `results`, `_start`, `_contacts`,
`_matrices`), `presliding.friction`, `presliding.hysteresis` and the root's shared modules.
Not the other rooms of network.
"""
