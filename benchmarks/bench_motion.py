"""Benchmark of the motion simulators (issue: motion with exact stiction).

Prints, measured in this run:
1. a free stop with several reversals solved exactly by the event method
   against a fixed-step simulation with dt = 1e-6 (the implicit stepper, the
   fastest fixed-step scheme here) of the same motion: times, ratio, and the
   fixed-step errors that the exact method does not have;
2. the implicit stepper's time per step for N = 5 elements (wall clock; see
   bench_kernels.py for CPU time and the straightforward-step ratio);
3. `free_response` (10,000 samples, N = 4) per call, as used inside a loss.

Run: python benchmarks/bench_motion.py
"""

from __future__ import annotations

import time

import numpy as np

import presliding as ps
from presliding.motion import _implicit
from presliding.motion._forcing import as_forcing
from presliding.motion._run import implicit_grid, run_event, run_implicit


def best_of(fn, repeat: int = 7, number: int = 1) -> float:
    """Best wall time of `number` calls, over `repeat` tries (seconds per call)."""
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        for _ in range(number):
            fn()
        best = min(best, (time.perf_counter() - t) / number)
    return best


def free_stop() -> None:
    # one Coulomb element and two presliding elements: several reversals
    model = ps.PIFriction(coulomb=0.1, stiffness=[400.0, 100.0], breakaway=[0.5, 0.4])
    kw = dict(initial_velocity=1.0, initial_state="saturated", t_end=2.0)
    t_eval = np.linspace(0.0, 2.0, 201)
    exact = ps.simulate(model, 1.0, t_eval=t_eval, **kw)
    fixed = ps.simulate(model, 1.0, t_eval=t_eval, method="implicit", step=1e-6, **kw)
    t_exact = best_of(lambda: ps.simulate(model, 1.0, t_eval=t_eval, **kw), number=20)
    t_fixed = best_of(
        lambda: ps.simulate(model, 1.0, t_eval=t_eval, method="implicit", step=1e-6, **kw),
        repeat=3,
    )
    err_y = np.max(np.abs(fixed.position - exact.position))
    print("1. free stop, exact event method vs fixed step dt = 1e-6 (whole `simulate` calls)")
    print(f"   reversals {exact.n_reversals} (fixed step: {fixed.n_reversals}), "
          f"stop at {exact.stop_time:.12f} s (fixed step: {fixed.stop_time:.12f} s)")  # fmt: skip
    print(f"   exact: {t_exact * 1e6:9.1f} us  ({exact.n_events} events, energy residual "
          f"{exact.energy.max_relative_residual:.1e})")  # fmt: skip
    print(
        f"   fixed: {t_fixed * 1e6:9.1f} us  ({fixed.n_events} steps, position error "
        f"{err_y:.1e} m, stop-time error {abs(fixed.stop_time - exact.stop_time):.1e} s)"
    )
    print(f"   ratio fixed / exact: {t_fixed / t_exact:,.0f}x  (target >= 1000x)")
    # The same two computations without the per-call Python work of `simulate`
    # (validation, result records): the compiled event loop against the
    # compiled fixed-step loop, on identical inputs.
    k, r = model.stiffness, model.threshold
    f0 = r.copy()  # saturated in the direction of the initial velocity
    forcing = as_forcing(0.0, "zoh", 0.0)
    args = (1.0, model.coulomb, k, r, f0, 0.0, 1.0, 1.0, forcing, t_eval, 0.0, 2.0)
    k_exact = best_of(lambda: run_event(*args, 10_000), number=200)
    k_fixed = best_of(lambda: run_implicit(*args, 2_000_000), repeat=3)  # steps of 1e-6 s
    print(
        f"   compiled loops only: exact {k_exact * 1e6:.1f} us, fixed step "
        f"{k_fixed * 1e6:.1f} us, ratio {k_fixed / k_exact:,.0f}x  (target >= 1000x)"
    )


def stepper_ns_per_step() -> None:
    m, c1 = 1.0, 0.3
    k = np.array([400.0, 200.0, 100.0, 50.0, 25.0])
    r = np.array([0.001, 0.002, 0.004, 0.008, 0.016])
    n = 2_000_000
    grid, out_idx = implicit_grid(0.0, 20.0, np.array([0.0, 20.0]), 20.0 / n)
    print("2. implicit stepper, N = 5, 2e6 steps of 1e-5 s (best of 5)")
    for amp, regime in ((3.0, "reversing gross sliding"), (1.0, "presliding, stick-slip")):
        u = amp * np.sin(np.pi * 0.5 * (grid[1:] + grid[:-1]))
        o = [np.zeros(2) for _ in range(8)]
        rev = [np.zeros(1024) for _ in range(2)]

        def run(u=u, o=o, rev=rev):
            _implicit.run_implicit(m, c1, k, r, np.zeros(5), 0.0, 0.0, 0.0, grid, u, out_idx,
                                   *o, *rev)  # fmt: skip

        run()
        t = best_of(run, repeat=5)
        print(f"   {regime:26s}: {t / n * 1e9:6.1f} ns/step  (target <= 18 ns)")


def free_response_call() -> None:
    k = np.array([2e4, 5e3, 1.5e3, 500.0])
    r = 0.175 / k
    args = (1.0, 0.3, k, r, 0.06, 1e-5, 10_000)
    ps.free_response(*args)
    t = best_of(lambda: ps.free_response(*args), number=50)
    print(f"3. free_response, 10,000 samples, N = 4: {t * 1e6:.0f} us per call (target < 1 ms)")


if __name__ == "__main__":
    free_stop()
    stepper_ns_per_step()
    free_response_call()
