"""Long numeric arrays of model files: read by a compiled scanner, written in chunks.

tomllib parses numbers one at a time in Python (minutes for 1e7 elements). `loads_toml`
finds the element arrays (``stiffness = [...]``, ``breakaway``, ``threshold``, their
``_negative`` sides, a density's ``breaks`` and ``heights``) of at least `FAST_ARRAY`
bytes, checks them against TOML's grammar of decimal numbers and converts them in one
compiled pass into a float64 array, and hands tomllib the rest of the file with each such
array replaced by a placeholder of as many lines (so tomllib's line numbers stay those of
the file). The conversion is correctly rounded, as Python's ``float()``: Clinger's exact
path (at most 2^53 and 10^±22), else the Eisel–Lemire algorithm (a 128-bit product with
a truncated power of five; Lemire, "Number parsing at a gigabyte per second", 2021), and
``float()`` itself for the rare numbers outside both (subnormal, beyond the range, more
than 19 significant digits).

Whatever the scanner does not take as plain decimal numbers (a string, ``inf``, an
underscore, an empty item, a stray character) is tomllib's to judge: the values of the
array before that item are blanked (newlines kept, so the line and column are the
file's) and tomllib reports the error exactly as on the whole file; if tomllib accepts the
item after all, it parses the whole file as it is.

Writing: `number_chunks` yields the text of a long float array in pieces of `CHUNK`
numbers, each the shortest repr that reads back bit for bit, so no list of all the
numbers and no string of the whole file is held.
"""

from __future__ import annotations

import re
import sys
from collections.abc import Iterator
from typing import Any

import numpy as np

from presliding.hysteresis._jit import njit

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = ["CHUNK", "FAST_ARRAY", "loads_toml", "number_chunks"]

#: Arrays shorter than this [bytes] are left to tomllib (about 13,000 numbers: well under a
#: second), so that a small file never waits for the scanner to compile on a cold cache.
FAST_ARRAY = 1 << 18
#: Numbers per piece of text when writing.
CHUNK = 1 << 13
_KEYS = ("breakaway_negative", "threshold_negative", "stiffness", "breakaway", "threshold",
         "breaks", "heights")  # fmt: skip
_ARRAY_KEY = re.compile(
    rb"(?m)^[ \t]*(?:" + b"|".join(k.encode() for k in _KEYS) + rb")[ \t]*=[ \t]*\["
)
#: After the closing bracket: only blanks, a comment and the end of the line.
_LINE_END = re.compile(rb"[ \t]*(?:#[^\n]*)?(?:\r?\n|$)")
_TOKEN = re.compile(rb"[0-9eE+\-.]+")
_BOM = b"\xef\xbb\xbf"
_BLANKS = bytes(b if b in (10, 13) else 32 for b in range(256))


# ---------------------------------------------------------------------- the tables
def _powers_of_five() -> tuple[np.ndarray, np.ndarray]:
    """5^q for q = −342 … 308 as 128-bit numbers with the top bit set (high, low words):
    truncated for q >= 0, the reciprocal rounded up for q < 0 (the table of Lemire's fast_float)."""
    hi, lo = np.empty(651, np.uint64), np.empty(651, np.uint64)
    for q in range(-342, 309):
        if q < 0:
            power = 5**-q
            z = power.bit_length()  # the least z with 2^z >= 5^-q (5^-q is no power of two)
            c = 2 ** ((z + 127) if q >= -27 else (2 * z + 128)) // power + 1
            c >>= max(c.bit_length() - 128, 0)
        else:
            c = 5**q
            c = c << (128 - c.bit_length()) if c.bit_length() < 128 else c >> (c.bit_length() - 128)
        hi[q + 342], lo[q + 342] = c >> 64, c & (2**64 - 1)
    return hi, lo


_POW5_HI, _POW5_LO = _powers_of_five()
_POW10 = np.array([10.0**k for k in range(23)])  # exact doubles

_U32 = np.uint64(0xFFFFFFFF)
_ALL = np.uint64(0xFFFFFFFFFFFFFFFF)
_SIGN = np.int64(-(1 << 63))  # the sign bit of a double's bits as int64
_OK, _OTHER, _FULL = 0, 1, 2


# ---------------------------------------------------------------------- compiled kernels
@njit(cache=True)
def _mul128(a: np.uint64, b: np.uint64) -> tuple[np.uint64, np.uint64]:
    """The 128-bit product a·b as (high, low) 64-bit words."""
    a_lo, a_hi, b_lo, b_hi = a & _U32, a >> np.uint64(32), b & _U32, b >> np.uint64(32)
    p0, p1, p2, p3 = a_lo * b_lo, a_lo * b_hi, a_hi * b_lo, a_hi * b_hi
    mid = (p0 >> np.uint64(32)) + (p1 & _U32) + (p2 & _U32)
    low = (mid << np.uint64(32)) | (p0 & _U32)
    return p3 + (p1 >> np.uint64(32)) + (p2 >> np.uint64(32)) + (mid >> np.uint64(32)), low


@njit(cache=True)
def _eisel_lemire(w: np.uint64, q: int, hi_tab: np.ndarray, lo_tab: np.ndarray) -> int:
    """The bits of the double nearest w·10^q (w > 0), or −1 where float() must decide."""
    if q < -342 or q > 308:
        return -1
    lz = 0
    for step in (32, 16, 8, 4, 2, 1):
        if (w >> np.uint64(64 - step)) == np.uint64(0):
            w = w << np.uint64(step)
            lz += step
    high, low = _mul128(w, hi_tab[q + 342])
    mask = np.uint64(0x1FF)  # the bits below the 55 that matter
    if (high & mask) == mask:  # the truncated table may matter: add the next 64 bits
        second_high, _ = _mul128(w, lo_tab[q + 342])
        low = low + second_high
        if second_high > low:
            high = high + np.uint64(1)
    if low == _ALL and (q < -27 or q > 55):  # too close to call with 128 bits
        return -1
    upper = int(high >> np.uint64(63))
    shift = np.uint64(upper + 9)
    mantissa = high >> shift
    power2 = ((217706 * q) >> 16) + 63 + upper - lz + 1023
    if power2 <= 0:  # subnormal
        return -1
    halfway = low <= np.uint64(1) and -4 <= q <= 23 and (mantissa & np.uint64(3)) == np.uint64(1)
    if halfway and (mantissa << shift) == high:  # exactly halfway: round to even
        mantissa = mantissa & ~np.uint64(1)
    mantissa = (mantissa + (mantissa & np.uint64(1))) >> np.uint64(1)
    if mantissa >= np.uint64(1 << 53):
        mantissa = np.uint64(1 << 52)
        power2 += 1
    mantissa = mantissa & np.uint64((1 << 52) - 1)
    if power2 >= 0x7FF:  # beyond the range
        return -1
    return int(mantissa) | (power2 << 52)


@njit(cache=True)
def _skip(buf: np.ndarray, pos: int) -> tuple[int, int]:
    """Past blanks, newlines and comments (ASCII); `_OTHER` at anything else odd."""
    n = buf.shape[0]
    while pos < n:
        c = buf[pos]
        if c == 32 or c == 9 or c == 10:
            pos += 1
        elif c == 13:  # only as part of CR LF
            if pos + 1 >= n or buf[pos + 1] != 10:
                return pos, _OTHER
            pos += 2
        elif c == 35:  # '#' to the end of the line: tabs and printable ASCII only
            pos += 1
            while pos < n and buf[pos] != 10:
                c = buf[pos]
                if (c < 32 and c != 9 and c != 13) or c >= 127:
                    return pos, _OTHER
                pos += 1
        else:
            break
    return pos, _OK


@njit(cache=True)
def _is_digit(c: int) -> bool:
    return 48 <= c <= 57


@njit(cache=True)
def _number(
    buf: np.ndarray, pos: int, pow10: np.ndarray, hi_tab: np.ndarray, lo_tab: np.ndarray
) -> tuple[float, int, int, int]:
    """The TOML decimal number (integer or float) at `pos`: (value, bits, kind, end).

    kind 0: the double is `value`; 1: its `bits`; 2: float() must convert the text
    (more than 19 significant digits, subnormal or beyond the range); 3: no plain number.
    """
    n = buf.shape[0]
    negative = False
    if pos < n and (buf[pos] == 43 or buf[pos] == 45):  # + -
        negative = buf[pos] == 45
        pos += 1
    if pos >= n or not _is_digit(buf[pos]):
        return 0.0, 0, 3, pos
    w = np.uint64(0)
    digits, q, exact, integer = 0, 0, True, True
    if buf[pos] == 48:  # a leading zero stands alone
        pos += 1
        if pos < n and _is_digit(buf[pos]):
            return 0.0, 0, 3, pos
    while pos < n and _is_digit(buf[pos]):  # the integer part, no leading zero
        if digits < 19:
            w = w * np.uint64(10) + np.uint64(buf[pos] - 48)
            digits += 1
        else:
            exact = False
        pos += 1
    if pos < n and buf[pos] == 46:  # '.' then at least one digit
        pos += 1
        integer = False
        if pos >= n or not _is_digit(buf[pos]):
            return 0.0, 0, 3, pos
        while pos < n and _is_digit(buf[pos]):
            d = np.uint64(buf[pos] - 48)
            if digits < 19:
                q -= 1
                if w != np.uint64(0) or d != np.uint64(0):
                    w = w * np.uint64(10) + d
                    digits += 1
            elif d != np.uint64(0):
                exact = False
            pos += 1
    if pos < n and (buf[pos] == 101 or buf[pos] == 69):  # e E, a sign, at least one digit
        pos += 1
        integer = False
        sign = 1
        if pos < n and (buf[pos] == 43 or buf[pos] == 45):
            sign = -1 if buf[pos] == 45 else 1
            pos += 1
        if pos >= n or not _is_digit(buf[pos]):
            return 0.0, 0, 3, pos
        e = 0
        while pos < n and _is_digit(buf[pos]):
            if e < 100_000:
                e = 10 * e + (buf[pos] - 48)
            pos += 1
        q += sign * e
    if pos >= n:
        return 0.0, 0, 3, pos
    c = buf[pos]  # then a blank, a line end, ',', ']' or '#'
    if not (c == 32 or c == 9 or c == 10 or c == 13 or c == 44 or c == 93 or c == 35):
        return 0.0, 0, 3, pos
    if not exact:
        return 0.0, 0, 2, pos
    if w == np.uint64(0):  # "-0" is the integer 0 (TOML), "-0.0" a negative zero
        return -0.0 if negative and not integer else 0.0, 0, 0, pos
    if w <= np.uint64(1 << 53) and -22 <= q <= 22:  # Clinger: one exact operation
        x = float(w) * pow10[q] if q >= 0 else float(w) / pow10[-q]
        return -x if negative else x, 0, 0, pos
    bits = _eisel_lemire(w, q, hi_tab, lo_tab)
    if bits < 0:
        return 0.0, 0, 2, pos
    return 0.0, (bits | _SIGN) if negative else bits, 1, pos


@njit(cache=True)
def _read_array(
    buf: np.ndarray,
    pos: int,
    out: np.ndarray,
    out_bits: np.ndarray,
    later: np.ndarray,
    pow10: np.ndarray,
    hi_tab: np.ndarray,
    lo_tab: np.ndarray,
) -> tuple[int, int, int, int]:
    """The array of plain numbers from just after its '[' into `out` (`out_bits`: the same
    memory as int64): (status, end, count, number left to float()).

    `_OK`: `end` is just after ']'. `_OTHER`: the array holds something else from `end`
    on (just after the '[' or the last ','). `_FULL`: more numbers than `out` holds. The
    index and start of each number float() must convert go to `later` (as many as fit).
    """
    n = buf.shape[0]
    count, n_later, cut = 0, 0, pos
    pos, status = _skip(buf, pos)
    if status != _OK:
        return _OTHER, cut, count, n_later
    if pos < n and buf[pos] == 93:  # ']'
        return _OK, pos + 1, count, n_later
    while True:
        x, bits, kind, end = _number(buf, pos, pow10, hi_tab, lo_tab)
        if kind == 3:
            return _OTHER, cut, count, n_later
        if count >= out.shape[0]:
            return _FULL, cut, count, n_later
        if kind == 0:
            out[count] = x
        elif kind == 1:
            out_bits[count] = bits
        else:
            if n_later < later.shape[0]:
                later[n_later, 0], later[n_later, 1] = count, pos
            n_later += 1
        count += 1
        pos, status = _skip(buf, end)
        if status != _OK or pos >= n:
            return _OTHER, cut, count, n_later
        if buf[pos] == 93:
            return _OK, pos + 1, count, n_later
        if buf[pos] != 44:  # ','
            return _OTHER, cut, count, n_later
        cut = pos + 1
        pos, status = _skip(buf, cut)
        if status != _OK:
            return _OTHER, cut, count, n_later
        if pos < n and buf[pos] == 93:  # a trailing comma
            return _OK, pos + 1, count, n_later


@njit(cache=True)
def _count(buf: np.ndarray, start: int, stop: int) -> tuple[int, int]:
    """The commas and line feeds in buf[start:stop]."""
    commas = lines = 0
    for i in range(start, stop):
        commas += buf[i] == 44
        lines += buf[i] == 10
    return commas, lines


# ---------------------------------------------------------------------- reading
def _read(raw: bytes, buf: np.ndarray, pos: int) -> tuple[int, int, np.ndarray, int]:
    """(status, end, numbers, line feeds) of the array whose '[' is just before `pos`."""
    close = raw.find(b"]", pos)  # the end, unless a comment holds a ']'
    commas, lines = _count(buf, pos, close if close >= 0 else len(raw))
    capacity = commas + 1
    later = np.empty((min(capacity, 4096), 2), dtype=np.int64)
    while True:
        out = np.empty(capacity)
        tables = (_POW10, _POW5_HI, _POW5_LO)
        status, end, count, n_later = _read_array(buf, pos, out, out.view(np.int64), later, *tables)
        if status == _FULL:  # a ']' in a comment: every ',' up to the end of the file
            capacity = raw.count(b",", pos) + 1
        elif n_later > later.shape[0]:
            later = np.empty((n_later, 2), dtype=np.int64)
        else:
            break
    if status != _OK:
        return status, end, out[:0], 0
    if end != close + 1:  # the array did not end at the first ']'
        lines = raw.count(b"\n", pos, end)
    for i, start in later[:n_later].tolist():
        match = _TOKEN.match(raw, start)
        assert match is not None  # the scanner read a number there
        out[i] = float(match.group())
    return status, end, out[:count] if count + 8 >= capacity else out[:count].copy(), lines


def _blanked(raw: bytes, start: int, stop: int) -> bytes:
    """raw[start:stop] with every byte but the line ends a blank."""
    return raw[start:stop].translate(_BLANKS)


def loads_toml(raw: bytes) -> dict[str, Any]:
    """The tables of the TOML file `raw` (UTF-8, optionally with a byte-order mark), its long
    element arrays as float64 arrays (the module notes); raises as ``tomllib.loads`` of
    ``raw.decode("utf-8-sig")`` would (TOMLDecodeError, UnicodeDecodeError)."""
    base = len(_BOM) if raw.startswith(_BOM) else 0
    pieces: list[bytes] = []
    arrays: dict[str, np.ndarray] = {}
    buf = np.frombuffer(raw, dtype=np.uint8)
    done = search = base
    while (match := _ARRAY_KEY.search(raw, search)) is not None:
        search = match.end()
        if raw.find(b"]", search, search + FAST_ARRAY) >= 0:
            continue  # a short array (or the bracket is in a comment): tomllib's
        status, end, values, lines = _read(raw, buf, search)
        if status == _OK and _LINE_END.match(raw, end) is None:
            status, end = _OTHER, end - 1  # text after ']': tomllib's error
        if status != _OK:
            head = b"".join([*pieces, raw[done:search], _blanked(raw, search, end)])
            _judge(raw, head + raw[end:])  # raises tomllib's error where the item is bad
            return _loads(raw, b"".join([*pieces, raw[done:]]), arrays)
        key = f"presliding-array-{len(arrays)}-{id(arrays)}"
        arrays[key] = values
        pieces += [raw[done : search - 1], f'"{key}"'.encode(), b"\n" * lines]
        done = search = end
    pieces.append(raw[done:])
    return _loads(raw, b"".join(pieces), arrays)


def _text(raw: bytes, reduced: bytes) -> str:
    try:
        return reduced.decode("utf-8-sig")
    except UnicodeDecodeError:
        raw.decode("utf-8-sig")  # the error at its place in the file
        raise


def _judge(raw: bytes, blanked: bytes) -> None:
    """Raise tomllib's error on the file whose accepted numbers are blanked (if it has one)."""
    tomllib.loads(_text(raw, blanked))


def _loads(raw: bytes, reduced: bytes, arrays: dict[str, np.ndarray]) -> dict[str, Any]:
    data = tomllib.loads(_text(raw, reduced))
    if arrays:
        _put_back(data, arrays)
    return data


def _put_back(table: dict[str, Any], arrays: dict[str, np.ndarray]) -> None:
    for key, value in table.items():
        if isinstance(value, dict):
            _put_back(value, arrays)
        elif isinstance(value, str) and value in arrays:
            table[key] = arrays[value]


# ---------------------------------------------------------------------- writing
def number_chunks(values: np.ndarray) -> Iterator[str]:
    """The TOML array of the float64 `values`, ``[x0, x1, ...]``, in pieces of `CHUNK`
    numbers: the shortest repr of each, which reads back bit for bit."""
    values = np.asarray(values, dtype=np.float64).reshape(-1)
    yield "["
    for start in range(0, values.shape[0], CHUNK):
        part = ", ".join(map(float.__repr__, values[start : start + CHUNK].tolist()))
        yield part if start == 0 else ", " + part
    yield "]"
