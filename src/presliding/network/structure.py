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
import scipy.sparse
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_count,
    as_list,
    as_real_array,
    as_real_scalar,
    check_increasing,
    check_size,
    check_type,
    fmt,
)
from presliding.friction.pi_friction import PIFriction
from presliding.network._matrices import as_contacts, check_dense_size, issparse, square

__all__ = ["NetworkStructure", "chain_structure", "modal_structure", "multi_contact_structure"]

FloatArray = NDArray[np.float64]


#: The symmetric (semi)definite matrix check, also `JointedStructure`'s (`_matrices.square`).
square_matrix = square


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
        sparse = any(issparse(x) for x in (self.mass, self.stiffness, self.damping,
                                           self.contacts))  # fmt: skip
        if not sparse:  # the sizes of the dense checks, before anything is copied
            shape_m, shape_w = np.shape(self.mass), np.shape(self.contacts)
            n0 = shape_m[0] if len(shape_m) else 1
            check_dense_size("mass", fmt(shape_m), n0, shape_w[-1] if len(shape_w) else 1,
                             "Pass scipy.sparse matrices for a large structure.")  # fmt: skip
        m = square("mass", self.mass, None, definite=True)
        n = m.shape[0]
        k = square("stiffness", self.stiffness, n, definite=False)
        if self.damping is None:
            c = scipy.sparse.csr_array((n, n)) if sparse else np.zeros((n, n))
            if not sparse:
                c.setflags(write=False)
        else:
            c = square("damping", self.damping, n, definite=False)
        if sparse:  # all sparse (CSR) when one is
            m, k, c = (x if issparse(x) else square(name, scipy.sparse.csr_array(x), n,
                                                     definite=name == "mass")
                       for name, x in (("mass", m), ("stiffness", k), ("damping", c)))  # fmt: skip
        w = as_contacts(scipy.sparse.csr_array(self.contacts) if sparse and not issparse(
            self.contacts) else self.contacts, n)  # fmt: skip
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
        c: Any = self.damping
        structural = bool(np.any(c.data != 0.0)) if issparse(c) else bool(np.any(c != 0.0))
        return structural or bool(np.any(self.viscous > 0.0))

    @property
    def is_sparse(self) -> bool:
        """True when M, C, K and W are scipy.sparse (CSR) matrices."""
        return issparse(self.mass)

    @property
    def n_elements(self) -> int:
        """Stop elements of all contacts together."""
        return int(sum(0 if f.stiffness is None else f.stiffness.shape[0] for f in self.friction))

    def _summary(self) -> list[tuple[str, str, str]]:
        n_f = self.forcing_times.shape[0]
        t0 = self.forcing_times[0]
        force = "constant" if n_f == 1 else f"{n_f} values held from t = {t0:g} s"
        return [("coordinates", str(self.n_coordinates), ""),
                ("contacts", str(self.n_contacts), ""),
                ("elements", str(self.n_elements), ""),
                ("damped", str(self.is_damped), ""),
                ("sparse", str(self.is_sparse), ""),
                ("forcing", force, "N")]  # fmt: skip

    def __repr__(self) -> str:
        c1 = self.coulomb
        return (
            f"NetworkStructure(n={self.n_coordinates}, n_contacts={self.n_contacts}, "
            f"n_elements={self.n_elements}, coulomb={_range(c1)}, damped={self.is_damped}, "
            f"sparse={self.is_sparse}, forcing_changes={self.forcing_times.shape[0] - 1})"
        )

    def _repr_html_(self) -> str:
        from presliding._display import result_html

        c1 = self.coulomb
        rows = [*self._summary(), ("Coulomb c1", _range(c1), "N"),
                ("breakaway F_c", _range(self.breakaway_level), "N")]  # fmt: skip
        return result_html(self, rows, title="NetworkStructure", show_model=False)

    def force_at(self, t: float) -> FloatArray:
        """The applied force f(t) [N] at time `t` [s]."""
        t = as_real_scalar("t", t)
        i = max(int(np.searchsorted(self.forcing_times, t, side="right")) - 1, 0)
        return np.asarray(self.forcing_values[i])

    def with_forcing(self, forcing: Any) -> NetworkStructure:
        """The same structure with another applied force."""
        return NetworkStructure(self.mass, self.stiffness, self.contacts, self.friction,
                                damping=self.damping, forcing=forcing)  # fmt: skip


def _range(values: FloatArray) -> str:
    if values.size == 0:
        return "none"
    lo, hi = float(np.min(values)), float(np.max(values))
    return f"{lo:.6g}" if lo == hi else f"{lo:.6g} … {hi:.6g}"


def _models(friction: PIFriction | Sequence[PIFriction], n_c: int) -> list[PIFriction]:
    if isinstance(friction, PIFriction):
        return [friction] * n_c
    return as_list("friction", friction)


def _per_mass(name: str, value: Any, n: int, *, positive: bool) -> FloatArray:
    """A scalar or one value per mass (n,), positive or nonnegative."""
    arr = as_real_array(name, value)
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    elif arr.shape != (n,):
        raise ValueError(f"`{name}` must be a number or one value per mass ({n}); got shape "
                         f"{arr.shape}.")  # fmt: skip
    bad = ~(arr > 0.0) if positive else arr < 0.0
    if bad.any():
        i = int(np.argmax(bad))
        rule = "positive" if positive else "nonnegative"
        raise ValueError(f"`{name}` must be {rule}; got {fmt(arr[i])} at index {i}.")
    return arr


def chain_structure(
    n_masses: int,
    mass: float | ArrayLike,
    spring: float | ArrayLike,
    friction: PIFriction | Sequence[PIFriction],
    *,
    damping: float | ArrayLike = 0.0,
    forcing: Any = 0.0,
    sparse: bool = False,
) -> NetworkStructure:
    """A chain of masses: mass i tied to mass i−1 by spring i (mass 0 to the ground), each
    mass on its own contact with the ground (g_i = q_i).

    ``mass`` (> 0), ``spring`` and ``damping`` (dashpots parallel to the springs, >= 0) are
    scalars or one value per mass; ``friction`` one model for all contacts or one per
    mass. ``sparse=True`` builds scipy.sparse (CSR) matrices: memory linear in the size,
    for `simulate_network_moreau` on long chains (dense matrices take 7·n² numbers).
    """
    n = as_count("n_masses", n_masses, minimum=1)
    check_type("sparse", sparse, (bool, np.bool_))
    if not sparse:
        check_dense_size("n_masses", n, n, n, "Pass sparse=True for a chain of this size "
                         "(scipy.sparse matrices, linear in the size).")  # fmt: skip
    else:
        check_size("n_masses", n, 12.0 * n, what="matrix entries")
    m = _per_mass("mass", mass, n, positive=True)
    ks = _per_mass("spring", spring, n, positive=False)
    cs = _per_mass("damping", damping, n, positive=False)
    models = _models(friction, n)

    def band(values: FloatArray) -> Any:
        upper = np.concatenate([values[1:], [0.0]])  # spring i+1 ties mass i to mass i+1
        diag = values + upper
        off = -values[1:]
        if sparse:
            return scipy.sparse.diags_array([off, diag, off], offsets=[-1, 0, 1], format="csr")
        out = np.diag(diag)
        idx = np.arange(n - 1)
        out[idx, idx + 1] = off
        out[idx + 1, idx] = off
        return out

    if sparse:
        mm: Any = scipy.sparse.diags_array(m, format="csr")
        w: Any = scipy.sparse.identity(n, format="csr")
    else:
        mm, w = np.diag(m), np.eye(n)
    return NetworkStructure(mm, band(ks), w, models, damping=band(cs), forcing=forcing)


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
    if not models:
        raise ValueError("`friction` must hold at least one model (one per contact); got none.")
    args = {}
    for name, value in (("mass", mass), ("stiffness", stiffness), ("damping", damping)):
        arr = as_real_array(name, value)
        if arr.size != 1:
            raise ValueError(f"`{name}` must be one number (one mass); got shape {arr.shape}.")
        args[name] = arr.reshape(1, 1)
    return NetworkStructure(args["mass"], args["stiffness"], np.ones((1, len(models))), models,
                            damping=args["damping"], forcing=forcing)  # fmt: skip


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
    w = as_real_array("frequencies", frequencies)
    if w.ndim > 1 or w.size == 0:
        raise ValueError(f"`frequencies` must be one or more numbers (one per mode); got shape "
                         f"{w.shape}.")  # fmt: skip
    w = w.reshape(-1)
    n = w.shape[0]
    check_dense_size("frequencies", f"{n} modes", n, n)
    if np.any(w < 0):
        raise ValueError(f"`frequencies` must be nonnegative; got {fmt(w[w < 0][0])}.")
    phi = as_real_array("mode_shapes", mode_shapes)
    if phi.ndim == 1 and n == 1:
        phi = phi.reshape(1, -1)
    if phi.ndim != 2 or phi.shape[0] != n or phi.shape[1] == 0:
        raise ValueError(
            f"`mode_shapes` must have shape ({n}, n_c): one row per mode (the {n} frequencies), "
            f"one column per contact; got shape {phi.shape}."
        )
    zero = ~np.any(phi != 0.0, axis=0)
    if zero.any():
        raise ValueError(f"`mode_shapes` must not have a zero column (a contact no mode moves); "
                         f"column {int(np.argmax(zero))} is zero.")  # fmt: skip
    zeta = as_real_array("damping_ratios", damping_ratios)
    if zeta.ndim == 0:
        zeta = np.full(n, float(zeta))
    if zeta.shape != (n,):
        raise ValueError(f"`damping_ratios` must be a number or one per mode ({n}); got shape "
                         f"{zeta.shape}.")  # fmt: skip
    if np.any(zeta < 0):
        raise ValueError(f"`damping_ratios` must be nonnegative; got {fmt(zeta[zeta < 0][0])}.")
    return NetworkStructure(np.eye(n), np.diag(w * w), phi, _models(friction, phi.shape[1]),
                            damping=np.diag(2.0 * zeta * w), forcing=forcing)  # fmt: skip
