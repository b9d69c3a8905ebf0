"""Quasi-static networks of springs, Coulomb sliders and stops, and their exact response.

Files
-----
slider_network.py     `SliderNetwork`: springs, Coulomb sliders and stops (quasi-static)
quasi_static.py       `quasi_static_network`: the exact piecewise-linear quasi-static response
_qs_solver.py         the event-driven active-set solution of the sweeping process

May import: `presliding.hysteresis`, `presliding.plotting` and the root's shared modules.
Not the other rooms of network, nor network's shared ground (a slider network is no
`NetworkStructure`).
"""
