"""The flat-direction probe: a far step along the least determined split of the stiffnesses.

Stops and loops determine the sum Σ k_j of the elements' stiffnesses well (the
initial presliding stiffness after a reversal, eq. 7) and the break-away forces
c_j = (F_c − c1)/N; the split of Σ k_j among the elements, through the
thresholds r_j = c_j/k_j (eq. 6), only where the records' swings cross those
thresholds. Where they do not, the cost has a long curved valley in the k_j,
and a second optimum at almost the same cost can lie far along it: the starts
all derive from one regression start, the neighbouring-valley probes
(`_probes`) move a tenth of a stiffness, and the profile walk stops at the
likelihood-ratio threshold, so none of them reaches it, and the local intervals
miss it by several standard errors.

The probe (`flat_probe`), from the best optimum θ̂:

1. A = JᵀJ at θ̂, split into the free k_j and the other free parameters z;
   the Schur complement S = A_kk − A_kz A_zz⁻¹ A_zk (A_zz⁻¹ by the scaled
   pseudo-inverse, `_normal_equations.scaled_pinv`) is the curvature of the cost
   in the k_j with every other parameter re-optimised (S⁻¹ = h_kk, their block
   of (JᵀJ)⁻¹). The flattest direction of the split is the eigenvector u of
   the smallest eigenvalue of diag(k) S diag(k) (relative steps, so that a
   stiff and a soft element weigh alike), δk = u·k. S is used, not h_kk: two
   elements coalesced (k_a = k_b, one column twice in J) leave S singular
   along their split, which the pseudo-inverse h_kk would hide;
2. every other parameter follows the linearised profile path,
   δz = −A_zz⁻¹ A_zk δk (the records' own initial position, velocity and
   preload included), clipped to the bounds;
3. both ways (±δθ), steps of `SHARES` of the step that brings the first
   stiffness to its bound (0, or an upper bound), at most the step that moves
   one stiffness by the largest of them: far, but every k_j stays inside;
4. each start (one of two mirror images, for elements of equal break-away
   force) solved short (`budget` evaluations); the lowest of those that
   ended within `REFINE_WITHIN` × the best's cost in another basin is solved
   on to its own optimum (`_probes.other_valley`). Every optimum a solve
   reaches is kept on the run, so one that the profile's threshold does not
   exclude widens the intervals and makes the fit ``not_identifiable`` (rule
   ``optima``, `_alternatives`); a lower one in another basin becomes the
   best (a solve that stayed in θ̂'s basin never does: in a flat valley it ends
   lower within the solver's tolerance, and differently for starts equal only
   to rounding, which would break the mirror symmetry).

Its cost: one Jacobian at θ̂, 2·len(`SHARES`) short solves and at most one solve
on. A well-determined split costs the same and changes nothing: the short
solves return to θ̂ or end far above it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from presliding.identification.intervals._alternatives import canonical
from presliding.identification.search._probes import other_valley
from presliding.identification.search._search import (
    REFINE_WITHIN,
    SAME_POINT,
    TIE,
    cost,
    same_point,
)
from presliding.identification.solve._least_squares import Solution
from presliding.identification.solve._normal_equations import FloatArray, normal_matrix, scaled_pinv

__all__ = ["SHARES", "flat_direction", "flat_probe", "flat_starts"]

#: shares of the step to the first stiffness's bound taken along the flat direction
SHARES = (0.5,)


def flat_direction(
    sol: Solution, k_names: Sequence[str]
) -> tuple[tuple[str, ...], FloatArray] | None:
    """The free parameters and δθ along the flattest direction of the free k_j (module
    notes, steps 1–2), or None where it is not defined (fewer than two free positive
    stiffnesses, no profiler, a Jacobian that is not finite)."""
    prof = sol.profiler
    if prof is None or sol.status == "failed":
        return None
    free = tuple(prof.free)
    ks = [free.index(x) for x in k_names if x in free and sol.values[x] > 0]
    if len(ks) < 2:
        return None
    x = np.array([sol.values[n] for n in free], dtype=float)
    normal = normal_matrix(prof.jacobian(x))
    if not np.all(np.isfinite(normal)):
        return None
    zs = [i for i in range(len(free)) if i not in ks]
    a_kz = normal[np.ix_(ks, zs)]
    inv_zz = scaled_pinv(normal[np.ix_(zs, zs)]) if zs else np.zeros((0, 0))
    schur = normal[np.ix_(ks, ks)] - a_kz @ inv_zz @ a_kz.T
    k = x[ks]
    _, vectors = np.linalg.eigh(schur * np.outer(k, k))
    dk = vectors[:, 0] * k
    step = np.zeros(len(free))
    step[ks] = dk
    step[zs] = -inv_zz @ a_kz.T @ dk
    return free, step


def _reach(k: FloatArray, dk: FloatArray, lo: FloatArray, hi: FloatArray) -> float:
    """The step along `dk` that brings the first stiffness to its bound, at most the one
    that moves a stiffness by the largest of them."""
    out = float(np.max(np.abs(k)) / np.max(np.abs(dk)))
    down, up = dk < 0, dk > 0
    if np.any(down):
        out = min(out, float(np.min((k[down] - np.maximum(lo[down], 0.0)) / -dk[down])))
    if np.any(up & np.isfinite(hi)):
        sel = up & np.isfinite(hi)
        out = min(out, float(np.min((hi[sel] - k[sel]) / dk[sel])))
    return max(out, 0.0)


def flat_starts(sol: Solution, k_names: Sequence[str],
                shares: Sequence[float] = SHARES) -> list[dict[str, float]]:  # fmt: skip
    """Starts stepped far along the flat direction, both ways (module notes, step 3)."""
    found = flat_direction(sol, k_names)
    if found is None:
        return []
    free, step = found
    prof = sol.profiler
    x = np.array([sol.values[n] for n in free], dtype=float)
    ks = np.array([i for i, n in enumerate(free) if n in k_names and sol.values[n] > 0])
    starts = []
    for sign in (1.0, -1.0):
        d = sign * step
        reach = _reach(x[ks], d[ks], prof.lower[ks], prof.upper[ks])
        if not np.isfinite(reach) or reach <= 0:
            continue
        for share in shares:
            moved = np.clip(x + share * reach * d, prof.lower, prof.upper)
            starts.append({**sol.values, **dict(zip(free, moved.tolist(), strict=True))})
    return starts


def flat_probe(
    problem,
    solve: Callable[..., Solution],
    sol: Solution,
    k_names: Sequence[str],
    budget: int,
    shares: Sequence[float] = SHARES,
    interchangeable: bool = True,
) -> tuple[Solution, list[Solution]]:
    """The flat-direction probe from `sol` (module notes): the best of it and `sol`, and
    the probe's solutions (the one solved on in place of its short solve). With
    `interchangeable` elements (equal break-away forces) a solution is compared with
    `sol` after relabelling its elements in `sol`'s order (`_alternatives.canonical`)."""
    labels = list(k_names) if interchangeable and set(k_names) <= set(sol.free) else []
    starts: list[dict[str, float]] = []
    for begin in flat_starts(sol, k_names, shares):  # a mirror image of one is that one
        seen = [canonical(s, sol.values, labels) for s in starts]
        if not any(_alike(canonical(begin, sol.values, labels), s) for s in seen):
            starts.append(begin)
    short = [solve(begin, max_evaluations=budget) for begin in starts]

    def elsewhere(t: Solution) -> bool:  # interchangeable elements relabelled first
        return not same_point(problem, canonical(t.values, sol.values, labels), sol.values)

    apart = [i for i, t in enumerate(short)
             if cost(t) <= REFINE_WITHIN * cost(sol) and elsewhere(t)]  # fmt: skip
    if apart:
        i = min(apart, key=lambda j: cost(short[j]))
        short[i] = other_valley(problem, solve, short[i], sol)
    # a solve that stayed in `sol`'s basin does not move the fit: in a flat valley it ends
    # lower within the solver's tolerance, differently for starts equal only to rounding
    # (a record and its mirror image)
    best = min((t for t in short if elsewhere(t)), key=cost, default=sol)
    return (best if cost(best) < cost(sol) * (1.0 - TIE) else sol), short


def _alike(a: dict[str, float], b: dict[str, float]) -> bool:
    """Two starts equal to `SAME_POINT` in every value (a split of coalesced elements taken
    both ways: one start after relabelling)."""
    names = list(a)
    return bool(np.allclose([a[x] for x in names], [b[x] for x in names], rtol=SAME_POINT,
                            atol=0.0))  # fmt: skip
