"""Quasi-static fit: position from a slowly applied force (torque-driven presliding).

A joint driven by a slow force (torque) below break-away moves through its
presliding hysteresis only: inertia and viscous friction are negligible, and
the position follows the force exactly through the inverse of the friction
model, y = Γ[u] with the Coulomb element c1 as a play on the force side
(`presliding.motion.quasi_static_response`). `fit_quasi_static` fits that
model to measured positions, pooling records like `fit_response`: the model
(c1 and the elements or a density) and a force offset are shared; each record
has its initial position and, with ``initial_state="preload"``, the elastic
force its memory starts with (the branch family of `preloaded_state`, on the
branch opposite to the record's first motion: the record starts with a
reversal at its preload; a branch the first motion continued could not be
told apart from a shift of the position).

F_c from below. A quasi-static response exists only while |u| < F_c, so the
Coulomb level is bounded below by the largest applied force (and by
`min_coulomb_level`): a model whose inverse would diverge is never returned.
Above that, loops that stay well below F_c hardly constrain it (the
intervals say so).

Start: eq. 8 as a regression, u = c1·sign(ẏ) + Σ_g w_g·stop_g(y) (+ offset) on
the samples where the position moves (there the balance holds with equality),
after each record's first reversal (an unknown earlier memory wiped out).

Asymmetric friction (``asymmetric=True``): F_c⁻ (``coulomb_level_negative``)
besides F_c⁺, every negative level the share F_c⁻/F_c⁺ of its positive one, as
in `fit_response`. The quasi-static response of an asymmetric model is exactly
that of the symmetric model of the mean levels under u − (F_c⁺ − F_c⁻)/2 (the
exact inverse walks each direction's thresholds, `_quasi_static_kernel`): the
records determine the difference of the levels as they would an offset, and
the fit reports it as the sides'. The symmetric fit runs first;
``result.asymmetry`` tests the difference.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from presliding._progress import Progress
from presliding.identification._fit_engine import run_fit
from presliding.identification.fit_result import FitResult, Tie
from presliding.identification.plans._asymmetric_plan import fit_asymmetric
from presliding.identification.plans._quasi_static_plan import (
    asymmetric_parts,
    check_quasi_static,
    quasi_static_plan,
    quasi_static_problem,
)
from presliding.identification.problem._parameters import check_flag
from presliding.identification.records._quasi_static_start import (  # noqa: F401 (their home before)
    lift_density,
    quasi_static_start,
)
from presliding.identification.result._fit_progress import FitProgress, shows_progress
from presliding.measurement.measurement import Measurement

__all__ = ["fit_quasi_static"]


@shows_progress("fit_quasi_static")
def fit_quasi_static(
    records: Measurement | Sequence[Measurement],
    n_elements: int = 3,
    equal_breakaway: bool = True,
    *,
    density: str | None = None,
    density_cells: int = 32,
    min_coulomb_level: float | None = None,
    offset: bool = False,
    creep: bool = False,
    asymmetric: bool = False,
    initial_state: str = "preload",
    initial: Mapping[str, float] | None = None,
    fixed: Mapping[str, float] | None = None,
    tied: Mapping[str, Tie] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    bootstrap: int = 0,
    seed: int | None = None,
    level: float = 0.95,
    max_evaluations: int | None = None,
    tolerance: float = 1e-8,
    progress: bool | Progress | FitProgress = False,
) -> FitResult:
    """Fit the quasi-static response y = Γ[u] (c1 included) to measured positions.

    Parameters
    ----------
    records : Measurement or sequence of Measurement
        Each with `position` y [m] and `applied_force` u [N] (a torque and an
        angle work alike), u slow enough for inertia to be negligible.
    n_elements, equal_breakaway, density, density_cells : as in `fit_response`
    min_coulomb_level : float, optional, keyword only
        A lower bound on F_c [N], besides the largest |u| (module notes).
    offset : bool, keyword only
        Fit a force offset (parameter ``offset``; the model sees u − offset).
    creep : bool, keyword only
        Put a Kelvin–Voigt element in series with the contact
        (`presliding.friction.CreepingFriction`): the position gains y_c,
        τ·ẏ_c + y_c = J·(u − offset), starting at rest with each record's first
        force (parameters ``creep_compliance`` J >= 0 [m/N] and ``creep_time`` τ >= 0
        [s], shared; the records' `time` is used). A joint that keeps moving under a
        constant torque below break-away creeps to a limit this way; with J = 0 the
        model is the PI model. The returned model is then a `CreepingFriction`.
    asymmetric : bool, keyword only
        Separate levels for the two directions (``coulomb_level_negative`` F_c⁻,
        bounded below by the largest −u; module notes); excludes `offset` and a
        `density`. ``result.asymmetry`` tests it against the symmetric fit.
    initial_state : {"preload", "continuing", "relaxed"}, keyword only
        The memory each record starts with: a fitted preload
        (``preload_fraction``; the record reverses at it), a branch its first
        motion continues (module notes), or relaxed.
    initial, fixed, tied, bounds, bootstrap, seed, level, max_evaluations, tolerance, progress
        As in `fit_response`.

    Returns
    -------
    FitResult
        Position against the applied force, records one after the other; the
        model is `PIFriction` (no mass: quasi-static; with ``creep=True`` a
        `CreepingFriction`), `predict` gives the response of another record.
    """
    request = dict(locals())
    if check_flag("asymmetric", asymmetric):
        if check_flag("creep", creep):
            raise ValueError(
                "`creep`=True fits one level for both directions; it is not available with "
                "`asymmetric`=True; got creep=True, asymmetric=True."
            )
        return fit_asymmetric(fit_quasi_static, request, check_quasi_static, asymmetric_parts)
    checked = check_quasi_static(request)
    problem, options = quasi_static_problem(checked)
    return run_fit(problem, options, quasi_static_plan(checked))
