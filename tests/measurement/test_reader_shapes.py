"""Files as rigs write them: trailing tabs, UTF-16, decimal commas, MAT v7.3, pint arrays."""

from __future__ import annotations

import numpy as np
import pytest

from presliding.measurement import Measurement
from presliding.measurement._readers import read_text

T = np.arange(200) * 1e-3
Y = 1e-3 * np.sin(2 * np.pi * 3 * T)
U = 0.5 * np.cos(2 * np.pi * 3 * T)


def _lines(rows, sep="\t", end=""):
    return "".join(sep.join(f"{v:.9g}" for v in row) + end + "\n" for row in rows)


@pytest.mark.parametrize("sep", ["\t", ";", ","])
def test_a_headerless_file_whose_lines_end_in_the_delimiter_keeps_its_first_row(tmp_path, sep):
    path = tmp_path / "servo.txt"
    path.write_text(_lines(np.column_stack([T, Y, U]), sep, end=sep))
    table = read_text(path)
    assert table.names is None and table.n_columns == 3
    m = Measurement.from_csv(path, 0, position=1, applied_force=2)
    assert m.n_samples == T.shape[0]
    np.testing.assert_allclose(m.position, Y, rtol=1e-8)
    np.testing.assert_allclose(m.time[:2], T[:2])


def test_a_header_whose_lines_end_in_a_tab(tmp_path):
    path = tmp_path / "servo.txt"
    path.write_text("t [s]\tx [mm]\t\n" + _lines(np.column_stack([T, Y * 1e3]), end="\t"))
    m = Measurement.from_csv(path, "t", position="x")
    np.testing.assert_allclose(m.position, Y, rtol=1e-8)


def test_header_false_reads_the_first_row_as_data(tmp_path):
    path = tmp_path / "odd.txt"
    path.write_text("0\t0.0\n" + _lines(np.column_stack([T[1:], Y[1:]])))
    assert read_text(path, header=True).names == ("0", "0.0")
    assert Measurement.from_csv(path, 0, position=1, header=False).n_samples == T.shape[0]
    path.write_text("0\tx1\n" + _lines(np.column_stack([T[1:], Y[1:]])))
    assert read_text(path).names == ("0", "x1")  # detected: a header (not all numbers)
    with pytest.raises(ValueError, match="line 1, column 'column 1': 'x1' is not a number"):
        Measurement.from_csv(path, 0, position=1, header=False)


def test_an_unclosed_unit_bracket_names_the_column(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("t [s],Position [mm\n" + _lines(np.column_stack([T, Y]), ","))
    with pytest.raises(ValueError, match=r"column 'Position \[mm': its unit's brackets"):
        Measurement.from_csv(path, "t [s]", position="Position [mm")


def test_time_going_backwards_names_the_files_line(tmp_path):
    rows = np.column_stack([T, Y])
    rows[150, 0] = rows[149, 0]
    path = tmp_path / "back.csv"
    path.write_text("# rig export\n\nt,x\n" + _lines(rows, ","))
    with pytest.raises(ValueError, match=r"back.csv: line 154, column 't': time 0.149 does not"):
        Measurement.from_csv(path, "t", position="x")


@pytest.mark.parametrize("encoding", ["utf-16", "utf-16-le", "utf-16-be"])
def test_utf16_text_with_a_byte_order_mark(tmp_path, encoding):
    path = tmp_path / "excel.txt"
    text = "t [s]\tx [µm]\n" + _lines(np.column_stack([T, Y * 1e6]))
    bom = {"utf-16": b"", "utf-16-le": b"\xff\xfe", "utf-16-be": b"\xfe\xff"}[encoding]
    path.write_bytes(bom + text.encode(encoding))
    m = Measurement.from_csv(path, "t [s]", position="x [µm]")
    np.testing.assert_allclose(m.position, Y, rtol=1e-7)


@pytest.mark.parametrize("sep", [";", "\t", " "])
def test_decimal_commas(tmp_path, sep):
    path = tmp_path / "eu.csv"
    body = _lines(np.column_stack([T, Y * 1e3, U]), sep).replace(".", ",")
    head = sep.join(["Zeit [s]", "Weg [mm]", "Kraft [N]"]) if sep != " " else "t x F"
    path.write_text(head + "\n" + body)
    columns = ("Zeit", "Weg", "Kraft") if sep != " " else ("t", "x", "F")
    m = Measurement.from_csv(path, columns[0], position=columns[1], applied_force=columns[2],
                             decimal=",")  # fmt: skip
    scale = 1e-3 if sep != " " else 1.0
    np.testing.assert_allclose(m.position, Y * 1e3 * scale, rtol=1e-7)
    np.testing.assert_allclose(m.applied_force, U, rtol=1e-7, atol=1e-12)
    with pytest.raises(ValueError, match="`decimal` must be"):
        Measurement.from_csv(path, 0, position=1, decimal=";")


def test_decimal_commas_with_a_comma_delimiter_are_refused(tmp_path):
    path = tmp_path / "eu.csv"
    path.write_text("t,x\n0,1\n")
    with pytest.raises(ValueError, match="needs cells separated by a tab"):
        Measurement.from_csv(path, 0, position=1, decimal=",", delimiter=",")


def test_a_bad_cell_is_named_with_pandas_and_without(tmp_path, monkeypatch):
    path = tmp_path / "gap.csv"
    rows = _lines(np.column_stack([T, Y]), ",").splitlines()
    rows[120] = rows[120].split(",")[0] + ",oops"
    path.write_text("t,x\n" + "\n".join(rows) + "\n")
    with pytest.raises(ValueError, match=r"line 122, column 'x': 'oops' is not a number"):
        Measurement.from_csv(path, "t", position="x")
    import builtins

    real = builtins.__import__

    def no_pandas(name, *args, **kwargs):
        if name == "pandas":
            raise ImportError(name)
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_pandas)
    with pytest.raises(ValueError, match=r"line 122, column 'x': 'oops' is not a number"):
        Measurement.from_csv(path, "t", position="x")
    good = tmp_path / "good.csv"
    good.write_text("t,x\n" + _lines(np.column_stack([T, Y]), ","))
    np.testing.assert_allclose(Measurement.from_csv(good, "t", position="x").position, Y)


def test_one_column_for_two_signals_is_refused(tmp_path):
    path = tmp_path / "one.txt"
    path.write_text(_lines(np.column_stack([T, Y, U])))
    with pytest.raises(ValueError, match="column 'column 1' is given to both `position` and"):
        Measurement.from_csv(path, 0, position=1, applied_force=1)


def test_matlab_73_files_through_h5py(tmp_path):
    h5py = pytest.importorskip("h5py")
    path = tmp_path / "rig.mat"
    with h5py.File(path, "w", userblock_size=512) as fh:
        for name, value in (("t", T), ("qm", Y), ("tau", U)):
            ds = fh.create_dataset(name, data=value[None, :])  # MATLAB's 1×N, column-major
            ds.attrs["MATLAB_class"] = np.bytes_("double")
        g = fh.create_dataset("gtau", data=np.array([[2.5]]))
        g.attrs["MATLAB_class"] = np.bytes_("double")
        c = fh.create_dataset("label", data=np.array([[ord(ch)] for ch in "joint"], np.uint16))
        c.attrs["MATLAB_class"] = np.bytes_("char")
    with open(path, "r+b") as fh:  # the text header MATLAB writes into the user block
        fh.write(b"MATLAB 7.3 MAT-file, Platform: GLNXA64".ljust(116, b" "))
    m = Measurement.from_mat(path, position="qm", applied_force="tau",
                             scale={"applied_force": "gtau"}, axis="rotary")  # fmt: skip
    np.testing.assert_allclose(m.position, Y)
    np.testing.assert_allclose(m.applied_force, 2.5 * U)
    assert m.axis == "rotary"
    with pytest.raises(ValueError, match=r"variable 'label' .* holds text, not numbers"):
        Measurement.from_mat(path, position="label")


def test_matlab_73_without_h5py_names_the_extra(tmp_path, monkeypatch):
    h5py = pytest.importorskip("h5py")
    path = tmp_path / "rig.mat"
    with h5py.File(path, "w") as fh:
        fh.create_dataset("t", data=T[None, :])
    import sys

    monkeypatch.setitem(sys.modules, "h5py", None)
    with pytest.raises(ImportError, match=r"presliding\[h5py\]"):
        Measurement.from_mat(path, position="t")


def test_pint_arrays_are_converted_to_si_with_a_dimension_check():
    pint = pytest.importorskip("pint")
    ureg = pint.UnitRegistry()
    m = Measurement(ureg.Quantity(T * 1e3, "ms"), position=ureg.Quantity(Y * 1e3, "mm"),
                    applied_force=ureg.Quantity(U * 1e3, "mN"))  # fmt: skip
    np.testing.assert_allclose(m.position, Y, rtol=1e-12)
    np.testing.assert_allclose(m.time, T, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(m.applied_force, U, rtol=1e-12, atol=1e-15)
    assert m.axis == "linear"
    joint = Measurement(T, position=ureg.Quantity(np.degrees(Y), "deg"))
    assert joint.axis == "rotary"
    np.testing.assert_allclose(joint.position, Y, rtol=1e-12)
    with pytest.raises(ValueError, match="`position`: the unit 'newton' is not a length"):
        Measurement(T, position=ureg.Quantity(Y, "N"))
    with pytest.raises(ValueError, match="contradicts"):
        Measurement(T, position=ureg.Quantity(Y, "mm"), axis="rotary")
