"""Asymmetric friction: separate levels for the two directions of sliding.

An asymmetric `PIFriction` has a Coulomb element c1⁺ (sliding in +y) and c1⁻
(sliding in −y), elements with break-away forces c_j⁺ and c_j⁻ (thresholds
r_j⁺ = c_j⁺/k_j and r_j⁻ = c_j⁻/k_j) and viscous coefficients σ⁺ and σ⁻. The
play operator of element j keeps its output in the asymmetric band

    y − r_j⁺ <= x_j <= y + r_j⁻,      x_j ← min(max(x_j, y − r_j⁺), y + r_j⁻),

so its deformation f_j = y − x_j lies in [−r_j⁻, r_j⁺] and its force k_j·f_j in
[−c_j⁻, c_j⁺]. The whole law along a path is

    F = c1^s·s + σ^s·ẏ + Σ_j k_j (y − x_j),      s = sign(ẏ), c1^± and σ^± by direction.

With the midpoint r̄_j = (r_j⁺ + r_j⁻)/2 and the shift δ_j = (r_j⁺ − r_j⁻)/2, the shifted
play x_j + δ_j follows the symmetric play of threshold r̄_j exactly, so the elastic
force is the symmetric stop sum of the shifted memory plus Σ_j k_j δ_j (this is
how `PIFriction.force` evaluates an asymmetric bank).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._validation import (
    as_nonnegative_scalar,
    as_parameter_vector,
    check_finite_derived,
)
from presliding.friction._model_checks import check_derived
from presliding.hysteresis import _kernels
from presliding.hysteresis.operators import PIState

#: a `PIFriction` (not imported here: `presliding.friction.pi_friction` imports this module)
PIFriction = Any

__all__ = ["Sides", "require_symmetric", "sides_of"]

FloatArray = NDArray[np.float64]


class Sides:
    """The two sides of a finite-element model: (positive, negative) of each level."""

    __slots__ = ("breakaway", "coulomb", "threshold", "viscous")

    def __init__(
        self,
        coulomb: tuple[float, float],
        threshold: tuple[FloatArray, FloatArray],
        breakaway: tuple[FloatArray, FloatArray],
        viscous: tuple[float, float],
    ) -> None:
        self.coulomb = coulomb
        self.threshold = threshold
        self.breakaway = breakaway
        self.viscous = viscous


def sides_of(model: PIFriction) -> Sides:
    """The (positive, negative) levels of a finite-element model (equal for a symmetric one)."""
    r, c = model.threshold, model.breakaway
    if r is None or c is None:
        raise TypeError(f"a model with a continuous density has no elements; got {model!r}.")
    rn = r if model.threshold_negative is None else model.threshold_negative
    cn = c if model.breakaway_negative is None else model.breakaway_negative
    c1n = model.coulomb if model.coulomb_negative is None else model.coulomb_negative
    sn = model.viscous if model.viscous_negative is None else model.viscous_negative
    return Sides((model.coulomb, c1n), (r, rn), (c, cn), (model.viscous, sn))


def require_symmetric(model: Any, route: str) -> None:
    """NotImplementedError when `model` is asymmetric and `route` takes only symmetric ones."""
    if getattr(model, "is_symmetric", True):
        return
    raise NotImplementedError(
        f"{route} supports only symmetric friction; got an asymmetric model (coulomb_negative, "
        "breakaway_negative/threshold_negative or viscous_negative set): `simulate`, "
        "`simulate_loop`, `quasi_static_response`, `PIFriction.force`, model files and "
        "`fit_motion` take both sides."
    )


def negative_scalar(name: str, value: Any, positive_side: float) -> float | None:
    """A validated negative-side scalar, or None when absent or equal to the positive side."""
    if value is None:
        return None
    x = as_nonnegative_scalar(name, value)
    return None if x == positive_side else x


def negative_elements(
    k: FloatArray, breakaway: Any, threshold: Any
) -> tuple[FloatArray, FloatArray] | tuple[None, None]:
    """(c⁻, r⁻) from `breakaway_negative` or `threshold_negative` (not both), validated."""
    if breakaway is None and threshold is None:
        return None, None
    if breakaway is not None and threshold is not None:
        raise TypeError(
            "`breakaway_negative` or `threshold_negative` may be given, not both; got both."
        )
    name = "breakaway_negative" if breakaway is not None else "threshold_negative"
    given = as_parameter_vector(name, breakaway if breakaway is not None else threshold,
                                allow_empty=True)  # fmt: skip
    if given.shape != k.shape:
        raise ValueError(
            f"`{name}` must have the same length as `stiffness` ({k.shape[0]}); "
            f"got {given.shape[0]}."
        )
    with np.errstate(over="ignore", under="ignore"):  # reported by check_derived
        if breakaway is not None:
            c, r = given, given / k
        else:
            c, r = k * given, given
    check_derived(k, c, r, given="breakaway" if breakaway is not None else "threshold")
    for arr in (c, r):
        arr.setflags(write=False)
    return c, r


def shifted_bank(model: PIFriction) -> tuple[FloatArray, FloatArray, float]:
    """(r̄, δ, Σ k_j δ_j): the symmetric bank the shifted memory follows."""
    s = sides_of(model)
    rp, rn = s.threshold
    r_mid = 0.5 * (rp + rn)
    delta = 0.5 * (rp - rn)
    k = np.asarray(model.stiffness)
    return r_mid, delta, float(np.dot(k, delta))


def check_band(model: PIFriction, last_input: float, play: FloatArray, name: str) -> None:
    """Every deformation y − x_j lies in [−r_j⁻, r_j⁺] (beyond rounding), else ValueError."""
    rp, rn = sides_of(model).threshold
    f = last_input - play
    slack = 1e-12 * (abs(last_input) + np.maximum(rp, rn))
    bad = (f > rp + slack) | (f < -rn - slack)
    if bad.any():
        j = int(np.argmax(bad))
        raise ValueError(
            f"`{name}` must satisfy −threshold_negative_j <= last_input − play_j <= threshold_j; "
            f"got {last_input - play[j]!r} outside [{-rn[j]!r}, {rp[j]!r}] at index {j}."
        )


def run_bank(model: PIFriction, y: FloatArray, state: Any) -> tuple[FloatArray, Any, float, float]:
    """Elastic force of an asymmetric bank along `y`, final PIState, input and direction before.

    The shifted memory x_j + δ_j runs through the symmetric stop sum of threshold r̄_j
    (see the module's note); the force adds Σ k_j δ_j and the final play drops δ_j.
    """
    k = np.asarray(model.stiffness)
    r_mid, delta, offset = shifted_bank(model)
    if state is None:
        x, prev, d0 = np.full(k.shape[0], y[0]), float(y[0]), 0.0
    elif not isinstance(state, PIState):
        raise TypeError(f"`state` must be a PIState or None; got {type(state).__name__}.")
    else:
        if state.play.shape != k.shape:
            raise ValueError(
                f"`state` must hold {k.shape[0]} play states for this model; got "
                f"{state.play.shape[0]}."
            )
        check_band(model, state.last_input, state.play, "state")
        x, prev, d0 = state.play.copy(), state.last_input, state.direction
    rp, rn = sides_of(model).threshold
    xs = x + delta
    elastic = np.empty(y.shape[0])
    d = _kernels.stop_sum(y, r_mid, k, xs, elastic, 0.0, 0.0, prev, d0)
    elastic += offset
    # the play back in the asymmetric band (the shift rounds; the band holds exactly)
    yl = float(y[-1])
    play = np.minimum(np.maximum(xs - delta, yl - rp), yl + rn)
    return elastic, PIState(yl, play, d), prev, d0


def virgin_curve(model: PIFriction, y: FloatArray, elastic_only: bool) -> FloatArray:
    """The initial loading curve of an asymmetric model: each side with its own levels."""
    s = sides_of(model)
    k = np.asarray(model.stiffness)
    ay = np.abs(y)
    pos = np.minimum(ay[:, None], s.threshold[0][None, :]) @ k
    neg = np.minimum(ay[:, None], s.threshold[1][None, :]) @ k
    if not elastic_only:
        pos = pos + s.coulomb[0]
        neg = neg + s.coulomb[1]
    return np.where(y > 0, pos, np.where(y < 0, -neg, 0.0))


def take_negative_elements(model: PIFriction, k: FloatArray, c: FloatArray, r: FloatArray) -> None:
    """Set the validated c⁻ and r⁻ of a finite-element model (None when equal to c and r)."""
    cn, rn = negative_elements(k, model.breakaway_negative, model.threshold_negative)
    if cn is not None and rn is not None and np.array_equal(cn, c) and np.array_equal(rn, r):
        cn = rn = None
    object.__setattr__(model, "breakaway_negative", cn)
    object.__setattr__(model, "threshold_negative", rn)
    if not model.is_symmetric:
        check_finite_derived("Coulomb level F_c⁻ = c1⁻ + Σ c_j⁻ (eq. 9)",
                             model.coulomb_levels[1],
                             ("coulomb_negative", "breakaway_negative"))  # fmt: skip


def repr_suffix(model: PIFriction) -> str:
    """The negative sides in a model's repr (empty for a symmetric model)."""
    out = ""
    if model.coulomb_negative is not None:
        out += f", coulomb_negative={model.coulomb_negative!r}"
    if model.breakaway_negative is not None:
        out += f", breakaway_negative={model.breakaway_negative.tolist()!r}"
    if model.viscous_negative is not None:
        out += f", viscous_negative={model.viscous_negative!r}"
    return out


def same_sides(a: PIFriction, b: PIFriction) -> bool:
    """Both models have the same negative sides (None for a symmetric one)."""
    for name in ("coulomb_negative", "viscous_negative", "breakaway_negative"):
        x, y = getattr(a, name), getattr(b, name)
        if (x is None) != (y is None) or (x is not None and not np.array_equal(x, y)):
            return False
    return True


def levels(model: PIFriction) -> tuple[float, float]:
    """(F_c⁺, F_c⁻) = (c1⁺ + Σ c_j⁺, c1⁻ + Σ c_j⁻) (eq. 9 for each direction)."""
    if model.is_symmetric:
        return model.coulomb_level, model.coulomb_level
    s = sides_of(model)
    return (s.coulomb[0] + float(np.sum(s.breakaway[0])),
            s.coulomb[1] + float(np.sum(s.breakaway[1])))  # fmt: skip


def force(model: PIFriction, y: FloatArray, state: Any, out: FloatArray) -> tuple[FloatArray, Any]:
    """c1^s·s + Σ k_j (y − x_j) of an asymmetric model into `out`, and the final PIState."""
    elastic, final, prev, d0 = run_bank(model, y, state)
    _kernels.motion_direction(y, prev, d0, out)
    c1p, c1n = sides_of(model).coulomb
    np.copyto(out, np.where(out > 0, c1p, np.where(out < 0, -c1n, 0.0)) + elastic)
    return out, final


def steady_force(model: PIFriction, v: Any) -> Any:
    """F_c⁺ + σ⁺·v for v > 0, −F_c⁻ + σ⁻·v for v < 0, 0 at rest."""
    fp, fn = levels(model)
    out = np.where(v > 0, fp, np.where(v < 0, -fn, 0.0)) + model.viscous_force(v)
    return float(out) if np.ndim(out) == 0 else out
