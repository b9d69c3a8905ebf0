"""Friction memories with a given elastic force: the preload a record starts with.

A measured record rarely starts from the relaxed (virgin) memory: the contact
carries an elastic force F0 left by its earlier motion. `preloaded_state` builds
a memory with F_el = F0 from one of two one-parameter families:

* ``path="branch"`` (default): the memory after gross sliding opposite to
  `direction`, a reversal, and travel Δ in `direction` (Masing's rule, section 1:
  F_el = −d·F_m + d·2·φ(Δ/2) with φ the elastic virgin curve). F0 = d·F_m is the
  saturated memory of steady sliding in direction d; F0 = −d·F_m the memory at the
  reversal. This is the memory a stop with one reversal leaves behind, and the
  one `fit_response` and `fit_quasi_static` fit per record.
* ``path="virgin"``: the memory after loading from the relaxed state along the
  virgin curve, F_el = sign(F0)·φ(δ); F0 = 0 is the relaxed memory.

For finite elements, Δ solves Σ_j k_j·min(Δ, 2 r_j) = F_m + d·F0 (branch) or
δ solves Σ_j k_j·min(δ, r_j) = |F0| (virgin): piecewise linear, solved exactly
(`preload_deformation`, also used compiled by the fits).

Asymmetric friction (thresholds r_j⁺ in +y and r_j⁻ in −y, `presliding.friction._sides`):
the branch is that of the symmetric bank of the mid thresholds r̄_j = (r_j⁺ + r_j⁻)/2 with
every deformation shifted by δ_j = (r_j⁺ − r_j⁻)/2, so F0 ranges over [−F_m⁻, F_m⁺]; the
virgin curve loads the side of sign(F0) with that side's thresholds
(`preload_deformation_sided`).
"""

from __future__ import annotations

import math

import numpy as np

from presliding._validation import as_choice, as_real_scalar, fmt
from presliding.friction._sides import sides_of
from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis._jit import njit
from presliding.hysteresis._sorting import stable_argsort
from presliding.hysteresis.general_pi import MemoryState
from presliding.hysteresis.operators import PIState

__all__ = ["preload_deformation", "preload_deformation_sided", "preloaded_state"]

PATHS = ("branch", "virgin")


@njit(cache=True)
def preload_deformation(k, r, fraction, direction, branch, out):  # pragma: no cover - compiled
    """Deformations f_j of a bank whose elastic force is fraction·F_m (|fraction| <= 1).

    ``branch``: on the branch from saturation in −direction (see the module
    notes); else along the virgin curve (direction unused). Written into `out`.
    """
    n = k.shape[0]
    fm = 0.0
    for j in range(n):
        fm += k[j] * r[j]
    fraction = min(max(fraction, -1.0), 1.0)
    if branch:
        target = fm * (1.0 + direction * fraction)  # Σ k_j min(Δ, 2 r_j)
        scale = 2.0
    else:
        target = fm * abs(fraction)
        scale = 1.0
    # G(Δ) = Σ k_j min(Δ, scale·r_j) is piecewise linear and increasing: walk its knots
    order = stable_argsort(r)
    g = 0.0  # G at the current knot
    slope = 0.0
    for j in range(n):
        slope += k[j]
    prev = 0.0
    delta = scale * r[order[n - 1]] if n else 0.0
    for i in range(n):
        j = order[i]
        knot = scale * r[j]
        g_next = g + slope * (knot - prev)
        if target <= g_next:
            delta = prev + (target - g) / slope if slope > 0 else prev
            break
        g = g_next
        prev = knot
        slope -= k[j]
    for j in range(n):
        if branch:
            out[j] = direction * (min(delta, 2.0 * r[j]) - r[j])
        else:
            sgn = 1.0 if fraction > 0 else (-1.0 if fraction < 0 else 0.0)
            out[j] = sgn * min(delta, r[j])


@njit(cache=True)
def preload_deformation_sided(k, rp, rn, fraction, direction, branch, out):  # pragma: no cover
    """`preload_deformation` of an asymmetric bank: thresholds rp in +y, rn in −y.

    ``branch``: the symmetric bank of the mid thresholds, its deformations shifted by
    (rp − rn)/2 (the elastic force is then fraction·Σ k_j r̄_j + Σ k_j δ_j, module notes);
    else the virgin curve of the side sign(fraction), fraction of that side's F_m. Equal
    sides run `preload_deformation` itself (bit for bit).
    """
    n = k.shape[0]
    same = True
    for j in range(n):
        if rp[j] != rn[j]:
            same = False
            break
    if same:
        preload_deformation(k, rp, fraction, direction, branch, out)
        return
    if not branch:
        preload_deformation(k, rp if fraction >= 0.0 else rn, fraction, direction, False, out)
        return
    mid = 0.5 * (rp + rn)
    preload_deformation(k, mid, fraction, direction, True, out)
    for j in range(n):
        out[j] += 0.5 * (rp[j] - rn[j])


def preloaded_state(
    model: PIFriction,
    elastic_force: float,
    *,
    direction: float = 1.0,
    position: float = 0.0,
    path: str = "branch",
) -> PIState | MemoryState:
    """A memory of `model` at `position` whose elastic force is `elastic_force` (module notes).

    Parameters
    ----------
    model : PIFriction
        Finite elements or a density.
    elastic_force : float
        F0 [N], with |F0| <= F_m (the largest elastic force, `max_elastic_force`);
        an asymmetric model: −F_m⁻ <= F0 <= F_m⁺ (Σ c_j⁻ and Σ c_j⁺).
    direction : {1, -1}, keyword only
        For ``path="branch"``: the direction of the motion along the branch
        (F0 = direction·F_m is the saturated memory of sliding that way).
    position : float, keyword only
        The displacement y [m] of the memory.
    path : {"branch", "virgin"}, keyword only
        Which family of memories (module notes).

    Returns
    -------
    PIState or MemoryState
        A memory with Σ k_j f_j = F0 (or ∫ f dμ = F0), reachable from a relaxed
        or saturated state; direction `direction` (branch) or sign(F0) (virgin).

    Raises
    ------
    ValueError
        If |F0| > F_m, or an option is out of its domain.
    """
    if not isinstance(model, PIFriction):
        raise TypeError(f"`model` must be a PIFriction; got {type(model).__name__}.")
    f0 = as_real_scalar("elastic_force", elastic_force)
    y = as_real_scalar("position", position)
    path = as_choice("path", path, PATHS)
    d = as_real_scalar("direction", direction)
    if d not in (-1.0, 1.0):
        raise ValueError(f"`direction` must be 1 or -1; got {fmt(direction)}.")
    if not model.is_symmetric:
        return _asymmetric_state(model, f0, d, y, path == "branch")
    fm = model.max_elastic_force
    if abs(f0) > fm * (1 + 1e-12):
        raise ValueError(
            f"`elastic_force` must be at most F_m = {fmt(fm)} in magnitude (the largest force "
            f"the elements carry); got {fmt(f0)}."
        )
    fraction = f0 / fm if fm > 0 else 0.0
    if model.is_discrete:
        k, r = model.stiffness, model.threshold
        f = np.empty(k.shape[0])
        preload_deformation(k, r, fraction, d, path == "branch", f)
        sgn = d if path == "branch" else float(np.sign(f0))
        return PIState(y, y - f, sgn)
    return _density_state(model, fraction, d, y, path)


def _asymmetric_state(model: PIFriction, f0: float, d: float, y: float, branch: bool) -> PIState:
    """The memory of an asymmetric finite-element model (module notes)."""
    k = np.asarray(model.stiffness)
    rp, rn = sides_of(model).threshold
    fmp, fmn = float(k @ rp), float(k @ rn)
    if not -fmn * (1 + 1e-12) <= f0 <= fmp * (1 + 1e-12):
        raise ValueError(
            f"`elastic_force` must lie in [−F_m⁻, F_m⁺] = [{fmt(-fmn)}, {fmt(fmp)}] (the "
            f"largest forces the elements carry in each direction); got {fmt(f0)}."
        )
    if branch:
        mid = 0.5 * (rp + rn)
        fm_mid, shift = float(k @ mid), float(k @ (0.5 * (rp - rn)))
        fraction = (f0 - shift) / fm_mid if fm_mid > 0 else 0.0
    else:
        side = fmp if f0 >= 0 else fmn
        fraction = f0 / side if side > 0 else 0.0
    f = np.empty(k.shape[0])
    preload_deformation_sided(k, np.ascontiguousarray(rp), np.ascontiguousarray(rn),
                              fraction, d, branch, f)  # fmt: skip
    return PIState(y, y - f, d if branch else float(np.sign(f0)))


def _density_state(
    model: PIFriction, fraction: float, d: float, y: float, path: str
) -> MemoryState:
    """The memory of a continuous density, through the inverse of its elastic virgin curve."""
    from scipy.optimize import brentq

    dens = model.density
    big_r = dens.max_threshold  # type: ignore[union-attr]
    fm = model.max_elastic_force

    def psi(force: float) -> float:
        """δ with φ(δ) = force, 0 <= force <= F_m."""
        if force <= 0.0:
            return 0.0
        if force >= fm:
            return big_r
        hi = big_r if math.isfinite(big_r) else 1.0
        while math.isinf(big_r) and dens.virgin_curve(hi) < force:  # type: ignore[union-attr]
            hi *= 2.0
        curve = dens.virgin_curve  # type: ignore[union-attr]
        return brentq(lambda s: curve(s) - force, 0.0, hi, xtol=1e-15 * hi, rtol=1e-15)

    if path == "virgin":
        delta = psi(abs(fraction) * fm)
        sgn = float(np.sign(fraction))
        if delta == 0.0:
            return MemoryState.relaxed(y)
        base = y - sgn * delta if delta < big_r else -sgn * math.inf
        return MemoryState(y, np.empty(0), base, sgn)
    if fraction * d >= 1.0:
        return MemoryState.saturated(y, d, big_r)
    if fraction * d <= -1.0:
        return MemoryState.saturated(y, -d, big_r)
    travel = 2.0 * psi(0.5 * fm * (1.0 + d * fraction))
    turn = y - d * travel
    base = turn + d * big_r if math.isfinite(big_r) else d * math.inf
    return MemoryState(y, np.array([turn]), base, d)
