"""A periodic orbit's pieces evaluated: samples, exact peak amplitudes, exact harmonics.

Within a piece q(τ) = Re(Σ_k V_k·c_k·e^{λ_k τ}) + q_h + Re(Ẑ·e^{iΩ(t0+τ)}), so the
Fourier coefficients Q_h = (2/T)∫ q·e^{−ihΩt} dt are sums of closed-form integrals of
exponentials, and a peak is where q̇_i = 0 (Brent's method near the sampled extreme).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from presliding.structural._pieces import Piece

FloatArray = NDArray[np.float64]


class Orbit:
    """The pieces of one period [0, T) of a periodic orbit."""

    def __init__(self, pieces: list[tuple[Piece, float]], period: float) -> None:
        self.pieces, self.period = pieces, period
        self.starts = np.array([p.t0 for p, _ in pieces])

    def state(self, t: FloatArray) -> tuple[FloatArray, FloatArray]:
        """q and q̇ at times t in [0, T], shape (len(t), n)."""
        i = np.clip(np.searchsorted(self.starts, t, side="right") - 1, 0, len(self.pieces) - 1)
        n = self.pieces[0][0].model.n
        q, v = np.zeros((t.shape[0], n)), np.zeros((t.shape[0], n))
        for k in np.unique(i):
            sel = i == k
            piece = self.pieces[k][0]
            qk, vk, _ = piece.state(t[sel] - piece.t0)
            q[sel], v[sel] = qk, vk
        return q, v

    def amplitude(self, samples: int = 256) -> FloatArray:
        """(max q_i − min q_i)/2 of every coordinate, the extremes refined to rounding."""
        t = np.linspace(0.0, self.period, samples + 1)
        q, v = self.state(t)
        n = q.shape[1]
        out = np.zeros(n)
        for i in range(n):
            top = self._extreme(i, t, q[:, i], v[:, i], 1.0)
            bottom = -self._extreme(i, t, -q[:, i], -v[:, i], -1.0)
            out[i] = 0.5 * (top - bottom)
        return out

    def _extreme(self, i: int, t: FloatArray, q: FloatArray, v: FloatArray, sign: float) -> float:
        """max of sign·q_i: the sampled one, refined where sign·q̇_i changes from + to −."""
        j = int(np.argmax(q))
        best = float(q[j])
        last = t.shape[0] - 1  # t[last] = T is t[0] again
        for a, b in ((j - 1, j), (j, j + 1)):
            if a < 0 or b > last or not (v[a] > 0.0 > v[b]):
                continue

            def vel(s: float) -> float:
                return sign * float(self.state(np.array([s]))[1][0, i])

            root = brentq(vel, t[a], t[b], xtol=1e-15 * self.period, rtol=4 * np.finfo(float).eps)
            best = max(best, sign * float(self.state(np.array([root]))[0][0, i]))
        return best

    def harmonics(self, order: int) -> NDArray[np.complex128]:
        """Q_h, h = 0..order, shape (order + 1, n): q(t) = Re(Σ_h Q_h·e^{ihΩt}) (Q_0 the mean)."""
        om = 2.0 * np.pi / self.period
        n = self.pieces[0][0].model.n
        out = np.zeros((order + 1, n), dtype=np.complex128)
        for piece, tau in self.pieces:
            lin = piece.lin
            vq = lin["vec"][:n] * piece.coef  # q_hom(τ) = Re(Σ_k vq_k e^{λ_k τ})
            for h in range(order + 1):
                s = -1j * h * om
                phase = np.exp(s * piece.t0)
                acc = np.zeros(n, dtype=np.complex128)
                for lam, conj in ((lin["lam"], False), (np.conj(lin["lam"]), True)):
                    coef = np.conj(vq) if conj else vq
                    acc += 0.5 * coef @ _integral(lam + s, tau)
                acc += piece.q_h * _integral(np.array([s]), tau)[0]
                zp = piece.z_hat
                if np.any(zp != 0):
                    e0 = np.exp(1j * piece.model.omega * piece.t0)
                    acc += 0.5 * zp * e0 * _integral(np.array([1j * piece.model.omega + s]), tau)[0]
                    acc += 0.5 * np.conj(zp * e0) * _integral(
                        np.array([-1j * piece.model.omega + s]), tau)[0]  # fmt: skip
                out[h] += phase * acc
        out *= 2.0 / self.period
        out[0] *= 0.5
        return out


def _integral(rate: NDArray[np.complex128], tau: float) -> NDArray[np.complex128]:
    """∫_0^τ e^{rate·s} ds, without cancellation for small |rate·τ|."""
    x = rate * tau
    small = np.abs(x) < 1e-5
    safe = np.where(small, 1.0, rate)
    return np.where(small, tau * (1 + x / 2 + x * x / 6), np.expm1(x) / safe)
