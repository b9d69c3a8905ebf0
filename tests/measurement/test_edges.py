"""Edges of the readers and of Measurement.segments: what is refused, named or read again."""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

import presliding as ps
from presliding.measurement import Measurement
from tests.measurement.test_segments import servo_record

matplotlib.use("Agg")

TEXT = "Time [s];Position [mm];Force [N]\n0;0.001;1.5\n0.001;0.002;1.6\n0.002;0.003;1.7\n"


# ---------------------------------------------------------------------- units
def test_empty_unit_brackets_mean_no_unit(tmp_path):
    """A regression: `Time []` was refused ("its unit's brackets do not pair up")."""
    path = tmp_path / "empty.csv"
    path.write_text("Time [],x (),F [N]\n0,0,1\n1,2,3\n")
    m = Measurement.from_csv(path, "Time []", position="x ()", friction_force="F [N]")
    np.testing.assert_array_equal(m.position, [0.0, 2.0])  # no unit: taken as SI
    assert "taken as m (no unit given)" in m.source.describe()
    with pytest.raises(ValueError, match="brackets do not pair up"):
        path.write_text("Time [s],x [mm,F [N]\n0,0,1\n1,2,3\n")
        Measurement.from_csv(path, "Time [s]", position="x [mm", friction_force="F [N]")


@pytest.mark.parametrize(
    ("header", "signals", "needle"),
    [
        ("t [s],angle [deg],friction [N]", {"position": "angle [deg]",
         "friction_force": "friction [N]"}, "`position` 'angle [deg]' is in deg"),
        ("t [s],x [mm],torque [N m]", {"position": "x [mm]", "applied_force": "torque [N m]"},
         "`applied_force` 'torque [N m]' is in N m"),
        ("t [s],x [mm],w [rpm]", {"position": "x [mm]", "velocity": "w [rpm]"}, "rpm"),
    ],
)  # fmt: skip
def test_units_of_a_rotary_and_a_linear_axis_together_are_refused(tmp_path, header, signals,
                                                                  needle):  # fmt: skip
    path = tmp_path / "mix.csv"
    path.write_text(f"{header}\n0,0,1\n1,2,3\n")
    with pytest.raises(ValueError, match="mix a rotary and a linear axis") as info:
        Measurement.from_csv(path, "t [s]", **signals)
    assert needle in str(info.value) and "--units" in str(info.value)
    # the way out the message names: a torque on a slide given as a force with its ratio
    if "torque" in header:
        m = Measurement.from_csv(path, "t [s]", **signals, units={"applied_force": "N"},
                                 scale={"applied_force": 2.0})  # fmt: skip
        assert m.axis == "linear" and m.applied_force[1] == 6.0


def test_quantities_of_a_rotary_and_a_linear_axis_together_are_refused():
    pint = pytest.importorskip("pint")
    q = pint.UnitRegistry().Quantity
    t = np.arange(3.0)
    with pytest.raises(ValueError, match="mix a rotary and a linear axis"):
        Measurement(t, position=q(np.arange(3.0), "deg"), friction_force=q(np.ones(3), "N"))
    assert Measurement(t, position=q(np.arange(3.0), "deg"),
                       friction_force=q(np.ones(3), "N m")).axis == "rotary"  # fmt: skip


# ---------------------------------------------------------------------- text files
def test_a_forgotten_decimal_comma_is_named(tmp_path):
    path = tmp_path / "eu.csv"
    path.write_text(TEXT.replace(".", ","))
    with pytest.raises(
        ValueError,
        match=r"'0,001' is not a number; it looks like a number "
        r"with a decimal comma \('0.001'\): read the file with decimal=','",
    ):
        Measurement.from_csv(path, "Time [s]", position="Position [mm]")  # fmt: skip
    m = Measurement.from_csv(path, "Time [s]", position="Position [mm]", decimal=",")
    np.testing.assert_allclose(m.position, [1e-6, 2e-6, 3e-6])
    path.write_text(TEXT.replace("0.002;0.003", "0.002;abc"))  # not a decimal comma
    with pytest.raises(ValueError, match=r"'abc' is not a number\.$"):
        Measurement.from_csv(path, "Time [s]", position="Position [mm]")


@pytest.mark.parametrize("codec", ["utf-16-le", "utf-16-be", "utf-16", "utf-32", "utf-32-le",
                                   "utf-32-be"])  # fmt: skip
def test_utf16_and_utf32_with_or_without_a_byte_order_mark(tmp_path, codec):
    """UTF-16 without its mark was "binary data", UTF-32 gave names full of NULs."""
    path = tmp_path / "wide.csv"
    path.write_bytes(TEXT.replace("Force", "Kraft µ").encode(codec))
    m = Measurement.from_csv(path, "Time [s]", position="Position [mm]",
                             applied_force="Kraft µ [N]")  # fmt: skip
    np.testing.assert_allclose(m.position, [1e-6, 2e-6, 3e-6])
    assert "\x00" not in m.source.describe()


def test_binary_data_is_still_refused(tmp_path):
    path = tmp_path / "blob.csv"
    path.write_bytes(bytes(range(256)) * 64)
    with pytest.raises(ValueError, match="not a text file"):
        Measurement.from_csv(path, 0, position=1)


# ---------------------------------------------------------------------- MAT files
def test_an_empty_matlab_variable_is_named(tmp_path):
    from scipy.io import savemat

    path = tmp_path / "empty.mat"
    savemat(path, {"t": np.arange(5.0), "x": np.ones(5), "q": np.zeros((0, 0)),
                   "g": np.zeros((0, 1))})  # fmt: skip
    with pytest.raises(ValueError, match="variable 'q' of `position` is empty"):
        Measurement.from_mat(path, position="q")
    with pytest.raises(ValueError, match=r"variable 'g' \(the scale of `position`\) is empty"):
        Measurement.from_mat(path, position="x", scale={"position": "g"})


def test_an_empty_matlab_73_variable_is_named(tmp_path):
    """MATLAB 7.3 writes an empty array as its dimensions with MATLAB_empty=1: it read as a
    vector of two samples, "a length mismatch"."""
    h5py = pytest.importorskip("h5py")
    path = tmp_path / "empty73.mat"
    with h5py.File(path, "w", userblock_size=512) as fh:
        fh.create_dataset("t", data=np.arange(5.0)[:, None].T)
        fh["t"].attrs["MATLAB_class"] = np.bytes_("double")
        empty = fh.create_dataset("q", data=np.array([0, 0], dtype=np.uint64))
        empty.attrs["MATLAB_class"] = np.bytes_("double")
        empty.attrs["MATLAB_empty"] = np.uint8(1)
    with open(path, "r+b") as fh:
        fh.write(b"MATLAB 7.3 MAT-file, Platform: GLNXA64".ljust(116, b" "))
    with pytest.raises(ValueError, match="variable 'q' of `position` is empty"):
        Measurement.from_mat(path, position="q")


# ---------------------------------------------------------------------- segments
def _servo(n_stops=3):
    t, y, u, _ = servo_record(n_stops)
    return Measurement(t, position=y, applied_force=u)


@pytest.mark.parametrize(
    ("kind", "options", "needle"),
    [
        ("loops", {"lead_in": 0.01}, "`lead_in` is an option of cutting stops, not loops"),
        ("ramps", {"rest_speed": 1e-3}, "`rest_speed` is an option of cutting stops"),
        ("stops", {"tolerance": 1e-6}, "`tolerance` is an option of cutting loops and ramps"),
        ("stops", {"min_samples": -1}, "`min_samples` must be at least 2"),
        ("stops", {"min_samples": 1}, "`min_samples` must be at least 2"),
        ("stops", {"lead_in": -0.1}, "`lead_in` must be nonnegative"),
    ],
)
def test_segments_refuse_what_they_would_ignore(kind, options, needle):
    with pytest.raises(ValueError, match=needle):
        _servo().segments(kind, **options)


def test_segments_take_whole_numbers_of_samples():
    with pytest.raises(TypeError, match=r"`min_samples` must be an integer; got 2\.5"):
        _servo().segments("stops", min_samples=2.5)
    with pytest.raises(TypeError, match="`min_samples` must be an integer"):
        _servo().segments("stops", min_samples=True)


def test_no_ramps_or_loops_in_a_signal_that_never_moves():
    """A constant position gave one "ramp" (turning points at its ends), jitter of a count too."""
    t = np.arange(400) * 1e-3
    with pytest.raises(ValueError, match="never moves"):
        Measurement(t, position=np.full(400, 2e-3)).segments("ramps")
    jitter = 1e-6 * (np.arange(400) % 2)  # one encoder count back and forth
    with pytest.raises(ValueError, match="no ramps found to cut"):
        Measurement(t, position=jitter).segments("ramps")


def test_an_index_out_of_range_is_named():
    seg = _servo().segments("stops")
    with pytest.raises(
        IndexError,
        match=r"segment index 3 is out of range: 3 stops were cut "
        r"from record \(indices 0 to 2, or -3 to -1\)",
    ):
        seg[3]  # fmt: skip
    with pytest.raises(TypeError, match="a segment index must be an integer or a slice"):
        seg["1"]
    assert seg[-1] is seg.records[2] and seg[1:] == seg.records[1:]
    assert len(list(seg)) == 3  # iteration stops at the end


def test_the_cut_is_reproducible_from_its_parameters():
    m = _servo(4)
    for kind in ("stops", "ramps"):
        seg = m.segments(kind)
        assert seg.parameters["kind"] == kind and seg.parameters["min_samples"] == 10
        again = m.segments(**seg.parameters)
        assert again.spans == seg.spans and again.parameters == seg.parameters
    stops = m.segments("stops", lead_in=0.0)
    assert stops.parameters["lead_in"] == 0.0  # from the drop itself
    assert all(stops.table()[i]["from"] == "input drop" for i in range(len(stops)))
    text = stops.report()
    assert "cut with rest speed" in text and "lead-in 0 s" in text


def test_segments_plot_their_windows():
    m = _servo()
    seg = m.segments("stops")
    ax = seg.plot()
    spans = [p for p in ax.patches] + [c for c in ax.collections]
    assert len(spans) >= len(seg)  # one shaded window per piece
    assert ax.get_xlabel() == "time [s]" and ax.get_ylabel() == "position [m]"
    assert [t.get_text() for t in ax.texts] == ["1", "2", "3"]
    assert ax.figure.axes[1].get_ylabel() == "applied force [N]"  # the input, on its own axis
    matplotlib.pyplot.close("all")


def test_segments_are_public():
    assert ps.Segments is type(_servo().segments("stops"))
    assert "Segments" in ps.__all__


def test_model_file_paths_are_checked():
    from presliding import model_io

    with pytest.raises(
        TypeError,
        match=r"`path` must be a file path \(str or os.PathLike\); "
        "got None",
    ):
        model_io.load_model(None)  # fmt: skip
    with pytest.raises(TypeError, match="`path` must be a file path"):
        model_io.save_model(3, ps.PIFriction(0.1))
