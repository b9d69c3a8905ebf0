"""Masing check: do measured loops follow from a virgin curve?

The PI model (any model of the Madelung/Masing class) predicts every branch of
a loop from the virgin curve V alone: after a reversal at (y_r, F_r) the force
follows

    F = F_r + d·2·V(|y − y_r|/2),     d = the sign of the new motion,

until the branch returns to the turning point before (Masing's rule, section
1). F_r is the force where the contact stopped at the turning point: the
extreme force over the samples at the turn (a driven force goes on changing by
up to 2·c1 before the contact moves back, so there it is the first sample of
the plateau; a driven displacement is still approaching the turn within the
reversal tolerance, so there it is the turning point itself), and a branch is
compared only until the contact reaches its next turning point. Creep (a force relaxing at rest or a
slow drift of the contact), a preload that changes between cycles, or a
rate-dependent contact break this; a model fitted anyway predicts loops that
are silently wrong. `masing_check` measures the discrepancy between each
measured branch and its Masing prediction, as an RMS relative to the force
range of the loops, and says whether it stays within `tolerance` (default
3 %). Samples where the contact has not yet left the turning point by more
than the reversal tolerance are left out (there the Coulomb element's force
is set-valued).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from presliding._display import fill_attrs, result_html, short_repr
from presliding._interop import require
from presliding._validation import (
    as_list,
    as_nonnegative_scalar,
    as_positive_scalar,
    fmt,
)
from presliding.friction.pi_friction import PIFriction
from presliding.identification.fit_result import FitResult
from presliding.identification.prediction import reversal_tolerance as auto_tolerance
from presliding.identification.problem import _pi_regression as pr
from presliding.measurement.measurement import Measurement

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["MasingCheck", "masing_check", "masing_verdict"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class MasingCheck:
    """Discrepancy between measured branches and their Masing prediction.

    Attributes
    ----------
    displacement, measured, predicted : ndarray
        The compared samples of every branch (records one after the other).
    branch_discrepancy : ndarray
        RMS(measured − predicted) of each branch over the force range.
    discrepancy : float
        RMS over all compared samples, over the force range of the loops.
    tolerance : float
        The largest discrepancy accepted.
    passed : bool
        discrepancy <= tolerance.
    status : str
        "passed" or "failed".
    message : str
    """

    displacement: FloatArray
    measured: FloatArray
    predicted: FloatArray
    branch_discrepancy: FloatArray
    discrepancy: float
    tolerance: float
    passed: bool
    status: str
    message: str

    @property
    def success(self) -> bool:
        """True when the loops follow the virgin curve within the tolerance."""
        return self.passed

    def report(self) -> str:
        """A short summary with the worst branches."""
        worst = np.argsort(self.branch_discrepancy)[::-1][:5]
        lines = [f"Masing check: {self.status} — {self.message}",
                 f"  {self.branch_discrepancy.shape[0]} branches, {self.measured.shape[0]} "
                 "samples compared"]  # fmt: skip
        lines += [f"  branch {int(i) + 1}: {100 * self.branch_discrepancy[i]:.3g} %" for i in worst]
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """The figures as plain values."""
        return {"status": self.status, "success": self.success, "message": self.message,
                "passed": self.passed,
                "discrepancy": self.discrepancy, "tolerance": self.tolerance,
                "branch_discrepancy": self.branch_discrepancy.tolist()}  # fmt: skip

    def to_pandas(self) -> Any:
        """A DataFrame of the compared samples."""
        pd = require("pandas", "`to_pandas()`")

        frame = pd.DataFrame({"displacement": self.displacement, "measured": self.measured,
                              "predicted": self.predicted})  # fmt: skip
        frame.attrs.update(discrepancy=self.discrepancy, tolerance=self.tolerance)
        return fill_attrs(frame, self, units={"measured": "N", "predicted": "N"})

    def __repr__(self) -> str:
        return short_repr(self)

    def _repr_html_(self) -> str:
        """The verdict, the discrepancy against the tolerance and the worst branches."""
        figures = [("discrepancy", f"{100 * self.discrepancy:.3g}", "% of the force range"),
                   ("tolerance", f"{100 * self.tolerance:.3g}", "% of the force range"),
                   ("branches", str(self.branch_discrepancy.shape[0]), ""),
                   ("samples compared", str(self.measured.shape[0]), "")]  # fmt: skip
        worst = np.argsort(self.branch_discrepancy)[::-1][:5]
        rows = [(int(i) + 1, f"{100 * self.branch_discrepancy[i]:.3g}") for i in worst]
        return result_html(self, figures, (("branch", "discrepancy [%]"), rows))

    def plot(self, ax: Axes | None = None) -> Axes:
        """Measured branches and their Masing prediction against displacement."""
        from presliding.plotting import new_axes, place_legend

        ax = new_axes(ax)
        ax.plot(self.displacement, self.measured, ".", ms=2, label="measured branches")
        ax.plot(self.displacement, self.predicted, ".", ms=2, label="Masing prediction")
        ax.set_xlabel("displacement [m]")
        ax.set_ylabel("force [N]")
        ax.set_title(f"Masing check: {self.status} ({100 * self.discrepancy:.3g} %)")
        place_legend(ax, markerscale=4)
        return ax


def _virgin(model: Any) -> PIFriction:
    if isinstance(model, FitResult):
        model = model.model
    if not isinstance(model, PIFriction):
        raise TypeError(
            f"`virgin_model` must be a PIFriction or the FitResult of a virgin-curve fit; got "
            f"{type(model).__name__}."
        )
    return model


def _loop_records(loops: Any) -> list[tuple[FloatArray, FloatArray]]:
    """(displacement, force) pairs from Measurements (position and friction or applied
    force) or (displacement, force) tuples."""
    items = [loops] if isinstance(loops, (Measurement, tuple)) else as_list("loops", loops)
    out = []
    for i, item in enumerate(items):
        if isinstance(item, Measurement):
            force = item.friction_force if item.friction_force is not None else item.applied_force
            if item.position is None or force is None:
                raise ValueError(
                    f"`loops[{i}]` must hold `position` and `friction_force` (or "
                    "`applied_force`); it lacks one."
                )
            out.append((np.asarray(item.position, float), np.asarray(force, float)))
        elif isinstance(item, tuple) and len(item) == 2:
            y, f = (np.asarray(a, dtype=float) for a in item)
            if y.ndim != 1 or y.shape != f.shape or not np.all(np.isfinite(y) & np.isfinite(f)):
                raise ValueError(
                    f"`loops[{i}]` must be two finite 1-D arrays of the same length; got shapes "
                    f"{y.shape} and {f.shape}."
                )
            out.append((y, f))
        else:
            raise TypeError(
                f"`loops` must hold Measurements or (displacement, force) pairs; got "
                f"{type(item).__name__} at index {i}."
            )
    return out


def _before_rest(seg: FloatArray, tol: float) -> NDArray[np.bool_]:
    """The samples of a branch up to the first that reaches its end position: after it,
    a driven force changes at the next turning point while the contact rests there."""
    at_end = np.flatnonzero(np.abs(seg - seg[-1]) <= tol)
    keep = np.ones(seg.shape[0], dtype=bool)
    if at_end.size:
        keep[at_end[0] + 1 :] = False
    return keep


def masing_check(
    virgin_model: PIFriction | FitResult,
    loops: Measurement | tuple | Sequence[Any],
    *,
    tolerance: float = 0.03,
    reversal_tolerance: float | None = None,
) -> MasingCheck:
    """Compare measured loop branches with 2·V(Δ/2) of a virgin curve (module notes).

    Parameters
    ----------
    virgin_model : PIFriction or FitResult
        The virgin curve V(s) = c1 + Σ k_j·min(s, r_j) (``virgin_curve``), e.g.
        from `fit_virgin_curve` on loading ramps.
    loops : Measurement, (displacement, force) pair, or a sequence of them
        Measured loops; a Measurement gives its position and friction force
        (or applied force, for torque-driven loops).
    tolerance : float, keyword only
        Largest accepted RMS discrepancy over the force range (> 0).
    reversal_tolerance : float, optional, keyword only
        Travel a turning point must be left by (default: each record's
        `reversal_tolerance`).

    Returns
    -------
    MasingCheck
    """
    model = _virgin(virgin_model)
    tol = as_positive_scalar("tolerance", tolerance)
    if reversal_tolerance is not None:
        reversal_tolerance = as_nonnegative_scalar("reversal_tolerance", reversal_tolerance)
    ys, ms, ps = [], [], []
    force_range = 0.0
    for y, f in _loop_records(loops):
        rt = auto_tolerance(y) if reversal_tolerance is None else reversal_tolerance
        idx = pr.reversal_indices(np.ascontiguousarray(y), rt)
        force_range = max(force_range, float(np.ptp(f)))
        marks = np.concatenate([idx, [y.shape[0] - 1]])
        for k in range(1, idx.shape[0]):
            i0, i1 = marks[k], marks[k + 1]
            # F_r, the force where the contact stopped at the turning point: the extreme
            # force (in the direction of the motion that ends there) over the samples at
            # the turn. Under a driven force the contact rests there while the force
            # falls back by up to 2·c1 (the extreme is the first such sample); under a
            # driven displacement the samples within the tolerance before the turn are
            # still on the way up (the extreme is at the turning point itself)
            first = i0
            while first > marks[k - 1] + 1 and abs(y[first - 1] - y[i0]) <= rt:
                first -= 1
            back = np.sign(y[i0] - y[marks[k - 1]]) or 1.0
            yr = y[i0]
            fr = f[first + int(np.argmax(back * f[first : i0 + 1]))]
            d = np.sign(y[i1] - yr)
            span = abs(yr - y[marks[k - 1]])
            seg_y, seg_f = y[i0 + 1 : i1 + 1], f[i0 + 1 : i1 + 1]
            travel = d * (seg_y - yr)
            ok = (travel > rt) & (travel <= span * (1 + 1e-12)) & _before_rest(seg_y, rt)
            if not ok.any():
                continue
            pred = fr + d * 2.0 * model.virgin_curve(0.5 * travel[ok])
            ys.append(seg_y[ok])
            ms.append(seg_f[ok])
            ps.append(pred)
    if not ys and reversal_tolerance is not None:
        raise ValueError(
            "`loops` and `reversal_tolerance` must give at least one branch from a second turning "
            f"point on (reversals beyond the tolerance); got none at {fmt(reversal_tolerance)}."
        )
    if not ys:
        raise ValueError(
            "`loops` must hold at least one branch from a second turning point on; got none "
            "(reverse the motion at least twice, beyond the reversal tolerance)."
        )
    disp, meas, pred = np.concatenate(ys), np.concatenate(ms), np.concatenate(ps)
    scale = force_range if force_range > 0 else 1.0
    per = np.array(
        [float(np.sqrt(np.mean((m - p) ** 2))) / scale for m, p in zip(ms, ps, strict=True)]
    )
    total = float(np.sqrt(np.mean((meas - pred) ** 2))) / scale
    passed = total <= tol
    message = (
        f"the branches follow 2·V(Δ/2) of the virgin curve within {100 * total:.3g} % of the "
        f"force range (tolerance {fmt(100 * tol)} %)"
        if passed
        else f"the branches differ from 2·V(Δ/2) by {100 * total:.3g} % of the force range "
        f"(tolerance {fmt(100 * tol)} %): the loops break Masing's rule (creep, a changing "
        "preload, rate dependence), so a PI model fitted to them will mispredict other loops"
    )
    return MasingCheck(disp, meas, pred, per, total, tol, passed,
                       "passed" if passed else "failed", message)  # fmt: skip


def masing_verdict(model: PIFriction | None, loops: Any) -> str:
    """A poor fit's note: `masing_check`'s verdict on `loops` against `model`'s virgin curve.

    "" when there is no model, no loop with a branch from a second turning point,
    or the check cannot run.
    """
    if model is None or not model.is_discrete:
        return ""
    try:
        check = masing_check(model, loops)
    except (ValueError, TypeError):
        return ""
    pct = f"{100 * check.discrepancy:.3g} % of the force range"
    if check.passed:
        return (
            f"masing_check: the loops follow Masing's rules against the fitted virgin curve "
            f"({pct}), so the branches are consistent and another model order may fit"
        )
    return (
        f"masing_check: the loops break Masing's rules against the fitted virgin curve "
        f"({pct} > {100 * check.tolerance:g} %): no PI (Masing) model reproduces them "
        "(creep, rate dependence or a preload changing between cycles)"
    )
