"""A structure with friction contacts: masses, springs, dampers and 1-D tangential contacts.

    M·q̈ + C·q̇ + K·q + W·λ = f(t),     λ_c = c1_c·σ_c + F_el,c(g_c) + σ_v,c·ġ_c,
    σ_c ∈ Sign(ġ_c),  g_c = w_cᵀ·q

q ∈ ℝⁿ; each contact c is a column w_c of the contact matrix W (n × n_c) and has
its own finite-element `PIFriction` (eq. 8): a Coulomb element c1_c > 0, a bank of
elasto-plastic (stop) elements k_j, r_j and an optional viscous term σ_v. The
applied force f(t) is constant or piecewise constant (samples held: zero-order hold).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import as_list, as_real_array, check_increasing, check_type, fmt
from presliding.friction.pi_friction import PIFriction

__all__ = ["NetworkStructure", "chain_structure", "modal_structure", "multi_contact_structure"]

FloatArray = NDArray[np.float64]


def square_matrix(name: str, value: Any, n: int | None, *, definite: bool) -> FloatArray:
    """A read-only symmetric n × n matrix, positive definite or semidefinite (a scalar is a
    1 × 1 one, a vector its diagonal; n None: any size). Also `JointedStructure`'s check."""
    arr = as_real_array(name, value)
    if arr.ndim == 0:
        arr = arr.reshape(1, 1)
    if arr.ndim == 1:
        arr = np.diag(arr)
    if arr.ndim != 2 or arr.shape[0] != arr.shape[1] or (n is not None and arr.shape[0] != n):
        want = "(n, n)" if n is None else f"({n}, {n})"
        raise ValueError(f"`{name}` must be a square matrix of shape {want}; got {arr.shape}.")
    scale = float(np.max(np.abs(arr), initial=0.0))
    if not np.allclose(arr, arr.T, rtol=0.0, atol=1e-12 * scale):
        raise ValueError(f"`{name}` must be symmetric; got {fmt(arr)}.")
    arr = 0.5 * (arr + arr.T)
    low = float(np.min(np.linalg.eigvalsh(arr))) if arr.size else 0.0
    if definite and not (low > 1e-13 * scale and scale > 0.0):
        raise ValueError(f"`{name}` must be positive definite; its smallest eigenvalue is {low!r}.")
    if not definite and low < -1e-12 * scale:
        raise ValueError(
            f"`{name}` must be positive semidefinite; its smallest eigenvalue is {low!r}."
        )
    arr.setflags(write=False)
    return arr


_square = square_matrix


def _forcing(value: Any, n: int) -> tuple[FloatArray, FloatArray]:
    """(times, values (K, n)): f = values[i] on [times[i], times[i+1]), held after the last."""
    if isinstance(value, tuple) and len(value) == 2:
        times = as_real_array("forcing times", value[0])
        vals = as_real_array("forcing values", value[1])
        if times.ndim != 1 or times.shape[0] == 0:
            raise ValueError(f"`forcing` times must be a non-empty 1-D array; got {times.shape}.")
        check_increasing("forcing times", times)
        if vals.ndim == 1 and n == 1:
            vals = vals.reshape(-1, 1)
        if vals.shape != (times.shape[0], n):
            raise ValueError(
                f"`forcing` values must have shape ({times.shape[0]}, {n}) (one row per time, "
                f"one column per coordinate); got {vals.shape}."
            )
    else:
        vals = as_real_array("forcing", value)
        if vals.ndim == 0:
            vals = np.full(n, float(vals))
        if vals.shape != (n,):
            raise ValueError(f"`forcing` must be a constant of shape ({n},); got {vals.shape}.")
        times = np.array([-np.inf])
        vals = vals.reshape(1, n)
    times.setflags(write=False)
    vals.setflags(write=False)
    return times, vals


@dataclass(frozen=True, eq=False)
class NetworkStructure:
    """Masses, springs and dampers with friction contacts (M, C, K, W, one model per contact).

    Parameters
    ----------
    mass : array_like, shape (n, n) or (n,)
        Mass matrix M, symmetric positive definite [kg] (a vector: diagonal).
    stiffness : array_like, shape (n, n) or (n,)
        Stiffness matrix K, symmetric positive semidefinite [N/m].
    contacts : array_like, shape (n, n_c)
        Contact matrix W: the relative displacement of contact c is g_c = w_cᵀ·q.
    friction : sequence of PIFriction, length n_c
        One finite-element friction model per contact (eq. 8), each with a
        Coulomb element c1 > 0 (a contact that can stick) and optional viscous σ_v.
    damping : array_like, shape (n, n) or (n,), optional, keyword only
        Structural damping matrix C, symmetric positive semidefinite [N·s/m]; zeros
        by default.
    forcing : float, array_like (n,) or (times, values), optional, keyword only
        Applied force f(t) [N]: a constant (a scalar is applied to every coordinate),
        or samples held constant, ``values[i]`` on ``[times[i], times[i+1])`` and the
        last one after (values of shape (K, n)). Zero by default.

    Examples
    --------
    >>> from presliding import PIFriction
    >>> s = NetworkStructure(1.0, 1.0, [[1.0]], [PIFriction(1.0)])
    >>> s.n_coordinates, s.n_contacts
    (1, 1)
    """

    mass: FloatArray
    stiffness: FloatArray
    contacts: FloatArray
    friction: tuple[PIFriction, ...]
    damping: FloatArray | None = field(default=None, kw_only=True)
    forcing: Any = field(default=0.0, kw_only=True)
    forcing_times: FloatArray = field(init=False, repr=False)
    forcing_values: FloatArray = field(init=False, repr=False)

    if TYPE_CHECKING:

        def __init__(self, mass: ArrayLike, stiffness: ArrayLike, contacts: ArrayLike,
                     friction: Sequence[PIFriction], *, damping: ArrayLike | None = None,
                     forcing: Any = 0.0) -> None: ...  # fmt: skip

    def __post_init__(self) -> None:
        m = _square("mass", self.mass, None, definite=True)
        n = m.shape[0]
        k = _square("stiffness", self.stiffness, n, definite=False)
        c = _square("damping", np.zeros((n, n)) if self.damping is None else self.damping, n,
                    definite=False)  # fmt: skip
        w = as_real_array("contacts", self.contacts)
        if w.ndim == 1 and n == 1:
            w = w.reshape(1, -1)
        if w.ndim != 2 or w.shape[0] != n or w.shape[1] == 0:
            raise ValueError(
                f"`contacts` must have shape ({n}, n_c) with n_c >= 1 (one column per contact); "
                f"got {w.shape}."
            )
        zero = ~np.any(w != 0.0, axis=0)
        if zero.any():
            col = int(np.argmax(zero))
            raise ValueError(f"`contacts` must not have a zero column; column {col} is zero.")
        models = tuple(as_list("friction", self.friction))
        if len(models) != w.shape[1]:
            raise ValueError(
                f"`friction` must hold one model per contact ({w.shape[1]}); got {len(models)}."
            )
        for i, model in enumerate(models):
            check_type(f"friction[{i}]", model, PIFriction)
            if not model.is_discrete:
                raise ValueError(
                    f"`friction[{i}]` must have finite elements (eq. 8), not a density; got "
                    f"{model.density!r}."
                )
            if not model.coulomb > 0.0:
                raise ValueError(
                    f"`friction[{i}]` must have a Coulomb element c1 > 0 (a contact that can "
                    f"stick); got coulomb={model.coulomb!r}."
                )
        w = np.ascontiguousarray(w)
        w.setflags(write=False)
        times, vals = _forcing(self.forcing, n)
        for name, value in (("mass", m), ("stiffness", k), ("damping", c), ("contacts", w),
                            ("friction", models), ("forcing_times", times),
                            ("forcing_values", vals)):  # fmt: skip
            object.__setattr__(self, name, value)

    @property
    def n_coordinates(self) -> int:
        """n, the number of coordinates q."""
        return int(self.mass.shape[0])

    @property
    def n_contacts(self) -> int:
        """n_c, the number of contacts."""
        return int(self.contacts.shape[1])

    @property
    def coulomb(self) -> FloatArray:
        """c1_c of every contact [N]."""
        return np.array([f.coulomb for f in self.friction])

    @property
    def viscous(self) -> FloatArray:
        """σ_v,c of every contact [N·s/m]."""
        return np.array([f.viscous for f in self.friction])

    @property
    def breakaway_level(self) -> FloatArray:
        """F_c = c1 + Σ c_j (eq. 9) of every contact [N]."""
        return np.array([f.coulomb_level for f in self.friction])

    @property
    def is_damped(self) -> bool:
        """True when C ≠ 0 or a contact has a viscous term."""
        return bool(np.any(self.damping != 0.0) or np.any(self.viscous > 0.0))

    def force_at(self, t: float) -> FloatArray:
        """The applied force f(t) [N]."""
        i = max(int(np.searchsorted(self.forcing_times, t, side="right")) - 1, 0)
        return np.asarray(self.forcing_values[i])

    def with_forcing(self, forcing: Any) -> NetworkStructure:
        """The same structure with another applied force."""
        return NetworkStructure(self.mass, self.stiffness, self.contacts, self.friction,
                                damping=self.damping, forcing=forcing)  # fmt: skip


def _models(friction: PIFriction | Sequence[PIFriction], n_c: int) -> list[PIFriction]:
    if isinstance(friction, PIFriction):
        return [friction] * n_c
    return as_list("friction", friction)


def chain_structure(
    n_masses: int,
    mass: float | ArrayLike,
    spring: float | ArrayLike,
    friction: PIFriction | Sequence[PIFriction],
    *,
    damping: float | ArrayLike = 0.0,
    forcing: Any = 0.0,
) -> NetworkStructure:
    """A chain of masses: mass i tied to mass i−1 by spring i (mass 0 to the ground), each
    mass on its own contact with the ground (g_i = q_i).

    ``mass``, ``spring`` and ``damping`` (dashpots parallel to the springs) are scalars or
    one value per mass; ``friction`` one model for all contacts or one per mass.
    """
    if isinstance(n_masses, bool) or not isinstance(n_masses, int | np.integer) or n_masses < 1:
        raise ValueError(f"`n_masses` must be a positive integer; got {fmt(n_masses)}.")
    n = int(n_masses)
    m = np.broadcast_to(as_real_array("mass", mass), (n,)).astype(float)
    ks = np.broadcast_to(as_real_array("spring", spring), (n,)).astype(float)
    cs = np.broadcast_to(as_real_array("damping", damping), (n,)).astype(float)

    def band(values: FloatArray) -> FloatArray:
        out = np.zeros((n, n))
        for i in range(n):
            out[i, i] += values[i]
            if i > 0:
                out[i - 1, i - 1] += values[i]
                out[i, i - 1] -= values[i]
                out[i - 1, i] -= values[i]
        return out

    return NetworkStructure(np.diag(m), band(ks), np.eye(n), _models(friction, n),
                            damping=band(cs), forcing=forcing)  # fmt: skip


def multi_contact_structure(
    mass: float,
    stiffness: float,
    friction: Sequence[PIFriction],
    *,
    damping: float = 0.0,
    forcing: Any = 0.0,
) -> NetworkStructure:
    """One mass on a spring to the ground and on several contacts (all with g = q)."""
    models = as_list("friction", friction)
    return NetworkStructure([[mass]], [[stiffness]], np.ones((1, len(models))), models,
                            damping=[[damping]], forcing=forcing)  # fmt: skip


def modal_structure(
    frequencies: ArrayLike,
    mode_shapes: ArrayLike,
    friction: PIFriction | Sequence[PIFriction],
    *,
    damping_ratios: ArrayLike = 0.0,
    forcing: Any = 0.0,
) -> NetworkStructure:
    """A linear modal model (unit modal masses) with contacts.

    ``frequencies`` ω_i [rad/s] (n modes), ``mode_shapes`` (n, n_c): the relative
    displacement of contact c per unit of mode i, so g_c = Σ_i φ_ic q_i; ``damping_ratios``
    ζ_i give C = diag(2 ζ_i ω_i).
    """
    w = as_real_array("frequencies", frequencies).reshape(-1)
    phi = as_real_array("mode_shapes", mode_shapes)
    if phi.ndim == 1:
        phi = phi.reshape(w.shape[0], -1)
    zeta = np.broadcast_to(as_real_array("damping_ratios", damping_ratios), w.shape)
    if np.any(w < 0) or np.any(zeta < 0):
        raise ValueError("`frequencies` and `damping_ratios` must be nonnegative.")
    return NetworkStructure(np.eye(w.shape[0]), np.diag(w * w), phi,
                            _models(friction, phi.shape[1] if phi.ndim == 2 else 0),
                            damping=np.diag(2.0 * zeta * w), forcing=forcing)  # fmt: skip
