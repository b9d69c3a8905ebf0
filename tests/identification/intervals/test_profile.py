"""Profile-likelihood intervals (`identification._profile`): exact for a linear model,
asymmetric where the model is not, unbounded where the data do not bound an end."""

from __future__ import annotations

import numpy as np
from scipy import optimize, stats

from presliding.identification.intervals._profile import profile_solution
from presliding.identification.judge._status import judge
from presliding.identification.solve._least_squares import solve_least_squares

RNG = np.random.default_rng(7)


def test_a_linear_model_gives_the_exact_f_interval():
    x = np.linspace(0.0, 1.0, 40)
    y = 1.5 - 0.7 * x + 0.4 * x**2 + RNG.normal(0.0, 0.05, x.shape)
    design = np.column_stack([np.ones_like(x), x, x**2])

    def residual(p):
        return design @ p - y

    sol = solve_least_squares(
        residual, {"a": 0.0, "b": 0.0, "c": 0.0}, jacobian=lambda p: design, tolerance=1e-12
    )
    prof = profile_solution(sol, "all")
    # closed form: the F (Student t) interval of ordinary least squares
    beta, res, *_ = np.linalg.lstsq(design, y, rcond=None)
    n, p = design.shape
    s2 = float(res[0]) / (n - p)
    se = np.sqrt(s2 * np.diag(np.linalg.inv(design.T @ design)))
    t = stats.t.ppf(0.975, n - p)
    for i, name in enumerate("abc"):
        lo, hi = prof.confidence_interval[name]
        assert prof.interval_method[name] == "profile"
        assert abs(lo - (beta[i] - t * se[i])) <= 1e-6 * se[i]
        assert abs(hi - (beta[i] + t * se[i])) <= 1e-6 * se[i]


def test_a_nonlinear_model_gets_an_asymmetric_interval_where_the_profile_crosses():
    """Each end agrees with the closed-form profile's crossing to 1e-3 of the Wald half width
    t·SE (`_profile_walk.END_ACCURACY`). That is the accuracy the search is built for: an end's
    sampling error is of the order of the half width itself (the estimate moves by SE from one
    data set to the next), so 1e-3 of it changes no coverage, and asking more only spends
    inner optimisations. The requirement is stated in the parameter, where it matters, not in
    the cost (1e-3 of the half width is about 2e-3·P_crit there)."""
    t = np.linspace(0.0, 3.0, 12)
    y = 2.0 * np.exp(-1.3 * t) + RNG.normal(0.0, 0.08, t.shape)

    def residual(p):
        return p[0] * np.exp(-p[1] * t) - y

    sol = solve_least_squares(residual, {"amplitude": 1.0, "rate": 1.0}, tolerance=1e-12)
    prof = profile_solution(sol, "all")
    k = sol.values["rate"]
    lo, hi = prof.confidence_interval["rate"]
    assert lo < k < hi
    assert abs((hi - k) - (k - lo)) > 0.05 * (hi - lo)  # Wald is symmetric, the profile is not

    def profile(rate):  # the amplitude enters linearly: its optimum in closed form
        e = np.exp(-rate * t)
        a = float(e @ y / (e @ e))
        r = a * e - y
        return float(r @ r)

    c0 = float(sol.residual @ sol.residual)
    n = t.shape[0]
    crit = stats.t.ppf(0.975, n - 2) ** 2 * c0 / (n - 2)
    half = stats.t.ppf(0.975, n - 2) * sol.standard_error["rate"]
    for end, far in ((lo, k - 4.0 * half), (hi, k + 4.0 * half)):
        exact = optimize.brentq(lambda r: profile(r) - c0 - crit, k, far, xtol=1e-14)
        assert abs(end - exact) <= 1e-3 * half
        assert abs(profile(end) - c0 - crit) <= 4e-3 * crit  # the same in the cost


def test_an_end_the_data_do_not_bound_is_unbounded_and_not_identifiable():
    """y = a·(1 − exp(−c·x)) on data that are a straight line: a → ∞, c → 0 fits as well."""
    x = np.linspace(0.0, 1.0, 30)
    y = 2.0 * x + RNG.normal(0.0, 0.01, x.shape)

    def residual(p):
        return p[0] * (1.0 - np.exp(-p[1] * x)) - y

    sol = solve_least_squares(
        residual, {"a": 5.0, "c": 0.5}, bounds={"a": (0.0, np.inf), "c": (0.0, np.inf)}
    )
    prof = profile_solution(sol, "all")
    assert prof.confidence_interval["a"][1] == np.inf
    status, message = judge(
        "converged", "ok", y, y + sol.residual, prof.free, prof.at_bounds, "y",
        values=prof.values, standard_error=prof.standard_error,
        intervals=prof.confidence_interval, covariance=None, bounds=prof.bounds,
    )  # fmt: skip
    assert status == "not_identifiable" and "unbounded" in message and " a " in f" {message}"


def test_a_parameter_whose_wald_interval_a_bound_cuts_is_profiled_first():
    """With budget for one profile only, it goes to the parameter the bound cuts (c), not to
    the first-named well-determined ones (a, b)."""
    x = np.linspace(0.0, 1.0, 40)
    y = 1.5 - 0.7 * x + 0.1 * x**2 + np.random.default_rng(1).normal(0.0, 0.05, x.shape)
    design = np.column_stack([np.ones_like(x), x, x**2])
    sol = solve_least_squares(
        lambda p: design @ p - y, {"a": 0.0, "b": 0.0, "c": 0.1}, jacobian=lambda p: design,
        bounds={"c": (0.0, np.inf)}, tolerance=1e-12,
    )  # fmt: skip
    c, se = sol.values["c"], sol.standard_error["c"]
    assert 0.0 < c < 2.0 * se  # the Wald interval reaches the bound
    assert sol.confidence_interval["c"][0] == 0.0
    prof = profile_solution(sol, "all", budget=1)
    assert prof.interval_method == {"a": "wald", "b": "wald", "c": "profile"}
    full = profile_solution(sol, "all")
    assert set(full.interval_method.values()) == {"profile"}


# ---------------------------------------------------------------- pooled records (blocks)
def _pooled_decays(seed: int = 5, records: int = 4, sparse_jacobian: bool = True):
    """Records y_i = A_i·exp(−k·t) + noise: k shared, each record its own amplitude A_i (a
    pooled fit's structure: the Jacobian has one full column and one block per record).
    The profile of k has a closed form: each A_i is linear, A_i(k) = e·y_i / e·e."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 3.0, 15)
    amplitudes = rng.uniform(1.0, 3.0, records)
    y = amplitudes[:, None] * np.exp(-1.3 * t) + rng.normal(0.0, 0.05, (records, t.size))

    def residual(p):
        return (p[1:, None] * np.exp(-p[0] * t) - y).ravel()

    def jacobian(p):
        e = np.exp(-p[0] * t)
        out = np.zeros((records * t.size, records + 1))
        for i in range(records):
            rows = slice(i * t.size, (i + 1) * t.size)
            out[rows, 0] = -t * p[1 + i] * e
            out[rows, 1 + i] = e
        return out

    start = {"rate": 1.0, **{f"amplitude_{i}": 1.0 for i in range(records)}}
    sol = solve_least_squares(residual, start, jacobian=jacobian, tolerance=1e-12)
    if sparse_jacobian:
        from dataclasses import replace

        from scipy import sparse

        prof = replace(sol.profiler, jac=lambda x: sparse.csc_matrix(jacobian(np.asarray(x))))
        sol = replace(sol, profiler=prof)

    def profile(rate):
        e = np.exp(-rate * t)
        a = y @ e / (e @ e)
        r = a[:, None] * e - y
        return float(np.sum(r * r))

    return sol, profile, y.size


def test_a_pooled_profile_end_meets_the_closed_form():
    """The inner optimisations with per-record steps (sparse Jacobian with record blocks):
    each end within 1e-3 of the Wald half width of the closed-form profile's crossing."""
    sol, profile, n = _pooled_decays()
    out = profile_solution(sol, ["rate"])
    assert out.interval_method["rate"] == "profile"
    k, c0 = sol.values["rate"], float(sol.residual @ sol.residual)
    p = len(sol.free)
    q = stats.t.ppf(0.975, n - p)
    crit = q**2 * c0 / (n - p)
    half = q * sol.standard_error["rate"]
    lo, hi = out.confidence_interval["rate"]
    for end, far in ((lo, k - 4.0 * half), (hi, k + 4.0 * half)):
        exact = optimize.brentq(lambda r: profile(r) - c0 - crit, k, far, xtol=1e-14)
        assert abs(end - exact) <= 1e-3 * half


def test_profile_ends_do_not_move_with_blas_threads_or_rounding():
    """The profile step on one BLAS thread and on the default pool, and from an optimum moved
    by rounding (1e-12 of a standard error): the ends agree to 1e-3 standard errors."""
    from dataclasses import replace

    from threadpoolctl import threadpool_limits

    sol, _, _ = _pooled_decays(seed=11, records=6)
    run = profile_solution.__wrapped__  # the step without its one-thread context
    with threadpool_limits(1):
        one = run(sol, "all", budget=200)
    many = run(sol, "all", budget=200)
    moved = replace(
        sol, values={n: v + 1e-12 * sol.standard_error[n] for n, v in sol.values.items()}
    )
    nudged = profile_solution(moved, "all", budget=200)
    for name in sol.free:
        se = sol.standard_error[name]
        assert one.interval_method[name] == many.interval_method[name] == "profile"
        for other in (many, nudged):
            ends = zip(one.confidence_interval[name], other.confidence_interval[name], strict=True)
            for a, b in ends:
                assert abs(a - b) <= 1e-3 * se


def test_an_optimum_that_is_not_a_minimum_on_the_scale_of_the_interval_keeps_wald():
    """Values two standard errors away from the optimum along `rate` (the others not
    re-optimised): re-optimising lowers the cost by far more than P_crit/10, so a profile
    measured from there would be decided by where the inner optimisations stop. The
    interval stays the Wald interval the solution carries, and says so."""
    from dataclasses import replace

    sol, _, _ = _pooled_decays()
    k, se = sol.values["rate"], sol.standard_error["rate"]
    off = replace(sol, values={**sol.values, "rate": k + 2.0 * se})
    out = profile_solution(off, "all")
    assert set(out.interval_method.values()) == {"wald"}
    assert out.confidence_interval == off.confidence_interval


def test_a_parameter_a_hair_inside_its_bound_is_put_on_it():
    """`_onto_bounds`: 1e-9 inside a bound goes onto it where the cost does not rise; a
    parameter well inside stays."""
    from presliding.identification.intervals._profile import _onto_bounds

    x = np.linspace(0.0, 1.0, 20)
    y = 1.0 - np.exp(-3.0 * x)

    def residual(p):
        return p[0] * (1.0 - np.exp(-p[1] * x)) - y

    sol = solve_least_squares(
        residual, {"a": 0.9, "c": 3.0}, bounds={"a": (0.0, 1.0), "c": (0.0, 10.0)}
    )
    prof = sol.profiler
    v = np.array([1.0 - 1e-9, 3.0])
    c = float(np.sum(residual(v) ** 2))
    y_on, c_on = _onto_bounds(prof, v, c)
    assert y_on[0] == 1.0 and y_on[1] == 3.0 and c_on <= c
    w = np.array([0.5, 3.0])
    assert np.array_equal(_onto_bounds(prof, w, float(np.sum(residual(w) ** 2)))[0], w)


def test_auto_profiles_a_doubtful_wald_interval_and_not_a_determined_one(monkeypatch):
    """Two independent parts: a slope fitted to 40 points (linear: the cost along its
    linearised path is the quadratic, its Wald interval exact) and a decay rate fitted to
    10 noisy points (the cost departs from the quadratic at its Wald ends). "auto" keeps the
    slope's Wald interval without an inner optimisation and profiles the rate, whose
    interval is then asymmetric about the estimate."""
    from presliding.identification.intervals import _profile_walk

    rng = np.random.default_rng(4)
    x, t = np.linspace(0.0, 1.0, 40), np.linspace(0.0, 3.0, 10)
    y1 = 3.0 * x + rng.normal(0.0, 0.05, x.size)
    y2 = np.exp(-1.3 * t) + rng.normal(0.0, 0.05, t.size)

    def residual(p):
        return np.concatenate([p[0] * x - y1, np.exp(-p[1] * t) - y2])

    sol = solve_least_squares(residual, {"slope": 1.0, "rate": 1.0}, tolerance=1e-12)
    held = []
    original = _profile_walk.Walker._solve

    def solve(walk, theta, z0):
        held.append(walk.prof.free[walk.j])
        return original(walk, theta, z0)

    monkeypatch.setattr(_profile_walk.Walker, "_solve", solve)
    out = profile_solution(sol, "auto")
    assert out.interval_method == {"slope": "wald", "rate": "profile"}
    assert set(held) == {"rate"}  # no inner optimisation spent on the slope
    assert out.confidence_interval["slope"] == sol.confidence_interval["slope"]
    lo, hi = out.confidence_interval["rate"]
    k = sol.values["rate"]
    assert abs((hi - k) - (k - lo)) > 0.05 * (hi - lo)
