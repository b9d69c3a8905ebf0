"""Benchmark of the viscous term σ·ẏ in the exact event method.

Prints, measured in this run:
1. the Coulomb–viscous stop against its closed form (m/σ)·ln(1 + σ·v0/F_c) and
   (m·F_c/σ²)·(x − ln(1 + x)), x = σ·v0/F_c (50-digit decimal reference), over a
   log grid of m, σ, F_c and v0: the largest relative errors;
2. the event method against the implicit method as the step goes to 0 with
   elements and σ > 0: the errors and the fitted order;
3. the energy balance residual of free stops and forced motions with σ > 0,
   relative to the initial energy (or to the work of u);
4. the cost of the event method with σ > 0 against σ = 0 on the same motion,
   per event (2 samples, the compiled loop alone) and per output sample
   (10,001 samples, whole `simulate` calls that include the viscous energy
   record, and `free_response`, which has no energy record), as medians and
   ranges of 7 repeats measured in this run, with their ratios.

Run: python benchmarks/bench_viscous.py
"""

from __future__ import annotations

import itertools
import time
from decimal import Decimal, getcontext

import numba as nb
import numpy as np

import presliding as ps
from presliding.motion import _event

getcontext().prec = 50
K = np.array([400.0, 60.0, 9.0])
R = np.array([0.002, 0.01, 0.05])


def timings(fn, repeat: int = 7, number: int = 1) -> np.ndarray:
    """Wall times of `number` calls (seconds per call), `repeat` times."""
    fn()
    out = []
    for _ in range(repeat):
        t = time.perf_counter()
        for _ in range(number):
            fn()
        out.append((time.perf_counter() - t) / number)
    return np.array(out)


def fmt_times(t: np.ndarray, unit: float = 1e-6, name: str = "us") -> str:
    lo, hi = t.min() / unit, t.max() / unit
    return f"median {np.median(t) / unit:8.2f} {name} (range {lo:.2f}-{hi:.2f})"


def closed_form() -> None:
    worst_t = worst_y = 0.0
    grid = itertools.product([0.01, 1.0, 100.0], [1e-4, 1e-2, 1.0, 1e2, 1e3], [0.01, 1.0, 100.0],
                             [1e-3, 0.1, 10.0])  # fmt: skip
    n = 0
    for m, sigma, fc, v0 in grid:
        mm, s, f, v = (Decimal(repr(a)) for a in (m, sigma, fc, v0))
        x = s * v / f
        t_ref = float(mm / s * (1 + x).ln())
        y_ref = float(mm * f / (s * s) * (x - (1 + x).ln()))
        res = ps.simulate(ps.PIFriction(fc, viscous=sigma), m, initial_velocity=v0,
                          t_eval=[0.0, 2 * t_ref])  # fmt: skip
        worst_t = max(worst_t, abs(res.stop_time - t_ref) / t_ref)
        worst_y = max(worst_y, abs(res.rest_position - y_ref) / y_ref)
        n += 1
    print(f"1. Coulomb-viscous stop, {n} cases (m, σ, F_c, v0 over 2-6 decades):")
    print(f"   largest relative error: stop time {worst_t:.1e}, rest position {worst_y:.1e}")


def convergence() -> None:
    print("2. event vs implicit as h -> 0 (3 elements, c1 = 0.3, m = 1, u piecewise constant)")
    u = (np.array([0.0, 0.4, 0.9]), np.array([2.5, -0.2, 0.0]))
    kw = dict(applied_force=u, initial_velocity=0.3, t_eval=np.linspace(0.0, 2.0, 201))
    steps = np.array([8e-4, 4e-4, 2e-4, 1e-4, 5e-5, 2.5e-5])
    for sigma in (0.05, 2.0, 40.0):
        model = ps.PIFriction(0.3, K, threshold=R, viscous=sigma)
        exact = ps.simulate(model, 1.0, method="event", **kw)
        errs = np.array([np.max(np.abs(ps.simulate(model, 1.0, method="implicit", step=h, **kw)
                                       .position - exact.position)) for h in steps])  # fmt: skip
        order = np.polyfit(np.log(steps), np.log(errs), 1)[0]
        print(
            f"   σ = {sigma:5g}: max |Δy| {errs[0]:.2e} .. {errs[-1]:.2e} m, "
            f"fitted order {order:.3f}"
        )


def energy() -> None:
    rng = np.random.default_rng(0)
    free, forced = [], []
    for _ in range(200):
        n = int(rng.integers(0, 6))
        sigma = 10 ** rng.uniform(-3, 2)
        model = ps.PIFriction(rng.uniform(0.05, 1.0), rng.uniform(10, 1000, n),
                              rng.uniform(0.1, 1.0, n), viscous=sigma)  # fmt: skip
        res = ps.simulate(model, rng.uniform(0.5, 2.0), initial_velocity=rng.uniform(0.2, 3.0),
                          initial_state="saturated", t_end=50.0)  # fmt: skip
        free.append(np.max(np.abs(res.energy.residual)) / res.energy.initial)
        u = (np.linspace(0, 2, 9), rng.uniform(-3, 3, 9))
        res = ps.simulate(model, 1.0, applied_force=u, initial_velocity=0.4, t_end=3.0)
        forced.append(res.energy.max_relative_residual)
    print("3. energy balance residual with σ > 0 (200 random models, σ in [1e-3, 1e2]):")
    print(
        f"   free stops: max {max(free):.1e}, median {np.median(free):.1e} (of the initial energy)"
    )
    print(f"   forced:     max {max(forced):.1e}, median {np.median(forced):.1e} (of max(E0, |W|))")


@nb.njit(cache=False)
def _events(n, sigma, energy, t_eval):  # pragma: no cover - compiled
    """n runs of the event kernel (3 elements, saturated start, free motion)."""
    total = 0.0
    for _ in range(n):
        o = np.zeros((9, t_eval.shape[0]))
        rev = np.zeros((2, 64))
        f = R.copy()
        u = np.zeros(1)
        if energy:
            res = _event.run_events(1.5, 0.02, K, R, f, 0.0, 0.8, 1.0, u, u, t_eval, t_eval[-1],
                                    10_000_000, o[0], o[1], o[2], o[3], o[4], o[5], o[6], o[8],
                                    rev[0], rev[1], sigma, o[7], u[:0],
                                    _event.damped_flag(sigma))  # fmt: skip
        else:
            res = _event.run_events(1.5, 0.02, K, R, f, 0.0, 0.8, 1.0, u, u, t_eval, t_eval[-1],
                                    10_000_000, o[0], o[1], o[2], o[3], o[4], o[5], o[6], o[8],
                                    rev[0], rev[1], sigma, u[:0], u[:0],
                                    _event.damped_flag(sigma))  # fmt: skip
        total += res[4]
    return total


def cost() -> None:
    print("4. cost of the event method, σ = 0.02 against σ = 0 on the same free stop (3 elements,")
    print("   20 events, 18 reversals each), compiled loops only; 'energy' also integrates the")
    print("   viscous loss σ·∫v² (what `simulate` records), without it is what batches,")
    print("   `free_response` and fits run. Medians (ranges) of 7 interleaved repeats:")
    model = ps.PIFriction(0.02, K, threshold=R, viscous=0.02)
    ref = ps.simulate(model, 1.5, initial_velocity=0.8, initial_state="saturated", t_end=60.0)
    plain = ps.simulate(ps.PIFriction(0.02, K, threshold=R), 1.5, initial_velocity=0.8,
                        initial_state="saturated", t_end=60.0)  # fmt: skip
    assert ref.n_events == plain.n_events == 20
    t_end = 1.01 * ref.stop_time
    runs = (("per event (2 samples)", np.array([0.0, t_end]), 400),
            ("per sample (10,001)", np.linspace(0.0, t_end, 10_001), 4))  # fmt: skip
    for label, t_eval, n in runs:
        per = 20 if t_eval.shape[0] == 2 else 10_001
        times = {key: [] for key in itertools.product((0.0, 0.02), (False, True))}
        for key in times:
            _events(1, key[0], key[1], t_eval)
        for _ in range(7):
            for key in times:
                t = time.perf_counter()
                _events(n, key[0], key[1], t_eval)
                times[key].append((time.perf_counter() - t) / n / per)
        print(f"   {label}:")
        for energy in (False, True):
            a, b = np.array(times[(0.0, energy)]), np.array(times[(0.02, energy)])
            ratio = b / a
            print(
                f"     {'energy   ' if energy else 'no energy'}  σ = 0: {fmt_times(a, 1e-9, 'ns')}"
            )
            print(f"                σ > 0: {fmt_times(b, 1e-9, 'ns')}")
            print(f"                ratio {np.median(ratio):.1f}x (range {ratio.min():.1f}-"
                  f"{ratio.max():.1f})")  # fmt: skip


if __name__ == "__main__":
    closed_form()
    convergence()
    energy()
    cost()
