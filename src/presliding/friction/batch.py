"""Many finite-element PI friction models on one displacement path: `friction_batch`.

A parameter study (B friction models, one displacement path) is one `PIBatch`
call: the elastic banks k_j, r_j become the batch's weights and thresholds and
each Coulomb element c1 its Coulomb term, so ``friction_batch(models).apply(y)``
gives F[T, B] with column b equal to ``models[b].force(y)`` (the same play
states bit for bit, forces within 1e-12 of F_c).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from presliding.friction._parts import elements
from presliding.friction.pi_friction import PIFriction
from presliding.hysteresis.batch import PIBatch

__all__ = ["friction_batch"]


def friction_batch(models: Sequence[PIFriction]) -> PIBatch:
    """A `PIBatch` whose member b is the friction law of ``models[b]`` (eq. 8).

    Parameters
    ----------
    models : sequence of PIFriction
        Finite-element models (not continuous densities), all with the same
        number of elements N.

    Returns
    -------
    PIBatch
        Thresholds r_bj, weights k_bj and Coulomb elements c1_b; ``apply(y)``
        returns the friction forces F[T, B] and a `PIBatchState` whose
        ``member(b)`` is the `PIState` that ``models[b].force`` would return.

    Examples
    --------
    >>> import numpy as np
    >>> from presliding import PIFriction
    >>> models = [PIFriction(c1, stiffness=[500.0, 10.0], breakaway=[1.0, 1.0]) for c1 in (0, 1)]
    >>> force, state = friction_batch(models).apply(np.linspace(0.0, 0.2, 5))
    >>> force.shape
    (5, 2)
    """
    models = list(models)
    for i, m in enumerate(models):
        if not isinstance(m, PIFriction):
            raise TypeError(f"`models` must hold PIFriction models; got {type(m).__name__} at {i}.")
        if not m.is_discrete:
            raise ValueError(
                "`models` must have finite elements (a continuous density has no batch "
                f"kernel); got density {m.density!r} at index {i}."
            )
    if not models:
        raise ValueError("`models` must not be empty; got 0 models.")
    n = models[0].n_elements
    for i, m in enumerate(models):
        if m.n_elements != n:
            raise ValueError(
                f"`models` must all have {n} elements; got {m.n_elements} at index {i}."
            )
    return PIBatch(
        np.stack([elements(m)[1] for m in models]).reshape(len(models), n),
        np.stack([elements(m)[0] for m in models]).reshape(len(models), n),
        coulomb=np.array([m.coulomb for m in models]),
    )
