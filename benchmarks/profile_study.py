"""Study of the profile step on the pooled benchmark (20 stops × 1000 samples, 67 parameters).

For the single-start and the default fit of `bench_pooled_fit.py`, the solution handed to
the profile step is kept and the step run on it on one BLAS thread and on the default
pool (`threadpoolctl`), and from an optimum moved by 1e-12 of each standard error.
Printed per fit: the time of each run, each profiled or checked parameter's method and
ends in standard errors from the estimate, and the largest move of an end between runs.

Then the roughness of the profile of `mass` itself: the fall of the cost when every
free parameter is re-optimised from the optimum, and P at ±1 and ±2 standard errors
solved from two starts (the linearised path, and the optimum's own values of the
others) with up to `--evaluations` residual evaluations each, in units of P_crit. Where
the two differ by a sizeable share of P_crit, an end found from them depends on where
the solver stops, and the step keeps the Wald interval.

Run: python benchmarks/profile_study.py [--evaluations N]
"""

from __future__ import annotations

import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _stops import stop_records
from threadpoolctl import threadpool_limits

from presliding import fit_response
from presliding.identification import fit_result
from presliding.identification.intervals import _profile, _profile_inner

_CAUGHT: list = []
_original = fit_result.profile_solution


def _catch(sol, *args, **kw):
    _CAUGHT.append(sol)
    return _original(sol, *args, **kw)


fit_result.profile_solution = _catch


def _ends(out, sol):
    rows = {}
    for name, method in out.interval_method.items():
        v, se = sol.values[name], sol.standard_error[name]
        lo, hi = out.confidence_interval[name]
        rows[name] = (method, (lo - v) / se, (hi - v) / se)
    return rows


def _roughness(sol, evaluations: int) -> None:
    prof = sol.profiler
    x = np.array([sol.values[n] for n in prof.free])
    c0 = _profile.cost(prof.fun(x))
    x, c0 = _profile._onto_bounds(prof, x, c0)
    normal = _profile._normal_matrix(prof.jacobian(x))
    hinv = _profile.scaled_pinv(normal)
    j = prof.free.index("mass")
    se = sol.standard_error["mass"]
    crit = (prof.quantile * se) ** 2 / hinv[j, j]
    full = _profile_inner.minimise(
        prof.fun, prof.jacobian, x, prof.lower, prof.upper, tol=1e-4 * crit,
        max_nfev=evaluations, step_limit=prof.step_limit,
    )  # fmt: skip
    print(f"  mass: re-optimising every parameter from the optimum lowers the cost by "
          f"{(c0 - full.cost) / crit:.3f} P_crit ({full.nfev} evaluations)")  # fmt: skip
    walk = _profile.Walker(prof, x, c0, normal, j, crit)
    for k in (-2.0, -1.0, 1.0, 2.0):
        theta = x[j] + k * se
        path = x[walk.keep] + k * se * walk.path
        got = []
        for z0 in (path, x[walk.keep]):
            z0 = np.clip(z0, prof.lower[walk.keep], prof.upper[walk.keep])
            res = _profile_inner.minimise(
                lambda z, t=theta: prof.fun(walk.full(z, t)),
                lambda z, t=theta: prof.jacobian(walk.full(z, t)).tocsc()[:, walk.keep],
                z0, prof.lower[walk.keep], prof.upper[walk.keep], tol=1e-4 * crit,
                max_nfev=evaluations,
                step_limit=lambda z, t=theta: prof.step_limit(walk.full(z, t))[walk.keep],
            )  # fmt: skip
            got.append((res.cost - c0) / crit)
        print(f"  mass {k:+.0f} SE: P/P_crit {got[0]:.3f} (path start), {got[1]:.3f} "
              f"(optimum's others): differ by {abs(got[0] - got[1]):.3f}")  # fmt: skip


def main(evaluations: int = 100) -> None:
    records, _, _ = stop_records(0, 20)
    fit_response(records[:2], signal="both", initial_state="preload", max_evaluations=5)
    for label, kw in (("single start", {"multistart": False}), ("default", {})):
        _CAUGHT.clear()
        fit_response(records, signal="both", initial_state="preload", **kw)
        sol = _CAUGHT[0]
        step = _profile.profile_solution.__wrapped__
        runs = {}
        for tag, limit, s in (("one thread", 1, sol), ("default pool", None, sol),
                              ("moved 1e-12 SE", 1, replace(sol, values={
                                  n: v + 1e-12 * sol.standard_error[n]
                                  for n, v in sol.values.items()}))):  # fmt: skip
            t0 = time.perf_counter()
            with threadpool_limits(limit):
                out = step(s, "auto")
            runs[tag] = (_ends(out, sol), time.perf_counter() - t0)
        print(f"{label}:")
        first = runs["one thread"][0]
        for tag, (rows, dt) in runs.items():
            shown = {n: r for n, r in rows.items() if r[0] == "profile" or n == "mass"}
            text = "; ".join(
                f"{n} {m} [{lo:+.3f}, {hi:+.3f}] SE" for n, (m, lo, hi) in shown.items()
            )
            move = max(
                max(abs(a - b) for a, b in zip(r[1:], first[n][1:], strict=True))
                for n, r in rows.items()
            )
            print(f"  {tag}: {dt:.2f} s; {text}; largest move of an end {move:.2g} SE")
        _roughness(sol, evaluations)


if __name__ == "__main__":
    n = int(sys.argv[sys.argv.index("--evaluations") + 1]) if "--evaluations" in sys.argv else 100
    main(n)
