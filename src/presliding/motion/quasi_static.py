"""Quasi-static response: the position under a slowly applied force (torque-driven presliding).

When the applied force u changes slowly enough that inertia (m·ÿ) and viscous
friction (σ·ẏ) are negligible, eq. 17 reduces to the balance

    u = c1·sign(ẏ) + F_el(y),       F_el = Σ_j k_j (y − x_j(y, r_j))   (eq. 8).

The contact moves only while |u − F_el| > c1, and then F_el(y) = u ∓ c1: the
elastic force is a play operator of threshold c1 acting on u, and the position
follows from the inverse of the elastic bank on its range |F_el| < F_m
(`presliding.hysteresis.PIInverse`). The result is exact (no time stepping), and
the Coulomb element c1 is included exactly. At |u| = F_c = c1 + F_m (eq. 9)
every element is saturated (the end of presliding, a finite position); beyond it
the contact slides without bound: there is no quasi-static position, and
`quasi_static_response` raises (the first value refused is one float step above
``model.coulomb_level``).

This is the torque-in/position-out model of a joint driven by a slow torque
below break-away; `presliding.identification.fit_quasi_static` fits it to
measured positions.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._display import figures_of, fill_attrs, result_html, short_repr
from presliding._interop import require
from presliding._validation import (
    as_real_scalar,
    as_signal,
    check_increasing,
    check_same_length,
    renamed,
)
from presliding.friction._parts import elements
from presliding.friction._sides import check_band, require_symmetric, shifted_bank, sides_of
from presliding.friction.creep import CreepingFriction, creep_deflections
from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis.inverse import PIInverse
from presliding.hysteresis.operators import PIOperator, PIState

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["QuasiStaticResponse", "friction_inverse", "quasi_static_response"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class QuasiStaticResponse:
    """The position of a contact under a slowly applied force (module notes).

    Attributes
    ----------
    time : ndarray, shape (T,) or None
        Sample times [s], when given.
    applied_force : ndarray, shape (T,)
        u [N].
    position : ndarray, shape (T,)
        y [m].
    elastic_force : ndarray, shape (T,)
        F_el = play_{c1}[u] [N].
    friction_force : ndarray, shape (T,)
        Equal to u (the balance holds at every sample) [N].
    final_state : PIState
        The friction memory after the last sample (pass it on to continue).
    model : PIFriction or CreepingFriction
    status : str
        "success".
    message : str
    creep_deflection : ndarray, shape (T,) or None
        The Kelvin–Voigt element's deflection y_c [m] of a `CreepingFriction` (included
        in `position`); None for a PIFriction.
    """

    time: FloatArray | None
    applied_force: FloatArray
    position: FloatArray
    elastic_force: FloatArray
    final_state: PIState
    model: PIFriction | CreepingFriction
    status: str = "success"
    message: str = "quasi-static balance solved exactly"
    creep_deflection: FloatArray | None = None

    @property
    def success(self) -> bool:
        """True (a response that cannot be computed raises instead)."""
        return self.status == "success"

    @property
    def friction_force(self) -> FloatArray:
        """c1·σ + F_el with σ ∈ Sign(ẏ): equal to u at every sample [N]."""
        return self.applied_force

    def to_dict(self) -> dict[str, Any]:
        """The sampled signals (and time, when given) by name, plus status and message."""
        out: dict[str, Any] = {} if self.time is None else {"time": self.time}
        out.update(
            applied_force=self.applied_force,
            position=self.position,
            elastic_force=self.elastic_force,
            **(
                {} if self.creep_deflection is None else {"creep_deflection": self.creep_deflection}
            ),
            status=self.status,
            message=self.message,
            success=self.success,
        )
        return out

    def to_pandas(self) -> Any:
        """A pandas DataFrame of the sampled signals (pandas must be installed)."""
        pd = require("pandas", "`to_pandas()`")

        data = {k: v for k, v in self.to_dict().items() if isinstance(v, np.ndarray)}
        return fill_attrs(pd.DataFrame(data), self)

    def __repr__(self) -> str:
        return short_repr(self)

    def _repr_html_(self) -> str:
        """The status, the signals' ranges and the model's parameters, for notebooks."""
        figures = [("Coulomb level F_c", f"{self.model.coulomb_level:.6g}", "N"),
                   *figures_of(self)]  # fmt: skip
        return result_html(self, figures)

    def plot(self, ax: Axes | None = None) -> Axes:
        """The position against the applied force (the presliding loops); returns the axes."""
        from presliding.plotting import new_axes

        ax = new_axes(ax)
        ax.plot(self.applied_force, self.position, lw=1.2)
        ax.set_xlabel("applied force u [N]")
        ax.set_ylabel("position y [m]")
        ax.set_title(f"quasi-static response, F_c = {self.model.coulomb_level:.4g} N")
        ax.grid(True, alpha=0.3)
        return ax

    def report(self) -> str:
        """A readable summary."""
        u, y = self.applied_force, self.position
        return "\n".join(
            [
                f"Quasi-static response of {self.model!r}",
                f"  {u.shape[0]} samples; status {self.status} ({self.message})",
                f"  applied force {np.min(u):.6g} .. {np.max(u):.6g} N "
                f"(F_c = {self.model.coulomb_level:.6g} N)",
                f"  position {np.min(y):.6g} .. {np.max(y):.6g} m; final {y[-1]:.12g} m",
            ]
        )


def friction_inverse(model: PIFriction) -> PIInverse:
    """The quasi-static inverse u → y of a friction model (`PIInverse` of its bank, with c1).

    Raises
    ------
    ValueError
        For a model without elements (its position is not determined by the
        force) or with a continuous density.
    """
    if not isinstance(model, PIFriction):
        raise TypeError(f"`model` must be a PIFriction; got {type(model).__name__}.")
    require_symmetric(model, "friction_inverse (one PIInverse; quasi_static_response takes both "
                      "sides) and fit_quasi_static")  # fmt: skip
    if not model.is_discrete or model.n_elements == 0:
        what = "a continuous density" if not model.is_discrete else "no elements"
        raise ValueError(
            "`model` must have elasto-plastic elements for a quasi-static inverse (the "
            f"displacement is determined by the elastic force only); got {what}."
        )
    stiffness, threshold, _ = elements(model)
    return PIInverse(PIOperator(threshold, stiffness), coulomb=model.coulomb)


def quasi_static_response(
    model: PIFriction | CreepingFriction,
    applied_force: ArrayLike,
    initial_state: PIState | str | None = None,
    *,
    time: ArrayLike | None = None,
    initial_creep: float | None = None,
) -> QuasiStaticResponse:
    """Position under a slowly applied force, with inertia negligible (module notes).

    Parameters
    ----------
    model : PIFriction or CreepingFriction
        Finite elements (at least one) and the Coulomb element c1; or such a contact
        in series with a Kelvin–Voigt element (`presliding.friction.CreepingFriction`),
        whose creep deflection is added to the position.
    applied_force : array_like, shape (T,)
        u [N], monotone between samples (the contact's response is rate independent;
        the creep element takes u linear in time between samples),
        with |u| <= F_c = ``model.coulomb_level`` throughout.
    initial_state : PIState or "relaxed", optional
        The friction memory before the first sample (default: relaxed at y = 0).
        A memory with a preload comes from
        `presliding.friction.preloaded_state`; the elastic force of the memory is
        where the play of c1 starts.
    time : array_like, shape (T,), optional
        Sample times [s], kept in the result (strictly increasing); needed by a
        `CreepingFriction` with creep (J > 0 and τ > 0).
    initial_creep : float, optional, keyword only
        The creep deflection y_c [m] at the first sample (a `CreepingFriction`);
        default J·u_0, at rest with the first force.

    Returns
    -------
    QuasiStaticResponse
        Position, elastic force and the final memory.

    Raises
    ------
    ValueError
        If some |u| > F_c (gross sliding has no quasi-static position), the
        model has no elements or a continuous density, or an argument is
        malformed.

    Examples
    --------
    >>> import numpy as np
    >>> model = PIFriction(0.1, [2e4, 5e3], breakaway=[0.3, 0.3])
    >>> u = 0.6 * np.sin(np.linspace(0.0, 4 * np.pi, 9))
    >>> res = quasi_static_response(model, u)
    >>> bool(np.all(np.abs(res.applied_force - res.elastic_force) <= 0.1 + 1e-12))
    True
    """
    if isinstance(model, CreepingFriction):
        return _creeping_response(model, applied_force, initial_state, time, initial_creep)
    if not isinstance(model, PIFriction):
        raise TypeError(
            f"`model` must be a PIFriction or CreepingFriction; got {type(model).__name__}."
        )
    if initial_creep is not None:
        raise ValueError(
            "`initial_creep` is the deflection of a CreepingFriction's creep element; got "
            f"{initial_creep!r} with a {type(model).__name__}."
        )
    u = as_signal("applied_force", applied_force)
    t = None
    if time is not None:
        t = as_signal("time", time)
        check_same_length(applied_force=u, time=t)
        check_increasing("time", t)
    if not isinstance(model, PIFriction) or model.is_symmetric:
        inverse = friction_inverse(model)
    if isinstance(initial_state, str):
        if initial_state != "relaxed":
            raise ValueError(
                f"`initial_state` must be a PIState, 'relaxed' or None; got {initial_state!r}."
            )
        initial_state = None
    if initial_state is not None and not isinstance(initial_state, PIState):
        raise TypeError(
            f"`initial_state` must be a PIState, 'relaxed' or None; "
            f"got {type(initial_state).__name__}."
        )
    if not model.is_symmetric:
        return _asymmetric_response(model, t, u, initial_state)
    start = initial_state if initial_state is not None else PIState.relaxed(0.0, model.n_elements)
    # u = ±F_c exactly is the end of presliding: F_c of the model and of the inverse
    # (c1 + Σ k_j·(c_j/k_j)) may differ in the last bit, so that value is the inverse's
    at_limit = np.abs(u) == model.coulomb_level
    if at_limit.any():
        u_in = np.where(at_limit, np.sign(u) * min(model.coulomb_level, inverse.force_limit), u)
    else:
        u_in = u
    with renamed(force="applied_force", state="initial_state"):
        fel = inverse.elastic_force(u_in, start)
        y, final = inverse.apply(u_in, start)
    return QuasiStaticResponse(t, u, y, fel, final, model)


def _creeping_response(
    model: CreepingFriction,
    applied_force: ArrayLike,
    initial_state: Any,
    time: ArrayLike | None,
    initial_creep: Any,
) -> QuasiStaticResponse:
    """The contact's response plus the creep deflection, integrated exactly (`creep`)."""
    start = np.full((1, 1), np.nan)
    if initial_creep is not None:
        start[0, 0] = as_real_scalar("initial_creep", initial_creep)
    inner = quasi_static_response(model.friction, applied_force, initial_state, time=time)
    u = inner.applied_force
    if time is None and model.has_creep and model.creep_time > 0.0:
        raise ValueError(
            "`time` must be given for a CreepingFriction with creep (its deflection depends on "
            "time); got None."
        )
    t = inner.time if inner.time is not None else np.zeros(u.shape[0])
    creep = np.zeros((1, u.shape[0]))
    creep_deflections(np.array([model.compliance]), np.array([model.creep_time]),
                      np.zeros(1), start, u, t, np.array([0, u.shape[0]]), creep)  # fmt: skip
    return QuasiStaticResponse(inner.time, u, inner.position + creep[0], inner.elastic_force,
                               inner.final_state, model, creep_deflection=creep[0])  # fmt: skip


def _asymmetric_response(
    model: PIFriction, t: FloatArray | None, u: FloatArray, initial_state: PIState | None
) -> QuasiStaticResponse:
    """The quasi-static response of an asymmetric model, exactly, through the symmetric one.

    With r̄_j = (r_j⁺ + r_j⁻)/2, δ_j = (r_j⁺ − r_j⁻)/2 and c̄1 = (c1⁺ + c1⁻)/2, the shifted
    play x_j + δ_j is the symmetric play of r̄_j, and the balance −c1⁻ <= u − F_el <= c1⁺
    reads |u − Δ − F̄_el| <= c̄1 with Δ = (F_c⁺ − F_c⁻)/2 (`presliding.friction._sides`): the
    symmetric inverse under u − Δ gives the same positions.
    """
    fp, fn = model.coulomb_levels
    bad = (u >= fp) | (u <= -fn)
    if bad.any():
        i = int(np.argmax(bad))
        raise ValueError(
            f"`applied_force` must stay inside (−F_c⁻, F_c⁺) = ({-fn!r}, {fp!r}) (gross "
            f"sliding has no quasi-static position); got {u[i]!r} at index {i}."
        )
    if model.n_elements == 0:
        friction_inverse(PIFriction(model.coulomb))  # its error: no elements
    k = np.asarray(model.stiffness)
    r_mid, delta, offset = shifted_bank(model)
    c1p, c1n = sides_of(model).coulomb
    mid = PIFriction(0.5 * (c1p + c1n), k, threshold=r_mid)
    if initial_state is None:
        initial_state = PIState.relaxed(0.0, model.n_elements)
    if initial_state.play.shape != k.shape:
        initial_state.check_against(r_mid, "initial_state")  # the count's error
    check_band(model, initial_state.last_input, initial_state.play, "initial_state")
    start = PIState(initial_state.last_input, initial_state.play + delta, initial_state.direction)
    shift = 0.5 * (fp - fn)
    inverse = friction_inverse(mid)
    with renamed(force="applied_force", state="initial_state"):
        fel = inverse.elastic_force(u - shift, start) + offset
        y, final = inverse.apply(u - shift, start)
    rp, rn = sides_of(model).threshold
    yl = final.last_input
    play = np.minimum(np.maximum(final.play - delta, yl - rp), yl + rn)
    return QuasiStaticResponse(t, u, y, fel, PIState(yl, play, final.direction), model)
