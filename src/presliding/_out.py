"""Output arrays given by the user (numpy's ``out=`` convention), checked on entry.

Whole-array calls (`PIOperator.apply`, `PIFriction.force`, `PIBatch.apply`)
write into ``out`` when it is given, so repeated large calls reuse one buffer;
the wording of the error follows `presliding._validation`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from presliding._validation import fmt

__all__ = ["as_output"]


def as_output(name: str, value: Any, shape: tuple[int, ...]) -> np.ndarray:
    """`value` if it is a writeable C-contiguous float64 ndarray of `shape`; new for None."""
    if value is None:
        return np.empty(shape)
    if (
        isinstance(value, np.ndarray)
        and value.dtype == np.float64
        and value.shape == shape
        and value.flags.c_contiguous
        and value.flags.writeable
    ):
        return value
    if isinstance(value, np.ndarray):
        order = "C-contiguous" if value.flags.c_contiguous else "non-contiguous"
        ro = "" if value.flags.writeable else "read-only "
        got = f"a {ro}{order} {value.dtype} array of shape {value.shape}"
    else:
        got = fmt(value)
    raise ValueError(
        f"`{name}` must be a writeable C-contiguous float64 array of shape {shape}; got {got}."
    )
