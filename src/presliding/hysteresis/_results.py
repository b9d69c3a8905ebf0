"""The result convention every result object of the package follows.

A result (`MotionResult`, `FitResult`, `SweepResult`, ...) has named arrays,
``success`` (bool), ``status`` (a string from the set its class documents),
``message``, ``plot(ax=None)`` returning the axes, ``report()`` returning a
string, ``to_dict()`` and ``to_pandas()``. `ResultMixin` gives a frozen result
dataclass default ``to_dict`` / ``to_pandas`` built from its fields; `Status`
is the string status of the results whose status was an integer code before
(motions and closed loops), still comparing equal to that code, with a
DeprecationWarning, for one release. It sits in the lowest layer so that every
layer's results can share it.
"""

from __future__ import annotations

import dataclasses
import warnings
from typing import Any, ClassVar

import numpy as np

from presliding._display import fill_attrs, result_html, short_repr
from presliding._interop import require

__all__ = ["ResultMixin", "Status", "deprecated_code"]

_DEPRECATED = (
    "integer status codes are deprecated and will be removed in the next release: "
    "`status` is a string ({names}); use `success` or compare `status` with a string"
)


class Status(str):
    """A result's status: a plain string, e.g. ``"success"`` or ``"event_limit"``.

    It also keeps the integer code of earlier releases in ``code`` (0 success,
    negative failure); comparing it with an integer (``status == 0``) still works
    for one release and emits a DeprecationWarning.
    """

    code: int

    def __new__(cls, value: str, code: int = 0) -> Status:
        obj = super().__new__(cls, value)
        obj.code = int(code)
        return obj

    def __eq__(self, other: object) -> bool:
        if isinstance(other, int | np.integer) and not isinstance(other, bool):
            warnings.warn(_DEPRECATED.format(names=f"here {str(self)!r}"), DeprecationWarning,
                          stacklevel=2)  # fmt: skip
            return self.code == int(other)
        return str.__eq__(self, other)

    def __ne__(self, other: object) -> bool:
        return not self.__eq__(other)

    __hash__ = str.__hash__

    def __reduce__(self) -> tuple[Any, ...]:
        return (Status, (str(self), self.code))


def deprecated_code(codes: Any, names: str) -> Any:
    """`codes` (the old integer status) with a DeprecationWarning naming the new strings."""
    warnings.warn(_DEPRECATED.format(names=names), DeprecationWarning, stacklevel=3)
    return codes


def _plain(value: Any) -> Any:
    """A field's value for `to_dict`: statuses as str, records with a ``to_dict`` as dicts
    (models and memory states stay objects)."""
    if isinstance(value, Status):
        return str(value)
    if not isinstance(value, type) and callable(getattr(value, "to_dict", None)):
        return value.to_dict()
    return value


class ResultMixin:
    """Default ``to_dict`` and ``to_pandas`` for a result dataclass.

    ``to_dict`` maps every field (and ``success``, ``status``, ``message``) to
    plain values: arrays stay numpy arrays, a status becomes a str, nested
    records with a ``to_dict`` (e.g. ``energy``) become dicts; models and
    memory states stay objects. ``to_pandas`` is the table of the
    one-dimensional arrays as long as the array named by ``_rows`` (also the
    index when ``_rows_are_index``), nested arrays prefixed with their field's
    name; ``df.attrs`` holds ``success``, ``status``, ``message``, the columns'
    ``units`` and the ``model`` and its ``parameters`` where there is one.
    ``repr`` is short (arrays summarised) and ``_repr_html_`` shows the status,
    the key figures with units and the model's parameters (`presliding._display`);
    a subclass declares its dataclass with ``repr=False`` to keep them.
    """

    _rows: ClassVar[str] = "time"
    _rows_are_index: ClassVar[bool] = True

    def to_dict(self) -> dict[str, Any]:
        """Every field by name as plain Python/numpy values, plus success, status and message."""
        out = {f.name: _plain(getattr(self, f.name)) for f in dataclasses.fields(self)}  # type: ignore[arg-type]
        for name in ("success", "status", "message"):
            out[name] = _plain(getattr(self, name))
        return out

    def to_pandas(self) -> Any:
        """A DataFrame of the sampled arrays (see the class notes); needs pandas."""
        pd = require("pandas", "`to_pandas()`")

        rows = np.asarray(getattr(self, self._rows))
        n = rows.shape[0]
        columns: dict[str, Any] = {}

        def take(name: str, value: Any) -> None:
            if isinstance(value, dict):
                for key, item in value.items():
                    take(f"{name}_{key}", item)
            elif isinstance(value, np.ndarray) and value.ndim == 1 and value.shape[0] == n:
                columns[name] = value

        for name, value in self.to_dict().items():
            if name != self._rows or not self._rows_are_index:
                take(name, value)
        index = pd.Index(rows, name=self._rows) if self._rows_are_index else None
        return fill_attrs(pd.DataFrame(columns, index=index), self)

    def __repr__(self) -> str:
        return short_repr(self)

    def _repr_html_(self) -> str:
        """The status, the key figures with units and the model's parameters, for notebooks."""
        return result_html(self)
