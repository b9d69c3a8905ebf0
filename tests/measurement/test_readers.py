"""Readers of real files: units from headers, headerless files, MAT files, DataFrames, joins."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import io

from presliding.measurement.measurement import Measurement


def _write(tmp_path, text, name="data.csv", encoding="utf-8"):
    path = tmp_path / name
    path.write_bytes(text.encode(encoding))
    return path


# ---------------------------------------------------------------------- units
@pytest.mark.parametrize(
    ("header", "signal", "factor", "si"),
    [
        ("Position [mm]", "position", 1e-3, "m"),
        ("x (um)", "position", 1e-6, "m"),
        ("x [µm]", "position", 1e-6, "m"),
        ("x [μm]", "position", 1e-6, "m"),
        ("angle [deg]", "position", np.pi / 180, "rad"),
        ("Friction [uN]", "friction_force", 1e-6, "N"),
        ("torque [mN m]", "applied_force", 1e-3, "N m"),
        ("torque [N·m]", "applied_force", 1.0, "N m"),
        ("torque [N*m]", "applied_force", 1.0, "N m"),
        ("torque [mNm]", "applied_force", 1e-3, "N m"),
        ("w [rad/s]", "velocity", 1.0, "rad/s"),
        ("n [rpm]", "velocity", 2 * np.pi / 60, "rad/s"),
        ("v [mm/s]", "velocity", 1e-3, "m/s"),
        ("a [m/s^2]", "acceleration", 1.0, "m/s^2"),
        ("a [mm/s²]", "acceleration", 1e-3, "m/s^2"),
        ("F [kN]", "applied_force", 1e3, "N"),
    ],
)
def test_units_in_headers_are_converted_to_si(tmp_path, header, signal, factor, si):
    path = _write(tmp_path, f"t [ms],{header}\n0,1.5\n10,-2.5\n20,4\n")
    m = Measurement.from_csv(path, "t [ms]", **{signal: header})
    np.testing.assert_allclose(m.time, [0.0, 0.01, 0.02], rtol=1e-15)
    np.testing.assert_allclose(getattr(m, signal), np.array([1.5, -2.5, 4.0]) * factor, rtol=1e-14)
    assert m.source.units[signal] == si
    text = m.source.describe()
    assert header in text and si in text


def test_scale_applies_on_top_of_the_unit_and_units_override_the_header(tmp_path):
    path = _write(tmp_path, "t [s],x [mm],F [uN]\n0,1,10\n1,2,20\n")
    m = Measurement.from_csv(path, 0, position=1, friction_force=2, scale={"friction_force": -1})
    np.testing.assert_allclose(m.friction_force, [-1e-5, -2e-5])
    m = Measurement.from_csv(path, 0, position=1, units={"position": "um"})
    np.testing.assert_allclose(m.position, [1e-6, 2e-6])
    m = Measurement.from_csv(path, 0, position=1, units={"position": None})  # taken as SI
    np.testing.assert_allclose(m.position, [1.0, 2.0])
    assert (
        "scaled × -1"
        in Measurement.from_csv(
            path, 0, friction_force=2, scale={"friction_force": -1}
        ).source.describe()
    )


@pytest.mark.parametrize(
    ("header", "signal", "needle"),
    [
        ("x [wibbles]", "position", r"the unit 'wibbles' is not a known unit"),
        ("x [mm]", "friction_force", r"the unit 'mm' is not a force"),
        ("F [N]", "position", r"the unit 'N' is not a length"),
        ("x [%]", "position", r"the unit '%' is not a length"),
        ("T [degC]", "time", r"the unit 'degC' is not a time"),
    ],
)
def test_unknown_or_wrong_units_name_file_column_and_unit(tmp_path, header, signal, needle):
    path = _write(tmp_path, f"t,{header}\n0,1\n1,2\n")
    with pytest.raises(ValueError, match=needle) as info:
        if signal == "time":
            Measurement.from_csv(path, header, position="t")
        else:
            Measurement.from_csv(path, "t", **{signal: header})
    assert str(path) in str(info.value) and repr(header) in str(info.value)


# ---------------------------------------------------------------------- layout
@pytest.mark.parametrize("sep", [",", "\t", ";", " ", "   "])
def test_delimiters_are_detected(tmp_path, sep):
    path = _write(tmp_path, f"time{sep}pos\n0{sep}1\n1{sep}2\n2{sep}4\n")
    m = Measurement.from_csv(path, "time", position="pos")
    np.testing.assert_array_equal(m.position, [1.0, 2.0, 4.0])


def test_headerless_files_take_columns_by_index_and_a_sample_rate(tmp_path):
    path = _write(tmp_path, "# rig 3\n0.0 1.0 5\n0.5 2.0 6\n1.0 3.0 7\n")
    m = Measurement.from_csv(path, 0, position=1, applied_force=2)
    np.testing.assert_array_equal(m.position, [1.0, 2.0, 3.0])
    m = Measurement.from_csv(path, sample_rate=4.0, position=1)
    np.testing.assert_array_equal(m.time, [0.0, 0.25, 0.5])
    assert "sample rate 4 Hz" in m.source.describe()
    with pytest.raises(ValueError, match=r"has no header line .* got 'x' for `position`"):
        Measurement.from_csv(path, 0, position="x")
    with pytest.raises(ValueError, match=r"must be an index in 0\.\.2; got 3"):
        Measurement.from_csv(path, 0, position=3)
    with pytest.raises(ValueError, match="`time` \\(a column\\) or `sample_rate`"):
        Measurement.from_csv(path, position=1)
    with pytest.raises(ValueError, match="not both"):
        Measurement.from_csv(path, 0, sample_rate=1.0, position=1)
    with pytest.raises(ValueError, match="`sample_rate` must be positive"):
        Measurement.from_csv(path, sample_rate=-1.0, position=1)


def test_a_byte_order_mark_and_windows_encoding_are_read(tmp_path):
    path = _write(tmp_path, "\ufeffTime [s],x [µm]\n0,1\n1,2\n")
    np.testing.assert_allclose(Measurement.from_csv(path, "Time [s]", position=1).position,
                               [1e-6, 2e-6])  # fmt: skip
    path = _write(tmp_path, "Time [s];x [µm]\n0;1\n1;2\n", name="w.csv", encoding="cp1252")
    np.testing.assert_allclose(Measurement.from_csv(path, "Time [s]", position=1).position,
                               [1e-6, 2e-6])  # fmt: skip


@pytest.mark.parametrize(
    ("body", "needle"),
    [
        ("0,1,2\n1,2\n2,3,4\n", r"line 3 has 2 cells but the header names 3 columns"),
        ("0 1 2\n1 2\n2 3 4\n", r"line 3 has 2 cells but the header names 3 columns"),
        ("0,1,2\n1,,3\n2,3,4\n", r"line 3, column 'x \[mm\]': empty cell"),
        ("0,1,2\n1,abc,3\n2,3,4\n", r"line 3, column 'x \[mm\]': 'abc' is not a number"),
        ("0,1,2\n1,nan,3\n2,3,4\n", r"line 3, column 'x \[mm\]': 'nan' is not a finite number"),
        ("0,1,2\n1,2,3\n1,3,4\n", r"line 4, column 't': time 1(\.0)? does not increase \(line 3"),
        ("0,1,2\n\n# pause\n1,2,3\n0.5,3,4\n", r"line 6, column 't': time 0\.5 does not incr"),
    ],
)
def test_bad_rows_name_file_line_and_column(tmp_path, body, needle):
    sep = " " if "0 1 2" in body else ","
    path = _write(tmp_path, sep.join(["t", "x [mm]", "F"]) + "\n" + body)
    with pytest.raises(ValueError, match=needle) as info:
        Measurement.from_csv(path, "t", position="x [mm]", applied_force="F")
    assert str(info.value).startswith(str(path))


def test_a_bad_cell_in_an_unused_column_is_not_an_error(tmp_path):
    path = _write(tmp_path, "t,x,note\n0,1,start\n1,2,\n")
    np.testing.assert_array_equal(Measurement.from_csv(path, "t", position="x").position, [1, 2])


def test_a_gap_in_an_unused_column_keeps_the_fast_reader(tmp_path, monkeypatch):
    """A NaN in an unused column sent the whole file through the line-by-line
    reader (19 times slower for 1e6 rows); a short row is still caught, never shifted."""
    from presliding.measurement import _readers

    rows = "\n".join(f"{i},{2 * i},{'nan' if i in (3, 5) else 1}" for i in range(9))
    path = _write(tmp_path, "t,x,extra\n" + rows + "\n")

    def line_by_line(self, indices):
        raise AssertionError("the line-by-line reader was used")

    with monkeypatch.context() as patch:
        patch.setattr(_readers.TextTable, "_slow_values", line_by_line)
        m = Measurement.from_csv(path, "t", position="x")
    np.testing.assert_array_equal(m.position, 2.0 * np.arange(9))
    # a row that lacks a cell: the parser pads its end with NaN, in the unused column
    short = _write(tmp_path, "t,x,extra\n0,0,1\n1,2\n2,4,1\n")
    with pytest.raises(ValueError, match=r"line 3 has 2 cells but the header names 3 columns"):
        Measurement.from_csv(short, "t", position="x")


@pytest.mark.parametrize(
    ("content", "error", "needle"),
    [
        (b"\x00\x01\x02binary\x00", ValueError, "not a text file"),
        (
            b"MATLAB 5.0 MAT-file, Platform: x\x00\x00",
            ValueError,
            "read it with Measurement.from_mat",
        ),
        (b"", ValueError, "holds no data"),
        (b"t,x\n", ValueError, "header line but no data rows"),
    ],
)
def test_files_that_are_not_tables(tmp_path, content, error, needle):
    path = tmp_path / "f.csv"
    path.write_bytes(content)
    with pytest.raises(error, match=needle) as info:
        Measurement.from_csv(path, "t", position="x")
    assert str(path) in str(info.value)


def test_paths_and_scales_are_checked(tmp_path):
    path = _write(tmp_path, "t,x\n0,1\n1,2\n")
    with pytest.raises(TypeError, match=r"`path` must be a file path .*; got None"):
        Measurement.from_csv(None, "t", position="x")
    with pytest.raises(FileNotFoundError, match="no such file"):
        Measurement.from_csv(tmp_path / "nope.csv", "t", position="x")
    with pytest.raises(ValueError, match="is a folder"):
        Measurement.from_csv(tmp_path, "t", position="x")
    with pytest.raises(TypeError, match=r"`scale\['position'\]` must be a real number .*MATLAB"):
        Measurement.from_csv(path, "t", position="x", scale={"position": "gtau"})
    with pytest.raises(ValueError, match=r"`scale\['position'\]` must be nonzero"):
        Measurement.from_csv(path, "t", position="x", scale={"position": 0})
    with pytest.raises(ValueError, match=r"`scale\['position'\]` must be finite"):
        Measurement.from_csv(path, "t", position="x", scale={"position": np.nan})
    with pytest.raises(ValueError, match="`scale` names 'velocity', which is not read"):
        Measurement.from_csv(path, "t", position="x", scale={"velocity": 2.0})
    with pytest.raises(TypeError, match="`scale` must be a mapping"):
        Measurement.from_csv(path, "t", position="x", scale=2.0)


@settings(max_examples=25, deadline=None)
@given(
    values=st.lists(st.floats(-1e6, 1e6, allow_subnormal=False), min_size=2, max_size=30),
    sep=st.sampled_from([",", "\t", ";", " "]),
    unit=st.sampled_from([("mm", 1e-3), ("um", 1e-6), ("m", 1.0), ("in", 0.0254)]),
    header=st.booleans(),
)
def test_text_round_trip_is_exact_up_to_the_unit(tmp_path_factory, values, sep, unit, header):
    path = tmp_path_factory.mktemp("rt") / "d.txt"
    rows = [f"{i}{sep}{v!r}" for i, v in enumerate(values)]
    head = [f"t [s]{sep}x [{unit[0]}]"] if header else []
    path.write_text("\n".join(head + rows) + "\n")
    m = Measurement.from_csv(path, 0, position=1, units=None if header else {"position": unit[0]})
    np.testing.assert_array_equal(m.position, np.array(values) * unit[1])


# ---------------------------------------------------------------------- MATLAB
def test_mat_files_give_clear_errors(tmp_path):
    path = tmp_path / "d.mat"
    t = np.arange(5) * 0.1
    io.savemat(path, {"t": t, "M": np.ones((5, 2)), "s": "text", "g": np.ones(3), "q": t})
    for kwargs, needle in [
        ({"position": "M"}, r"variable 'M' of `position` must be a vector; got shape \(5, 2\)"),
        ({"position": "s"}, r"variable 's' \(`position`\) holds text, not numbers"),
        ({"position": "q", "scale": {"position": "g"}}, r"variable 'g' .* must be a scalar"),
        ({"position": "zz"}, r"no variable 'zz' \(`position`\); it holds M, g, q, s, t"),
    ]:
        with pytest.raises(ValueError, match=needle):
            Measurement.from_mat(path, **kwargs)
    m = Measurement.from_mat(path, None, sample_rate=10.0, position="q", units={"position": "mm"})
    np.testing.assert_allclose(m.position, t * 1e-3)
    csv = _write(tmp_path, "t,x\n0,1\n1,2\n")
    with pytest.raises(ValueError, match=f"{csv}: is a text file, not a MATLAB file"):
        Measurement.from_mat(csv, position="x")
    v73 = tmp_path / "new.mat"
    v73.write_bytes(b"MATLAB 7.3 MAT-file, Platform: GLNXA64" + b"\x00" * 100)
    with pytest.raises(ValueError, match=r"7\.3 \(HDF5\)"):
        Measurement.from_mat(v73, position="x")
    junk = tmp_path / "junk.mat"
    junk.write_bytes(b"\x00\x01" * 200)
    with pytest.raises(ValueError, match=f"{junk}: cannot be read as a MATLAB file"):
        Measurement.from_mat(junk, position="x")
    with pytest.raises(TypeError, match="got None"):
        Measurement.from_mat(None, position="x")


# ---------------------------------------------------------------------- DataFrames
def test_from_dataframe_reads_units_from_column_names():
    pd = pytest.importorskip("pandas")
    df = pd.DataFrame({"t [ms]": [0.0, 1.0, 2.0], "x [um]": [1.0, 2.0, 3.0], "F [mN]": [4, 5, 6]})
    m = Measurement.from_dataframe(df, "t [ms]", position="x [um]", friction_force="F [mN]")
    np.testing.assert_allclose(m.time, [0.0, 1e-3, 2e-3])
    np.testing.assert_allclose(m.position, [1e-6, 2e-6, 3e-6])
    np.testing.assert_allclose(m.friction_force, [4e-3, 5e-3, 6e-3])
    indexed = df.set_index(pd.to_timedelta(df["t [ms]"], unit="ms"))
    m = Measurement.from_dataframe(indexed, position="x [um]")
    np.testing.assert_allclose(m.time, [0.0, 1e-3, 2e-3])
    m = Measurement.from_dataframe(df, sample_rate=100.0, position=1)
    np.testing.assert_allclose(m.time, [0.0, 0.01, 0.02])
    bad = df.assign(**{"x [um]": ["1", "oops", "3"]})
    with pytest.raises(ValueError, match=r"column 'x \[um\]' of `position`: row 1 holds 'oops'"):
        Measurement.from_dataframe(bad, "t [ms]", position="x [um]")
    with pytest.raises(ValueError, match="has no column 'y'"):
        Measurement.from_dataframe(df, "t [ms]", position="y")
    with pytest.raises(TypeError, match="`df` must be a pandas DataFrame"):
        Measurement.from_dataframe({"t": [0, 1]}, "t", position="t")


# ---------------------------------------------------------------------- joins
def test_join_on_one_clock_keeps_the_overlap():
    t = np.arange(10) * 0.1
    a = Measurement(t, position=t**2)
    b = Measurement(t[2:] + 1e-6 * 0.1, applied_force=np.arange(8.0))  # jitter well below a step
    m = Measurement.join([a, b])
    np.testing.assert_array_equal(m.time, t[2:])
    np.testing.assert_array_equal(m.position, (t**2)[2:])
    np.testing.assert_array_equal(m.applied_force, np.arange(8.0))
    assert "record 0: 2 samples outside the overlap dropped" in m.source.describe()


def test_join_refuses_other_clocks_unless_asked_to_interpolate():
    t = np.arange(11) * 0.1
    a = Measurement(t, position=2.0 * t)
    b = Measurement(
        np.arange(20) * 0.05 + 0.025, applied_force=3.0 * (np.arange(20) * 0.05 + 0.025)
    )
    with pytest.raises(ValueError, match=r"sampled at different times .* interpolate=True"):
        Measurement.join([a, b])
    m = Measurement.join([a, b], interpolate=True)
    assert m.time[0] == pytest.approx(0.1) and m.time[-1] == pytest.approx(0.9)
    np.testing.assert_allclose(m.applied_force, 3.0 * m.time, rtol=1e-12)
    assert "interpolated onto the times of record 0" in m.source.describe()


def test_join_checks_its_records():
    t = np.arange(5.0)
    a = Measurement(t, position=t)
    with pytest.raises(ValueError, match="`position` is in records 0 and 1"):
        Measurement.join([a, Measurement(t, position=t)])
    with pytest.raises(ValueError, match="overlap in time by at least 2 samples"):
        Measurement.join([a, Measurement(t + 10, velocity=t)])
    with pytest.raises(TypeError, match=r"`records\[1\]` must be a Measurement"):
        Measurement.join([a, t])
    with pytest.raises(ValueError, match="at least one"):
        Measurement.join([])


def test_window_is_recorded_in_the_source(tmp_path):
    path = _write(tmp_path, "t [s],x [mm]\n0,1\n1,2\n2,3\n3,4\n")
    m = Measurement.from_csv(path, 0, position=1).window(1.0, 2.0)
    np.testing.assert_allclose(m.position, [2e-3, 3e-3])
    assert "window: 1 s to 2 s" in m.source.describe()


def test_pint_and_pandas_are_imported_only_when_used():
    import subprocess
    import sys

    code = "import sys, presliding; print('pint' in sys.modules, 'pandas' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "False"]


def test_blank_and_comment_lines_keep_the_line_numbers(tmp_path):
    path = _write(tmp_path, "# rig 7\nt,x\n0,1\n\n# pause\n1,2\n2,oops\n")
    with pytest.raises(ValueError, match=r"line 7, column 'x': 'oops' is not a number"):
        Measurement.from_csv(path, "t", position="x")
    path = _write(tmp_path, "t,x\n0,1\n\n# pause\n1,2\n", name="ok.csv")
    np.testing.assert_array_equal(Measurement.from_csv(path, "t", position="x").position, [1, 2])
