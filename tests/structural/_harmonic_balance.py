"""A small harmonic balance (alternating frequency–time) for structures with Jenkins joints.

Written for the comparisons with the exact periodic orbits (tests and benchmarks): the
unknowns are the cosine and sine coefficients of q up to harmonic H, the joints' forces
are found in the time domain on N samples of a period (the stop run over two periods
from its relaxed state, the second period kept: the steady loop) and projected back
onto the harmonics (a discrete Fourier transform); scipy's `fsolve` solves the balance.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import fsolve


def _stop_forces(g, k, r):
    """The stop's force along two periods of g (N samples each), the second period."""
    n = g.shape[0]
    x, out = 0.0, np.empty(n)
    for i in range(2 * n):
        gi = g[i % n]
        x = min(max(x, gi - r), gi + r)
        if i >= n:
            out[i - n] = k * (gi - x)
    return out


class HarmonicBalance:
    """M q̈ + C q̇ + K q + Σ_c w_c·F_c(w_cᵀq) = Re(F̂ e^{iΩt}), F_c a stop (k_c, r_c)."""

    def __init__(self, mass, damping, stiffness, contacts, stops, force, harmonics, samples=256):
        self.m, self.c, self.k = (np.atleast_2d(np.asarray(a, float)) for a in
                                  (mass, damping, stiffness))  # fmt: skip
        self.w = np.atleast_2d(np.asarray(contacts, float))
        self.stops = stops
        self.f = np.asarray(force, complex).reshape(-1)
        self.h, self.samples = harmonics, samples
        self.n = self.m.shape[0]
        theta = 2 * np.pi * np.arange(samples) / samples
        hs = np.arange(1, harmonics + 1)
        self.basis = np.hstack([np.ones((samples, 1)), np.cos(np.outer(theta, hs)),
                                np.sin(np.outer(theta, hs))])  # fmt: skip

    def displacement(self, coef):
        """q at the N samples, shape (N, n), from coefficients (2H + 1, n)."""
        return self.basis @ coef

    def residual(self, y, omega):
        n, hh = self.n, self.h
        coef = y.reshape(2 * hh + 1, n)
        q = self.displacement(coef)
        g = q @ self.w
        fnl = np.zeros_like(q)
        for c, (k, r) in enumerate(self.stops):
            fnl += np.outer(_stop_forces(g[:, c], k, r), self.w[:, c])
        proj = np.linalg.lstsq(self.basis, fnl, rcond=None)[0]  # the DFT coefficients
        res = np.empty_like(coef)
        res[0] = self.k @ coef[0] + proj[0]
        for h in range(1, hh + 1):
            a, b = coef[h], coef[hh + h]
            w = h * omega
            dyn = self.k - w * w * self.m
            fc = self.f.real if h == 1 else 0.0
            fs = -self.f.imag if h == 1 else 0.0
            res[h] = dyn @ a + w * self.c @ b + proj[h] - fc
            res[hh + h] = dyn @ b - w * self.c @ a + proj[hh + h] - fs
        return res.reshape(-1)

    def solve(self, omega, guess=None):
        """The coefficients (2H + 1, n) at Ω; converged flag."""
        if guess is None:
            stuck = self.k + sum(k * np.outer(self.w[:, c], self.w[:, c])
                                 for c, (k, _) in enumerate(self.stops))  # fmt: skip
            amp = np.linalg.solve(stuck - omega**2 * self.m + 1j * omega * self.c, self.f)
            guess = np.zeros((2 * self.h + 1, self.n))
            guess[1], guess[self.h + 1] = amp.real, -amp.imag
        y, _, ok, _ = fsolve(self.residual, np.ravel(guess), args=(omega,), xtol=1e-12,
                             full_output=True)  # fmt: skip
        return y.reshape(2 * self.h + 1, self.n), ok == 1

    def amplitude(self, coef, dense=4096):
        """(max − min)/2 of every coordinate from the truncated series."""
        theta = 2 * np.pi * np.arange(dense) / dense
        hs = np.arange(1, self.h + 1)
        basis = np.hstack([np.ones((dense, 1)), np.cos(np.outer(theta, hs)),
                           np.sin(np.outer(theta, hs))])  # fmt: skip
        q = basis @ coef
        return 0.5 * (q.max(axis=0) - q.min(axis=0))
