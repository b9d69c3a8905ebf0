"""A separable fit's residual as the adequacy tests read it (`_adequacy`).

The direct fits (`fit_presliding`, `fit_motion`, `fit_virgin_curve`) fit one
target (a force) on the samples used; their residual is one `_adequacy.Block`
whose noise is the target's own white noise (`_noise_floor.white_variance`) or,
for an equation error whose noise combines several measured signals (the
acceleration's with the force's in `fit_motion`, derivatives estimated through
a filter), a noise of the residual's own colour: only the independence test
judges it. The exact Jacobian of the separable problem and the
fit's covariance give the share the fitted parameters' own error may leave.

The candidate mechanisms are columns the model lacks, added at zero (the
score test of `_adequacy.score_causes`): a force offset, or the Coulomb level's
difference between the two directions (an asymmetry by direction); the velocity
(a viscous force) where the fit has time; the fitted target one sample later (a
delay between force and motion); and one element more at each of a few
thresholds.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding.identification.judge._adequacy import (
    Adequacy,
    Block,
    Candidate,
    assess,
    score_causes,
)
from presliding.identification.judge._noise_floor import (
    RELATIVE_FLOOR,
    quantum,
    shows_noise,
    white_variance,
)
from presliding.identification.problem._separable_problem import Separable

FloatArray = NDArray[np.float64]

__all__ = ["separable_adequacy"]

#: thresholds tried for one more element, geometric between these shares of the span
ELEMENT_RANGE = (1e-3, 0.5)
#: how many of them
ELEMENT_TRIES = 8


def separable_adequacy(sep: Separable, sol: Any, regressors: Mapping[str, FloatArray], *,
                       own_noise: bool = False, signal: str = "force",
                       extra: Mapping[str, FloatArray] | None = None,
                       span: float | None = None) -> Adequacy | None:  # fmt: skip
    """The residual tests of a separable fit's optimum (module notes).

    `regressors` (on every sample) are what the independence test correlates the residual
    with; `own_noise` takes the noise from the residual instead of the target, of a colour
    the data do not tell (`_adequacy.Block.colored`: the independence test alone); `extra`
    are candidate columns (on every sample) of mechanisms the fit may lack, by name
    (``"asymmetry"``, ``"velocity"``); `span` the range of the elements' thresholds.
    """
    used = sep.used
    values = np.array([sol.values[x] for x in sol.values], dtype=float)
    r = sep.residual(values)
    target = sep.target[used]
    q = quantum(target)
    noise = white_variance(target, q)
    if own_noise:  # at least the round-off of the target (noise-free data fit to rounding)
        if not shows_noise(target, float(np.mean(r * r))):
            return None  # a residual at the target's round-off: nothing to judge
        noise = max(white_variance(r), (RELATIVE_FLOOR**2) * float(np.mean(target**2)))
    elif not (q > 0 or shows_noise(target, noise)):
        return None  # noise-free data: no noise model to judge the residual against
    if not noise > 0 or r.shape[0] < 4:
        return None
    free = [j for j, x in enumerate(sol.values) if x not in sol.fixed]
    jac = sep.jacobian(values)[:, free]
    cov = None if sol.covariance is None else np.asarray(sol.covariance)[np.ix_(free, free)]
    regs = {k: np.asarray(v, dtype=float)[used] for k, v in regressors.items()}
    block = Block(0, signal, r, noise, None, 0.0 if own_noise else q, None, None, regs, True,
                  jac, jac, cov, colored=own_noise)  # fmt: skip
    result = assess([block], 1)
    if result.passed:
        return result
    found = _candidates(sep, sol.values, extra or {}, span)
    return result.with_cause(score_causes(r, jac, found, noise * r.shape[0]))


def _candidates(sep: Separable, values: Mapping[str, float], extra: Mapping[str, FloatArray],
                span: float | None) -> list[Candidate]:  # fmt: skip
    used = sep.used
    fitted = sep.fitted(values)
    out: list[Candidate] = []
    if "asymmetry" in extra:
        out.append(Candidate("asymmetry", np.asarray(extra["asymmetry"])[used], lambda e: (
            f"an asymmetry by direction (or a force offset of {e:.3g}): the residual differs "
            "between the two directions of motion; fit it with `asymmetric=True` (command "
            "line `--asymmetric`) or `offset=True`")))  # fmt: skip
    if "velocity" in extra:
        out.append(
            Candidate(
                "velocity",
                np.asarray(extra["velocity"])[used],
                lambda e: (
                    f"a velocity dependence: the residual asks for a viscous force σ·ẏ with σ = "
                    f"{e:.3g} beyond the Coulomb element's sign; fit it with `viscous=True`"
                ),
            )
        )
    later = np.concatenate([fitted[:1], fitted[:-1]])
    out.append(Candidate("delay", (later - fitted)[used], lambda e: (
        f"a delay between force and motion: the fit is better with the model shifted by "
        f"{abs(e):.2g} sample(s) {'later' if e > 0 else 'earlier'}")))  # fmt: skip
    if span and span > 0:
        tries = np.geomspace(ELEMENT_RANGE[0] * span, ELEMENT_RANGE[1] * span, ELEMENT_TRIES)
        g = sep.basis(tries)[0][used]
        for j, rn in enumerate(tries):
            out.append(Candidate("elements", g[:, j], _more_elements(float(rn))))
    return out


def _more_elements(threshold: float) -> Callable[[float], str]:
    """The text naming too few elements, one more at `threshold` [its stiffness]."""
    return lambda e: (f"too few elements: one more element of threshold {threshold:.3g} "
                      f"(stiffness {e:.3g}) would take up the structure; fit more "
                      "elements")  # fmt: skip
