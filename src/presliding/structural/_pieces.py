"""The closed form of a jointed structure between events (joints of stops, c1 = 0).

Between events every stop j of joint c is elastic (force k_j·(g_c − x_j), x_j fixed) or
sliding in direction s_j (force s_j·k_j·r_j, x_j = g_c − s_j·r_j), so that

    M·q̈ + C·q̇ + K_e·q = Re(F̂·e^{iΩt}) + h,   K_e = K + Σ_c k_el,c·w_c·w_cᵀ,
    h = Σ_c w_c·(Σ_elastic k_j·x_j − Σ_sliding s_j·k_j·r_j),

a linear system with constant coefficients: z = (q, q̇) is the static part K_e⁻¹h, the
harmonic part Re(Ẑ·e^{iΩt}) with (K_e − Ω²M + iΩC)·Ẑ = F̂, and the homogeneous part
V·e^{Λτ}·V⁻¹·z_0 from the eigenvectors of the first-order matrix A. The state transition
of perturbations of (q, q̇, x) over a piece is closed form too (`Piece.transition`).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._validation import as_real_array, as_si, fmt
from presliding.structural.structure import JointedStructure

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: Largest condition number of a piece's eigenvectors (a nearly defective piece refused).
MAX_CONDITION = 1e9


def harmonic_force(force: Any, n: int) -> NDArray[np.complex128]:
    """F̂ of a harmonic force (a real vector: F̂·cos Ωt), checked: nonzero, shape (n,)."""
    force = as_si("force", force)  # a Quantity in N (complex too) before numpy sees it
    arr = np.asarray(force)
    if arr.dtype.kind == "c":
        parts = np.stack([arr.real, arr.imag])
        as_real_array("force", parts)
        out = arr.astype(np.complex128)
    else:
        out = as_real_array("force", force).astype(np.complex128)
    out = out.reshape(-1) if out.ndim == 0 and n == 1 else out
    if out.shape != (n,) or not np.any(out != 0):
        raise ValueError(f"`force` must be a nonzero vector of shape ({n},); got {fmt(arr)}.")
    return out


class Model:
    """A structure whose joints are stops: matrices, the stops flattened, the forcing."""

    def __init__(self, structure: JointedStructure, force: ComplexArray, frequency: float) -> None:
        if not structure.is_discrete or np.any([j.coulomb > 0 for j in structure.joints]):
            raise ValueError(
                "`structure` must have joints of stops only (finite elements, c1 = 0: Iwan or "
                "Jenkins joints) for this exact solver; joints with a Coulomb element c1 > 0 "
                "are simulated by `simulate_network`, and a density must be discretised."
            )
        if np.min(np.linalg.eigvalsh(structure.stiffness)) <= 1e-13 * np.max(
            np.abs(structure.stiffness)
        ):
            raise ValueError(
                "`structure` must have a positive definite stiffness K (the structure held "
                "without its joints), so that every piece, all stops sliding, has a rest state."
            )
        self.m, self.k = structure.mass, structure.stiffness
        self.c = np.asarray(structure.damping, dtype=np.float64)
        self.w = structure.contacts
        self.n, self.n_c = self.w.shape
        ks = [np.asarray(j.stiffness) for j in structure.joints]
        self.ek = np.concatenate(ks)
        self.er = np.concatenate([np.asarray(j.threshold) for j in structure.joints])
        self.owner = np.concatenate([np.full(k.shape[0], c) for c, k in enumerate(ks)])
        self.n_e = int(self.ek.shape[0])
        self.minv = np.linalg.inv(self.m)
        self.force = np.asarray(force, dtype=np.complex128)
        self.omega = float(frequency)
        self._cache: dict[bytes, Any] = {}

    def with_forcing(self, force: ComplexArray, frequency: float) -> Model:
        """The same model (its eigen data shared) with another harmonic force."""
        out = object.__new__(Model)
        out.__dict__.update(self.__dict__)
        out.force = np.asarray(force, dtype=np.complex128)
        out.omega = float(frequency)
        return out

    def linear(self, elastic: NDArray[np.bool_]) -> dict[str, Any]:
        """Eigen data of the piece with these stops elastic (cached)."""
        key = elastic.tobytes()
        got = self._cache.get(key)
        if got is not None:
            return dict(got)
        n = self.n
        kel = np.bincount(self.owner, self.ek * elastic, minlength=self.n_c)
        k_e = self.k + (self.w * kel) @ self.w.T
        a = np.zeros((2 * n, 2 * n))
        a[:n, n:] = np.eye(n)
        a[n:, :n] = -self.minv @ k_e
        a[n:, n:] = -self.minv @ self.c
        lam, vec = np.linalg.eig(a)
        if np.linalg.cond(vec) > MAX_CONDITION:
            raise ValueError(
                "`structure` gives a piece with a (nearly) critically damped mode, whose "
                "closed form this solver does not hold; change its damping slightly."
            )
        got = {"k_e": k_e, "k_e_inv": np.linalg.inv(k_e), "lam": lam, "vec": vec,
               "inv": np.linalg.inv(vec), "wq": self.w.T @ vec[:n], "wv": self.w.T @ vec[n:],
               "omega_max": float(np.max(np.abs(lam))), "harmonic": {}}  # fmt: skip
        self._cache[key] = got
        return dict(got)

    def harmonic(self, lin: dict[str, Any]) -> ComplexArray:
        """Ẑ of the piece: (K_e − Ω²M + iΩC)·Ẑ = F̂ (cached per Ω)."""
        store = lin["harmonic"]
        key = (self.omega, self.force.tobytes())
        if key not in store:
            if not np.any(self.force != 0):
                store[key] = np.zeros(self.n, dtype=np.complex128)
            else:
                dyn = lin["k_e"] - self.omega**2 * self.m + 1j * self.omega * self.c
                store[key] = np.linalg.solve(dyn, self.force)
        return np.asarray(store[key])


class Piece:
    """One piece: the stops' modes fixed, from (t0, q0, v0, x0)."""

    def __init__(self, model: Model, t0: float, q0: FloatArray, v0: FloatArray,
                 x0: FloatArray, sliding: FloatArray) -> None:  # fmt: skip
        self.model, self.t0, self.x0 = model, t0, x0.copy()
        self.sliding = sliding.copy()
        elastic = sliding == 0
        self.elastic = elastic
        lin = model.linear(elastic)
        self.lin = lin
        md = model
        el = np.bincount(md.owner, md.ek * x0 * elastic, minlength=md.n_c)
        sl = np.bincount(md.owner, sliding * md.ek * md.er, minlength=md.n_c)
        self.q_h = lin["k_e_inv"] @ (md.w @ (el - sl))
        self.z_hat = md.harmonic(lin)
        zp_q, zp_v = self._particular(np.array([t0]))
        z0 = np.r_[q0 - self.q_h - zp_q[0], v0 - zp_v[0]]
        self.coef = lin["inv"] @ z0
        self.g0 = md.w.T @ q0
        self.omega_max = max(lin["omega_max"], md.omega)

    def _particular(self, t: FloatArray) -> tuple[FloatArray, FloatArray]:
        """The harmonic part of q and q̇ at absolute times t, shape (T, n)."""
        om = self.model.omega
        if om == 0.0 or not np.any(self.z_hat != 0):
            z = np.zeros((t.shape[0], self.model.n))
            return z, z
        e = np.exp(1j * om * t)[:, None] * self.z_hat[None, :]
        return e.real, (1j * om * e).real

    def state(self, tau: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """q, q̇, q̈ at piece times τ, shape (T, n) each."""
        lin, n = self.lin, self.model.n
        e = np.exp(np.outer(tau, lin["lam"])) * self.coef
        z = (e @ lin["vec"].T).real
        dz = ((e * lin["lam"]) @ lin["vec"].T).real
        pq, pv = self._particular(self.t0 + tau)
        om = self.model.omega
        pa = -(om**2) * pq
        return z[:, :n] + self.q_h + pq, z[:, n:] + pv, dz[:, n:] + pa

    def contacts(self, tau: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """g, ġ, g̈ of every joint at piece times τ, shape (T, n_c) each."""
        lin = self.lin
        e = np.exp(np.outer(tau, lin["lam"])) * self.coef
        g = (e @ lin["wq"].T).real
        gd = (e @ lin["wv"].T).real
        gdd = ((e * lin["lam"]) @ lin["wv"].T).real
        w = self.model.w
        pq, pv = self._particular(self.t0 + tau)
        om = self.model.omega
        return g + (self.q_h @ w) + pq @ w, gd + pv @ w, gdd - om**2 * (pq @ w)

    def elements(self, tau: float, q: FloatArray) -> FloatArray:
        """x of every stop at piece time τ (sliding ones follow their joint)."""
        g = self.model.w.T @ q
        dx = (g - self.g0)[self.model.owner]
        return np.where(self.sliding != 0, self.x0 + dx, self.x0)

    def _particular_derivative(self, t: float, d_force: ComplexArray, d_omega: float
                               ) -> FloatArray:  # fmt: skip
        """∂(q_p, q̇_p)/∂p at absolute time t for dF̂/dp = d_force, dΩ/dp = d_omega."""
        md, om, z = self.model, self.model.omega, self.z_hat
        n = md.n
        if om == 0.0:
            return np.zeros(2 * n)
        dyn = self.lin["k_e"] - om**2 * md.m + 1j * om * md.c
        rhs = d_force - d_omega * ((-2.0 * om * md.m + 1j * md.c) @ z)
        dz = np.linalg.solve(dyn, rhs) if np.any(rhs != 0) else np.zeros(n, complex)
        e = np.exp(1j * om * t)
        dq = (dz + d_omega * 1j * t * z) * e
        dv = (1j * d_omega * z + 1j * om * dz - d_omega * om * t * z) * e
        return np.r_[dq.real, dv.real]

    def parameter_derivative(self, tau: float, d_force: ComplexArray, d_omega: float
                             ) -> FloatArray:  # fmt: skip
        """∂(q, q̇, x)(τ)/∂p of the piece from an unperturbed start: the forcing's
        derivative (its amplitude, its frequency at fixed time), shape (N,)."""
        md, lin, n = self.model, self.lin, self.model.n
        e = ((lin["vec"] * np.exp(lin["lam"] * tau)) @ lin["inv"]).real
        d0 = self._particular_derivative(self.t0, d_force, d_omega)
        d1 = self._particular_derivative(self.t0 + tau, d_force, d_omega)
        out = np.zeros(2 * n + md.n_e)
        out[: 2 * n] = d1 - e @ d0
        sl = np.flatnonzero(~self.elastic)
        out[2 * n + sl] = md.w[:, md.owner[sl]].T @ out[:n]
        return out

    def transition(self, tau: float) -> FloatArray:
        """∂(q, q̇, x)(τ)/∂(q, q̇, x)(0) over the piece, shape (N, N), N = 2n + n_e."""
        md, lin, n = self.model, self.lin, self.model.n
        e = (lin["vec"] * np.exp(lin["lam"] * tau)) @ lin["inv"]
        e = e.real
        big = 2 * n + md.n_e
        out = np.zeros((big, big))
        out[: 2 * n, : 2 * n] = e
        # elastic stops shift the rest state: q_h = K_e⁻¹·W·(k_j·x_j)
        b = np.zeros((2 * n, md.n_e))
        b[:n] = lin["k_e_inv"] @ (md.w[:, md.owner] * (md.ek * self.elastic))
        out[: 2 * n, 2 * n :] = b - e @ b
        out[2 * n :, 2 * n :] = np.eye(md.n_e)
        sl = np.flatnonzero(~self.elastic)
        if sl.size:
            wsl = md.w[:, md.owner[sl]].T  # (s, n)
            out[2 * n + sl, :] += wsl @ out[:n, :]
            out[2 * n + sl, :n] -= wsl
        return out
