"""Long element arrays of model files: read bit for bit as tomllib would, written exactly."""

from __future__ import annotations

import sys
import tracemalloc

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import presliding._model_arrays as model_arrays
from presliding import PIFriction
from presliding._model_arrays import FAST_ARRAY, loads_toml, number_chunks
from presliding.model_io import ModelFileError, load_model, model_to_toml, read_tables, save_model

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

#: Arrays of at least this many bytes are the scanner's in these tests (`small_arrays`).
SHORT = 4096
#: Enough numbers that the compiled scanner, not tomllib, reads the array.
LONG = SHORT // 2


@pytest.fixture(autouse=True, scope="module")
def small_arrays():
    """The scanner takes arrays from `SHORT` bytes on (files of tens of numbers suffice)."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(model_arrays, "FAST_ARRAY", SHORT)
        yield


def _document(numbers: list[str], sep: str = ", ") -> bytes:
    return ("# σ [N s/m]\n[friction]\ncoulomb = 0.5\nstiffness = [" + sep.join(numbers)
            + "]  # k_j\nbreakaway = [1.0]\n").encode()  # fmt: skip


def _outcome(call):
    try:
        return "ok", call()
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        return f"{type(exc).__name__}: {exc}", None


def _bits(values) -> np.ndarray:
    return np.asarray(values, dtype=np.float64).view(np.int64)


def test_short_arrays_are_left_to_tomllib():
    """Below FAST_ARRAY bytes tomllib reads the array (a list), as it does every file."""
    numbers = [repr(0.5 + i) for i in range(20)]
    assert isinstance(loads_toml(_document(numbers))["friction"]["stiffness"], list)
    assert FAST_ARRAY >= 1 << 16  # files of a few thousand elements never compile anything


def test_a_million_elements_round_trip_bit_for_bit(tmp_path):
    rng = np.random.default_rng(11)
    n = 1_000_000
    k = rng.uniform(1.0, 1e4, n) * 10.0 ** rng.integers(-5, 6, n)
    c = rng.uniform(1.0, 2.0, n) * 2.0 ** rng.integers(-400, 400, n)  # exponents far apart
    c[:4] = [2.2250738585072014e-300, 1.2345678901234567e120, 0.1, 1 / 3]
    model = PIFriction(0.25, k, c)
    path = tmp_path / "big.toml"
    save_model(path, model)
    tables = read_tables(path)["friction"]
    assert isinstance(tables["stiffness"], np.ndarray)  # the scanner read it, not tomllib
    np.testing.assert_array_equal(_bits(tables["stiffness"]), _bits(k))
    np.testing.assert_array_equal(_bits(tables["breakaway"]), _bits(c))
    assert load_model(path).model == model


finite = st.floats(allow_nan=False, allow_infinity=False, allow_subnormal=True)


@settings(max_examples=40, deadline=None)
@given(st.lists(finite, min_size=1, max_size=50), st.sampled_from([", ", ",", ",\n  ", " ,\t"]))
def test_written_numbers_read_back_bit_for_bit(values, sep):
    """repr-exact writing, scanner reading: ±0, subnormals, both ends of the range."""
    x = np.array(values * (LONG // len(values) + 1))
    text = "".join(number_chunks(x))
    assert text == "[" + ", ".join(map(repr, x.tolist())) + "]"
    raw = _document([repr(v) for v in x.tolist()], sep)
    got = loads_toml(raw)["friction"]["stiffness"]
    assert isinstance(got, np.ndarray)
    np.testing.assert_array_equal(_bits(got), _bits(x))


number_text = st.builds(
    "{}{}{}{}".format,
    st.sampled_from(["", "-", "+"]),
    st.one_of(st.just("0"), st.from_regex(r"[1-9][0-9]{0,24}", fullmatch=True)),
    st.one_of(st.just(""), st.from_regex(r"\.[0-9]{1,25}", fullmatch=True)),
    st.one_of(st.just(""), st.from_regex(r"[eE][+-]?[0-9]{1,3}", fullmatch=True)),
)


@settings(max_examples=60, deadline=None)
@given(st.lists(number_text, min_size=1, max_size=40))
def test_any_decimal_number_is_read_as_python_reads_it(numbers):
    """Correct rounding: every TOML decimal number gives what tomllib gives, bit for bit
    (float() of a float's text, of an integer's value: "-0" is the integer 0)."""
    numbers = numbers * (LONG // len(numbers) + 1)
    got = loads_toml(_document(numbers))["friction"]["stiffness"]
    want, parsed = _outcome(lambda: tomllib.loads(_document(numbers).decode()))
    assert want == "ok"
    np.testing.assert_array_equal(
        _bits(got), _bits([float(v) for v in parsed["friction"]["stiffness"]])
    )


BAD = ["abc", "", "1.0.0", "01.5", "1.", ".5", "1e", "+-1", "1 2", "1.0x", "é", "1e5.5"]
OTHER = ["nan", "-inf", "1_000.5", '"x"', "[1.0]", "1979-05-27", "true", "0x10"]


@pytest.mark.parametrize("multiline", [False, True])
@pytest.mark.parametrize("item", BAD + OTHER)
def test_anything_but_plain_numbers_gets_tomllibs_answer(item, multiline):
    """A bad value is named by tomllib's own message and line/column; a valid TOML value
    that is not a plain number (inf, a string, ...) is parsed by tomllib as before."""
    numbers = [repr(0.5 + i) for i in range(LONG)]
    numbers[LONG // 2 + 3] = item
    raw = _document(numbers, ",\n  " if multiline else ", ")
    want, expected = _outcome(lambda: tomllib.loads(raw.decode()))
    got, parsed = _outcome(lambda: loads_toml(raw))
    assert got == want
    if want == "ok":
        assert str(parsed) == str(expected)
    else:
        assert "line" in want


@pytest.mark.parametrize(
    "text",
    [
        "[friction]\nstiffness = [{}] x = 1\n",  # text after the array
        "[friction]\nstiffness = [{},\n",  # never closed
        "[friction]\nstiffness = [\n  {}  # a comment \x01\n]\n",  # a control character
        "\ufeff[friction]\r\nstiffness = [\r\n  {}, # ]\r\n]\r\n",  # byte-order mark, CR LF
        "[friction]\nstiffness = [{}]\n# \udcff\n",  # not UTF-8, after the array
    ],
)
def test_the_file_around_the_array_is_judged_as_tomllib_would(text):
    body = ", ".join(repr(0.25 * i) for i in range(LONG))
    raw = text.format(body).encode("utf-8", errors="surrogateescape")
    want, _ = _outcome(lambda: tomllib.loads(raw.decode("utf-8-sig")))
    got, parsed = _outcome(lambda: loads_toml(raw))
    assert got == want
    if want == "ok":
        np.testing.assert_array_equal(parsed["friction"]["stiffness"], 0.25 * np.arange(LONG))


def test_line_numbers_after_a_long_multiline_array_are_the_files(tmp_path):
    numbers = ",\n  ".join(repr(0.5 + i) for i in range(LONG))
    path = tmp_path / "m.toml"
    path.write_text(f"[friction]\ncoulomb = 0.5\nstiffness = [\n  {numbers}\n]\nbad = = 1\n")
    with pytest.raises(ModelFileError, match=f"line {LONG + 5},"):
        load_model(path)


def test_saving_streams_the_arrays_and_reading_holds_no_lists(tmp_path):
    """Neither the whole text nor a list of all the numbers is held: the peak while saving
    is a chunk's text, while reading the file's bytes and the arrays themselves."""
    rng = np.random.default_rng(5)
    n = 200_000
    model = PIFriction(0.5, rng.uniform(1.0, 1e4, n), rng.uniform(1e-3, 1.0, n))
    path = tmp_path / "m.toml"
    save_model(path, model)  # compiled code and caches warm
    read_tables(path)
    tracemalloc.start()
    try:
        save_model(path, model, overwrite=True)
        _, saving = tracemalloc.get_traced_memory()
        tracemalloc.reset_peak()
        read_tables(path)
        _, reading = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    size = path.stat().st_size
    assert path.read_text(encoding="utf-8") == model_to_toml(model)
    assert saving < 0.25 * size  # a list of n floats alone would be 32 bytes each
    assert reading < size + 2 * 8 * n + (1 << 20)
