"""Calibration of the asymmetry test of ``fit_response(asymmetric=True)``.

Synthetic stop records (the search study's design: a preload anywhere in ±0.8 of each side's
F_m, initial velocities of both signs, a decelerating force of random level and length, a
1 µm encoder with 0.2 µm noise, the velocity the quantised position's difference quotient)
from a symmetric PI model and from the same model with every negative level 0.8 of its
positive one (F_c⁻/F_c⁺ = 0.8). Each seed is fitted with ``asymmetric=True``; the test must
reject the symmetric model at about its level (5 %) on symmetric truths and detect the
asymmetry in at least 90 % of the asymmetric seeds. Also reported: how often the classical
likelihood-ratio test (independent residuals) and ΔBIC < 0 would have said the same, and the
fitted ratio against the truth.

The same test on a model linear in its parameters, where its F distribution is exact: eq. 17
without elements (mass, c1, and c1⁻ with ``asymmetric=True``) fitted by ``fit_motion`` to a
symmetric truth with independent Gaussian force noise, `DRAWS` draws: it must reject at its
level to within the binomial scatter.

Run from the repository root::

    python benchmarks/study_asymmetry.py [SEEDS] [RECORDS] [DRAWS]
"""

from __future__ import annotations

import sys
import time

import numpy as np

from presliding import Measurement, PIFriction, fit_motion, fit_response, preloaded_state, simulate

MASS = 2.0
RATIO = 0.8
DRAWS = 400


def model(ratio: float = 1.0) -> PIFriction:
    """c1 = 0.3, F_c = 1 and two elements of equal break-away force; the negative side's levels
    `ratio` times the positive side's."""
    c1, k, c = 0.3, [4000.0, 1000.0], [0.35, 0.35]
    if ratio == 1.0:
        return PIFriction(c1, k, breakaway=c)
    return PIFriction(c1, k, breakaway=c, coulomb_negative=ratio * c1,
                      breakaway_negative=[ratio * x for x in c])  # fmt: skip


def stops(seed: int, friction: PIFriction, n_records: int = 4, samples: int = 500) -> list:
    """The stop records of one seed (module notes)."""
    rng = np.random.default_rng(seed)
    t = np.arange(samples) * 1e-3
    fmp, fmn = (level - c for level, c in zip(friction.coulomb_levels, (
        friction.coulomb, friction.coulomb if friction.coulomb_negative is None
        else friction.coulomb_negative), strict=True))  # fmt: skip
    out = []
    for _ in range(n_records):
        v0 = rng.choice([-1.0, 1.0]) * rng.uniform(0.02, 0.06)
        d = float(np.sign(v0))
        share = rng.uniform(-0.8, 0.8)
        y0 = rng.uniform(-1e-3, 1e-3)
        state = preloaded_state(friction, share * (fmp if share > 0 else fmn), direction=d,
                                position=y0)  # fmt: skip
        u = np.where(t < rng.uniform(0.03, 0.08), -d * rng.uniform(0.1, 0.6), 0.0)
        res = simulate(friction, MASS, applied_force=(t, u), initial_position=y0,
                       initial_velocity=v0, initial_state=state, t_eval=t)  # fmt: skip
        y = 1e-6 * np.round((res.position + 2e-7 * rng.standard_normal(samples)) / 1e-6)
        out.append(Measurement(t, position=y, velocity=np.gradient(y, t), applied_force=u))
    return out


def study(seeds: int, n_records: int) -> dict[float, list[tuple]]:
    """(verdict, p, classical p, ΔBIC, fitted ratio, status) per seed, for both truths."""
    rows: dict[float, list[tuple]] = {1.0: [], RATIO: []}
    for ratio in rows:
        truth = model(ratio)
        for seed in range(seeds):
            fit = fit_response(stops(seed, truth, n_records), 2, initial_state="preload",
                               asymmetric=True)  # fmt: skip
            a = fit.asymmetry
            ratio_fit = fit.derived.get("coulomb_level_ratio", np.nan)
            rows[ratio].append((a.verdict, a.p_value, a.likelihood_ratio_p_value, a.delta_bic,
                                ratio_fit, fit.status))  # fmt: skip
    return rows


def motion_calibration(draws: int = DRAWS) -> float:
    """The share of `draws` symmetric truths (independent noise) whose asymmetry `fit_motion`
    calls supported (module notes)."""
    t = np.arange(600) * 1e-3
    v = 0.05 * np.sin(2 * np.pi * 3 * t) + 0.02 * np.sin(2 * np.pi * 7.3 * t)
    a = np.gradient(v, t)
    clean = MASS * a + 0.3 * np.sign(v)
    rng = np.random.default_rng(0)
    hits = 0
    for _ in range(draws):
        u = clean + 0.05 * rng.standard_normal(t.shape[0])
        m = Measurement(t, position=np.cumsum(v) * 1e-3, velocity=v, acceleration=a,
                        applied_force=u)  # fmt: skip
        hits += fit_motion(m, 0, asymmetric=True).asymmetry.verdict == "supported"
    return hits / draws


def main(seeds: int = 40, n_records: int = 4, draws: int = DRAWS) -> int:
    start = time.process_time()
    share = motion_calibration(draws)
    scatter = 2 * np.sqrt(0.05 * 0.95 / draws)
    print(f"linear model (fit_motion, independent noise): asymmetry supported in "
          f"{100 * share:.1f} % of {draws} symmetric draws (level 5 %, ±{100 * scatter:.1f} % "
          "binomial 2σ)")  # fmt: skip
    rows = study(seeds, n_records)
    for ratio, got in rows.items():
        label = "symmetric truth" if ratio == 1.0 else f"F_c⁻/F_c⁺ = {ratio} truth"
        supported = np.mean([g[0] == "supported" for g in got])
        undecided = np.mean([g[0] == "undetermined" for g in got])
        classical = np.mean([g[2] < 0.05 for g in got])
        bic = np.mean([g[3] < 0 for g in got])
        fitted = np.array([g[4] for g in got])
        converged = np.mean([g[5] == "converged" for g in got])
        print(f"{label}: {len(got)} seeds; asymmetry supported in {100 * supported:.0f} % "
              f"(undetermined {100 * undecided:.0f} %); classical LR test {100 * classical:.0f} %"
              f", ΔBIC < 0 {100 * bic:.0f} %; fitted ratio median {np.median(fitted):.3f} "
              f"(IQR {np.subtract(*np.percentile(fitted, [75, 25])):.3f}); converged "
              f"{100 * converged:.0f} %")  # fmt: skip
    print(f"({time.process_time() - start:.0f} s CPU)")
    return 0


if __name__ == "__main__":
    args = [int(a) for a in sys.argv[1:4]]
    sys.exit(main(*args))
