"""Networks and structures driven through one input, reduced to one exact PI operator.

Krejčí et al., Phys. Rev. E 90, 032822 (2014): an order-preserving network driven
through one input is a PI operator; the reduction is checked (every slider's direction
watched, the network replayed over nested reversals against the compiled operator).

Files
-----
compile.py            `compile_network`: a network driven through one input as a `PIFriction`
compile_joints.py     `compile_structure`: a structure with joints loaded along one vector as a
                      linear spring plus a PI operator (force-driven, order-preservation checked)

May import: the room `sliders` of network, `presliding.friction`, `presliding.hysteresis`
and the root's shared modules. Not the rooms `events` and `stepping`.
"""
