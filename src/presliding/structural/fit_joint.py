"""`fit_joint`: a joint model and the mode's damping from measured ω(a), ζ(a) or D(a).

The data are a `RingDown` (ω, ζ and their stated errors against the amplitude; its
windows half overlap, so every second one is used: independent residuals) or arrays of
amplitudes with frequencies and damping ratios (ring-downs or stepped sines) or
dissipations. The model (`_joint_model`) is one mode per unit modal mass: a joint
(Segalman's four-parameter Iwan density, Mindlin's contact or one Jenkins element), a
linear spring k₀ for the rest of the mode's stiffness and a viscous c, the fixture's
damping, fitted beside the joint. The residual is the data's deviations over their
errors (given, or 1e-3 of ω and 1e-2 of the largest ζ). The fit runs the engine of
every fit (`identification._fit_engine.run_fit`: a direct problem, several starts of the
joint's shape, the least-squares core, the status judge and profile-likelihood
intervals) and returns a `FitResult` whose model is the fitted joint.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import replace
from functools import partial
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._validation import as_bounds, as_choice, as_parameter_vector, fmt
from presliding.identification._fit_engine import FitPlan, FitRun, Found, cost, run_fit
from presliding.identification.fit_result import FitResult
from presliding.identification.problem._fit_problem import FitOptions, FitProblem
from presliding.structural._joint_model import (
    DEFINITIONS,
    JOINTS,
    MODE,
    MODE_UNITS,
    JointKind,
    predict,
)
from presliding.structural.ring_down import RingDown

__all__ = ["fit_joint"]

FloatArray = NDArray[np.float64]


class _Data:
    """Amplitudes and what was measured there, with the errors of the residual."""

    w: FloatArray | None
    z: FloatArray | None
    d: FloatArray | None
    sw: FloatArray | None
    sz: FloatArray | None
    sd: FloatArray | None

    def __init__(self, data: Any, definition: str) -> None:
        self.definition = definition
        if isinstance(data, RingDown):
            keep = slice(None, None, 2)  # half-overlapping windows: every second one
            self.a = data.amplitude[keep]
            self.w, self.z = data.frequency[keep], data.damping_ratio[keep]
            self.sw, self.sz = data.frequency_error[keep], data.damping_ratio_error[keep]
            self.d = self.sd = None
            return
        if not isinstance(data, Mapping):
            raise TypeError(f"`data` must be a RingDown or a mapping of arrays; got "
                            f"{type(data).__name__}.")  # fmt: skip
        known = {"amplitude", "frequency", "damping_ratio", "dissipation", "frequency_error",
                 "damping_ratio_error", "dissipation_error"}  # fmt: skip
        extra = set(data) - known
        if extra:
            raise ValueError(f"`data` must name only {sorted(known)}; got {sorted(extra)}.")
        self.a = np.asarray(as_parameter_vector("data['amplitude']", data.get("amplitude")))
        n = self.a.shape[0]

        def column(name: str, positive: bool = True) -> FloatArray | None:
            if data.get(name) is None:
                return None
            arr = as_parameter_vector(f"data[{name!r}]", data[name], positive=positive)
            if arr.shape[0] != n:
                raise ValueError(f"`data[{name!r}]` must have one value per amplitude ({n}); "
                                 f"got {arr.shape[0]}.")  # fmt: skip
            return np.asarray(arr)

        self.w, self.z, self.d = column("frequency"), column("damping_ratio", False), column(
            "dissipation", False)  # fmt: skip
        if self.w is None and self.z is None and self.d is None:
            raise ValueError("`data` must hold 'frequency', 'damping_ratio' or 'dissipation'.")
        self.sw = column("frequency_error")
        self.sz = column("damping_ratio_error")
        self.sd = column("dissipation_error")
        if self.w is not None and self.sw is None:
            self.sw = 1e-3 * self.w
        if self.z is not None and self.sz is None:
            self.sz = np.full(n, 1e-2 * max(float(np.max(self.z)), 1e-12))
        if self.d is not None and self.sd is None:
            self.sd = np.maximum(1e-2 * self.d, 1e-12 * float(np.max(self.d)))

    def blocks(self) -> list[tuple[str, FloatArray, FloatArray]]:
        out = []
        for name, y, s in (("frequency", self.w, self.sw), ("damping_ratio", self.z, self.sz),
                           ("dissipation", self.d, self.sd)):  # fmt: skip
            if y is not None and s is not None:
                out.append((name, y, s))
        return out

    def residual(self, kind: JointKind, names: tuple[str, ...], x: FloatArray) -> FloatArray:
        values = dict(zip(names, x, strict=True))
        try:
            w, z, d = predict(kind, values, self.a, self.definition)
        except ValueError:  # parameters the joint refuses (on a bound): a large residual
            return np.full(sum(b[1].shape[0] for b in self.blocks()), 1e10)
        model = {"frequency": w, "damping_ratio": z, "dissipation": d}
        return np.concatenate([(model[n] - y) / s for n, y, s in self.blocks()])


def _starts(data: _Data, kind_name: str) -> list[dict[str, float]]:
    """Starts from the data's ends: ω² at the smallest and largest amplitudes split into the
    joint's and the rest's stiffness, the slip where ζ peaks, several shapes."""
    a = data.a
    order = np.argsort(a)
    if data.w is not None:
        w_lo, w_hi = float(data.w[order[0]]), float(data.w[order[-1]])
    else:
        w_lo, w_hi = 1.0, 0.9
    k_total = w_lo**2
    k0 = min(w_hi**2, 0.95 * k_total)
    kt = max(k_total - k0, 0.05 * k_total)
    peak = float(np.median(a))
    if data.z is not None:
        peak = float(a[order][int(np.argmax(data.z[order]))])
    elif data.d is not None:  # D ∝ a^(χ+3) before macroslip, 4·F_S·a after: where it bends
        slope = np.gradient(np.log(data.d[order]), np.log(a[order]))
        bend = np.flatnonzero(slope < 0.5 * (slope[0] + 1.0))
        peak = float(a[order][bend[0]]) if bend.size else float(a[order][-1])
        kt = float(np.max(data.d / (4.0 * a))) / peak
    z_small = float(data.z[order[0]]) if data.z is not None else 0.0
    c = max(2.0 * w_lo * z_small * 0.5, 0.0)
    base = {"linear_stiffness": k0, "viscous": c}
    out = []
    if kind_name == "segalman":
        for chi, beta, slip in ((-0.5, 0.1, 1.0), (-0.2, 1.0, 1.0), (-0.8, 0.01, 0.5),
                                (-0.5, 0.5, 3.0)):  # fmt: skip
            out.append({**base, "stiffness": kt, "slip_force": kt * peak * slip, "exponent": chi,
                        "mass_ratio": beta})  # fmt: skip
    elif kind_name == "mindlin":
        for slip in (0.5, 1.0, 3.0):
            delta = peak * slip
            out.append({**base, "slip_force": 2.0 * kt * delta / 3.0, "slip_displacement": delta})
    else:
        for slip in (0.3, 1.0, 3.0):
            out.append({**base, "stiffness": kt, "slip_force": kt * peak * slip})
    return out


def _search(problem: FitProblem, starts: list[dict[str, float]], run: FitRun) -> Found:
    """Every start solved; the best kept (how many reached it, counted)."""
    sols = [run.solve(begin=s) for s in starts]
    costs = np.array([cost(s) for s in sols])
    best = int(np.argmin(costs))
    at_best = int(np.sum(costs <= costs[best] * (1 + 1e-6) + 1e-300))
    return Found(sols[best], n_starts=len(sols), n_starts_at_best=at_best,
                 note=f"{at_best} of {len(sols)} starts reached the best optimum")  # fmt: skip


def _result(data: _Data, kind: JointKind, run: FitRun, sol: Any, boot: Any,
            found: Any) -> FitResult:  # fmt: skip
    values = dict(sol.values)
    model = kind.build(values)
    w, z, d = predict(kind, values, data.a, data.definition)
    fitted = {"frequency": w, "damping_ratio": z, "dissipation": d}
    measured, modelled, abscissa = [], [], []
    for name, y, s in data.blocks():
        # each block about its mean, over its mean error: the variance rule sees its shape
        mean, scale = float(np.mean(y)), float(np.mean(s))
        measured.append((y - mean) / scale)
        modelled.append((fitted[name] - mean) / scale)
        abscissa.append(data.a)
    k_total = values["linear_stiffness"] + model.initial_stiffness
    derived = {
        "natural_frequency": math.sqrt(k_total),
        "linear_damping_ratio": values["viscous"] / (2.0 * math.sqrt(k_total)),
    }
    if isinstance(found, Found) and found.note:
        sol = replace(sol, message=sol.message + f" ({found.note})")
    units = {**kind.units, **MODE_UNITS, "natural_frequency": "rad/s",
             "linear_damping_ratio": ""}  # fmt: skip
    return FitResult.from_solution(
        sol, model, np.concatenate(abscissa), np.concatenate(measured),
        np.concatenate(modelled), kind=f"joint ({data.definition})",
        abscissa_label="amplitude a", signal_label=" and ".join(b[0] for b in data.blocks())
        + " about their means over their mean errors (stacked)", signal_unit="",
        derived=derived, units=units,
    )  # fmt: skip


def fit_joint(
    data: RingDown | Mapping[str, Any],
    joint: str = "segalman",
    *,
    definition: str | None = None,
    initial: Mapping[str, float] | None = None,
    fixed: Mapping[str, float] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    level: float = 0.95,
    max_evaluations: int | None = None,
    tolerance: float = 1e-10,
) -> FitResult:
    """Fit a joint model and the mode's viscous damping to ω(a), ζ(a) or D(a).

    Parameters
    ----------
    data : RingDown or mapping
        A `RingDown` (`analyze_ring_down`), or arrays by name: 'amplitude' (required),
        'frequency' [rad/s], 'damping_ratio', 'dissipation' [J per unit modal mass], and
        optionally their '..._error' (the residual's scale).
    joint : {'segalman', 'mindlin', 'jenkins'}
        Segalman's four-parameter Iwan model (stiffness K_T, slip_force F_S, exponent χ,
        mass_ratio β), Mindlin's contact (slip_force, slip_displacement), or one Jenkins
        element (stiffness, slip_force); besides them linear_stiffness k₀ and viscous c.
        All per unit modal mass in the amplitude's coordinate.
    definition : {'ring_down', 'steady_state', 'quasi_static'}, optional
        What ω and ζ are (`_joint_model`); default 'ring_down'.
    initial, fixed, bounds : mapping, optional
        Start values, held values and (lower, upper) bounds by parameter name.
    level : float
        Confidence level of the intervals.
    max_evaluations : int, optional
    tolerance : float

    Returns
    -------
    FitResult
        ``model`` the fitted joint (a `PIFriction`, per unit modal mass), ``parameters``
        with intervals, ``derived`` the small-amplitude natural frequency and the
        viscous damping ratio there.
    """
    kind_name = as_choice("joint", joint, tuple(JOINTS))
    kind = JOINTS[kind_name]
    definition = "ring_down" if definition is None else as_choice("definition", definition,
                                                                  DEFINITIONS)  # fmt: skip
    d = _Data(data, definition)
    names = (*kind.names, *MODE)
    natural = {**kind.bounds, **MODE}
    user_bounds = as_bounds("bounds", bounds, names)
    fixed = {} if fixed is None else dict(fixed)
    for key in fixed:
        if key not in names:
            raise ValueError(f"`fixed` must name parameters of {names}; got {key!r}.")
    starts = _starts(d, kind_name)
    if initial is not None:
        for key in initial:
            if key not in names:
                raise ValueError(f"`initial` must name parameters of {names}; got {key!r}.")
        starts = [{**s, **{k: float(v) for k, v in initial.items()}} for s in starts]
    starts = [{k: float(s[k]) for k in names} for s in starts]  # the residual's order
    n_data = sum(b[1].shape[0] for b in d.blocks())
    if n_data <= len(names) - len(fixed):
        raise ValueError(
            f"`data` must hold more values than free parameters ({len(names) - len(fixed)}); "
            f"got {n_data}."
        )
    problem = FitProblem(
        names=names, initial=starts[0], bounds={**natural, **user_bounds},
        fixed={k: float(v) for k, v in fixed.items()}, tied={},
        residual_function=partial(d.residual, kind, names),
    )  # fmt: skip
    if not np.isfinite(level) or not 0 < level < 1:
        raise ValueError(f"`level` must be in (0, 1); got {fmt(level)}.")
    options = FitOptions(float(level), max_evaluations, float(tolerance))
    plan = FitPlan(search=partial(_search, problem, starts), result=partial(_result, d, kind))
    return run_fit(problem, options, plan)
