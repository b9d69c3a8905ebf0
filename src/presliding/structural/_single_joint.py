"""The virgin curve of a structure with one joint, in closed form (any density).

With one joint λ = F(g), g = wᵀq, loaded along b (K·q + w·λ = P·b, u = bᵀq), the
state is linear in (g, λ): [[K, −b], [wᵀ, 0]]·[q; P] = [−w·λ; g], so
q = g·q_g + λ·q_λ, P = g·P_g + λ·P_λ. On the virgin curve λ = F_v(g) (c1 + the
density's virgin curve), and u(g) = g·u_g + F_v(g)·u_λ is increasing; a rigid joint
(c1 > 0) first stays stuck (g = 0, λ a reaction) until |λ| = c1. The amplitude u = a
is solved for g to rounding (Brent's method on the closed form), and the loop's
dissipation is the joint's, D = 4·c1·g + 4·(g·M1(g) − M2(g)), at that g.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from presliding.analysis import amplitude_response
from presliding.friction import PIFriction
from presliding.structural._slow_flow import harmonic_stiffness_curve

FloatArray = NDArray[np.float64]


class SingleJoint:
    """The closed-form virgin curve u(g), P(g), q(g) of a structure with one joint."""

    def __init__(self, k: FloatArray, w: FloatArray, b: FloatArray, joint: PIFriction) -> None:
        n = k.shape[0]
        self.joint = joint
        s = np.zeros((n + 1, n + 1))
        s[:n, :n], s[:n, n], s[n, :n] = k, -b, w
        try:
            base = np.linalg.solve(s, np.c_[np.r_[np.zeros(n), 1.0], np.r_[-w, 0.0]])
        except np.linalg.LinAlgError:
            raise ValueError(
                "`structure` must be held when its joint is given a displacement along the "
                "load (the equations [[K, −b], [wᵀ, 0]] are singular)."
            ) from None
        self.q_g, self.q_l = base[:n, 0], base[:n, 1]
        self.p_g, self.p_l = float(base[n, 0]), float(base[n, 1])
        self.u_g, self.u_l = float(b @ self.q_g), float(b @ self.q_l)
        sign = -1.0 if self.u_g < 0 else 1.0  # the joint is odd: (g, λ) → (−g, −λ)
        self.q_g, self.p_g, self.u_g = sign * self.q_g, sign * self.p_g, sign * self.u_g
        self.q_l, self.p_l, self.u_l = sign * self.q_l, sign * self.p_l, sign * self.u_l
        tol = 1e-12 * float(np.linalg.norm(b) * np.linalg.norm(base[:, 1]))
        if not (self.u_g > 0 and self.u_l >= -tol):  # u(g) must grow with g: Cauchy–Schwarz
            raise ValueError(
                "`structure` is not order-preserving along this load (its joint's displacement "
                "does not grow with the modal amplitude); no backbone is returned."
            )
        self.u_l = max(self.u_l, 0.0)
        # stuck (g = 0): [[K, w, −b], [wᵀ, 0, 0], [bᵀ, 0, 0]]·[q; λ; P] = [0; 0; u]
        self.rigid = joint.coulomb > 0.0
        if self.rigid:
            t = np.zeros((n + 2, n + 2))
            t[:n, :n], t[:n, n], t[:n, n + 1], t[n, :n], t[n + 1, :n] = k, w, -b, w, b
            rhs = np.zeros(n + 2)
            rhs[-1] = 1.0
            stuck = np.linalg.solve(t, rhs)
            self.q_s, self.l_s, self.p_s = stuck[:n], float(stuck[n]), float(stuck[n + 1])
            self.u_slip = joint.coulomb / abs(self.l_s) if self.l_s != 0 else np.inf

    def virgin(self, g: float) -> float:
        """F_v(g) for g >= 0 (c1 at g = 0+ when rigid; 0 at g = 0)."""
        return float(self.joint.virgin_curve(g))

    def u_of(self, g: float) -> float:
        return self.u_g * g + self.u_l * self.virgin(g)

    def solve(self, a: float) -> tuple[float, float, float, FloatArray]:
        """(g, λ, P, q) on the virgin curve at u = a > 0."""
        if self.rigid and a <= self.u_slip:
            return 0.0, self.l_s * a, self.p_s * a, self.q_s * a
        lo = 0.0
        hi = a / max(self.u_g, 1e-300)
        for _ in range(200):
            if self.u_of(hi) >= a:
                break
            lo, hi = hi, 2.0 * hi
        else:
            raise ValueError(f"the amplitude {a!r} is beyond the structure's reach along the load.")
        g = float(brentq(lambda x: self.u_of(x) - a, lo, hi, xtol=1e-300, rtol=8.9e-16))
        lam = self.virgin(g)
        return g, lam, self.p_g * g + self.p_l * lam, self.q_g * g + self.q_l * lam

    def tangent(self, g: float) -> float:
        """dP/du on the virgin curve at joint displacement g (g = 0: the stuck slope)."""
        if g == 0.0:
            return self.p_s if self.rigid else (self.p_g + self._slope(0.0) * self.p_l) / (
                self.u_g + self._slope(0.0) * self.u_l)  # fmt: skip
        t = self._slope(g)
        return (self.p_g + t * self.p_l) / (self.u_g + t * self.u_l)

    def _slope(self, g: float) -> float:
        """dF_v/dg of the joint: the tail T(g) of its elements (eq. 10)."""
        density = self.joint.density
        assert density is not None
        return float(density.tail(g)) if g < density.max_threshold else 0.0

    def sampler(self, top: float) -> Any:
        """P_v(u) for 0 <= u <= top, interpolated on 4000 exact points of the curve."""
        g_top = self.solve(top)[0]
        gs = np.r_[0.0, np.geomspace(max(g_top, 1e-300) * 1e-9, max(g_top, 1e-300), 4000)]
        lam = np.asarray(self.joint.virgin_curve(gs), dtype=np.float64)
        us = self.u_g * gs + self.u_l * lam
        ps = self.p_g * gs + self.p_l * lam
        if self.rigid:  # the stuck segment u <= u_slip
            us, ps = np.r_[0.0, us[1:]], np.r_[0.0, ps[1:]]
        return lambda u: np.interp(u, us, ps)


def single_joint_curve(
    k: FloatArray, w: FloatArray, b: FloatArray, joint: PIFriction, amplitudes: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """(P, D, q, P', ω₁²) at modal amplitudes a: the force, the loop's dissipation, the
    deflection, the backbone's tangent and the loop's first-harmonic stiffness."""
    sj = SingleJoint(k, w, b, joint)
    rows = [sj.solve(float(a)) for a in amplitudes]
    g = np.array([r[0] for r in rows])
    p = np.array([r[2] for r in rows])
    q = np.array([r[3] for r in rows])
    d = np.zeros_like(g)
    slid = g > 0
    if slid.any():
        d[slid] = amplitude_response(joint, g[slid]).dissipation
    tangent = np.array([sj.tangent(float(x)) for x in g])
    virgin = sj.sampler(float(np.max(amplitudes)))
    first = harmonic_stiffness_curve(virgin, np.asarray(amplitudes, dtype=np.float64))
    return p, d, q, tangent, first
