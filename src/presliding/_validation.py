"""The one home of input validation and its wording.

Every public constructor and function checks its inputs on entry with these helpers, so a
bad input is reported in one sentence naming the argument, the rule and the value received
("`stiffness` must be positive; got -3.0 at index 1."). Nothing is clipped silently, and
no NaN or inf is returned in place of an error. Beyond the plain checks: quantities derived
from the arguments (F_c, Σ k_j, r_j = c_j/k_j, energies, ranges) are checked for finiteness
naming their sources (`check_finite_derived`, `check_derived`); `check_size` compares an
allocation with `size_limit()` before it is made; `check_time_span` bounds simulated time;
`renamed` makes errors of an inner call name the argument the user passed. A pint
Quantity is converted to SI wherever a number enters (`as_si`): of the kind its argument's
name has in `presliding._interop.QUANTITY_KINDS` (or the `kind` a helper is given), its
dimension checked; an argument without a unit refuses it.
"""

from __future__ import annotations

import math
import numbers
import os
import warnings as _warnings
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from typing import Any

import numpy as np

from presliding._interop import SI_UNITS, is_quantity, quantity_kind, si_magnitude

__all__ = [
    "BY_NAME", "as_bounds", "as_choice", "as_count", "as_list", "as_nonnegative_scalar",
    "as_parameter_matrix", "as_parameter_vector", "as_positive_scalar", "as_real_array",
    "as_real_scalar", "as_real_vector", "as_si", "as_signal", "as_state_vector",
    "check_finite_derived", "check_increasing", "check_same_length", "check_size",
    "check_time_span", "check_type", "fmt", "renamed", "size_limit"
]  # fmt: skip


def fmt(value: Any) -> str:
    """Format a received value for an error message (short, unambiguous)."""
    if isinstance(value, (float, np.floating)):
        return repr(float(value))
    if isinstance(value, np.ndarray):
        return f"an array of shape {value.shape}" if value.size > 6 else repr(value.tolist())
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


#: `kind` of the helpers: the kind the argument's name has (`quantity_kind`)
BY_NAME = "by name"


def as_si(name: str, value: Any, kind: str | None = BY_NAME) -> Any:
    """A pint Quantity `value` as its magnitude in SI, its dimension checked (of `kind`, by
    default the kind of the argument `name`: `presliding._interop.QUANTITY_KINDS`); anything
    else unchanged. An argument without a unit (`kind` None) refuses a Quantity."""
    if not is_quantity(value):
        return value
    kind = quantity_kind(name) if kind == BY_NAME else kind
    magnitude = None if kind is None else si_magnitude(value, kind)
    if magnitude is None:
        units = " or ".join(SI_UNITS[kind]) if kind else ""
        need = (f"a {kind} (a Quantity in {units} or any unit of the same dimension)" if kind
                else "a plain number or array (it has no unit)")  # fmt: skip
        error = TypeError if kind is None else ValueError
        raise error(f"`{name}` must be {need}; got a Quantity in {value.units}.")
    return magnitude


def _real_array(name: str, value: Any, kind: str | None = BY_NAME) -> np.ndarray:
    """Convert to a float64 array, rejecting booleans, strings, complex and objects (a pint
    Quantity: to SI, `as_si`)."""
    rule = f"`{name}` must be a real number or array of real numbers; got"
    value = as_si(name, value, kind)
    if value is None or isinstance(value, (str, bytes)):
        raise TypeError(f"{rule} {fmt(value)}.")
    try:
        arr = np.asarray(value)
    except ValueError:  # ragged nested sequences
        raise ValueError(f"`{name}` must be a rectangular array; got {fmt(value)}.") from None
    if arr.dtype == object or arr.dtype.kind not in "iuf":
        raise TypeError(f"{rule} dtype {arr.dtype}.")
    return np.array(arr, dtype=np.float64, copy=True)


def _first_bad(arr: np.ndarray, bad: np.ndarray) -> str:
    idx = np.argwhere(bad)[0]
    where = "" if arr.ndim == 0 else f" at index {idx[0] if arr.ndim == 1 else tuple(idx.tolist())}"
    return f"got {fmt(arr[tuple(idx)])}{where}"


def _check_finite(name: str, arr: np.ndarray) -> None:
    # a sum is finite only if every term is (no O(size) temporary); else search in pieces
    with np.errstate(over="ignore", invalid="ignore"):
        if math.isfinite(np.sum(arr)):
            return
    flat = arr.reshape(-1)
    for start in range(0, flat.shape[0], 1 << 16):
        bad = ~np.isfinite(flat[start : start + (1 << 16)])
        if bad.any():
            whole = np.zeros(arr.shape, dtype=bool)  # the error path only
            whole.reshape(-1)[start + int(np.argmax(bad))] = True
            raise ValueError(f"`{name}` must be finite; {_first_bad(arr, whole)}.")


def as_signal(
    name: str, value: Any, *, min_length: int = 1, copy: bool = True, kind: str | None = BY_NAME
) -> np.ndarray:
    """A sampled signal: 1-D, finite, float64, with at least `min_length` samples
    (``copy=False``: a float64 C-contiguous ndarray itself, only read; `kind`: Quantity to SI)."""
    value = as_si(name, value, kind)
    plain = type(value) is np.ndarray and value.dtype == np.float64
    arr = value if not copy and plain and value.flags.c_contiguous else _real_array(name, value)
    if arr.ndim != 1:
        raise ValueError(f"`{name}` must be one-dimensional (shape (T,)); got shape {arr.shape}.")
    if arr.shape[0] < min_length:
        rule = (
            "must not be empty" if min_length == 1 else f"must have at least {min_length} samples"
        )
        raise ValueError(f"`{name}` {rule}; got {arr.shape[0]} samples.")
    _check_finite(name, arr)
    if arr.shape[0] > 1:  # increments (time steps, displacements) are finite within the range
        check_finite_derived("range max − min", float(arr.max()) - float(arr.min()), name)
    return np.ascontiguousarray(arr)


def _as_scalar(name: str, value: Any, finite: bool = True, kind: str | None = BY_NAME) -> float:
    value = as_si(name, value, kind)
    if type(value) is float or type(value) is int:  # the common case, without numpy
        try:
            x = float(value)
        except OverflowError:  # an int beyond the float range
            raise ValueError(f"`{name}` must be finite; got {fmt(value)}.") from None
        if finite and not math.isfinite(x):
            raise ValueError(f"`{name}` must be finite; got {fmt(x)}.")
        return x
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, np.ndarray, np.generic)):
        raise TypeError(f"`{name}` must be a real number; got {fmt(value)}.")
    arr = _real_array(name, value)
    if arr.ndim != 0:
        raise ValueError(f"`{name}` must be a scalar; got shape {arr.shape}.")
    if finite:
        _check_finite(name, arr)
    return float(arr)


def as_nonnegative_scalar(name: str, value: Any, *, kind: str | None = BY_NAME) -> float:
    """A finite real number >= 0 (`kind`: a pint Quantity of that kind in SI)."""
    x = _as_scalar(name, value, kind=kind)
    if x < 0:
        raise ValueError(f"`{name}` must be nonnegative; got {fmt(x)}.")
    return x


def as_positive_scalar(name: str, value: Any, *, kind: str | None = BY_NAME) -> float:
    """A finite real number > 0 (`kind`: a pint Quantity of that kind in SI)."""
    x = _as_scalar(name, value, kind=kind)
    if not x > 0:
        raise ValueError(f"`{name}` must be positive; got {fmt(x)}.")
    return x


def as_real_scalar(
    name: str, value: Any, *, finite: bool = True, kind: str | None = BY_NAME
) -> float:
    """A real number, finite unless `finite` is False (`kind`: a Quantity of it in SI)."""
    return _as_scalar(name, value, finite, kind)


def as_parameter_vector(
    name: str,
    value: Any,
    *,
    positive: bool | None = True,
    allow_empty: bool = False,
) -> np.ndarray:
    """A read-only 1-D float64 vector of finite parameters, positive (or nonnegative; None: any
    sign); a scalar becomes a vector of length one."""
    arr = _real_array(name, value)
    if arr.ndim == 0:
        arr = arr.reshape(1)
    if arr.ndim != 1:
        raise ValueError(f"`{name}` must be a scalar or one-dimensional; got shape {arr.shape}.")
    if arr.shape[0] == 0 and not allow_empty:
        raise ValueError(f"`{name}` must not be empty; got 0 elements.")
    _check_finite(name, arr)
    bad = ~(arr > 0) if positive else arr < 0
    if positive is not None and bad.any():
        rule = "positive" if positive else "nonnegative"
        raise ValueError(f"`{name}` must be {rule}; {_first_bad(arr, bad)}.")
    arr = np.ascontiguousarray(arr)
    arr.setflags(write=False)
    return arr


def as_real_vector(name: str, value: Any, *, allow_empty: bool = False) -> np.ndarray:
    """`as_parameter_vector` of any sign."""
    return as_parameter_vector(name, value, positive=None, allow_empty=allow_empty)


def as_state_vector(name: str, value: Any, size: int) -> np.ndarray:
    """A finite float64 vector of exactly `size` entries (a scalar is broadcast)."""
    arr = _real_array(name, value)
    if arr.ndim == 0:
        arr = np.full(size, float(arr))
    if arr.shape != (size,):
        raise ValueError(f"`{name}` must have shape ({size},); got shape {arr.shape}.")
    _check_finite(name, arr)
    return np.ascontiguousarray(arr)


def check_same_length(**arrays: np.ndarray) -> None:
    """All given arrays have the same length along their first axis."""
    lengths = {k: len(v) for k, v in arrays.items()}
    if len(set(lengths.values())) > 1:
        listing = " and ".join(str(n) for n in lengths.values())
        names = " and ".join(f"`{k}`" for k in lengths)
        raise ValueError(f"{names} must have the same length; got {listing}.")


def as_choice(name: str, value: Any, choices: tuple[str, ...]) -> str:
    """One of a fixed set of strings."""
    if not isinstance(value, str) or value not in choices:
        options = ", ".join(repr(c) for c in choices)
        raise ValueError(f"`{name}` must be one of {options}; got {fmt(value)}.")
    return value


def check_increasing(name: str, arr: np.ndarray, after: float | None = None) -> None:
    """A 1-D array that is strictly increasing (and starts above `after` when given)."""
    bad = np.diff(arr) <= 0
    if bad.any():
        i = int(np.argmax(bad)) + 1
        got = f"got {fmt(arr[i])} after {fmt(arr[i - 1])} at index {i}"
        raise ValueError(f"`{name}` must be strictly increasing; {got}.")
    if after is not None and arr.shape[0] and not arr[0] > after:
        raise ValueError(f"`{name}` must start after the state's time {after}; got {fmt(arr[0])}.")


def as_count(name: str, value: Any, *, minimum: int = 0, maximum: int | None = None) -> int:
    """An integer in [`minimum`, `maximum`] (a count); bools are rejected. `maximum` bounds
    counts that set the length of a loop, so that an absurd value is an error, not a hang."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"`{name}` must be an integer; got {fmt(value)}.")
    if (value := int(value)) < minimum:
        rule = {0: "nonnegative", 1: "a positive integer"}.get(minimum, f"at least {minimum}")
        raise ValueError(f"`{name}` must be {rule}; got {fmt(value)}.")
    if maximum is not None and value > maximum:
        raise ValueError(f"`{name}` must be at most {maximum}; got {fmt(value)}.")
    return value


#: Longest simulated time span [s] (float64 times resolve 0.2 ms there; 1e308 s overflows).
MAX_TIME_SPAN = 1e12


def check_time_span(name: str, value: Any, span: float) -> None:
    """A simulated time span `span` (set by the argument `name` = `value`) is at most 1e12 s."""
    if not abs(span) <= MAX_TIME_SPAN:
        raise ValueError(
            f"`{name}` must keep the simulated time span within {MAX_TIME_SPAN:g} s (about "
            f"31,700 years, where float64 times still resolve 0.2 ms); got {fmt(value)}."
        )


def as_list(name: str, value: Any) -> list[Any]:
    """A sequence of items (a list, tuple or any iterable but a string or a mapping) as a list."""
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__iter__"):
        raise TypeError(f"`{name}` must be a list; got {fmt(value)}.")
    return list(value)


@contextmanager
def renamed(**names: str) -> Iterator[None]:
    """Errors raised inside name the caller's arguments (``renamed(force="applied_force")``)."""
    try:
        yield
    except (ValueError, TypeError) as exc:
        text = str(exc)
        for inner, outer in names.items():
            text = text.replace(f"`{inner}`", f"`{outer}`").replace(f"`{inner}[", f"`{outer}[")
        if text == str(exc):
            raise
        raise type(exc)(text) from exc


def renamed_keyword(options: dict[str, Any], old: str, new: str, value: Any, where: str) -> Any:
    """Keyword `new`'s `value`, or its old name `old` from `options` (a DeprecationWarning)."""
    if old in options and value is not None:
        raise TypeError(f"{where}: give `{new}` only (`{old}` is its old name); got both.")
    if old in options:
        _warnings.warn(f"{where}: `{old}` is renamed `{new}`.", DeprecationWarning, stacklevel=3)
    return options.pop(old, value)


def check_type(name: str, value: Any, expected: type | tuple[type, ...], *, where: str = "") -> Any:
    """`value` is an instance of `expected` (class or tuple); `where` locates it (" at index 2")."""
    if not isinstance(value, expected):
        classes = expected if isinstance(expected, tuple) else (expected,)
        names = [c.__name__ for c in classes]
        listing = names[0] if len(names) == 1 else ", ".join(names[:-1]) + " or " + names[-1]
        article = "an" if listing[0] in "AEIOUaeiou" else "a"
        raise TypeError(f"`{name}` must be {article} {listing}; got {type(value).__name__}{where}.")
    return value


# ---------------------------------------------------------------------- overflow
def _sources(names: str | tuple[str, ...]) -> str:
    names = (names,) if isinstance(names, str) else names
    quoted = [f"`{n}`" for n in names]
    return quoted[0] if len(quoted) == 1 else ", ".join(quoted[:-1]) + " and " + quoted[-1]


def check_finite_derived(what: str, value: Any, names: str | tuple[str, ...]) -> None:
    """The quantity `what` (with its formula), computed from the arguments `names` the user
    passed, came out finite (an array element by element)."""
    bad = ~np.isfinite(arr := np.asarray(value, dtype=np.float64))
    if bad.any():
        raise ValueError(
            f"{_sources(names)} must give a finite {what}; {_first_bad(arr, bad)} (beyond the "
            "floating-point range: express the values in units that keep them moderate)."
        )


# ---------------------------------------------------------------------- sizes
#: Largest allocation [bytes] `check_size` lets through; None: half the physical memory.
MAX_ALLOCATION_BYTES: int | None = None


def size_limit() -> int:
    """Bytes `check_size` accepts: `MAX_ALLOCATION_BYTES`, else half the physical memory."""
    if MAX_ALLOCATION_BYTES is not None:
        return int(MAX_ALLOCATION_BYTES)
    total = 0
    with suppress(AttributeError, OSError, ValueError):
        total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    return int(total) // 2 if total > 0 else 32 * 2**30 // 2


def _bytes(n: float) -> str:
    k = min(int(math.log(max(n, 1.0), 1024)), 6)
    return f"{int(n)} B" if k == 0 else f"{n / 1024**k:.3g} {'KMGTPE'[k - 1]}iB"


def _amount(count: float) -> str:
    if not math.isfinite(count):
        return "more than 1.8e308"
    return str(int(count)) if count < 1e15 and count == int(count) else f"{count:.3g}"


def check_size(
    name: str, value: Any, count: float, *, what: str = "values", item_bytes: int = 8
) -> int:
    """Before allocating: `count` items of `item_bytes` fit `size_limit()`; returns int(count).
    `name` = `value` is the argument that sets the size; a float `count` may be inf."""
    limit = size_limit()
    most = limit // max(int(item_bytes), 1)
    count = float(count) if not isinstance(count, numbers.Integral) else count
    if not (count <= most):  # also catches nan and inf
        origin = "" if MAX_ALLOCATION_BYTES is not None else ", half of this machine's memory"
        need = count * item_bytes if math.isfinite(count) else math.inf
        raise ValueError(
            f"`{name}` must ask for at most {most} {what} ({_bytes(limit)}{origin}); got "
            f"{fmt(value)}, which asks for {_amount(count)} {what} "
            f"({_bytes(need) if math.isfinite(need) else 'beyond any memory'})."
        )
    return int(count)


def as_parameter_matrix(name: str, value: Any) -> np.ndarray:
    """A 2-D float64 array (B, N) of finite, positive parameters, one row per batch member
    (a scalar becomes shape (1, 1) and a 1-D vector one row (1, N); N may be 0)."""
    arr = _real_array(name, value)
    arr = arr.reshape(1, -1) if arr.ndim < 2 else arr
    if arr.ndim != 2:
        raise ValueError(f"`{name}` must have shape (B, N) or (N,); got shape {arr.shape}.")
    _check_finite(name, arr)
    bad = ~(arr > 0)
    if bad.any():
        raise ValueError(f"`{name}` must be positive; {_first_bad(arr, bad)}.")
    return np.ascontiguousarray(arr)


def as_real_array(name: str, value: Any, *, finite: bool = True) -> np.ndarray:
    """A float64 array of any shape (a scalar stays 0-d), finite (``finite=False``: ±inf ok)."""
    arr = _real_array(name, value)
    if finite:
        _check_finite(name, arr)
    elif np.isnan(arr).any():
        raise ValueError(f"`{name}` must not be NaN; {_first_bad(arr, np.isnan(arr))}.")
    return arr if arr.ndim == 0 else np.ascontiguousarray(arr)


def as_bounds(name: str, value: Any, names: Any) -> dict[str, tuple[float, float]]:
    """A mapping of parameter names (among `names`) to (lower, upper) with lower < upper."""
    out: dict[str, tuple[float, float]] = {}
    for key, pair in check_type(name, {} if value is None else value, dict).items():
        if key not in names:
            raise ValueError(f"`{name}` must name parameters of the fit; got {key!r}.")
        if not isinstance(pair, (tuple, list)) or len(pair) != 2:
            raise ValueError(f"`{name}` must map {key!r} to a pair (lo, hi); got {fmt(pair)}.")
        lo, hi = (as_real_scalar(f"{name}[{key!r}]", v, finite=False) for v in pair)
        if not lo < hi:
            raise ValueError(f"`{name}` must map {key!r} to lower < upper; got {fmt(pair)}.")
        out[key] = (lo, hi)
    return out
