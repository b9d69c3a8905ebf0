"""`JointedStructure`: masses, springs and dampers with PI or Iwan joints.

    M·q̈ + C·q̇ + K·q + W·λ = f(t),     λ_c = F_c(g_c),  g_c = w_cᵀq

Each joint c is a symmetric PI model F_c (eq. 8 or eq. 10) of its relative displacement
g_c: a `PIFriction` with finite elements or a density (an Iwan joint: `SegalmanIwan`,
`MindlinContact`, ...), with a Coulomb element c1 >= 0. A joint without a Coulomb element
(c1 = 0) is a hysteretic spring of stiffness Σ k_j at small amplitudes; with one (c1 > 0)
it is rigid until it slips. Its linear modes with the joints stuck are those of
(M, K + Σ_c k_c·w_c·w_cᵀ) with the rigid joints as constraints.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import as_count, as_list, as_real_array, check_type, fmt
from presliding.friction import PIFriction
from presliding.hysteresis import Density
from presliding.network import NetworkStructure
from presliding.network.structure import square_matrix

__all__ = ["JointedStructure"]

FloatArray = NDArray[np.float64]


def _joint(i: int, value: Any) -> PIFriction:
    if isinstance(value, Density):
        value = PIFriction(0.0, density=value)
    check_type(f"joints[{i}]", value, (PIFriction, Density))
    if not value.is_symmetric:
        raise ValueError(f"`joints[{i}]` must be symmetric (one level both ways); got {value!r}.")
    if value.viscous != 0.0:
        raise ValueError(
            f"`joints[{i}]` must have no viscous term (put viscous damping in `damping`); got "
            f"viscous={value.viscous!r}."
        )
    if value.coulomb == 0.0 and value.is_discrete and value.n_elements == 0:
        raise ValueError(f"`joints[{i}]` must hold c1 > 0, an element or a density; got none.")
    return value


@dataclass(frozen=True, eq=False)
class JointedStructure:
    """A structure with joints: M, K, C, the joints' directions W and one PI model each.

    Parameters
    ----------
    mass : array_like, shape (n, n) or (n,)
        M, symmetric positive definite [kg] (a vector: diagonal).
    stiffness : array_like, shape (n, n) or (n,)
        K, symmetric positive semidefinite [N/m]: the structure without its joints.
    contacts : array_like, shape (n, n_c)
        W: joint c acts on the relative displacement g_c = w_cᵀq.
    joints : sequence of PIFriction or Density, length n_c
        One symmetric PI model per joint without a viscous term: finite elements (eq. 8)
        or a density (eq. 10; a `Density` alone stands for ``PIFriction(0, density=...)``).
    damping : array_like, shape (n, n) or (n,), optional, keyword only
        C, symmetric positive semidefinite [N·s/m] (the fixture's or material damping).

    Examples
    --------
    A mass on a spring with one Jenkins joint (20 N/m, slipping at 1 N):

    >>> s = JointedStructure(1.0, 3.0, [[1.0]], [PIFriction(0.0, [20.0], breakaway=[1.0])])
    >>> w, phi = s.linear_modes()
    >>> round(float(w[0]) ** 2, 12), float(phi[0, 0])
    (23.0, 1.0)
    """

    mass: FloatArray
    stiffness: FloatArray
    contacts: FloatArray
    joints: tuple[PIFriction, ...]
    damping: FloatArray | None = field(default=None, kw_only=True)

    if TYPE_CHECKING:

        def __init__(self, mass: ArrayLike, stiffness: ArrayLike, contacts: ArrayLike,
                     joints: Sequence[PIFriction | Density], *,
                     damping: ArrayLike | None = None) -> None: ...  # fmt: skip

    def __post_init__(self) -> None:
        m = square_matrix("mass", self.mass, None, definite=True)
        n = m.shape[0]
        k = square_matrix("stiffness", self.stiffness, n, definite=False)
        damping = np.zeros((n, n)) if self.damping is None else self.damping
        c = square_matrix("damping", damping, n, definite=False)
        w = as_real_array("contacts", self.contacts)
        w = w.reshape(1, -1) if (w.ndim == 1 and n == 1) else w
        if w.ndim != 2 or w.shape[0] != n or w.shape[1] == 0:
            raise ValueError(
                f"`contacts` must have shape ({n}, n_c) with n_c >= 1 (one column per joint); "
                f"got {w.shape}."
            )
        if (~np.any(w != 0.0, axis=0)).any():
            col = int(np.argmax(~np.any(w != 0.0, axis=0)))
            raise ValueError(f"`contacts` must not have a zero column; column {col} is zero.")
        joints = tuple(_joint(i, j) for i, j in enumerate(as_list("joints", self.joints)))
        if len(joints) != w.shape[1]:
            raise ValueError(
                f"`joints` must hold one model per contact ({w.shape[1]}); got {len(joints)}."
            )
        w = np.ascontiguousarray(w)
        w.setflags(write=False)
        for name, value in (("mass", m), ("stiffness", k), ("damping", c), ("contacts", w),
                            ("joints", joints)):  # fmt: skip
            object.__setattr__(self, name, value)

    # ------------------------------------------------------------------ properties
    @property
    def n_coordinates(self) -> int:
        """n, the number of coordinates q."""
        return int(self.mass.shape[0])

    @property
    def n_contacts(self) -> int:
        """n_c, the number of joints."""
        return int(self.contacts.shape[1])

    @property
    def is_discrete(self) -> bool:
        """True when every joint has finite elements (eq. 8)."""
        return all(j.is_discrete for j in self.joints)

    @property
    def is_damped(self) -> bool:
        """True when C ≠ 0."""
        return bool(np.any(self.damping != 0.0))

    @property
    def rigid(self) -> NDArray[np.bool_]:
        """Per joint: rigid while stuck (a Coulomb element c1 > 0, or an infinite stiffness)."""
        return np.array([j.coulomb > 0.0 or not np.isfinite(j.initial_stiffness)
                         for j in self.joints])  # fmt: skip

    @property
    def joint_stiffness(self) -> FloatArray:
        """Per joint: its stiffness when stuck, Σ k_j or μ([0, R]) (eq. 7) [N/m]."""
        return np.array([j.initial_stiffness for j in self.joints])

    def stuck_stiffness(self) -> FloatArray:
        """K + Σ_c k_c·w_c·w_cᵀ over the joints that are not rigid [N/m]."""
        soft = ~self.rigid
        w = self.contacts[:, soft]
        return np.asarray(self.stiffness + (w * self.joint_stiffness[soft]) @ w.T)

    def linear_modes(self) -> tuple[FloatArray, FloatArray]:
        """The modes with every joint stuck: frequencies ω_i [rad/s] in increasing order and
        mass-normalised shapes φ_i (columns, φᵀMφ = I), rigid joints as constraints
        (w_cᵀφ = 0); a shape's largest entry is made positive."""
        rigid = self.contacts[:, self.rigid]
        if rigid.shape[1]:
            u, s, _ = np.linalg.svd(rigid, full_matrices=True)
            rank = int(np.sum(s > 1e-12 * s[0]))
            z = u[:, rank:]
        else:
            z = np.eye(self.n_coordinates)
        if z.shape[1] == 0:
            raise ValueError(
                "`contacts` must leave the structure a motion with its rigid joints stuck; the "
                "joints with c1 > 0 hold every coordinate, so it has no linear mode."
            )
        mr = z.T @ self.mass @ z
        kr = z.T @ self.stuck_stiffness() @ z
        lam, psi = _generalised_eigh(kr, mr)
        phi = z @ psi
        big = np.argmax(np.abs(phi), axis=0)
        phi = phi * np.sign(phi[big, np.arange(phi.shape[1])])
        return np.sqrt(np.maximum(lam, 0.0)), phi

    def mode(self, index: int) -> tuple[float, FloatArray]:
        """(ω [rad/s], φ) of linear mode `index` (0: the lowest), joints stuck."""
        w, phi = self.linear_modes()
        i = as_count("mode", index, maximum=w.shape[0] - 1)
        return float(w[i]), np.ascontiguousarray(phi[:, i])

    # ------------------------------------------------------------------ conversions
    @classmethod
    def from_network(cls, structure: NetworkStructure) -> JointedStructure:
        """The same masses, springs, dampers and contacts (the forcing is not kept)."""
        check_type("structure", structure, NetworkStructure)
        return cls(structure.mass, structure.stiffness, structure.contacts, structure.friction,
                   damping=structure.damping)  # fmt: skip

    def to_network(self, forcing: Any = 0.0) -> NetworkStructure:
        """The `NetworkStructure` of `simulate_network` (every joint with finite elements and
        a Coulomb element c1 > 0)."""
        bad = [i for i, j in enumerate(self.joints) if not (j.is_discrete and j.coulomb > 0.0)]
        if bad:
            raise ValueError(
                f"`joints` must all have finite elements and c1 > 0 for `simulate_network`; "
                f"joint {bad[0]} is {self.joints[bad[0]]!r}."
            )
        return NetworkStructure(self.mass, self.stiffness, self.contacts, self.joints,
                                damping=self.damping, forcing=forcing)  # fmt: skip

    @classmethod
    def modal(cls, frequencies: ArrayLike, mode_shapes: ArrayLike,
              joints: PIFriction | Density | Sequence[PIFriction | Density], *,
              damping_ratios: ArrayLike = 0.0) -> JointedStructure:  # fmt: skip
        """A modal model (unit modal masses) with joints: K = diag(ω_i²), C = diag(2ζ_iω_i),
        ``mode_shapes`` (n, n_c) the joints' relative displacement per unit of each mode."""
        w = as_real_array("frequencies", frequencies).reshape(-1)
        phi = as_real_array("mode_shapes", mode_shapes)
        phi = phi.reshape(w.shape[0], -1) if phi.ndim == 1 else phi
        zeta = np.broadcast_to(as_real_array("damping_ratios", damping_ratios), w.shape)
        if np.any(w < 0) or np.any(zeta < 0):
            raise ValueError(
                f"`frequencies` and `damping_ratios` must be nonnegative; got {fmt(w)} and "
                f"{fmt(zeta)}."
            )
        n_c = phi.shape[1] if phi.ndim == 2 else 0
        models = [joints] * n_c if isinstance(joints, PIFriction | Density) else joints
        return cls(np.eye(w.shape[0]), np.diag(w * w), phi, models,
                   damping=np.diag(2.0 * zeta * w))  # fmt: skip

    def __repr__(self) -> str:
        return (
            f"JointedStructure(n_coordinates={self.n_coordinates}, n_contacts={self.n_contacts}, "
            f"damped={self.is_damped})"
        )


def _generalised_eigh(k: FloatArray, m: FloatArray) -> tuple[FloatArray, FloatArray]:
    """K·ψ = λ·M·ψ with ψᵀMψ = I, M positive definite (by its Cholesky factor)."""
    low = np.linalg.cholesky(m)
    inv = np.linalg.inv(low)
    lam, y = np.linalg.eigh(inv @ k @ inv.T)
    return lam, inv.T @ y


def as_structure(structure: Any) -> JointedStructure:
    """A `JointedStructure` (a `NetworkStructure` converted), else a TypeError."""
    if isinstance(structure, NetworkStructure):
        return JointedStructure.from_network(structure)
    return check_type("structure", structure, JointedStructure)
