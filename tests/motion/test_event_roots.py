"""The single mass's events are closed-form first roots: none hides between samples.

`presliding.motion._event` finds no event on a grid (see its notes): the time to rest is
the first zero of the velocity, and the time to a threshold the unique crossing of an
increasing displacement. Checked here against 5,001 samples of the closed form.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from presliding.motion import _damped
from presliding.motion._event import closed_form, reach, time_to_reach, time_to_rest

speeds = st.floats(1e-3, 10.0)
accelerations = st.floats(-20.0, 20.0)


def _first_roots(times, t_rest, velocity, displacement, dist, t_dist):
    """v > 0 before t_rest, d < dist before t_dist, both within rounding at the roots."""
    before = times[times < t_rest * (1.0 - 1e-9)]
    assert np.all(velocity(before) > 0.0)
    early = times[times < t_dist * (1.0 - 1e-9)]
    assert np.all(displacement(early) < dist)
    assert abs(displacement(np.array([t_dist]))[0] - dist) <= 1e-12 * max(dist, 1e-300) + 1e-15


@settings(max_examples=60, deadline=None)
@given(vp=speeds, ap=accelerations, w=st.one_of(st.just(0.0), st.floats(0.1, 30.0)),
       frac=st.floats(0.01, 1.0))  # fmt: skip
def test_undamped_rest_and_threshold_times_are_first_roots(vp, ap, w, frac):
    t_rest = time_to_rest(vp, ap, w)
    if not np.isfinite(t_rest):  # accelerating for ever (no spring, ap >= 0)
        assert w == 0.0 and ap >= 0.0
        return
    dmax = reach(vp, ap, w)
    dist = frac * dmax
    t_dist = time_to_reach(vp, ap, w, dist)
    assert 0.0 < t_dist <= t_rest * (1 + 1e-12)

    def velocity(t):
        return np.array([closed_form(vp, ap, w, x)[1] for x in t])

    def displacement(t):
        return np.array([closed_form(vp, ap, w, x)[0] for x in t])

    times = np.linspace(0.0, t_rest, 5001)[1:]
    _first_roots(times, t_rest, velocity, displacement, dist, t_dist)
    assert abs(velocity(np.array([t_rest]))[0]) <= 1e-12 * (vp + abs(ap) * t_rest)


@settings(max_examples=60, deadline=None)
@given(vp=speeds, fp=st.floats(-20.0, -0.01), gam=st.floats(0.01, 20.0),
       w0sq=st.one_of(st.just(0.0), st.floats(0.01, 400.0)), frac=st.floats(0.01, 1.0))  # fmt: skip
def test_damped_rest_and_threshold_times_are_first_roots(vp, fp, gam, w0sq, frac):
    """Under-, critically and over-damped pieces (σ > 0): the rest is the first zero of the
    velocity, the threshold the one crossing before it."""
    ap = fp - 2.0 * gam * vp
    t_rest = _damped.rest_time(vp, fp, gam, w0sq)
    assert np.isfinite(t_rest)  # a decelerating force stops the mass
    dmax = _damped.state(vp, ap, gam, w0sq, t_rest)[0]
    dist = frac * dmax
    t_dist = _damped.time_to_distance(vp, ap, gam, w0sq, dist, t_rest)

    def velocity(t):
        return np.array([_damped.state(vp, ap, gam, w0sq, x)[1] for x in t])

    def displacement(t):
        return np.array([_damped.state(vp, ap, gam, w0sq, x)[0] for x in t])

    times = np.linspace(0.0, t_rest, 5001)[1:]
    _first_roots(times, t_rest, velocity, displacement, dist, t_dist)
