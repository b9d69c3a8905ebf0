"""The one decorator of every compiled kernel: `numba.njit`, typed as the function it compiles.

``@njit(cache=True, ...)`` compiles as ``@numba.njit(cache=True, ...)`` (the
flags are passed on unchanged, so the machine code is the same) without numba's
C-callable wrapper, which no kernel needs (a kernel is never passed to compiled
code as a first-class function) and which costs a cold cache about a fifth of a
small kernel's compile time; and a type checker sees the decorated kernel with the signature of
the Python function: calls into kernels are checked against their annotations.
The flags themselves are checked against `JitFlags`, the options the kernels of
presliding use. Every layer's kernel modules import it from here.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Literal, TypedDict, TypeVar

import numba as nb

if TYPE_CHECKING:  # pragma: no cover
    from typing_extensions import Unpack

__all__ = ["JitFlags", "njit"]

_Kernel = TypeVar("_Kernel", bound=Callable[..., Any])


class JitFlags(TypedDict, total=False):
    """Options of `numba.njit` that the kernels use (see numba's documentation)."""

    cache: bool
    fastmath: bool | set[str]
    error_model: Literal["python", "numpy"]
    boundscheck: bool
    nogil: bool
    parallel: bool
    inline: Literal["never", "always"]


def njit(*, refcount: bool = True, **flags: Unpack[JitFlags]) -> Callable[[_Kernel], _Kernel]:
    """`numba.njit` with `flags`, returning the compiled dispatcher typed as the function.

    Parameters
    ----------
    refcount : bool, keyword only
        False compiles without numba's reference counting (its ``_nrt=False``), for
        kernels that allocate no array: their calls and array views then cost no
        atomic operations (a kernel called once per period of a loop).
    **flags
        Passed to `numba.njit` unchanged (``cache=True``, ``fastmath``, ...).

    Returns
    -------
    callable
        A decorator; the dispatcher it returns is called like the function.
    """

    def compile_kernel(function: _Kernel) -> _Kernel:
        # no C-callable (cfunc) wrapper: no kernel is passed to compiled code as a
        # first-class function, and the wrapper costs about a fifth of a small kernel's
        # compile time on a cold cache (the machine code of the kernel is the same)
        extra: dict[str, Any] = {"no_cfunc_wrapper": True}
        if not refcount:
            extra["_nrt"] = False
        dispatcher: Any = nb.njit(**flags, **extra)(function)
        return dispatcher  # type-checked as `function`: a dispatcher is called like it

    return compile_kernel
