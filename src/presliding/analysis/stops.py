"""When does a free mass with PI friction stop? (section 3, eqs. 12–16).

Free motion (eq. 12 with a mass m): m·ÿ + c1·sign(ẏ) + F_el(y) = 0. Between two
turning points the mass moves monotonically, the elastic force follows one
Masing branch of the memory, and the next turning point follows from the
work-energy balance alone — no time stepping (see `_turning`). At a turning
point the mass sticks if |F_el| <= c1: the Coulomb element is set-valued at
zero velocity, so **equality sticks** (the paper's eq. 16 is written with a
strict inequality; at equality the static friction balances the elastic force
exactly and the mass stays). Comparisons allow a relative slack of 8 rounding
units of F_c so that an exact tie computed with rounding still sticks.

From the saturated start the paper assumes (elastic force F_m at the first
turning point y = 0, motion towards positive y), the elastic force is

    Φ(y) = ∫_0^{y/2} r dμ + ∫_{y/2}^R (y − r) dμ = −F_m + 2·Φv(y/2)      (eq. 14)

with Φv the elastic virgin curve, the second turning point y_e is the smallest
positive root of c1·y + ∫_0^y Φ = 0 (eq. 15), and the mass stops there iff
c1 >= Φ(y_e) (eq. 16, equality sticking).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    _first_bad,
    as_count,
    as_positive_scalar,
    as_real_array,
    as_real_scalar,
    fmt,
)
from presliding.analysis._turning_result import TurningPoints
from presliding.analysis._walks import (
    DensitySwing,
    DensityWalk,
    ElementWalk,
    check_reach,
    element_swing,
)
from presliding.friction._model_checks import check_finite_stiffness
from presliding.friction._parts import density_of, elements
from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis import _general_pi as gk
from presliding.hysteresis.general_pi import MemoryState
from presliding.hysteresis.operators import PIState

if TYPE_CHECKING:  # pragma: no cover
    pass

__all__ = ["TurningPoints", "phi", "stops_at_turning_point", "turning_point", "turning_points"]

FloatArray = NDArray[np.float64]
_SLACK = 8 * np.finfo(np.float64).eps
#: The largest `max_reversals` of `turning_points` (each reversal of a density
#: model costs a root search, about 0.1 ms).
MAX_REVERSALS = 100_000


def _model(model: PIFriction) -> PIFriction:
    if not isinstance(model, PIFriction):
        raise TypeError(f"`model` must be a PIFriction; got {type(model).__name__}.")
    return model


def _undamped(model: PIFriction, what: str) -> PIFriction:
    """The model, checked to have no viscous term (the work-energy balance of eqs. 13–16)."""
    model = _model(model)
    if model.viscous != 0.0:
        raise ValueError(
            f"{what} assumes no viscous friction (the paper's assumption (i)); got "
            f"`model.viscous` = {fmt(model.viscous)}: the viscous loss depends on the time "
            "course of the motion, so simulate it with `presliding.simulate` (exact event "
            "method) instead."
        )
    return model


def sticks(model: PIFriction, elastic_force: float) -> bool:
    """A mass at rest sticks when |F_el| <= c1 (equality sticks, within rounding)."""
    return bool(abs(elastic_force) <= model.coulomb + _SLACK * model.coulomb_level)


def phi(model: PIFriction, displacement: ArrayLike) -> FloatArray | float:
    """Φ(y), the elastic force after a reversal from saturation (eq. 14).

    Parameters
    ----------
    model : PIFriction
    displacement : float or array_like
        y >= 0, the distance from the turning point where the elastic force was
        −F_m (the motion reverses towards positive y).

    Returns
    -------
    float or ndarray
        Φ(y) = −F_m + 2·Φv(y/2): −F_m at y = 0, rising with slope μ([0, R])
        (eq. 7), F_m once y >= 2R.
    """
    model = _model(model)
    y = as_real_array("displacement", displacement)  # rejects strings, bools, NaN
    if np.any(y < 0):
        raise ValueError(f"`displacement` must be nonnegative; {_first_bad(y, y < 0)}.")
    out = -model.max_elastic_force + 2.0 * model.virgin_curve(0.5 * y, elastic_only=True)
    return float(out) if np.ndim(out) == 0 else out


def turning_point(model: PIFriction) -> float:
    """y_e, the smallest positive root of c1·y + ∫_0^y Φ(s) ds = 0 (eq. 15).

    The second turning point of a free motion that reached the first one (at
    y = 0) with the elastic force saturated at F_m. Exact (a quadratic) for
    finite elements; `scipy.optimize.brentq` to rounding for a density.

    Parameters
    ----------
    model : PIFriction
        Finite elements or a density, with c1 < F_m.

    Returns
    -------
    float
        y_e > 0 [m], measured from the first turning point.

    Raises
    ------
    ValueError
        If c1 >= F_m: the mass sticks at the first turning point and eq. 15 has
        no positive root; or if the model has a viscous term (σ > 0), which
        eq. 15 does not include (use `presliding.simulate`).
    """
    model = _undamped(model, "`turning_point` (eq. 15)")
    fm, c1 = model.max_elastic_force, model.coulomb
    if c1 >= fm:
        raise ValueError(
            f"`model.coulomb` must be below F_m = Σc_j for eq. 15 to have a positive root "
            f"(otherwise the mass sticks at the first turning point); got {fmt(c1)} >= {fmt(fm)}."
        )
    if model.is_discrete:
        k, r, _ = elements(model)
        u, _ = element_swing(k, r, c1, -r, 1.0, 0.0)
        return float(u)
    state = MemoryState.saturated(0.0, -1.0, density_of(model).max_threshold)
    head, stack = _start(model, state, 1.0)
    y, _ = DensitySwing(density_of(model), c1).swing(head, stack, 1.0, 0.0)
    return float(y)


def stops_at_turning_point(model: PIFriction) -> bool:
    """Eq. 16: does the free motion from saturation stop at y_e after one reversal?

    True iff c1 >= Φ(y_e) (equality sticks, see the module notes). Also True
    when c1 >= F_m: the mass then sticks at the first turning point already,
    with no reversal at all.

    Parameters
    ----------
    model : PIFriction
        Finite elements or a density.

    Returns
    -------
    bool
        Whether c1 >= Φ(y_e) (eq. 16) or c1 >= F_m.

    Raises
    ------
    ValueError
        If the model has a viscous term (σ > 0): eq. 16 assumes σ = 0; use
        `presliding.simulate`.
    """
    model = _undamped(model, "`stops_at_turning_point` (eq. 16)")
    if model.coulomb >= model.max_elastic_force:
        return True
    return sticks(model, float(phi(model, turning_point(model))))


def _start(model: PIFriction, state: MemoryState, s: float) -> tuple[FloatArray, FloatArray]:
    """Working memory with the motion set to direction s (a reversal pushed if needed)."""
    d = density_of(model)
    head, stack = state.working_memory(d)
    if head[1] != 0.0 and head[1] != s:
        stack = gk._push(head, stack, d._kind, d._par, d._tab)
    head[1] = s
    return head, stack


def turning_points(
    model: PIFriction,
    mass: float,
    initial_velocity: float,
    initial_state: str | PIState | MemoryState = "relaxed",
    *,
    initial_position: float = 0.0,
    max_reversals: int = 1000,
) -> TurningPoints:
    """Every turning point of the free motion m·ÿ + c1·sign(ẏ) + F_el(y) = 0 (eq. 12).

    Exact: each half swing solves the work-energy balance along one Masing
    branch (a quadratic for finite elements, a scalar root for a density), for
    any number of reversals. Only ½·m·v0² matters for the positions.

    Parameters
    ----------
    model : PIFriction
    mass : float
        m > 0 [kg].
    initial_velocity : float
        v0 [m/s]; 0 starts at rest (the mass moves only if |F_el| > c1).
    initial_state : {'relaxed', 'saturated'} or PIState or MemoryState
        'saturated' means saturated in the direction of v0 (a long slide
        before, the paper's assumption for eqs. 13–16). A state object fixes
        the position itself (its last input). A finite-element model also
        accepts a `MemoryState` (its `Discrete` density is then walked level by
        level with root finding instead of the element-wise quadratics).
    initial_position : float
        y0 for the string states.
    max_reversals : int
        Stop counting after this many reversals (status 'max_reversals' or
        'never_stops'); at most `MAX_REVERSALS` (100000, about 10 s for a
        density model).

    Raises
    ------
    ValueError
        If the model has a viscous term (σ > 0): the half swings follow from
        the work-energy balance only without it (the paper's assumption (i));
        `presliding.simulate` solves the damped motion exactly.
    """
    model = _undamped(model, "`turning_points`")
    check_finite_stiffness(model.initial_stiffness, "`turning_points`", model.density)
    m = as_positive_scalar("mass", mass)
    v0 = as_real_scalar("initial_velocity", initial_velocity)
    y0 = as_real_scalar("initial_position", initial_position)
    max_reversals = as_count("max_reversals", max_reversals, maximum=MAX_REVERSALS)
    state = _initial_state(model, initial_state, y0, v0)
    check_reach(model, state, m, v0)
    walk = ElementWalk(model, state) if isinstance(state, PIState) else DensityWalk(model, state)
    y0 = walk.position
    kinetic, s = 0.5 * m * v0 * v0, float(np.sign(v0))
    positions: list[float] = []
    forces: list[float] = []
    status, message = "stopped", ""
    if s == 0.0:
        f = walk.force()
        if sticks(model, f):
            message = f"at rest with |F_el| = {abs(f):.6g} N <= c1 = {model.coulomb:.6g} N: sticks."
            return _result(walk, [y0], [f], 0, "stopped", message, y0, v0, m, model, state)
        s = -float(np.sign(f))
    while True:
        slid = walk.swing(s, kinetic)
        positions.append(walk.position)
        f = walk.force()
        forces.append(f)
        if sticks(model, f):
            message = (
                f"stopped after {len(positions) - 1} reversal(s) with |F_el| = {abs(f):.6g} N "
                f"<= c1 = {model.coulomb:.6g} N."
            )
            break
        if model.coulomb == 0.0 and not slid and kinetic == 0.0:
            status = "oscillating"
            message = (
                f"c1 = 0 and no stop slid in the last swing: an undamped oscillation inside "
                f"presliding between {positions[-2]:.10g} and {positions[-1]:.10g}, forever."
            )
            break
        if len(positions) > max_reversals:
            positions.pop()
            forces.pop()
            if model.coulomb > 0.0:
                status, message = (
                    "max_reversals",
                    "the mass has not stopped yet; raise `max_reversals`",
                )
            elif walk.min_threshold == 0.0:
                status = "never_stops"
                message = (
                    "c1 = 0 with stops of arbitrarily small threshold: the motion never stops, "
                    "it makes infinitely many reversals of vanishing amplitude"
                )
            else:
                status = "never_stops"
                message = (
                    "c1 = 0: nothing dissipates once every stop sticks; the motion never stops"
                )
            message += f" (the first {max_reversals} reversals listed)."
            break
        kinetic, s = 0.0, -float(np.sign(f))
    n_rev = len(positions) - (1 if status == "stopped" else 0)
    return _result(walk, positions, forces, n_rev, status, message, y0, v0, m, model, state)


def _result(
    walk, positions, forces, n_rev, status, message, y0, v0, m, model, initial
) -> TurningPoints:
    rest = positions[-1] if status == "stopped" else None
    return TurningPoints(
        np.array(positions, dtype=np.float64),
        np.array(forces, dtype=np.float64),
        int(n_rev),
        rest,
        status,
        message,
        walk.state(),
        y0,
        v0,
        m,
        model,
        initial,
    )


def _initial_state(
    model: PIFriction, initial_state: object, y0: float, v0: float
) -> PIState | MemoryState:
    if isinstance(initial_state, str):
        if initial_state == "relaxed":
            return model.relaxed_state(y0)
        if initial_state == "saturated":
            if v0 == 0.0:
                raise ValueError(
                    "`initial_velocity` must be nonzero with initial_state='saturated' "
                    "(it sets the direction of saturation); got 0.0."
                )
            return model.saturated_state(y0, float(np.sign(v0)))
        raise ValueError(
            f"`initial_state` must be 'relaxed', 'saturated' or a state; got {initial_state!r}."
        )
    expected = (PIState, MemoryState) if model.is_discrete else (MemoryState,)
    if not isinstance(initial_state, expected):
        raise TypeError(
            f"`initial_state` must be 'relaxed', 'saturated' or a "
            f"{' or '.join(e.__name__ for e in expected)}; got {type(initial_state).__name__}."
        )
    if isinstance(initial_state, PIState):
        initial_state.check_against(elements(model)[1], "initial_state")
    return initial_state
