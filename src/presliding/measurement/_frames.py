"""pandas DataFrames for `Measurement.from_dataframe` (pandas imported only here, when used)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._interop import require
from presliding.measurement._units import header_unit

__all__ = ["dataframe_columns"]

FloatArray = NDArray[np.float64]


def dataframe_columns(
    df: Any, wanted: Mapping[str, Any]
) -> dict[str, tuple[str, FloatArray, str | None]]:
    """Columns of a pandas DataFrame by name (or position), checked; `raw` for `assemble`.

    The special column ``"index"`` of the time takes the DataFrame's index (a
    numeric index [s, or the unit in its name], a TimedeltaIndex or a
    DatetimeIndex: seconds since its first entry).
    """
    pd = require("pandas", "`Measurement.from_dataframe`")
    if not isinstance(df, pd.DataFrame):
        raise TypeError(f"`df` must be a pandas DataFrame; got {type(df).__name__}.")
    raw: dict[str, tuple[str, FloatArray, str | None]] = {}
    for sig, col in wanted.items():
        if sig == "time" and isinstance(col, str) and col == "index" and "index" not in df.columns:
            series, label = df.index.to_series(), str(df.index.name or "index")
            if isinstance(df.index, (pd.DatetimeIndex, pd.TimedeltaIndex)):
                delta = series - series.iloc[0]
                raw[sig] = (label, (delta / pd.Timedelta(seconds=1)).to_numpy(float), "s")
                continue
        elif isinstance(col, (int, np.integer)) and not isinstance(col, bool):
            if col not in df.columns:
                if not 0 <= col < df.shape[1]:
                    raise ValueError(
                        f"column of `{sig}` must be a column name or a position in "
                        f"0..{df.shape[1] - 1}; got {col}."
                    )
                series, label = df.iloc[:, int(col)], str(df.columns[int(col)])
            else:
                series, label = df[col], str(col)
        elif col in df.columns:
            series, label = df[col], str(col)
        else:
            raise ValueError(
                f"`df` has no column {col!r} for `{sig}`; its columns are "
                f"{', '.join(repr(str(c)) for c in df.columns)}."
            )
        if isinstance(series, pd.DataFrame):
            raise ValueError(f"`df` has several columns named {col!r}; choose `{sig}` by position.")
        values = pd.to_numeric(series, errors="coerce")
        bad = values.isna().to_numpy() | ~np.isfinite(values.to_numpy(dtype=float, na_value=np.nan))
        if bad.any():
            i = int(np.argmax(bad))
            raise ValueError(
                f"`df` column {label!r} of `{sig}`: row {series.index[i]!r} holds "
                f"{series.iloc[i]!r}, not a finite number."
            )
        raw[sig] = (label, values.to_numpy(dtype=np.float64), header_unit(label))
    return raw
