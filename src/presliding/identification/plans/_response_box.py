"""Start values and bounds of a pooled `fit_response`: the regression start (eq. 17),
each record's measured start, the user's `initial` and `bounds` within the natural ones."""

from __future__ import annotations

from typing import Any

import numpy as np

from presliding._validation import as_bounds
from presliding.identification.plans._response_setup import initial_bounds
from presliding.identification.problem._model_spec import ModelSpec
from presliding.identification.records._pooled_start import pooled_start

__all__ = ["start_and_box"]


def start_and_box(
    problem: Any,
    spec: ModelSpec,
    recs: list[Any],
    fixed: dict[str, float],
    forced: bool,
    offset: bool,
    viscous: bool,
    initial_state: str,
    initial: Any,
    bounds: Any,
    fmin: float | None,
) -> tuple[dict[str, float], dict[str, tuple[float, float]]]:
    """The start of every parameter and its (lower, upper) bounds, in `problem.names` order."""
    names = problem.names
    start = pooled_start(recs, spec, fixed.get("mass", None if forced else 1.0), offset, viscous)
    if not forced and "mass" not in fixed and "coulomb_level" in fixed:  # forces scaled
        factor = fixed["coulomb_level"] / start["coulomb_level"]
        start = {key: val * factor for key, val in start.items()}
    for i, rec in enumerate(recs):
        start[problem.nuisance("initial_position", i)] = float(rec.position[0])
        start[problem.nuisance("initial_velocity", i)] = float(rec.velocity[0])
        if initial_state == "preload":
            start[problem.nuisance("preload_fraction", i)] = (
                float(problem.direction[i]) if rec.velocity[0] else 0.0
            )
    for key, val in dict(initial or {}).items():
        if key not in names:
            raise ValueError(f"`initial` must name parameters of the fit; got {key!r}.")
        start[key] = float(val)
    start = {x: start[x] for x in names}
    box = {**spec.bounds(), "mass": (0.0, np.inf), "offset": (-np.inf, np.inf),
           "viscous": (0.0, np.inf), "viscous_negative": (0.0, np.inf)}  # fmt: skip
    box.update(initial_bounds(problem, initial_state))
    if fmin is not None and spec.has_level_parameter:
        box["coulomb_level"] = (fmin, np.inf)
        start["coulomb_level"] = max(start["coulomb_level"], fmin)
    for key, (lo, hi) in as_bounds("bounds", bounds, names).items():
        old = box.get(key, (-np.inf, np.inf))
        box[key] = (max(old[0], float(lo)), min(old[1], float(hi)))
    box = {x: box.get(x, (-np.inf, np.inf)) for x in names}
    return start, box
