"""The event kernel at the edge of the stick band, where rounding decides: a break-away whose
net force rounds to zero in one order of operations, and a piece too small to move the
state in floating point. Both used to burn through `max_events` without advancing."""

from __future__ import annotations

import numpy as np

import presliding as ps
from presliding import PIState
from tests.helpers import rounding_break_away


def test_break_away_whose_net_force_rounds_to_zero_moves_on():
    c1 = 0.005
    u, fel = rounding_break_away(c1)
    s = np.sign(u - fel)
    # one element (k = 1 N/m, far from its threshold) preloaded to F_el = fel
    model = ps.PIFriction(c1, stiffness=[1.0], threshold=[10.0])
    state = PIState(0.0, np.array([-fel]))
    res = ps.simulate(model, 1.0, u, initial_state=state, t_end=1.0, max_events=1000)
    assert res.success, res.message
    assert res.n_events == 1
    # the stick test said it breaks away: it moves, by a tiny amount, in the direction of
    # u − F_el (the net force is of the order of the rounding unit of F_el)
    assert np.sign(res.position[-1]) == s
    assert 0.0 < abs(res.position[-1]) < 1e-15
    assert np.all(s * np.diff(res.position) >= 0.0)


def test_a_piece_that_cannot_move_the_state_ends_the_motion_until_u_changes():
    """Two elements deformed against each other (F_el = 0) and u one rounding unit above c1:
    the piece from rest back to rest (half a period, π/ω = 2.2 s) moves y and both
    deformations by 1e-18, less than their rounding unit, so the state repeats exactly. The
    kernel ends the motion after that piece instead of repeating it until u changes (450
    times over 1000 s)."""
    c1 = 0.005
    u = float(np.nextafter(c1, 1.0))
    model = ps.PIFriction(c1, stiffness=[1.0, 1.0], threshold=[10.0, 10.0])
    state = PIState(1.0, np.array([0.0, 2.0]))  # deformations +1 and -1
    t_change = 1000.0
    force = (np.array([0.0, t_change]), np.array([u, 2.0]))
    t_eval = np.linspace(0.0, 1001.0, 1002)
    res = ps.simulate(model, 1.0, force, initial_position=1.0, initial_state=state,
                      t_end=1001.0, t_eval=t_eval, max_events=100)  # fmt: skip
    assert res.success, res.message
    assert res.n_events <= 3
    assert np.all(res.position[res.time < t_change] == 1.0)
    quiet = (res.time > np.pi / np.sqrt(2.0)) & (res.time < t_change)
    assert np.all(res.velocity[quiet] == 0.0) and np.all(res.acceleration[quiet] == 0.0)
    # a change of u ends the rest: the larger force moves the mass
    assert res.position[-1] - 1.0 > 1e-3
