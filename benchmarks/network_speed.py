"""Speed and accuracy of the network paths (issue 25).

1. Exact path: a chain of 10 masses on 10 PI contacts (4 elements each), 1 s of motion
   with several hundred events (target <= 0.1 s): the compiled event loop, CPU time,
   against the general loop (the one general redundant stick sets and ill-conditioned
   damped modes run) in the same run, and the largest difference between the two; the
   same with dashpots (damped pieces: complex modes in the compiled loop).
2. Moreau–Jean: a chain of 1,000 masses and contacts, 1 s at a step of 1e-4 s
   (target <= 60 s).
3. Accuracy of Moreau–Jean against the exact path on the 10-mass chain, and where the
   two cost the same (the crossover step).
4. A bar on a Coulomb foundation (EA, τ per length) pulled at its end by ±F, cut into N
   masses and sliders, by Moreau–Jean with tiny masses (each backward-Euler step is the
   quasi-static response): the dissipation per cycle against 2F³/(3·EA·τ), its error
   divided by about 4 when N doubles.

Run: PYTHONPATH=src python benchmarks/network_speed.py   (CPU times, time.process_time:
the best of a few runs after a warm-up; the machine may be shared, so the ratios printed
compare runs of the same process.)
"""

from __future__ import annotations

import time

import numpy as np

import presliding.network.events.exact as exact_module
from presliding import PIFriction
from presliding.network import chain_structure, simulate_network, simulate_network_moreau

PI = PIFriction(0.2, [2e3, 1e3, 500.0, 200.0], [0.1, 0.1, 0.1, 0.1])


def best(fn, repeat=3):
    """(best CPU time, result)."""
    out, times = None, []
    for _ in range(repeat):
        t0 = time.process_time()
        out = fn()
        times.append(time.process_time() - t0)
    return min(times), out


def general_loop(fn):
    """Run `fn` with the compiled loop switched off (the general loop runs instead)."""
    compiled = exact_module._run_compiled
    exact_module._run_compiled = lambda *args: None
    try:
        return fn()
    finally:
        exact_module._run_compiled = compiled


def chain10():
    force = np.outer([1.0, -1.0, 1.0, -1.0], np.r_[np.zeros(9), 2.0])
    s = chain_structure(10, 0.1, 2e3, PI, forcing=([0.0, 0.25, 0.5, 0.75], force))
    return s, 0.3 * np.sin(np.arange(10))


def chain1000():
    n = 1000
    force = np.zeros(n)
    force[-1] = 2.0
    return chain_structure(n, 0.1, 2e3, PI, forcing=force), 0.3 * np.sin(np.arange(n))


def bar_dissipation(n, ea=1.0, tau=1.0, force=0.5):
    """Coulomb dissipation over one steady cycle of the bar cut into n nodes (length 1)."""
    dx = 1.0 / n
    models = [PIFriction(tau * dx)] * (n - 1) + [PIFriction(0.5 * tau * dx)]  # end: half
    mass = np.full(n, 1e-10)
    mass[-1] *= 0.5
    per = 8
    cycle = [
        np.linspace(force, -force, 2 * per + 1)[1:],
        np.linspace(-force, force, 2 * per + 1)[1:],
    ]
    values = np.concatenate([np.linspace(0.0, force, per + 1)] + cycle * 2)
    times = np.arange(values.shape[0], dtype=float)
    f = np.zeros((values.shape[0], n))
    f[:, -1] = values
    s = chain_structure(n, mass, ea / dx, models, forcing=(times, f))
    t_end = times[-1] + 1.0
    res = simulate_network_moreau(
        s, t_end, 0.25, samples=int(t_end / 0.25) + 1, max_sweeps=100_000, tolerance=1e-14
    )
    e = res.energy.coulomb.sum(axis=1)
    i_a, i_b = np.searchsorted(res.time, [times[5 * per] + 0.99, times[9 * per] + 0.99])
    return e[i_b] - e[i_a], 2 * force**3 / (3 * ea * tau)


def main():
    s, v0 = chain10()
    c0 = time.process_time()
    exact_module.compile_now()  # warm-up: loads the kernels from the cache, or compiles them
    print(f"first call (kernels loaded from the cache, or compiled): "
          f"{time.process_time() - c0:.1f} s CPU")  # fmt: skip
    te = np.linspace(0, 1, 201)

    def run():
        return simulate_network(s, 1.0, None, v0, t_eval=te)

    cpu, exact = best(run, 5)
    cpu_py, py = general_loop(lambda: best(run, 2))
    diff = max(float(np.max(np.abs(getattr(exact, k) - getattr(py, k))))
               for k in ("position", "velocity", "contact_force"))  # fmt: skip
    cert = exact.certification
    print(
        f"exact, 10 masses, 10 PI contacts, {exact.n_events} events: compiled loop {cpu:.4f} s "
        f"CPU ({1e6 * cpu / exact.n_events:.0f} µs per event), target 0.1 s: "
        f"{cpu / 0.1:.2f}x the target; general loop {cpu_py:.3f} s CPU: {cpu_py / cpu:.0f}x "
        f"slower; largest difference of q, q̇, λ {diff:.1e}; energy residual "
        f"{exact.energy.max_relative_residual:.1e}; certification: {cert['cells']} cells free "
        f"of events, {cert['isolated']} isolated roots, {cert['resolved']} resolved, "
        f"{cert['grazes']} grazes"
    )
    damped = chain_structure(10, 0.1, 2e3, PI, damping=0.5,
                             forcing=(s.forcing_times, s.forcing_values))  # fmt: skip

    def run_d():
        return simulate_network(damped, 1.0, None, v0, t_eval=te)

    cpu_d, res_d = best(run_d, 5)
    cpu_dpy, py_d = general_loop(lambda: best(run_d, 2))
    diff_d = max(float(np.max(np.abs(getattr(res_d, k) - getattr(py_d, k))))
                 for k in ("position", "velocity", "contact_force"))  # fmt: skip
    diss = abs(res_d.energy.damping[-1] - py_d.energy.damping[-1]) / py_d.energy.damping[-1]
    print(f"the same chain with dashpots (0.5 N s/m), {res_d.n_events} events "
          f"(general loop {py_d.n_events}): compiled loop {cpu_d:.4f} s CPU "
          f"({1e6 * cpu_d / res_d.n_events:.0f} µs per event, {cpu_d / cpu:.1f}x the undamped "
          f"one); general loop {cpu_dpy:.3f} s CPU: {cpu_dpy / cpu_d:.0f}x slower; largest "
          f"difference of q, q̇, λ {diff_d:.1e}, of the dashpots' dissipation {diss:.1e} "
          f"(relative); energy residual {res_d.energy.max_relative_residual:.1e}")  # fmt: skip

    simulate_network_moreau(s, 0.01, 1e-3, None, v0)  # compile
    print("Moreau–Jean on the 10-mass chain against the exact path (mean |q error|, ~200 samples):")
    rows = []
    for h in (1e-3, 3e-4, 1e-4, 3e-5, 1e-5):
        t_mj, mj = best(lambda h=h: simulate_network_moreau(s, 1.0, h, None, v0, samples=201))
        ref = simulate_network(s, 1.0, None, v0, t_eval=mj.time)
        err = float(np.mean(np.abs(mj.position - ref.position)))
        rows.append((h, t_mj, err))
        print(f"  h = {h:.0e} s: {t_mj:.4f} s CPU, error {err:.2e} m, cost / exact = "
              f"{t_mj / cpu:.3f}")  # fmt: skip
    hs, ts, es = (np.array(c) for c in zip(*rows, strict=True))
    slope = np.polyfit(np.log(hs), np.log(es), 1)[0]
    # cost ≈ a·h^b (from the two smallest steps, past the fixed costs) and error ≈ c·h^slope,
    # fitted; the step where the cost equals the
    # exact path's (extrapolated when it lies beyond the steps measured)
    b, a = np.polyfit(np.log(hs[-2:]), np.log(ts[-2:]), 1)  # the small steps: cost ∝ 1/h
    log_cross = (np.log(cpu) - a) / b
    err_cross = np.exp(np.polyval(np.polyfit(np.log(hs), np.log(es), 1), log_cross))
    print(
        f"  log-log slope of the error: {slope:.2f} (first order: 1); cost ∝ h^{b:.2f}; the "
        f"two cost the same at h ≈ {np.exp(log_cross):.1e} s, where the Moreau–Jean error "
        f"is ≈ {err_cross:.1e} m (the exact path's is rounding)"
    )

    print("bar on a Coulomb foundation, dissipation per cycle against 2F³/(3·EA·τ):")
    previous = None
    for n in (4, 8, 16):
        t0 = time.process_time()
        w, exact_w = bar_dissipation(n)
        err = abs(w - exact_w) / exact_w
        ratio = "" if previous is None else f", error ratio {previous / err:.3f}"
        print(f"  N = {n:3d}: {w:.10f} J (exact {exact_w:.10f}), error {err:.3e}{ratio}; "
              f"{time.process_time() - t0:.2f} s CPU")  # fmt: skip
        previous = err

    big, v0b = chain1000()
    simulate_network_moreau(big, 1e-3, 1e-4, None, v0b)  # warm-up of this size
    t_big, res = best(lambda: simulate_network_moreau(big, 1.0, 1e-4, None, v0b, samples=101), 1)
    print(
        f"Moreau–Jean, 1,000 masses and contacts, 1 s at h = 1e-4 s (10,000 steps): "
        f"{t_big:.2f} s CPU; target 60 s: {t_big / 60:.2f}x the target; {res.message}"
    )


if __name__ == "__main__":
    main()
