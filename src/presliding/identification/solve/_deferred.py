"""A solve whose covariance is deferred: what a search needs now, the errors when kept.

A search solves from many starts and keeps one optimum. For a large pooled
problem the covariance (`_covariance.fit_covariance`: the HAC sandwich of a
40 000 × 67 Jacobian, several factorisations) costs as much as a dozen residual
evaluations, and a start's errors are never read. `solve_least_squares(...,
errors=False)` therefore returns the solution without them
(`deferred_solution`): its values, residual, status and message are those of the
full solve (the undetermined columns found by the same factorisation,
`_covariance.undetermined_columns`, and the same rule, `verdict`), its errors
NaN; `complete` computes them exactly as the full solve would have, from the
Jacobian the solver ended with.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import sparse

from presliding.identification.intervals._covariance import undetermined_columns
from presliding.identification.solve._solution import Solution, name_list, solution_of
from presliding.identification.solve._structured_lm import one_blas_thread

__all__ = ["complete", "deferred_solution", "dense", "verdict"]

FloatArray = NDArray[np.float64]


def complete(sol: Solution) -> Solution:
    """A solution with its errors: one whose covariance was deferred (``errors=False``)
    computed now, any other as it is."""
    return sol.pending() if sol.pending is not None else sol


def verdict(setup: Any, found: Any, undetermined: Any) -> tuple[str, str]:
    """The status and message of a solve: not identifiable where the Jacobian is singular."""
    names, pm = setup.names, setup.pm
    status, message = found.status, found.message
    if undetermined and status == "converged":
        status = "not_identifiable"
        which = {names[i] for j in undetermined for i in np.flatnonzero(pm.matrix[:, j])}
        message = f"the data do not determine {name_list(which, names)} (singular Jacobian)"
    return status, message


def dense(jac: Any) -> FloatArray:
    """A Jacobian as a dense array (the structured solver keeps it sparse)."""
    return jac.toarray() if sparse.issparse(jac) else jac


def deferred_solution(setup: Any, found: Any, blocks: Any,
                      full_solution: Callable[[], Solution]) -> Solution | None:  # fmt: skip
    """The solution of a solve (`_least_squares`: its `_Setup` and `_Found`) without its
    covariance (module notes); `full_solution()` computes the complete one. None where the
    covariance takes no blocks of residuals (it is then cheap: computed at once)."""
    if not setup.pm.free:
        return None
    with one_blas_thread():
        undetermined = undetermined_columns(dense(found.jac_free), blocks)
    if undetermined is None:
        return None
    names = setup.names
    status, message = verdict(setup, found, undetermined)
    nan = float("nan")
    return solution_of(
        setup, found, status, message, standard_error=dict.fromkeys(names, nan),
        confidence_interval=dict.fromkeys(names, (nan, nan)), pending=full_solution,
    )  # fmt: skip
