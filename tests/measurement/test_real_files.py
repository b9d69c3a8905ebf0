"""The readers on the shared real data, in the shapes other rigs write (skipped without it)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from presliding.measurement import Measurement

DATA = Path(__file__).resolve().parents[3] / "shared" / "data"  # ../shared/data of the checkout
TRIBOMETER = DATA / "tribometer" / "tribometer_loops.txt"
EMPS = DATA / "emps" / "DATA_EMPS.mat"


def _tribometer(path, **options):
    return Measurement.from_csv(path, "Time [s]", position="Position [mm]",
                                friction_force="Friction [uN]", **options)  # fmt: skip


@pytest.fixture(scope="module")
def tribometer():
    if not TRIBOMETER.exists():
        pytest.skip("the shared real data are absent")
    return _tribometer(TRIBOMETER)


def test_utf16_and_decimal_comma_copies_read_alike(tribometer, tmp_path):
    text = TRIBOMETER.read_text(encoding="utf-8", errors="replace")
    utf16 = tmp_path / "tribometer_unicode.txt"
    utf16.write_bytes(text.encode("utf-16"))  # Excel's "Unicode text": a BOM, UTF-16 LE
    np.testing.assert_array_equal(_tribometer(utf16).position, tribometer.position)
    comma = tmp_path / "tribometer_eu.txt"
    comma.write_text(text.replace(".", ","), encoding="utf-8")
    m = _tribometer(comma, decimal=",")
    np.testing.assert_allclose(m.friction_force, tribometer.friction_force, rtol=1e-15)


def test_pandas_and_numpy_parse_alike(tribometer, monkeypatch):
    import builtins

    real = builtins.__import__

    def no_pandas(name, *args, **kwargs):
        if name == "pandas":
            raise ImportError(name)
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_pandas)
    np.testing.assert_array_equal(_tribometer(TRIBOMETER).position, tribometer.position)


def test_the_tribometers_cycles_are_cut_into_loops_and_ramps(tribometer):
    loops = tribometer.segments("loops")
    ramps = tribometer.segments("ramps")
    # about 50 reciprocation cycles at 0.25 Hz over ~200 s (two ramps each)
    assert 40 <= len(loops) <= 60
    assert len(ramps) == pytest.approx(2 * len(loops), abs=2)
    for piece in ramps.records[1:-1]:
        travel = np.ptp(piece.position)
        assert travel > 0.15e-3  # whole strokes, not quantisation steps


def test_emps_as_a_matlab_73_file(tmp_path):
    h5py = pytest.importorskip("h5py")
    if not EMPS.exists():
        pytest.skip("the shared real data are absent")
    from scipy.io import loadmat

    raw = loadmat(EMPS)
    path = tmp_path / "DATA_EMPS_v73.mat"
    with h5py.File(path, "w", userblock_size=512) as fh:
        for name in ("t", "qm", "vir", "gtau"):
            ds = fh.create_dataset(name, data=np.asarray(raw[name], dtype=float).T)
            ds.attrs["MATLAB_class"] = np.bytes_("double")
    with open(path, "r+b") as fh:
        fh.write(b"MATLAB 7.3 MAT-file, Platform: GLNXA64".ljust(116, b" "))
    kw = {"position": "qm", "applied_force": "vir", "scale": {"applied_force": "gtau"}}
    new, old = Measurement.from_mat(path, **kw), Measurement.from_mat(EMPS, **kw)
    np.testing.assert_array_equal(new.position, old.position)
    np.testing.assert_array_equal(new.applied_force, old.applied_force)
