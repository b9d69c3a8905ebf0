"""The readers of `Measurement`: delimited text, MATLAB files, DataFrames, and joins.

A mixin of class methods (`from_csv`, `from_mat`, `from_dataframe`, `join`),
kept apart from the signal processing of `measurement.py`; the file formats
themselves are read by `_readers`, `_mat` and `_frames`, converted to SI by
`_source.assemble` and `_units`.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from typing import Any

from presliding.measurement._source import (
    build,
    check_distinct_columns,
    check_signal_names,
    check_time_lines,
    with_time,
)
from presliding.measurement._units import header_unit

__all__ = ["MeasurementReaders"]


class MeasurementReaders:
    """Class methods that read a `Measurement` (mixed into it)."""

    @classmethod
    def from_csv(
        cls,
        path: str | os.PathLike[str],
        time: str | int | None = None,
        *,
        sample_rate: float | None = None,
        delimiter: str | None = None,
        header: bool | None = None,
        decimal: str = ".",
        units: Mapping[str, str | None] | None = None,
        scale: Mapping[str, float] | None = None,
        axis: str | None = None,
        **columns: str | int,
    ) -> Any:
        """Read a delimited text file (comma, tab, semicolon or whitespace separated).

        Parameters
        ----------
        path : path-like
        time : str or int, optional
            Column of the time: a header name (with or without its unit,
            ``"Time [s]"`` or ``"Time"``) or a 0-based index.
        sample_rate : float, optional
            Sample rate [Hz] when the file has no time column (t = 0, 1/rate, ...).
        delimiter : {",", ";", "\\t", " "}, optional
            Default: detected from the first line (tab, semicolon, comma, else whitespace).
        header : bool, optional
            Whether the first line names the columns; default: detected (a header
            when any of its cells is not a number). Without a header, columns are
            chosen by 0-based index.
        decimal : {".", ","}
            The decimal mark (``","`` for European exports such as ``0,5;1,25``).
        units : mapping, optional
            Unit per signal name (``{"position": "mm"}``), overriding the header's;
            None or "" takes the values as SI.
        scale : mapping, optional
            Factor per signal name applied after the unit conversion.
        axis : {'linear', 'rotary'}, optional
            The kind of axis (default: from the units read, else linear); see
            `Measurement`.
        **columns : str or int
            Columns of the signals, by signal name, e.g. ``position="Position [mm]"``
            or ``position=1``.

        Raises
        ------
        ValueError
            Naming the file, line and column, for a row with a missing cell, an
            empty, non-numeric or non-finite value, an unknown unit or one of the
            wrong dimension; for a binary file; for time that does not increase.

        Examples
        --------
        The tribometer file of the shared data (units from the header; friction sign flipped)::

            Measurement.from_csv(path, "Time [s]", position="Position [mm]",
                                 friction_force="Friction [uN]", scale={"friction_force": -1})

        A headerless two-column file sampled at 1 kHz: ``from_csv(path, sample_rate=1e3,
        position=0, applied_force=1)``.
        """
        from presliding.measurement._readers import read_text

        check_signal_names(columns)
        table = read_text(path, delimiter=delimiter, header=header, decimal=decimal)
        wanted = with_time(columns, time, sample_rate)
        index = {sig: table.index(sig, col) for sig, col in wanted.items()}
        check_distinct_columns(index, table.label)
        values = table.values(sorted(set(index.values())))
        where = f"{table.path}: "
        raw = {}
        for sig, j in index.items():
            label = table.label(j)
            raw[sig] = (label, values[j], header_unit(label, where) if table.names else None)
        if "time" in index:
            check_time_lines(table, values[index["time"]], table.label(index["time"]))
        return build(cls, raw, table.path, "csv", scale, units, sample_rate, axis=axis)

    @classmethod
    def from_mat(
        cls,
        path: str | os.PathLike[str],
        time: str | None = "t",
        *,
        sample_rate: float | None = None,
        units: Mapping[str, str | None] | None = None,
        scale: Mapping[str, float | str] | None = None,
        axis: str | None = None,
        **variables: str,
    ) -> Any:
        """Read a MATLAB file (versions 4 to 7.2 through scipy.io.loadmat; 7.3 through h5py).

        Parameters
        ----------
        path : path-like
        time : str or None
            Variable holding the time [s] (None with `sample_rate`).
        sample_rate : float, optional
            Sample rate [Hz] when the file has no time variable.
        units : mapping, optional
            Unit per signal name (variables carry none; default SI).
        scale : mapping, optional
            Factor per signal name; a string names a scalar variable of the file
            (e.g. ``{"applied_force": "gtau"}`` for force = gtau · voltage).
        axis : {'linear', 'rotary'}, optional
            The kind of axis (variables carry no units: give it for a joint).
        **variables : str
            Variables of the signals, by signal name, e.g. ``position="qm"``.

        Examples
        --------
        The EMPS benchmark file::

            Measurement.from_mat(path, position="qm", applied_force="vir",
                                 scale={"applied_force": "gtau"})
        """
        from presliding.measurement._mat import read_mat

        check_signal_names(variables)
        mat = read_mat(path)
        wanted = with_time(variables, time if sample_rate is None else None, sample_rate)
        check_distinct_columns(wanted)
        raw = {sig: (var, mat.vector(var, sig), None) for sig, var in wanted.items()}
        return build(cls, raw, mat.path, "mat", scale, units, sample_rate, mat.scalar, axis)

    @classmethod
    def from_dataframe(
        cls,
        df: Any,
        time: str | int | None = None,
        *,
        sample_rate: float | None = None,
        units: Mapping[str, str | None] | None = None,
        scale: Mapping[str, float] | None = None,
        axis: str | None = None,
        **columns: str | int,
    ) -> Any:
        """Read columns of a pandas DataFrame (pandas is needed only for this).

        Parameters
        ----------
        df : pandas.DataFrame
        time : str or int, optional
            Column of the time, or ``"index"`` for the DataFrame's index (numeric
            [s, or the unit in its name], TimedeltaIndex or DatetimeIndex: seconds
            since the first entry). Default: the index, unless `sample_rate` is given.
        sample_rate, units, scale, axis : as in `from_csv`
            A unit at the end of a column name (``"x [mm]"``) is converted to SI.
        **columns : str or int
            Columns of the signals by signal name (a name, or a position).

        Examples
        --------
        ``Measurement.from_dataframe(df, "t [ms]", position="x [um]", friction_force="F [mN]")``
        """
        from presliding.measurement._frames import dataframe_columns

        check_signal_names(columns)
        if time is None and sample_rate is None:
            time = "index"
        wanted = with_time(columns, time, sample_rate)
        raw = dataframe_columns(df, wanted)
        check_distinct_columns({k: v for k, v in wanted.items() if v != "index"})
        return build(cls, raw, None, "dataframe", scale, units, sample_rate, axis=axis)

    @classmethod
    def join(cls, records: Sequence[Any], *, interpolate: bool = False) -> Any:
        """Join records of different signals (e.g. one file per signal) on one time base.

        The result spans the records' overlap in time. Records on the same clock
        (times equal to within 0.1 % of a step; lengths may differ) are joined as
        they are; records on different clocks are an error unless
        ``interpolate=True``, which interpolates them linearly onto the first
        record's times. No signal may appear twice. The samples dropped and any
        interpolation are noted in `source`.

        Parameters
        ----------
        records : sequence of Measurement
        interpolate : bool
            Interpolate records on other clocks onto the first record's times.
        """
        from presliding.measurement._join import join_records

        return join_records(records, interpolate, cls)
