"""Exact event-driven motion: closed-form pieces between certified events.

Between two events every contact sticks or slides in a fixed direction with a fixed
set of elastic elements, so the motion is a closed form; at each event the contacts at
rest decide stick or slip together by one box QP over the Delassus matrix. One
compiled event loop runs it; a general loop in numpy follows the same rules (and runs
while a cold cache is being filled by a second process).

Files
-----
exact.py              `simulate_network`: exact event-driven motion
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

May import: network's shared ground (`structure`, `results`, `_start`, `_contacts`,
`_matrices`), `presliding.friction`, `presliding.hysteresis` and the root's shared modules.
Not the other rooms of network.
"""
