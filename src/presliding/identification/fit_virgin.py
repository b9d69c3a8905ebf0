"""Virgin-curve fits: the initial loading curve from ramps or loops (Madelung/Masing).

The virgin curve F_v(s) = c1 + Σ_j k_j·min(s, r_j) (s > 0) determines every
loop of a PI friction model: after a reversal at (y_r, F_r) each branch
follows F_r ∓ 2·F_v(|y − y_r|/2) at least until it returns to the previous
turning point (section 1; Madelung's and Masing's rules). `fit_virgin_curve`
reads virgin-curve samples from

* loading ramps from a relaxed contact (``loops=False``): s = |y − y_0|,
  F_v = ±F, ramps of either sign pooled;
* hysteresis loops (``loops=True``): each branch from the second turning point
  on gives F_v(s) = ±(F − F_r)/2 at s = |y − y_r|/2 (`virgin_samples`), so a
  force offset cancels.

Quantised data. An encoder's position steps back and forth by a quantum (and
noise) even on a ramp: each record's own tolerance (`count_reversals`', three
times its quantum or noise) decides what a turning point is, and a ramp is
taken on the monotone envelope of its travel (isotonic regression), so that a
retreat of a few quanta, or up to a tenth of the travel, is not a reversal.
The samples of all records are pooled and sorted by s, and the monotone envelope F_iso(s), the
nondecreasing function closest to them in least squares
(`scipy.optimize.isotonic_regression`, pool-adjacent-violators), gives a
second start: the thresholds fitted to the envelope (which no noise makes
turn back), refined on the samples themselves. The better of that fit and
the fit from the threshold grid is kept. The final fit is always to the
samples: the envelope is biased upwards where the curve is flat and noisy
(pool-adjacent-violators keeps the running maxima there), the samples are not.

Asymmetric friction (``asymmetric=True``, ramps only): the two branches of the
virgin curve, F_v⁺ of ramps in +y and F_v⁻ of ramps in −y, share the elements'
stiffnesses and have each their Coulomb element and thresholds
(`problem._sided_virgin`). The symmetric fit of the same samples runs first, the
asymmetric one starts from it (and from it with the − branch scaled to its
level), and ``result.asymmetry`` tests the two against each other
(`judge._asymmetry`). Loops cannot tell the sides apart: every branch after a
reversal follows the mean of the two curves.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from functools import partial
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._progress import Progress
from presliding._validation import as_nonnegative_scalar, as_signal, check_same_length, fmt
from presliding.identification._fit_engine import FitPlan, FitRun, Found, run_fit
from presliding.identification.checks._response_checks import cost
from presliding.identification.fit_presliding import (
    check_enough,
    check_fit_options,
    check_varies,
    derived_quantities,
    element_count,
    pi_model,
)
from presliding.identification.fit_result import FitResult, Tie
from presliding.identification.prediction import reversal_tolerance as auto_tolerance
from presliding.identification.problem import _pi_regression as pr
from presliding.identification.problem._fit_problem import FitOptions, FitProblem
from presliding.identification.problem._parameters import check_flag, resolve_parameters
from presliding.identification.problem._separable_adequacy import separable_adequacy
from presliding.identification.problem._separable_problem import Separable, separable_problem
from presliding.identification.result._fit_progress import FitProgress, as_reporter, shows_progress

__all__ = ["fit_virgin_curve", "virgin_samples"]

FloatArray = NDArray[np.float64]


def virgin_samples(
    displacement: FloatArray, force: FloatArray, reversal_tolerance: float = 0.0
) -> tuple[FloatArray, FloatArray]:
    """Virgin-curve samples (s, F_v(s)) from the branches of measured loops (Masing's rule).

    Every branch that starts at the second or a later turning point measures
    F_v(s) = ±(F − F_r)/2 at s = |y − y_r|/2 until it has travelled as far as the
    branch before it (where it closes the loop and may join an older branch).
    F_r is the force where the contact stopped (the first sample of a plateau at
    the turning point, for a driven force that goes on changing there).

    Parameters
    ----------
    displacement, force : ndarray, shape (T,)
        A checked path with hysteresis loops and its force.
    reversal_tolerance : float
        Travel a turning point must be left by to count (nonnegative).

    Returns
    -------
    s, virgin_force : ndarray
        The abscissa s = |y − y_r|/2 and F_v(s) of every usable sample, branch
        after branch (not sorted).
    """
    idx = pr.reversal_indices(np.ascontiguousarray(displacement), reversal_tolerance)
    if idx.shape[0] < 2:
        raise ValueError(
            f"`displacement` must have at least two turning points to read the virgin curve from "
            f"its loops; got {idx.shape[0]}."
        )
    marks = np.concatenate([idx, [displacement.shape[0] - 1]])
    s_parts, f_parts = [], []
    for k in range(1, idx.shape[0]):
        i0, i1 = marks[k], marks[k + 1]
        # the force where the contact stopped: the first sample of a plateau at the
        # turning point (a driven force keeps changing there, by up to 2·c1)
        first = i0
        while first > marks[k - 1] + 1 and abs(displacement[first - 1] - displacement[i0]) <= (
            reversal_tolerance
        ):
            first -= 1
        yr, fr = displacement[i0], force[first]
        direction = np.sign(displacement[i1] - yr)
        span = abs(yr - displacement[marks[k - 1]])
        seg_y, seg_f = displacement[i0 + 1 : i1 + 1], force[i0 + 1 : i1 + 1]
        travel = direction * (seg_y - yr)
        ok = (travel > 0) & (travel <= span * (1 + 1e-12)) & _before_rest(seg_y, reversal_tolerance)
        s_parts.append(0.5 * travel[ok])
        f_parts.append(0.5 * direction * (seg_f[ok] - fr))
    return np.concatenate(s_parts), np.concatenate(f_parts)


def _before_rest(seg: FloatArray, tol: float) -> NDArray[np.bool_]:
    """The samples of a branch up to the first that reaches its end position: after it,
    a driven force changes at the next turning point while the contact rests there."""
    at_end = np.flatnonzero(np.abs(seg - seg[-1]) <= tol)
    keep = np.ones(seg.shape[0], dtype=bool)
    if at_end.size:
        keep[at_end[0] + 1 :] = False
    return keep


#: A ramp may retreat by this share of its travel (quantisation, noise, a settling drive)
#: before it counts as reversing; beyond it (and beyond `reversal_tolerance`) it is a loop.
RAMP_RETREAT = 0.1


def _ramp_samples(y: FloatArray, f: FloatArray, tol: float, which: str) -> tuple:
    """(s, F_v) of a loading ramp from rest at y[0]; its travel made monotone first.

    A ramp that retreats by up to `tol` or a tenth of its travel (a few quanta of
    an encoder, noise) is taken on its monotone envelope: s is the isotonic
    (nondecreasing, least-squares) fit of the travel |y − y[0]|. A larger
    retreat is a reversal: the record is a loop, not a ramp.
    """
    from scipy.optimize import isotonic_regression

    sign = np.sign(y[-1] - y[0])
    if sign == 0:
        raise ValueError(f"{which}: a virgin loading must end away from its start; got none.")
    raw = sign * (y - y[0])
    retreat = np.maximum.accumulate(raw) - raw
    allowed = max(tol, RAMP_RETREAT * float(np.max(raw)))
    if float(np.max(retreat)) > allowed:
        i = int(np.argmax(retreat > allowed))
        raise ValueError(
            f"{which} must be a loading ramp for loops=False (retreats up to "
            f"{fmt(allowed)} are taken on its monotone envelope); it reverses by "
            f"{fmt(float(retreat[i]))} at index {i}: fit it with loops=True."
        )
    s = isotonic_regression(raw, increasing=True).x
    keep = s > 0
    return s[keep], sign * f[keep]


def _as_records(displacement: Any, force: Any) -> list[tuple[FloatArray, FloatArray]]:
    """One (displacement, force) pair or sequences of them, checked."""
    if isinstance(displacement, np.ndarray):
        single = displacement.ndim == 1
    else:
        single = not (
            isinstance(displacement, Sequence)
            and len(displacement) > 0
            and all(np.ndim(d) == 1 for d in displacement)
        )
    if single:
        pairs = [(displacement, force)]
    else:
        if not isinstance(displacement, Sequence) or not isinstance(force, Sequence):
            raise TypeError(
                "`displacement` and `force` must be arrays or sequences of arrays (one per "
                f"ramp or record); got {type(displacement).__name__}."
            )
        if len(displacement) != len(force) or not displacement:
            raise ValueError(
                "`displacement` and `force` must hold the same number of records (at least "
                f"one); got {len(displacement)} and {len(force)}."
            )
        pairs = list(zip(displacement, force, strict=True))
    out = []
    for i, (y_in, f_in) in enumerate(pairs):
        tag = "" if single else f"[{i}]"
        y, f = as_signal(f"displacement{tag}", y_in), as_signal(f"force{tag}", f_in)
        check_same_length(**{f"displacement{tag}": y, f"force{tag}": f})
        check_varies(f"displacement{tag}", y)
        out.append((y, f))
    return out


@shows_progress("fit_virgin_curve")
def fit_virgin_curve(
    displacement: ArrayLike | Sequence[ArrayLike],
    force: ArrayLike | Sequence[ArrayLike],
    n_elements: int | None = None,
    thresholds: ArrayLike | None = None,
    *,
    loops: bool = True,
    reversal_tolerance: float | None = None,
    envelope: bool = True,
    asymmetric: bool = False,
    fixed: Mapping[str, float] | None = None,
    tied: Mapping[str, Tie] | None = None,
    initial: Mapping[str, float] | Any = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    level: float = 0.95,
    grid_size: int = pr.DEFAULT_GRID,
    max_evaluations: int | None = None,
    tolerance: float = 1e-8,
    progress: bool | Progress | FitProgress = False,
) -> FitResult:
    """Fit the virgin (initial loading) curve F_v(s) = c1 + Σ_j k_j·min(s, r_j), s > 0.

    Parameters
    ----------
    displacement, force : array_like, shape (T,), or sequences of them
        One record or several (ramps of both signs, or loop records), pooled.
        With ``loops=True``: paths with hysteresis loops (module notes). With
        ``loops=False``: loadings from the relaxed state at their first sample
        (where the force is taken as zero); s = |y − y[0]|, F_v = ±F.
    n_elements, thresholds : as in `fit_presliding`
    reversal_tolerance : float or None
        Travel [m] a turning point must be left by to count (loops); None
        (default): each record's own `reversal_tolerance` (three times its
        quantum or noise). A ramp (``loops=False``) is taken on the monotone
        envelope of its travel: retreats up to this tolerance or a tenth of its
        travel are quantisation and noise, not reversals.
    envelope : bool
        Also start from the thresholds fitted to the monotone envelope of the
        pooled samples (module notes), keeping the better fit to the samples.
    asymmetric : bool
        Fit the two branches of ramps in +y and in −y (``loops=False`` only):
        ``coulomb_negative`` c1⁻ and ``threshold_negative_j`` r_j⁻ besides c1
        and r_j, the stiffnesses shared (module notes); ``result.asymmetry``
        tests them against the symmetric fit.
    fixed, tied, initial, bounds, level, grid_size, max_evaluations, tolerance, progress
        As in `fit_presliding`.

    Returns
    -------
    FitResult
        Fitted against s (sorted); `measured` holds the pooled samples, `fitted`
        the model; the model reproduces every loop by the Madelung/Masing rules.
    """
    if check_flag("asymmetric", asymmetric):
        return _fit_sided(dict(locals()))
    records = _as_records(displacement, force)
    n = element_count(n_elements, thresholds, 3)
    if reversal_tolerance is not None:
        reversal_tolerance = as_nonnegative_scalar("reversal_tolerance", reversal_tolerance)
    initial, bounds, fixed, tied = resolve_parameters(initial, bounds, fixed, tied)
    fixed, tied, level, grid_size, max_evaluations, tolerance = check_fit_options(
        fixed, tied, level, grid_size, max_evaluations, tolerance
    )
    s, fv = _pooled_samples(records, loops, reversal_tolerance)
    check_enough(s.shape[0], 1 + 2 * n, "virgin-curve samples")
    # grid thresholds at the first samples would mimic the Coulomb element
    lo = max(4.0 * float(s[0]), float(np.quantile(s, 0.01)))
    grid = pr.geometric_grid(lo, float(s[-1]), float(s[-1]), grid_size)
    shown = as_reporter(progress)

    def model_of(target: FloatArray) -> Separable:
        return Separable(target, np.ones((s.shape[0], 1)), ("coulomb",), pr.virgin_basis(s), n,
                         np.ones(s.shape[0], dtype=bool))  # fmt: skip

    def problem(sep: Separable, start: ArrayLike | None) -> FitProblem:
        return separable_problem(
            sep, {"coulomb": (0.0, np.inf)}, grid=grid, thresholds=start, fixed=fixed, tied=tied,
            smallest_threshold=float(s[0]), progress=shown, user_initial=initial,
            user_bounds=bounds,
        )  # fmt: skip

    samples = model_of(fv)
    use_envelope = envelope and thresholds is None and n > 0
    plan = FitPlan(search=partial(_search, problem, model_of, samples, use_envelope),
                   result=partial(_result, samples, s, loops),
                   adequacy=lambda run, sol: separable_adequacy(
                       samples, sol, {"s": s}, signal="virgin-curve force",
                       span=float(s[-1]) if n else None))  # fmt: skip
    options = FitOptions(level, max_evaluations, tolerance, progress=shown)
    return run_fit(problem(samples, thresholds), options, plan)


def _pooled_samples(records: list, loops: bool, tolerance: float | None) -> tuple:
    """Every record's virgin-curve samples (s, F_v), pooled and sorted by s."""
    s_parts, f_parts = [], []
    for i, (y, f) in enumerate(records):
        check_varies("force" if len(records) == 1 else f"force[{i}]", f)
        tol = auto_tolerance(y) if tolerance is None else tolerance
        which = "`displacement`" if len(records) == 1 else f"`displacement[{i}]`"
        s, fv = virgin_samples(y, f, tol) if loops else _ramp_samples(y, f, tol, which)
        s_parts.append(s)
        f_parts.append(fv)
    s, fv = np.concatenate(s_parts), np.concatenate(f_parts)
    order = np.argsort(s, kind="stable")
    return s[order], fv[order]


def _search(problem: Callable[..., FitProblem], model_of: Callable[..., Separable],
            samples: Separable, use_envelope: bool, run: FitRun) -> Found:  # fmt: skip
    """The grid start solved; with the envelope, its thresholds too (the better kept)."""
    from scipy.optimize import isotonic_regression

    fit = run.problem.solve(run.options)
    if use_envelope:
        run.stage("start thresholds from the monotone envelope")
        envelope = model_of(isotonic_regression(samples.target, increasing=True).x)
        shaped = problem(envelope, None).solve(run.options)
        r_names = pr.element_names(samples.n_elements)[1]
        start = np.array([shaped.values[x] for x in r_names])
        other = problem(samples, start).solve(run.options)
        if cost(other) < cost(fit):
            fit = other
    return Found(fit)


def _result(samples: Separable, s: FloatArray, loops: bool, run: FitRun, sol: Any,
            boot: Any, found: Any) -> FitResult:  # fmt: skip
    """The public result against s: the model reproduces every loop (Madelung, Masing)."""
    model, note = pi_model(sol.values, samples.n_elements, sol.values["coulomb"])
    fitted, fv = samples.fitted(sol.values), samples.target
    if note:
        sol = replace(sol, message=sol.message + note)
    return FitResult.from_solution(
        sol, model, s, fv, fitted, kind="virgin curve",
        abscissa_label="s = half travel since reversal" if loops else "s = travel from rest",
        signal_label="virgin-curve force", signal_unit="N", derived=derived_quantities(model),
    )  # fmt: skip


def _sided_samples(records: list, tolerance: float | None) -> tuple:
    """Every ramp's samples (s, F_v) with its side (+1, −1): the + branch, then the − branch,
    each sorted by s; both sides needed."""
    parts = []
    for i, (y, f) in enumerate(records):
        check_varies("force" if len(records) == 1 else f"force[{i}]", f)
        tol = auto_tolerance(y) if tolerance is None else tolerance
        which = "`displacement`" if len(records) == 1 else f"`displacement[{i}]`"
        s, fv = _ramp_samples(y, f, tol, which)
        parts.append((s, fv, np.full(s.shape[0], np.sign(y[-1] - y[0]))))
    s, fv, side = (np.concatenate(x) for x in zip(*parts, strict=True))
    if not (np.any(side > 0) and np.any(side < 0)):
        raise ValueError(
            "`asymmetric=True` needs loading ramps in both directions (the two branches of the "
            f"virgin curve); got ramps in {'+' if side[0] > 0 else '−'}y only."
        )
    order = np.lexsort((s, -side))
    return s[order], fv[order], side[order]


def _fit_sided(request: dict[str, Any]) -> FitResult:
    """``asymmetric=True``: the symmetric fit, then both branches from it (module notes)."""
    from presliding.identification.plans._asymmetric_plan import split_negative
    from presliding.identification.plans._virgin_sides import fit_branches

    if request["loops"]:
        raise ValueError(
            "`asymmetric=True` needs loops=False (loading ramps from rest): after a reversal "
            "every branch follows the mean of the two sides' curves, so loops cannot tell them "
            "apart; got loops=True."
        )
    tol = request["reversal_tolerance"]
    tol = None if tol is None else as_nonnegative_scalar("reversal_tolerance", tol)
    samples = _sided_samples(_as_records(request["displacement"], request["force"]), tol)
    symmetric = fit_virgin_curve(**{**split_negative(request), "asymmetric": False})
    return fit_branches(request, symmetric, *samples)
