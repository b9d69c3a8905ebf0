"""MATLAB files for `Measurement.from_mat` and the command line.

Versions 4 to 7.2 are read through scipy.io.loadmat, version 7.3 (HDF5) through
h5py (the `h5py` extra; an ImportError naming it otherwise), with clear errors
naming the file for a text file, a file that cannot be parsed, and variables
that are not numeric vectors (signals) or scalars (scales).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._interop import require
from presliding._validation import fmt
from presliding.measurement._readers import check_path, read_bytes

__all__ = ["MatFile", "read_mat"]

FloatArray = NDArray[np.float64]
_SNIFF = 1 << 16
_KINDS = {"U": "text", "S": "text", "O": "a cell array or struct", "c": "complex values",
          "V": "a struct", "b": "logical values"}  # fmt: skip


class MatFile:
    """The variables of a MATLAB file, with checked access."""

    def __init__(self, path: Any) -> None:
        from scipy.io import loadmat

        self.path = check_path(path)
        raw = read_bytes(self.path)[:_SNIFF]
        if raw.startswith(b"MATLAB 7.3 MAT-file") or raw.startswith(b"\x89HDF"):
            self.contents = _read_hdf5(self.path)
            self.names = sorted(self.contents)
            return
        if b"\x00" not in raw:
            raise ValueError(
                f"{self.path}: is a text file, not a MATLAB file; read it with "
                "Measurement.from_csv."
            )
        try:
            self.contents = loadmat(self.path)
        except Exception as exc:  # scipy raises ValueError, TypeError, OSError, ...
            raise ValueError(
                f"{self.path}: cannot be read as a MATLAB file ({type(exc).__name__}: {exc})."
            ) from None
        self.names = sorted(k for k in self.contents if not k.startswith("__"))

    def _numeric(self, name: str, what: str) -> np.ndarray:
        if not isinstance(name, str):
            raise TypeError(f"{what} must be a variable name (str); got {fmt(name)}.")
        if name not in self.contents or name.startswith("__"):
            raise ValueError(
                f"{self.path}: no variable {name!r} ({what}); it holds "
                f"{', '.join(self.names) or 'no variables'}."
            )
        arr = np.asarray(self.contents[name])
        if arr.dtype.kind not in "iuf":
            kind = _KINDS.get(arr.dtype.kind, str(arr.dtype))
            raise ValueError(f"{self.path}: variable {name!r} ({what}) holds {kind}, not numbers.")
        return arr.astype(np.float64).squeeze()

    def vector(self, name: str, signal: str) -> FloatArray:
        """A numeric vector variable (any of N, 1×N, N×1)."""
        arr = self._numeric(name, f"`{signal}`")
        if arr.size == 0:
            raise ValueError(
                f"{self.path}: variable {name!r} of `{signal}` is empty (it holds no values); "
                "choose the variable that holds the samples."
            )
        if arr.ndim != 1:
            raise ValueError(
                f"{self.path}: variable {name!r} of `{signal}` must be a vector; got shape "
                f"{np.shape(self.contents[name])}."
            )
        bad = ~np.isfinite(arr)
        if bad.any():
            i = int(np.argmax(bad))
            raise ValueError(
                f"{self.path}: variable {name!r} of `{signal}` holds {arr[i]} at index {i}; "
                "every value must be finite."
            )
        return arr

    def scalar(self, name: str, signal: str) -> float:
        """A numeric scalar variable (a scale factor)."""
        arr = self._numeric(name, f"the scale of `{signal}`")
        if arr.size == 0:
            raise ValueError(
                f"{self.path}: variable {name!r} (the scale of `{signal}`) is empty; it must "
                "hold one number."
            )
        if arr.ndim != 0:
            raise ValueError(
                f"{self.path}: variable {name!r} (the scale of `{signal}`) must be a scalar; got "
                f"shape {np.shape(self.contents[name])}."
            )
        return float(arr)


def _read_hdf5(path: str) -> dict[str, Any]:
    """The top-level variables of a MATLAB 7.3 file (HDF5, through h5py; arrays transposed)."""
    h5py = require(
        "h5py", f"{path}: a MATLAB 7.3 (HDF5) file (or save it with save(..., '-v7')); reading it"
    )
    out: dict[str, Any] = {}
    try:
        with h5py.File(path, "r") as fh:
            for name, item in fh.items():
                if name.startswith("#"):  # MATLAB's references and subsystem
                    continue
                kind = item.attrs.get("MATLAB_class", b"")
                kind = kind.decode() if isinstance(kind, bytes) else str(kind)
                if not isinstance(item, h5py.Dataset) or kind in ("cell", "struct"):
                    out[name] = np.empty(0, dtype=object)  # named as a cell or struct
                elif item.attrs.get("MATLAB_empty", 0):  # its data are its dimensions
                    out[name] = np.empty(0, dtype=bool if kind == "logical" else float)
                elif kind == "char":
                    out[name] = np.asarray("".join(map(chr, np.ravel(item[()]))))
                elif kind == "logical":
                    out[name] = np.asarray(item[()], dtype=bool)
                else:  # MATLAB writes column-major: transpose back
                    out[name] = np.asarray(item[()]).T
    except OSError as exc:
        raise ValueError(f"{path}: cannot be read as a MATLAB 7.3 (HDF5) file ({exc}).") from None
    return out


def read_mat(path: Any) -> MatFile:
    """Open a MATLAB file (see `MatFile`)."""
    return MatFile(path)
