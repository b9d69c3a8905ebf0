"""The motion figures of issue 18 (items 2 and 5) and the cost of the viscous energy record.

Each figure is a ratio measured in one run, so that a busy machine moves both
sides alike:

2. `simulate` against its own compiled loop on the same inputs, for 1e6 steps
   (implicit method, N = 5, u sampled and held linearly) and for 1e6 pieces of
   a sampled u (event method), with 1001 samples and with a sample at every
   step or piece. The loop is timed writing into buffers it was given, and
   with fresh buffers (what any call that returns the samples allocates);
   targets: <= 1.3x with 1001 samples, <= 2x with every step;
5. the density stepper (uniform and exponential μ, a forced motion that keeps
   moving and reversing), ns per step through `simulate`, against the
   straightforward stepper written here (the same inclusion solved with the
   operator's pure trial `force_at` and its commit `advance_dissipating`, one
   compiled call each); target <= 150 ns/step;
v. the energy record with σ > 0 (the closed-form viscous loss) against σ = 0,
   per event and per sample, compiled loops only.

Timing on a shared machine: each figure is the median of ``--repeats`` runs of
the CPU time of the calling thread (`time.thread_time`), with the range over
the runs; the load average is printed before and after. Run::

    python benchmarks/bench_motion_overhead.py [--repeats 7]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402

import numba as nb  # noqa: E402
import numpy as np  # noqa: E402

import presliding as ps  # noqa: E402
from presliding.hysteresis import _general_pi as gk  # noqa: E402
from presliding.motion import _event  # noqa: E402
from presliding.motion import _implicit_loop as loop  # noqa: E402
from presliding.motion._forcing import as_forcing  # noqa: E402

K = np.array([400.0, 200.0, 100.0, 50.0, 25.0])
R = np.array([0.001, 0.002, 0.004, 0.008, 0.016])
C1 = 0.3


def runs(call, repeats: int) -> list[float]:
    call()
    out = []
    for _ in range(repeats):
        start = time.thread_time()
        call()
        out.append(time.thread_time() - start)
    return out


def med(x: list[float]) -> float:
    return statistics.median(x)


def span(x: list[float], scale: float) -> str:
    return f"{med(x) * scale:.1f} [{min(x) * scale:.1f}, {max(x) * scale:.1f}]"


def ratio(a: list[float], b: list[float]) -> str:
    r = sorted(x / y for x, y in zip(a, b, strict=True))
    return f"{med(a) / med(b):.2f}x [{r[0]:.2f}, {r[-1]:.2f}]"


def paired(fa, fb, repeats: int) -> tuple[list[float], list[float]]:
    """Interleaved runs of two calls (each pair sees the same load)."""
    fa()
    fb()
    a, b = [], []
    for _ in range(repeats):
        for call, out in ((fa, a), (fb, b)):
            start = time.thread_time()
            call()
            out.append(time.thread_time() - start)
    return a, b


# ---------------------------------------------------------------------- 2. simulate overhead
def implicit_overhead(repeats: int) -> list[tuple]:
    """(samples, simulate runs, loop runs, loop-with-fresh-buffers runs) for 1001 and every step."""
    out = []
    model = ps.PIFriction(coulomb=C1, stiffness=K, threshold=R)
    n, t_end = 1_000_000, 10.0
    ts = np.linspace(0.0, t_end, 2001)
    us = 3.0 * np.sin(np.pi * ts)
    forcing = as_forcing((ts, us), "linear", 0.0)
    kind, u_t, u_val, u_mid = forcing.loop_form(0.0, t_end, n)
    for n_out in (1001, n + 1):
        t_eval = np.linspace(0.0, t_end, n_out)
        given = [np.empty(n_out) for _ in range(9)]
        rev = [np.empty(4096) for _ in range(2)]

        def kernel(o=given, t_eval=t_eval, rev=rev) -> None:
            loop.run_uniform(1.0, C1, 0.0, K, R, np.zeros(5), 0.0, 0.0, 0.0, 0.0, t_end, n, kind,
                             u_t, u_val, u_mid, t_eval, *o, *rev)  # fmt: skip

        def fresh(t_eval=t_eval, n_out=n_out) -> None:
            o = [np.empty(n_out) for _ in range(9)]
            kernel(o, t_eval)

        def whole(t_eval=t_eval) -> None:
            ps.simulate(model, 1.0, (ts, us), hold="linear", t_eval=t_eval, step=t_end / n)

        s, k = paired(whole, kernel, repeats)
        _, f = paired(whole, fresh, repeats)
        out.append((n_out, s, k, f))
        target = 1.3 if n_out == 1001 else 2.0
        print(f"2. implicit, 1e6 steps, {n_out} samples: simulate {span(s, 1e9 / n)} ns/step, "
              f"loop {span(k, 1e9 / n)}; simulate/loop {ratio(s, k)}, /loop with fresh buffers "
              f"{ratio(s, f)}  (target <= {target}x)")  # fmt: skip
    return out


def event_overhead(repeats: int) -> list[tuple]:
    """(samples, simulate runs, loop runs, fresh-buffer loop runs): 1001 and every piece."""
    out = []
    model = ps.PIFriction(coulomb=C1, stiffness=K, threshold=R)
    n = 1_000_000
    t_u = np.arange(n) * 1e-5
    u = np.random.default_rng(0).uniform(-3.0, 3.0, n)
    t_end = float(t_u[-1])
    for n_out in (1001, n):
        t_eval = np.linspace(0.0, t_end, n_out) if n_out < n else t_u
        res = ps.simulate(model, 1.0, (t_u, u), t_eval=t_eval)
        given = [np.empty(n_out) for _ in range(9)]
        rev = [np.empty(max(4096, 2 * n)) for _ in range(2)]
        piece = np.empty(5 + K.shape[0])

        def kernel(o=given, t_eval=t_eval, rev=rev, piece=piece) -> None:
            _event.run_events(1.0, C1, K, R, np.zeros(5), 0.0, 0.0, 0.0, t_u, u, t_eval, t_end,
                              10**8, *o[:7], o[8], *rev, 0.0, o[7], piece, None)  # fmt: skip

        def fresh(t_eval=t_eval, n_out=n_out) -> None:
            o = [np.empty(n_out) for _ in range(9)]
            kernel(o, t_eval)

        def whole(t_eval=t_eval) -> None:
            ps.simulate(model, 1.0, (t_u, u), t_eval=t_eval)

        s, k = paired(whole, kernel, repeats)
        _, f = paired(whole, fresh, repeats)
        out.append((n_out, s, k, f))
        target = 1.3 if n_out == 1001 else 2.0
        print(f"2. event, 1e6 pieces of u ({res.n_events} events), {n_out} samples: simulate "
              f"{span(s, 1e3)} ms, loop {span(k, 1e3)}; simulate/loop {ratio(s, k)}, /loop with "
              f"fresh buffers {ratio(s, f)}  (target <= {target}x)")  # fmt: skip
    return out


# ---------------------------------------------------------------------- 5. density stepper
@nb.njit(cache=False)
def straightforward_density(m, c1, head, stack, kind, par, tab, u, h):  # pragma: no cover
    """The same implicit steps with one compiled trial call per Newton iterate and a commit call."""
    fel, slope = gk.force_at(head[0], head, stack, kind, par, tab)
    t_total = gk.primitives(kind, par, tab, 0.0)[2]
    v = 0.0
    mh2 = m / (h * h)
    for i in range(u.shape[0]):
        g = m / h * v + u[i] - fel
        if abs(g) <= c1:
            v = 0.0
            continue
        s = 1.0 if g > 0.0 else -1.0
        b = abs(g) - c1
        y = head[0]
        lo, hi = 0.0, b / mh2
        d = b / (mh2 + (slope if s == head[1] else t_total))
        for _ in range(200):
            f, sl = gk.force_at(y + s * d, head, stack, kind, par, tab)
            phi = mh2 * d + s * (f - fel) - b
            if phi < 0.0:
                lo = d
            elif phi > 0.0:
                hi = d
            else:
                break
            dn = d - phi / (mh2 + sl)
            if not (dn > lo and dn < hi):
                dn = 0.5 * (lo + hi)
            if dn == d or hi - lo <= 4.4e-16 * hi:
                break
            d = dn
        fel, slope, _, stack = gk.advance_dissipating(y + s * d, head, stack, kind, par, tab)
        v = s * d / h
    return head[0]


def density(repeats: int) -> list[tuple]:
    """(name, simulate runs, straightforward runs, steps) for a uniform and an exponential μ."""
    out = []
    n, t_end = 200_000, 20.0
    h = t_end / n
    densities = (("uniform", ps.Uniform(2.0, 1.0)), ("exponential", ps.Exponential(3.0, 0.4)))
    for name, dens in densities:
        model = ps.PIFriction(0.1 * dens.max_elastic_force, density=dens)
        amp = 1.5 * model.coulomb_level
        ts = np.linspace(0.0, t_end, 4001)
        us = amp * np.sin(2.0 * ts)
        u_mid = np.interp((np.arange(n) + 0.5) * h, ts, us)
        t_eval = np.linspace(0.0, t_end, 201)

        def whole(model=model, ts=ts, us=us, t_eval=t_eval) -> None:
            ps.simulate(model, 1.0, (ts, us), hold="linear", t_eval=t_eval, step=h)

        def straight(model=model, dens=dens, u_mid=u_mid) -> None:
            head, stack = model.relaxed_state(0.0).working_memory(dens)
            straightforward_density(1.0, model.coulomb, head, stack, dens._kind, dens._par,
                                    dens._tab, u_mid, h)  # fmt: skip

        s, b = paired(whole, straight, repeats)
        out.append((name, s, b, n))
        res = ps.simulate(model, 1.0, (ts, us), hold="linear", t_eval=t_eval, step=h)
        print(f"5. density stepper, {name}: simulate {span(s, 1e9 / n)} ns/step; the "
              f"straightforward stepper {span(b, 1e9 / n)} ns/step; speed-up {ratio(b, s)} "
              f"({res.n_reversals} reversals; target <= 150 ns/step)")  # fmt: skip
    return out


# ---------------------------------------------------------------------- viscous energy record
@nb.njit(cache=False)
def _events(n, sigma, energy, t_eval, k, r):  # pragma: no cover - compiled
    total = 0.0
    o = np.zeros((9, t_eval.shape[0]))
    rev = np.zeros((2, 64))
    u = np.zeros(1)
    for _ in range(n):
        f = r.copy()
        if energy:
            res = _event.run_events(1.5, 0.02, k, r, f, 0.0, 0.8, 1.0, u, u, t_eval, t_eval[-1],
                                    10_000_000, o[0], o[1], o[2], o[3], o[4], o[5], o[6], o[8],
                                    rev[0], rev[1], sigma, o[7], u[:0],
                                    _event.damped_flag(sigma))  # fmt: skip
        else:
            res = _event.run_events(1.5, 0.02, k, r, f, 0.0, 0.8, 1.0, u, u, t_eval, t_eval[-1],
                                    10_000_000, o[0], o[1], o[2], o[3], o[4], o[5], o[6], o[8],
                                    rev[0], rev[1], sigma, u[:0], u[:0],
                                    _event.damped_flag(sigma))  # fmt: skip
        total += res[4]
    return total


def viscous(repeats: int) -> None:
    k = np.array([300.0, 80.0, 20.0])
    r = np.array([0.002, 0.006, 0.02])
    for label, t_eval, count in (
        ("per event (2 samples)", np.array([0.0, 20.0]), 2000),
        ("per sample (20,001 samples)", np.linspace(0, 20.0, 20001), 20),
    ):
        cells = {}
        for sigma in (0.0, 0.02):
            for energy in (False, True):
                cells[sigma, energy] = runs(
                    lambda s=sigma, e=energy, t=t_eval, c=count: _events(c, s, e, t, k, r),
                    repeats,
                )
        print(f"v. viscous loss, {label}: σ > 0 with the energy record / σ = 0 "
              f"{ratio(cells[0.02, True], cells[0.0, True])}; / σ > 0 without it "
              f"{ratio(cells[0.02, True], cells[0.02, False])}")  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()}")
    implicit_overhead(args.repeats)
    event_overhead(args.repeats)
    density(args.repeats)
    viscous(args.repeats)
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
