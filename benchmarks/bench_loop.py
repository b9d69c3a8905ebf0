"""Benchmark of the exact closed loop (issue: control engineering, item 4).

Prints, measured in this run:
1. `simulate_loop` against python-control's `input_output_response` on the same
   loop (a saturating PID with anti-windup, the friction-loaded mass of
   `to_iosys`, 2000 samples), without and with viscous friction σ > 0: time
   per sample of each (median and range of several runs), their ratio against
   the target (>= 1000×), and the largest difference of the samples;
2. `simulate_loop_batch`: a 40 × 40 tuning map (1600 gain sets, 2000 samples each,
   summaries only) on all cores, time per loop and per sample;
3. the describing-function prediction against the exact loop for hunting cycles of
   several gain sets (amplitude and frequency errors), and where it misses.

Run: python benchmarks/bench_loop.py
"""

from __future__ import annotations

import os
import time

import numpy as np

import presliding as ps


def timed(fn, repeat: int, clock=time.process_time) -> list[float]:
    """Seconds per call of `repeat` calls; CPU time of the process by default (what a busy
    machine disturbs least; it counts the work of any helper threads too)."""
    out = []
    for _ in range(repeat):
        t = clock()
        fn()
        out.append(clock() - t)
    return out


def speed(viscous: float = 0.0) -> None:
    import control

    model = ps.PIFriction(coulomb=0.1, stiffness=[2e4, 5e3, 1.5e3], breakaway=[0.2, 0.2, 0.3],
                          viscous=viscous)  # fmt: skip
    pid = ps.PID(600.0, 6000.0, 25.0, dt=1e-3, limit=2.0, anti_windup="back-calculation")
    n = 2000
    t = np.arange(n + 1) * pid.dt
    ref = 2e-3 * np.sign(np.sin(2 * np.pi * t)) + 1e-3 * np.sin(9 * t)
    loop = control.interconnect(
        [ps.to_iosys(pid), ps.to_iosys(model, mass=1.0, dt=pid.dt)],
        inputs="reference", outputs=["position", "velocity", "u"],
    )  # fmt: skip
    x0 = np.concatenate([ps.iosys_state(pid), ps.iosys_state(model, mass=1.0)])
    ps.simulate_loop(model, 1.0, pid, ref)  # compile
    res = ps.simulate_loop(model, 1.0, pid, ref)
    resp = {}

    def with_control():
        resp["r"] = control.input_output_response(loop, t, ref, x0)

    with_control()  # compile the friction block's kernel
    ours = timed(lambda: ps.simulate_loop(model, 1.0, pid, ref), 21)
    theirs = timed(with_control, 3)
    y, _, u = resp["r"].outputs
    diff = max(np.max(np.abs(y - res.measured)), np.max(np.abs(u - res.control)) * 1e-3)
    ratio = np.median(theirs) / np.median(ours)
    print(f"1. one loop, viscous σ = {viscous:g} N·s/m, {n} samples, {res.n_reversals} reversals, "
          f"{res.n_events} events")  # fmt: skip
    print(f"   simulate_loop              {np.median(ours) / n * 1e9:9.1f} ns/sample "
          f"(range {min(ours) / n * 1e9:.1f}..{max(ours) / n * 1e9:.1f})")  # fmt: skip
    print(f"   input_output_response      {np.median(theirs) / n * 1e6:9.1f} µs/sample "
          f"(range {min(theirs) / n * 1e6:.1f}..{max(theirs) / n * 1e6:.1f})")  # fmt: skip
    verdict = "met" if ratio >= 1000 else "MISSED"
    print(f"   ratio (medians)            {ratio:9.0f}×   (target >= 1000×: {verdict})")
    print(
        f"   largest difference: position {np.max(np.abs(y - res.measured)):.1e} m, "
        f"control {np.max(np.abs(u - res.control)):.1e} N  (target <= 1e-12; {diff:.1e})"
    )


def batch() -> None:
    model = ps.PIFriction(coulomb=0.05, stiffness=[2e4, 5e3, 1.5e3], breakaway=[0.2, 0.2, 0.3])
    pid = ps.PID(500.0, 5000.0, 20.0, dt=1e-3, limit=3.0)
    kp, ki = np.meshgrid(np.geomspace(100, 3000, 40), np.geomspace(500, 5e4, 40))
    args = dict(kp=kp.ravel(), ki=ki.ravel(), t_end=2.0, outputs="summary")
    ps.simulate_loop_batch(model, 1.0, pid, 1e-3, **args)  # compile
    times = timed(
        lambda: ps.simulate_loop_batch(model, 1.0, pid, 1e-3, **args), 5, clock=time.perf_counter
    )  # wall clock: the batch runs on every core
    b = kp.size
    print(
        f"2. tuning map: {b} gain sets × 2000 samples, all cores: {np.median(times):.3f} s "
        f"({np.median(times) / b * 1e6:.0f} µs per loop, "
        f"{np.median(times) / b / 2000 * 1e9:.0f} ns per sample)"
    )


def limit_cycles() -> None:
    print(
        "3. hunting cycles: describing function against the exact loop (dt = 1e-4 s, "
        "cycle measured over 4..8 s)"
    )
    print(
        "   c1 [N]  kp     ki       kd    predicted A [m]  ω [rad/s]   simulated A [m]  "
        "ω [rad/s]   ΔA      Δω     rests"
    )
    bank = ([2e4, 5e3, 1.5e3, 500.0], [0.2, 0.2, 0.2, 0.2])
    sets = [(0.0, 400, 4e4, 0), (0.0, 400, 4e4, 0.5), (0.0, 1000, 2e5, 1), (0.0, 200, 2e4, 0),
            (0.0, 2000, 1e5, 0), (0.0, 100, 2e4, 0), (0.0, 800, 1.6e5, 2),
            (2e-3, 1000, 2e5, 1), (5e-3, 2000, 1e5, 0), (1e-3, 400, 4e4, 0),
            (3e-3, 400, 4e4, 0)]  # fmt: skip
    for c1, kp, ki, kd in sets:
        model = ps.PIFriction(c1, *bank)
        pid = ps.PID(kp, ki, kd, dt=1e-4)
        pred = ps.predict_limit_cycles(1.0, model, pid)
        res = ps.simulate_loop(model, 1.0, pid, 0.0, t_end=8.0, initial_velocity=1e-3)
        sim = res.limit_cycle(4.0)
        rests = float(np.mean(res.velocity[res.time > 4.0] == 0.0))
        st = np.flatnonzero(pred.stable)
        pa, pw = (pred.amplitude[st[0]], pred.frequency[st[0]]) if st.size else (np.nan, np.nan)
        sa, sw = (sim.amplitude, sim.frequency) if sim.steady else (np.nan, np.nan)
        da, dw = sa / pa - 1, sw / pw - 1
        print(
            f"   {c1:<7g} {kp:<6g} {ki:<8g} {kd:<5g} {pa:<16.4g} {pw:<11.4g} {sa:<16.4g} "
            f"{sw:<11.4g} {da:<+7.2%} {dw:<+7.2%} {rests:.0%}"
        )
    print("   (nan: no stable cycle predicted, or no steady cycle simulated)")


if __name__ == "__main__":
    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    speed()
    speed(viscous=2.0)
    batch()
    limit_cycles()
